"""The numba options every physics kernel compiles with, in one place.

``cache=True``: a warm start loads the machine code instead of compiling it.
``error_model="numpy"``: a division by zero gives inf or NaN, which the divergence check
sees, instead of raising. ``fastmath={"contract"}``: fused multiply-add contraction only
(no reassociation), applied alike to the vectorized loops and their scalar remainders, so
results stay bit-identical for any batch size. ``INLINE``: helpers inlined into the loops
that call them (numba's own inlining, before LLVM sees the loop).
"""

JIT = dict(cache=True, error_model="numpy", fastmath={"contract"})
INLINE = dict(cache=True, error_model="numpy", inline="always", fastmath={"contract"})
