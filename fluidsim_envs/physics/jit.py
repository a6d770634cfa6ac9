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


def target_cpu() -> str:
    """The CPU the kernels are compiled for: the host's (LLVM's name for it, such as
    ``skylake-avx512``), unless ``NUMBA_CPU_NAME`` names another. Results are bit-identical
    run to run on one such CPU; on another the vector width and the fused multiply-adds LLVM
    picks differ, so the last bits round differently, and a long evaluation of a chaotic
    flight can carry them as far as an episode's outcome."""
    import numba
    from llvmlite import binding

    return numba.config.CPU_NAME or binding.get_host_cpu_name()
