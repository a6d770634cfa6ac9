"""The step kernel: all environments, all bodies, ``steps`` time steps in one compiled call.

Layout (why it is fast). The state lives in one array ``st[13, B, E]``: rows x(3) q(4) v(3)
L(3), then body slot, then environment, so that the innermost index runs over environments.
Environments are cut into blocks of ``BLOCK``; a block's state is copied into a small scratch
``scr[block, B, ROWS * BLOCK]`` that stays in cache for all the steps of the call. Every loop
over a block runs over bodies innermost with straight-line arithmetic, so the compiler
vectorizes it across bodies: the sample loops are outside (``for sample: for body:``),
accumulating each sample's force into per-body rows. No allocation, no Python, no branch on
data. Each body's arithmetic is independent of its neighbours, of the block it falls in and of
the thread that runs it, so results are bit-identical for any batch size and thread count.
Of fast-math only fused multiply-add contraction is on (the same contraction is applied to the
vectorized loop and its scalar remainder: tests/physics/test_determinism.py checks it); no
reassociation, and inf/NaN stay visible to the divergence check.

Vectorization is fragile in two known ways, both handled here: a tuple must not be indexed
with a loop variable, and helpers that take the scratch array must be branch-free (a branch in
an inlined array helper leaves reference counting in the loop).

State per body: position x, orientation quaternion q (w, x, y, z; body -> world), linear
velocity v and angular momentum L about the center of mass, all in the world frame. Angular
velocity is derived, ``w = R I^-1 R^T L``, so torque-free motion conserves L exactly.

The water surface and the clock. Each environment has its own time ``clock[E]`` (float64 in
either simulation dtype, so that wave phases stay exact over long episodes); the kernel
advances it by ``dt`` (the simulation dtype's) per step and writes it back. The force loops
read a sample's height above the surface from the row ``HEIGHT`` (the body's z minus the surface
height under the sample): in calm water (no waves: ``prm[P_NWAVES] = 0``, an empty ``swell``
table) ``HEIGHT`` is a copy of z, made once per force evaluation, and the force loops do exactly
what they did on a flat surface at z = 0. With swell, ``_phase_rows`` stores each wave's time
phase ``phase - omega t`` per environment at the start of each step (rows ``PHASE``, from the
float64 clock and ``swell`` table), and ``_swell_rows`` (not inlined, like ``_wake_rows``;
vectorized across environments thanks to a branch-free cosine, ``surface.wave_cos``) fills
``HEIGHT`` for each sample's point before that sample's force loop, from the waves in ``prm``.
The integrators and ``_evaluate`` take no array beyond those they took on a flat surface (each
array argument of a compiled call costs reference counting, measurable at small batches).
Each force evaluation sees the surface at its own stage time, ``tau`` after the step's start:
t for (symplectic, explicit) Euler and Verlet's first evaluation, t + dt for Verlet's second
(its positions are the step's end), t and t + dt/2 for RK2, t, t + dt/2, t + dt/2, t + dt for
RK4, so that every integrator keeps its order of accuracy when the surface moves (a surface
frozen at the step's start would make RK2 and RK4 first order in time). The wake, likewise,
is evaluated where its source is at the stage time (``_wake_rows``).

Contact. When any body has collision shapes and there is a ground or a second body
(``model.cprm[C_ON]``), each step's integration is followed by ``contact.collide`` for each
environment of the block in turn: scalar, branchy code that reads and writes the bodies'
state rows in place (it does not vectorize and need not: a body costs it one distance test
per pair until something touches). It reads that environment's rows of ``model.shape``,
``model.body`` and ``model.contact_body``, and ``data.warm``, ``data.touch``.

What a first step compiles (``benchmarks/bench_compile.py``, docs/bench_compile.csv). Numba
links each compiled callee into its caller and optimizes and emits the whole again, so a
cold compile grows with the code times the levels of calls above it. Hence: the block's load
and advance are inlined into the step kernels (numba's inlining: a level less); the loops
that copy state, body and source rows run to the arrays' shapes, not to constants, which LLVM
would unroll into one vectorized copy per row (the step tree was 50k lines of IR, now 20k);
the step kernels take the integrator id as a literal and compile its block step only
(``STEPPERS``, ``_step_block``; ``step_*_shared`` hold all six, chosen at run time, for a
process that runs several); and ``contact`` and ``pairs`` are None where nothing touches or no
two bodies can meet, branches numba prunes, so contact.py and its body-pair tests compile only
where they can run. Together a first step went from 93/58/55 s (dart, submarine, boat) to
the CSV's figures; the dart's rest is mostly contact.py's scalar solver.

External force. ``data.external`` [E, B, 6] holds a world force and torque per body that
``_evaluate`` adds to the samples' (``Simulator.set_external_force``: a scene's mooring line).

The data. Kernels take ``(model, samples, data)``, the named tuples of ``model.py``; row layouts are
named in ``state.py`` (state, body constants, this scratch) and ``model.py`` (samples).
Each environment's craft: mass, inertia and center-of-mass shift are read per environment
(``model.body``, copied into the scratch's BODY rows with the state); a sample's offset is the
craft's minus the shift (``_arm``), and its sizes the craft's times the environment's factors
(``samples.factor``, a row per set of samples scaled together: ``factors.py``). The craft's
own sample table is read once per sample, whatever E: per-environment copies of it (a boat's
is 3.6 kB per environment) made the E = 4096 step 10-20% slower. Shift and factors cost it
2-5%.
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit, prange, types
from numba.extending import overload

from . import integrators as IT
from .contact import C_ON, NW, collide, may_touch, num_pairs
from .forces import (
    HALF,
    ONE,
    TINY,
    TWO,
    ZERO,
    buoyancy_force,
    cylinder_force,
    friction_force,
    inverse_viscosity,
    plate_force,
    rotate_about_axis,
    thrust_of,
    water_fraction,
)
from .jit import INLINE as _INLINE
from .jit import JIT as _JIT
from .model import (
    F_AREA,
    F_EFFICIENCY,
    F_THRUST,
    KINDS,
    S_AREA,
    S_BUOY_AREA,
    S_CYL_AREA,
    S_EFFICIENCY,
    S_FRICTION_CF,
    S_FRICTION_ITTC,
    S_FRICTION_LENGTH,
    S_OFFSET,
    S_ONE_SIDED,
    S_SKIN_AREA,
    S_THRUST_MAX,
    S_THRUST_MIN,
    S_VOLUME,
)
from .rotation import env_inv_inertia, quat_rate, quat_to_matrix, world_omega
from .state import (
    B_COM_SHIFT,
    B_INV_INERTIA,
    B_MASS,
    B_RUNAWAY,
    B_SECOND_MOMENT,
    BLOCK,
    BODY,
    CARRY,
    CHANGE,
    DERIV,
    END,
    FLUID,
    HEIGHT,
    ITERATIONS,
    MEMORY,
    NBODY,
    NSTATE,
    OL,
    OMEGA,
    OQ,
    OV,
    OWN_WATER,
    OX,
    PHASE,
    RECORD,
    RECORD_ROWS,
    RK_SUM,
    ROT,
    ROWS,
    SAMPLE_X,
    SAMPLE_Y,
    SAMPLE_Z,
    SOURCE,
    STALE,
    START,
    STATE,
)
from .surface import MAX_WAVES, time_phase, wave_cos, wave_exp
from .wake import W_ON, wake_at

# A slot's scratch is one flat row-major array S[row * BLOCK + i] (rows: state.SCRATCH_FIELDS):
# with the row length a compile-time constant the compiler can prove that rows do not
# overlap, and vectorizes.
assert ROWS == CHANGE + 2 and MEMORY == BODY + NBODY
# _evaluate has one loop per sample kind, in this order: a kind added to model.KINDS needs
# its loop there (and its share of _first_sample) before this module imports
assert tuple(k.name for k in KINDS) == ("plate", "flap", "cyl", "buoy", "thr"), KINDS

# name -> kernel id, evaluations per step and drift share: views of the one table
INTEGRATORS = {m.name: m.id for m in IT.TABLE}
EVALS_PER_STEP = {m.name: m.evals_per_step for m in IT.TABLE}
DRIFT_SHARE = {m.name: m.drift_share for m in IT.TABLE}
EXPLICIT_EULER, SYMPLECTIC_EULER, VELOCITY_VERLET = (
    IT.EXPLICIT_EULER,
    IT.SYMPLECTIC_EULER,
    IT.VELOCITY_VERLET,
)
RK2, RK4, VERLET_TETRA = IT.RK2, IT.RK4, IT.VERLET_TETRA
ACCURATE_EULER, POSITION_VERLET = IT.ACCURATE_EULER, IT.POSITION_VERLET
PRESCALED_SYMPLECTIC_EULER = IT.PRESCALED_SYMPLECTIC_EULER
VELOCITY_VERLET_CACHED = IT.VELOCITY_VERLET_CACHED
TRAPEZOID_SYMPLECTIC_EULER, IMPLICIT_MIDPOINT = IT.TRAPEZOID_SYMPLECTIC_EULER, IT.IMPLICIT_MIDPOINT

# prm[] slots: world and step parameters, in the simulation dtype
P_G, P_RHO_AIR, P_RHO_WATER, P_WATER = 0, 1, 2, 3
P_WIND, P_CURRENT = 4, 7  # 3 each: the World's defaults (the kernel reads flow[6, E])
P_INV_BLEND, P_VMAX, P_FMAX, P_DT = 10, 11, 12, 13
P_NWAVES = 14  # swell: the number of waves (0: calm water), then per wave (a, kx, ky, omega)
P_SWELL = 15
P_TETRA_SWITCH = P_SWELL + 4 * MAX_WAVES  # verlet_tetra: rigid above this |w| dt (rad)
P_GM = P_TETRA_SWITCH + 1  # World.central_gravity_m3s2 (0: none)
# implicit_midpoint: the iteration's tolerance (integrators.IMPLICIT_TOLERANCE_ULP times the
# dtype's machine epsilon), its most iterations, and the round-off stop's bound (the dtype's
# epsilon to the 3/4: _implicit_midpoint)
P_IMPLICIT_TOL, P_IMPLICIT_MAX, P_IMPLICIT_LOOSE = P_GM + 1, P_GM + 2, P_GM + 3
P_ORBITAL = P_IMPLICIT_LOOSE + 1  # World.wave_orbital_velocity: 1 the water moves with the waves
NPRM = P_ORBITAL + 1
POLAR_ITERATIONS = 8  # fit passes from the rigid turn: energy floor ~1e-11 (docs/tetra_spin.csv)

SIX = np.float32(6.0)
HALF_PI = 0.5 * math.pi  # wave_cos(x - HALF_PI) is sin(x)
EIGHTH, INV48, INV384 = np.float32(1 / 8), np.float32(1 / 48), np.float32(1 / 384)  # series
T0 = 0.0  # the step's start, as a float64 stage time offset


# --------------------------------------------------------------------------------------------
# rigid-body kinematics (scalar; shared by the kernel and the public accessors)


@njit(**_INLINE)
def body_state(st, b, e, inv_inertia):
    """Position, velocity, rotation matrix (row-major 9-tuple) and world angular velocity of
    body slot b in environment e of a state ``st[13, B, E]``: what env kernels observe."""
    rot = quat_to_matrix(st[OQ, b, e], st[OQ + 1, b, e], st[OQ + 2, b, e], st[OQ + 3, b, e])
    w = world_omega(rot, st[OL, b, e], st[OL + 1, b, e], st[OL + 2, b, e], inv_inertia)
    return (
        (st[OX, b, e], st[OX + 1, b, e], st[OX + 2, b, e]),
        (st[OV, b, e], st[OV + 1, b, e], st[OV + 2, b, e]),
        rot,
        w,
    )


# --------------------------------------------------------------------------------------------
# block loops (inlined into the integrators)


@njit(**_INLINE)
def _matrix(S, i):
    """The rotation matrix rows ROT of body i as a row-major 9-tuple."""
    return (
        S[ROT * BLOCK + i],
        S[(ROT + 1) * BLOCK + i],
        S[(ROT + 2) * BLOCK + i],
        S[(ROT + 3) * BLOCK + i],
        S[(ROT + 4) * BLOCK + i],
        S[(ROT + 5) * BLOCK + i],
        S[(ROT + 6) * BLOCK + i],
        S[(ROT + 7) * BLOCK + i],
        S[(ROT + 8) * BLOCK + i],
    )


@njit(**_INLINE)
def _inv_inertia(S, i):
    """Body i's inverse body inertia entries (xx, yy, zz, xy, xz, yz) from its BODY rows."""
    k = BODY + B_INV_INERTIA
    return (
        S[k * BLOCK + i],
        S[(k + 1) * BLOCK + i],
        S[(k + 2) * BLOCK + i],
        S[(k + 3) * BLOCK + i],
        S[(k + 4) * BLOCK + i],
        S[(k + 5) * BLOCK + i],
    )


@njit(**_INLINE)
def _omega_row(S, n):
    """Rotation matrix rows ROT and angular velocity rows OMEGA from the state rows STATE."""
    for i in range(n):
        m = quat_to_matrix(
            S[(STATE + OQ) * BLOCK + i],
            S[(STATE + OQ + 1) * BLOCK + i],
            S[(STATE + OQ + 2) * BLOCK + i],
            S[(STATE + OQ + 3) * BLOCK + i],
        )
        # written out: indexing a tuple with a loop variable defeats vectorization
        S[ROT * BLOCK + i], S[(ROT + 1) * BLOCK + i], S[(ROT + 2) * BLOCK + i] = m[0], m[1], m[2]
        S[(ROT + 3) * BLOCK + i], S[(ROT + 4) * BLOCK + i], S[(ROT + 5) * BLOCK + i] = (
            m[3],
            m[4],
            m[5],
        )
        S[(ROT + 6) * BLOCK + i], S[(ROT + 7) * BLOCK + i], S[(ROT + 8) * BLOCK + i] = (
            m[6],
            m[7],
            m[8],
        )
        w = world_omega(
            m,
            S[(STATE + OL) * BLOCK + i],
            S[(STATE + OL + 1) * BLOCK + i],
            S[(STATE + OL + 2) * BLOCK + i],
            _inv_inertia(S, i),
        )
        S[(OMEGA) * BLOCK + i] = w[0]
        S[(OMEGA + 1) * BLOCK + i] = w[1]
        S[(OMEGA + 2) * BLOCK + i] = w[2]


@njit(**_INLINE)
def _add_force(S, i, rx, ry, rz, fx, fy, fz):
    """Accumulate a force applied at world offset r from the center of mass (and its torque)."""
    S[(DERIV + OV) * BLOCK + i] += fx
    S[(DERIV + OV + 1) * BLOCK + i] += fy
    S[(DERIV + OV + 2) * BLOCK + i] += fz
    S[(DERIV + OL) * BLOCK + i] += ry * fz - rz * fy
    S[(DERIV + OL + 1) * BLOCK + i] += rz * fx - rx * fz
    S[(DERIV + OL + 2) * BLOCK + i] += rx * fy - ry * fx


@njit(**_INLINE)
def _forces(model, data):
    """What a force evaluation takes of the model and the data besides the samples
    (``_evaluate``'s arguments): passed as separate arrays, since every array of a compiled
    call's arguments costs it time."""
    return model.prm, model.wprm, data.ctrl, data.flap_now, data.external


@njit(**_INLINE)
def _first_sample(samples, b):
    """The number of samples (plates, cylinders, buoyancy, thrusters) of bodies before b."""
    at = samples.plate_at[b] + samples.flap_at[b] + samples.cyl_at[b]
    return at + samples.buoy_at[b] + samples.thr_at[b]


# A recording ``rec = (slot[N], out[P, R, E'], e0)`` of ``_evaluate`` (``out`` C-contiguous):
# sample j (all bodies' samples in order) goes to ``out[slot[j], :, e0 + i]`` for environment
# i of the block, or nowhere where ``slot[j] < 0`` (``_picked``). Rows: the world offset from
# the center of mass and the force (``sample_forces``: R = R_FORCE); a fourth element
# (``sample_flows``: ``(slot, out, e0, True)``, R = R_SENSE) also records what the sample
# senses, in SENSE_FIELDS' order (the tuple's length is its type: no branch at run time).
R_FORCE = 6
SENSE_FIELDS = (
    "inflow_x_mps",  # the fluid's velocity relative to the sample, body frame
    "inflow_y_mps",
    "inflow_z_mps",
    "inflow_normal_mps",  # along the plate's normal (the cylinder's axis)
    "density_kgm3",  # the fluid's there: the air's, the water's, or a blend at the surface
    "height_m",  # the sample's height above the surface under it (above z = 0 without one)
    "pressure_pa",  # the force against the normal per unit of area: onto a hull whose
    # normals point out of it (0: no area)
)
R_SENSE = R_FORCE + len(SENSE_FIELDS)
assert R_SENSE == RECORD_ROWS, "state.SCRATCH_FIELDS' record rows are a recording's"


@njit(**_INLINE)
def _record(rec, j, i, S, got):
    """Sample j's world offset r and force F for body i of the block, and, where ``rec``
    says so (its fourth element), what it senses, into the scratch's RECORD rows (then
    :func:`_flush`: a loop that stores only into the scratch, at rows known when compiled,
    vectorizes; one that stores into ``out`` beside the scratch's loads ran scalar, 2.7
    times a force evaluation for the dart's ten probed samples). ``got = (rx, ry, rz, fx,
    fy, fz, flow, nx, ny, nz, area)`` as the ``_plate_at`` kind return, ``flow`` as
    ``_flow``'s (its velocity through the fluid and the density), n its normal (world). Not
    on the step path: ``rec`` is None there."""
    rx, ry, rz, fx, fy, fz, flow, nx, ny, nz, area = got
    S[RECORD * BLOCK + i] = rx
    S[(RECORD + 1) * BLOCK + i] = ry
    S[(RECORD + 2) * BLOCK + i] = rz
    S[(RECORD + 3) * BLOCK + i] = fx
    S[(RECORD + 4) * BLOCK + i] = fy
    S[(RECORD + 5) * BLOCK + i] = fz
    if len(rec) > 3:  # sample_flows' recording: a type, so no branch is compiled
        vx, vy, vz, rho = flow
        m = _matrix(S, i)  # body = M^T world; the inflow is the fluid's: -v
        S[(RECORD + 6) * BLOCK + i] = -(m[0] * vx + m[3] * vy + m[6] * vz)
        S[(RECORD + 7) * BLOCK + i] = -(m[1] * vx + m[4] * vy + m[7] * vz)
        S[(RECORD + 8) * BLOCK + i] = -(m[2] * vx + m[5] * vy + m[8] * vz)
        S[(RECORD + 9) * BLOCK + i] = -(vx * nx + vy * ny + vz * nz)
        S[(RECORD + 10) * BLOCK + i] = rho
        S[(RECORD + 11) * BLOCK + i] = S[HEIGHT * BLOCK + i] + rz
        pressure = -(fx * nx + fy * ny + fz * nz) / area if area > ZERO else ZERO
        S[(RECORD + 12) * BLOCK + i] = pressure


@njit(**_INLINE)
def _flush(rec, j, n, S):
    """Copy sample j's recorded rows (:func:`_record`) of the block's n environments from
    the scratch to ``out[slot[j], :, e0:e0 + n]``."""
    slot, out, e0 = rec[0], rec[1], rec[2]
    s = slot[j]
    for r in range(out.shape[1]):
        for i in range(n):
            out[s, r, e0 + i] = S[(RECORD + r) * BLOCK + i]


@njit(**_INLINE)
def _rotate(S, i, x, y, z):
    """World vector of the body vector (x, y, z)."""
    return (
        S[(ROT) * BLOCK + i] * x + S[(ROT + 1) * BLOCK + i] * y + S[(ROT + 2) * BLOCK + i] * z,
        S[(ROT + 3) * BLOCK + i] * x + S[(ROT + 4) * BLOCK + i] * y + S[(ROT + 5) * BLOCK + i] * z,
        S[(ROT + 6) * BLOCK + i] * x + S[(ROT + 7) * BLOCK + i] * y + S[(ROT + 8) * BLOCK + i] * z,
    )


@njit(**_INLINE)
def _arm(S, i, ox, oy, oz):
    """World offset from the center of mass of the sample at (ox, oy, oz) from the craft's:
    the environment's center of mass is shifted by rows BODY + B_COM_SHIFT (0: the craft's)."""
    c = (BODY + B_COM_SHIFT) * BLOCK + i
    return _rotate(S, i, ox - S[c], oy - S[c + BLOCK], oz - S[c + 2 * BLOCK])


@njit(**_INLINE)
def _fluid(prm):
    """Fluid parameters as scalars (read once, outside the loops): water flag, 1/blend,
    densities."""
    return prm[P_WATER], prm[P_INV_BLEND], prm[P_RHO_AIR], prm[P_RHO_WATER]


@njit(**_INLINE)
def _body_point(S, i):
    """Height above the surface under the current sample, velocity relative to the air,
    angular velocity and the water's velocity relative to the air at body i:
    (z - eta, vx, vy, vz, wx, wy, wz, dux, duy, duz)."""
    return (
        S[HEIGHT * BLOCK + i],
        S[(STATE + OV) * BLOCK + i] - S[FLUID * BLOCK + i],
        S[(STATE + OV + 1) * BLOCK + i] - S[(FLUID + 1) * BLOCK + i],
        S[(STATE + OV + 2) * BLOCK + i] - S[(FLUID + 2) * BLOCK + i],
        S[OMEGA * BLOCK + i],
        S[(OMEGA + 1) * BLOCK + i],
        S[(OMEGA + 2) * BLOCK + i],
        S[(FLUID + 3) * BLOCK + i],
        S[(FLUID + 4) * BLOCK + i],
        S[(FLUID + 5) * BLOCK + i],
    )


@njit(**_INLINE)
def _flow(pt, rx, ry, rz, fluid):
    """At the sample point x + r of a body ``pt = _body_point(S, i)``: density and velocity
    relative to the fluid; ``fluid`` is the tuple ``_fluid(prm)``.

    Helpers that take the scratch array must stay branch-free: the compiler then vectorizes
    the loops that inline them; this one has branches (the surface blend), so it takes
    scalars only."""
    z0, v0x, v0y, v0z, wx, wy, wz, dux, duy, duz = pt
    water, inv_blend, rho_a, rho_w = fluid
    frac = water_fraction(z0 + rz, water, inv_blend)
    rho = rho_a + frac * (rho_w - rho_a)
    vx = v0x + wy * rz - wz * ry - frac * dux
    vy = v0y + wz * rx - wx * rz - frac * duy
    vz = v0z + wx * ry - wy * rx - frac * duz
    return vx, vy, vz, rho


@njit(**_INLINE)
def _source(S, i):
    """The wake source row of environment i as a tuple of scalars (branch-free)."""
    return (
        S[SOURCE * BLOCK + i], S[(SOURCE + 1) * BLOCK + i], S[(SOURCE + 2) * BLOCK + i],
        S[(SOURCE + 3) * BLOCK + i], S[(SOURCE + 4) * BLOCK + i], S[(SOURCE + 5) * BLOCK + i],
        S[(SOURCE + 6) * BLOCK + i], S[(SOURCE + 7) * BLOCK + i], S[(SOURCE + 8) * BLOCK + i],
        S[(SOURCE + 9) * BLOCK + i], S[(SOURCE + 10) * BLOCK + i], S[(SOURCE + 11) * BLOCK + i],
        S[(SOURCE + 12) * BLOCK + i], S[(SOURCE + 13) * BLOCK + i], S[(SOURCE + 14) * BLOCK + i],
        S[(SOURCE + 15) * BLOCK + i], S[(SOURCE + 16) * BLOCK + i], S[(SOURCE + 17) * BLOCK + i],
    )  # fmt: skip


@njit(**_JIT)
def _wake_rows(S, n, ox, oy, oz, wprm, tau):
    """Water-minus-air rows FLUID + 3.. at one sample's point: the environment's own (rows
    OWN_WATER) plus the wake there, ``tau`` after the step's start. Not inlined: the field branches,
    so this loop stays scalar, and the force loop that follows keeps its vectorized form
    whether or not there is a wake."""
    for i in range(n):
        rx, ry, rz = _arm(S, i, ox, oy, oz)
        # the source has moved on by tau u since the step's start (rows SOURCE hold it there;
        # the wake moves rigidly with it): the field at p then is the field at p - tau u now.
        # A source frozen over the step made rk2 and rk4 first order behind a moving wake.
        w = wake_at(
            S[(STATE + OX) * BLOCK + i] + rx - tau * S[(SOURCE + 12) * BLOCK + i],
            S[(STATE + OX + 1) * BLOCK + i] + ry - tau * S[(SOURCE + 13) * BLOCK + i],
            S[(STATE + OX + 2) * BLOCK + i] + rz - tau * S[(SOURCE + 14) * BLOCK + i],
            _source(S, i),
            wprm,
        )
        S[(FLUID + 3) * BLOCK + i] = S[OWN_WATER * BLOCK + i] + w[0]
        S[(FLUID + 4) * BLOCK + i] = S[(OWN_WATER + 1) * BLOCK + i] + w[1]
        S[(FLUID + 5) * BLOCK + i] = S[(OWN_WATER + 2) * BLOCK + i] + w[2]


@njit(**_JIT)
def _phase_rows(S, n, e0, swell, clock):
    """Rows PHASE: each wave's time phase ``phase - omega t`` at each environment's clock, 0
    for the rows past the swell's waves (which the loops below add as waves of no height)."""
    for j in range(MAX_WAVES):
        for i in range(n):
            on = j < swell.shape[0]
            S[(PHASE + j) * BLOCK + i] = time_phase(clock[e0 + i], swell, j) if on else ZERO


# _swell_rows and _sea_rows add every wave by name, w0 to w3
assert MAX_WAVES == 4, "kernels: _swell_rows and _sea_rows unroll four waves"


@njit(**_INLINE)
def _wave(prm, j, tau):
    """Wave j's (a, kx, ky, omega tau) from ``prm``: zeros past the swell's waves."""
    w = P_SWELL + 4 * j
    return prm[w], prm[w + 1], prm[w + 2], prm[w + 3] * tau


@njit(**_INLINE)
def _wave_angle(S, i, j, x, y, wave):
    """Wave j's angle at (x, y) in environment i of the block, ``kx x + ky y + phase - omega
    tau`` (the argument of :func:`surface.surface_height`'s cosine)."""
    _, kx, ky, shift = wave
    phase = kx * x + ky * y
    return phase + (S[(PHASE + j) * BLOCK + i] - shift)


@njit(**_INLINE)
def _surface_at(S, i, ox, oy, oz, w0, w1, w2, w3):
    """Row HEIGHT of environment i at one sample's point (see :func:`_swell_rows`); returns
    each wave's angle and cosine there (the orbital velocity's, :func:`_sea_rows`)."""
    rx, ry, _ = _arm(S, i, ox, oy, oz)
    S[SAMPLE_X * BLOCK + i] = S[(STATE + OX) * BLOCK + i] + rx
    S[SAMPLE_Y * BLOCK + i] = S[(STATE + OX + 1) * BLOCK + i] + ry
    # read back, and each wave added into the row: in the scratch's precision (float32)
    x, y = S[SAMPLE_X * BLOCK + i], S[SAMPLE_Y * BLOCK + i]
    t0, t1 = _wave_angle(S, i, 0, x, y, w0), _wave_angle(S, i, 1, x, y, w1)
    t2, t3 = _wave_angle(S, i, 2, x, y, w2), _wave_angle(S, i, 3, x, y, w3)
    c0, c1, c2, c3 = wave_cos(t0), wave_cos(t1), wave_cos(t2), wave_cos(t3)
    h = HEIGHT * BLOCK
    S[h + i] = ZERO
    S[h + i] += w0[0] * c0
    S[h + i] += w1[0] * c1
    S[h + i] += w2[0] * c2
    S[h + i] += w3[0] * c3
    S[h + i] = S[(STATE + OX + 2) * BLOCK + i] - S[h + i]
    return t0, t1, t2, t3, c0, c1, c2, c3


@njit(**_JIT)
def _swell_rows(S, n, ox, oy, oz, prm, tau):
    """Row HEIGHT at one sample's point: the body's z minus the surface height under the sample,
    at the step's start plus ``tau``. Not inlined, like ``_wake_rows``: it runs only with
    swell, and the force loops keep their vectorized form. ``surface.surface_height`` with
    the time phases of rows PHASE and every wave (``MAX_WAVES``; past the swell's, waves of
    no height, which add exact zeros) inside one loop over environments, each row at an
    offset known when compiled, so that it vectorizes (``wave_cos`` is branch-free; a loop
    per wave, reading a row that depends on the wave, ran scalar: 8 times slower)."""
    w0, w1, w2, w3 = _wave(prm, 0, tau), _wave(prm, 1, tau), _wave(prm, 2, tau), _wave(prm, 3, tau)
    for i in range(n):
        _surface_at(S, i, ox, oy, oz, w0, w1, w2, w3)


@njit(**_INLINE)
def _orbital_wave(wave, omega):
    """Wave (a, kx, ky, omega tau) as (a omega, k, ux, uy): its surface speed, wavenumber and
    direction; zeros past the swell's waves."""
    a, kx, ky, _ = wave
    k = math.sqrt(kx * kx + ky * ky)
    if k == ZERO:  # no wave
        return ZERO, ZERO, ZERO, ZERO
    return a * omega, k, kx / k, ky / k


@njit(**_INLINE)
def _orbital_add(S, i, z, wave, theta, cos_theta):
    """Add one wave's orbital velocity at depth z in environment i of the block to rows
    FLUID + 3.. (see :func:`_sea_rows`), in the scratch's precision; ``theta`` its angle
    at the sample's point, ``cos_theta`` its cosine (the surface's)."""
    a_omega, k, ux, uy = wave
    speed = a_omega * wave_exp(k * z)
    along = speed * cos_theta
    S[(FLUID + 3) * BLOCK + i] += along * ux
    S[(FLUID + 4) * BLOCK + i] += along * uy
    S[(FLUID + 5) * BLOCK + i] += speed * wave_cos(theta - HALF_PI)


@njit(**_JIT)
def _sea_rows(S, n, ox, oy, oz, wake, prm, tau):
    """:func:`_swell_rows`, and rows FLUID + 3.. at the sample's point: the water's own
    velocity (or, with a wake, the wake's rows) plus each wave's orbital velocity there.
    Linear deep-water theory for ``eta = a cos(theta)``: ``a omega e^(k z') cos(theta)``
    along the wave's direction and ``a omega e^(k z') sin(theta)`` up, at ``z' = min(z -
    eta, 0)`` below the moving surface (Wheeler's stretching in deep water: the surface's
    own velocity at the surface, decaying with depth below it). The surface and the
    velocity in one loop over environments, so the surface's cosines serve both."""
    w0, w1, w2, w3 = _wave(prm, 0, tau), _wave(prm, 1, tau), _wave(prm, 2, tau), _wave(prm, 3, tau)
    w = P_SWELL + 3  # each wave's omega: its row of prm
    o0, o1 = _orbital_wave(w0, prm[w]), _orbital_wave(w1, prm[w + 4])
    o2, o3 = _orbital_wave(w2, prm[w + 8]), _orbital_wave(w3, prm[w + 12])
    if not wake:  # the water's own velocity, then each wave's
        for i in range(n):
            S[(FLUID + 3) * BLOCK + i] = S[OWN_WATER * BLOCK + i]
            S[(FLUID + 4) * BLOCK + i] = S[(OWN_WATER + 1) * BLOCK + i]
            S[(FLUID + 5) * BLOCK + i] = S[(OWN_WATER + 2) * BLOCK + i]
    for i in range(n):
        t0, t1, t2, t3, c0, c1, c2, c3 = _surface_at(S, i, ox, oy, oz, w0, w1, w2, w3)
        # the sample's depth below the surface: HEIGHT holds the body's z - eta (stored and
        # read back: in the scratch's precision)
        S[SAMPLE_Z * BLOCK + i] = min(S[HEIGHT * BLOCK + i] + _arm(S, i, ox, oy, oz)[2], ZERO)
        z = S[SAMPLE_Z * BLOCK + i]
        _orbital_add(S, i, z, o0, t0, c0)
        _orbital_add(S, i, z, o1, t1, c1)
        _orbital_add(S, i, z, o2, t2, c2)
        _orbital_add(S, i, z, o3, t3, c3)


@njit(**_JIT)
def _where_rows(S, n, ox, oy, oz, wake, sea, wprm, prm, tau):
    """The rows that depend on where the sample at (ox, oy, oz) is, those that are on: the
    wake's flow there, the surface's height under it. Every kind's loop calls it first,
    only when one is on (a call per sample and evaluation costs a calm one-environment step
    20%; so does an inlined helper with these branches)."""
    if wake:
        _wake_rows(S, n, ox, oy, oz, wprm, tau)
    if sea and prm[P_ORBITAL] != 0.0:
        _sea_rows(S, n, ox, oy, oz, wake, prm, tau)
    elif sea:
        _swell_rows(S, n, ox, oy, oz, prm, tau)


@njit(**_INLINE)
def _skin(pt, rx, ry, rz, nx, ny, nz, fluid, area, cf, ittc, length, vmax, fmax):
    """Skin friction (``forces.friction_force``) on a plate at world offset r with world
    normal n of the body at ``pt = _body_point(S, i)``, of wetted ``area``, coefficient or
    roughness allowance ``cf``, ITTC-1957 line ``ittc`` (0 or 1) on ``length``: for the
    plates that have it, in a loop of their own after the pressure's, so that a craft
    without it runs the loops it ran before. Scalars only, as :func:`_flow` (it branches):
    taking the scratch, it left reference counting in the loop and ran 10 times slower."""
    vx, vy, vz, rho = _flow(pt, rx, ry, rz, fluid)
    inv_nu = inverse_viscosity(water_fraction(pt[0] + rz, fluid[0], fluid[1]))
    return friction_force(vx, vy, vz, nx, ny, nz, rho, inv_nu, area, cf, ittc, length, vmax, fmax)


@njit(**_INLINE)
def _record_add(rec, j, i, got):
    """Add a force to sample j's recorded one (its skin friction; the sensed pressure is the
    plate's normal force's only)."""
    slot, out, e0 = rec[0], rec[1], rec[2]
    s, e = slot[j], e0 + i
    out[s, 3, e] += got[3]
    out[s, 4, e] += got[4]
    out[s, 5, e] += got[5]


@njit(**_INLINE)
def _adding(rec, n):
    """The environments a force loop adds up: all n on the step path (``rec`` None, pruned
    when compiled), none for a recording, which reads each sample's force in a loop of its
    own and sums nothing."""
    if rec is None:
        return n
    return 0


@njit(**_INLINE)
def _skipped(rec, j) -> bool:
    """Whether a recording ``rec`` leaves sample j out: then its loops need not run (what a
    recording reads of a sample depends on the state and that sample alone). Never on the
    step path (``rec`` None: pruned when compiled)."""
    if rec is None:
        return False
    return rec[0][j] < 0


@njit(**_INLINE)
def _picked(rec, j) -> bool:
    """Whether a recording ``rec`` (None on the step path) takes sample j."""
    if rec is None:
        return False
    return rec[0][j] >= 0


# One sample's force in environment i of a block, from its offset and body-frame direction:
# what the force loops add up and what a recording (``_record``'s arguments after S) holds;
# the loops call them once to add and, where they record, again in a loop of their own.


@njit(**_INLINE)
def _plate_at(S, i, ox, oy, oz, bx, by, bz, fluid, area, eff, vmax, fmax, side):
    """A plate: (r, F, flow, world normal, area)."""
    rx, ry, rz = _arm(S, i, ox, oy, oz)
    nx, ny, nz = _rotate(S, i, bx, by, bz)
    flow = _flow(_body_point(S, i), rx, ry, rz, fluid)
    vx, vy, vz, rho = flow
    fx, fy, fz = plate_force(vx, vy, vz, nx, ny, nz, rho, area, eff, vmax, fmax, side)
    return rx, ry, rz, fx, fy, fz, flow, nx, ny, nz, area


@njit(**_INLINE)
def _skin_at(S, i, ox, oy, oz, bx, by, bz, fluid, area, friction):
    """A plate's skin friction (``friction``: cf, ittc, length, vmax, fmax): (r, F)."""
    cf, ittc, reach, vmax, fmax = friction
    rx, ry, rz = _arm(S, i, ox, oy, oz)
    nx, ny, nz = _rotate(S, i, bx, by, bz)
    pt = _body_point(S, i)
    fx, fy, fz = _skin(pt, rx, ry, rz, nx, ny, nz, fluid, area, cf, ittc, reach, vmax, fmax)
    return rx, ry, rz, fx, fy, fz


@njit(**_INLINE)
def _cylinder_at(S, i, ox, oy, oz, bx, by, bz, fluid, area, vmax, fmax):
    """A cylinder: (r, F, flow, world axis, 0: no pressure area)."""
    rx, ry, rz = _arm(S, i, ox, oy, oz)
    ax, ay, az = _rotate(S, i, bx, by, bz)
    flow = _flow(_body_point(S, i), rx, ry, rz, fluid)
    vx, vy, vz, rho = flow
    fx, fy, fz = cylinder_force(vx, vy, vz, ax, ay, az, rho, area, vmax, fmax)
    return rx, ry, rz, fx, fy, fz, flow, ax, ay, az, ZERO


@njit(**_INLINE)
def _buoyancy_at(S, i, ox, oy, oz, fluid, g, volume, area):
    """A buoyancy sample at rest in the water it displaces: (r, F, flow, its floor's normal
    (down: the pressure is its lift per area), area)."""
    water, inv_blend, rho_a, rho_w = fluid
    rx, ry, rz = _arm(S, i, ox, oy, oz)
    z = S[HEIGHT * BLOCK + i] + rz  # the sample's height above the surface
    frac = water_fraction(z, water, inv_blend)
    fz = buoyancy_force(z, frac, water, rho_w, g, volume, area)
    flow = (ZERO, ZERO, ZERO, rho_a + frac * (rho_w - rho_a))
    return rx, ry, rz, ZERO, ZERO, fz, flow, ZERO, ZERO, -ONE, area


@njit(**_JIT)
def _evaluate(S, b, n, e0, samples, prm, wprm, ctrl, flap_now, external, tau, rec):
    """Derivative rows DERIV of the state rows STATE: dx = v, dq, dv = F/m + g, dL = torque;
    the surface ``tau`` seconds after the time phases of rows PHASE (the step's start).

    Each sample kind is one loop: the sample's offset, and :func:`_where_rows` (the rows that
    depend on where it is), then per environment the sample's world offset (:func:`_arm`:
    from the environment's center of mass), its sizes times the environment's factors
    (``Samples.factor``), its force law (``forces.py``) and :func:`_add_force`.

    ``rec``: None in the step path, or a recording (``_record``: ``sample_forces``,
    ``sample_flows``) that gets each sample's world offset from the center of mass and force
    (and what it senses), j counting the samples of all bodies in order (fixed plates,
    control plates, cylinders, buoyancy, thrusters); the external force is not a sample.
    ``rec is None`` is resolved when numba compiles (a branch on a None argument is pruned),
    so the step kernels' machine code has no recording in it at all, and the forces have one
    source: these loops."""
    e0 = max(e0, 0)  # tells the compiler e0 + i >= 0: no negative-index wraparound per lane
    # each field taken out of the tuples once: every take costs a reference count per call
    plate_at, flap_at, cyl_at, buoy_at, thr_at = (
        samples.plate_at,
        samples.flap_at,
        samples.cyl_at,
        samples.buoy_at,
        samples.thr_at,
    )
    j = _first_sample(samples, b)  # rec row of this body's first sample
    vmax, fmax = prm[P_VMAX], prm[P_FMAX]
    wake = wprm[W_ON] != 0.0
    sea = prm[P_NWAVES] > ZERO
    fluid = _fluid(prm)
    _omega_row(S, n)
    for i in range(n):
        S[HEIGHT * BLOCK + i] = S[(STATE + OX + 2) * BLOCK + i]  # calm water: the surface is z = 0
        for k in range(3):
            S[(DERIV + OX + k) * BLOCK + i] = S[(STATE + OV + k) * BLOCK + i]
            S[(DERIV + OV + k) * BLOCK + i] = ZERO
            S[(DERIV + OL + k) * BLOCK + i] = ZERO
        dq = quat_rate(
            S[(STATE + OQ) * BLOCK + i],
            S[(STATE + OQ + 1) * BLOCK + i],
            S[(STATE + OQ + 2) * BLOCK + i],
            S[(STATE + OQ + 3) * BLOCK + i],
            S[(OMEGA) * BLOCK + i],
            S[(OMEGA + 1) * BLOCK + i],
            S[(OMEGA + 2) * BLOCK + i],
        )
        S[(DERIV + OQ) * BLOCK + i], S[(DERIV + OQ + 1) * BLOCK + i] = dq[0], dq[1]
        S[(DERIV + OQ + 2) * BLOCK + i], S[(DERIV + OQ + 3) * BLOCK + i] = dq[2], dq[3]

    factor, frow = samples.factor, samples.factor_row  # sizes times factor[row, e]
    tab, normal = samples.plate, samples.plate_normal
    for p in range(plate_at[b], plate_at[b + 1]):  # fixed plates
        if _skipped(rec, j):  # a recording reads only the samples it picks
            j += 1
            continue
        ox, oy, oz = tab[S_OFFSET, p], tab[S_OFFSET + 1, p], tab[S_OFFSET + 2, p]
        if wake or sea:
            _where_rows(S, n, ox, oy, oz, wake, sea, wprm, prm, tau)
        bx, by, bz = normal[0, p], normal[1, p], normal[2, p]
        area, eff, ra, re = (
            tab[S_AREA, p],
            tab[S_EFFICIENCY, p],
            frow[F_AREA, j],
            frow[F_EFFICIENCY, j],
        )
        side, skin = tab[S_ONE_SIDED, p], tab[S_SKIN_AREA, p]
        friction = (tab[S_FRICTION_CF, p], tab[S_FRICTION_ITTC, p], tab[S_FRICTION_LENGTH, p],
                    vmax, fmax)  # fmt: skip
        for i in range(_adding(rec, n)):
            e = e0 + i
            rx, ry, rz, fx, fy, fz, _, nx, ny, nz, _ = _plate_at(
                S, i, ox, oy, oz, bx, by, bz, fluid, area * factor[ra, e], eff * factor[re, e],
                vmax, fmax, side,
            )  # fmt: skip
            _add_force(S, i, rx, ry, rz, fx, fy, fz)
        if _picked(rec, j):  # a loop of its own: the force loop stays vectorized
            for i in range(n):
                e = e0 + i
                _record(rec, j, i, S, _plate_at(
                    S, i, ox, oy, oz, bx, by, bz, fluid, area * factor[ra, e],
                    eff * factor[re, e], vmax, fmax, side,
                ))  # fmt: skip
            _flush(rec, j, n, S)
        if skin > ZERO:  # skin friction, where the craft has it
            for i in range(_adding(rec, n)):
                rx, ry, rz, fx, fy, fz = _skin_at(
                    S, i, ox, oy, oz, bx, by, bz, fluid, skin * factor[ra, e0 + i], friction
                )
                _add_force(S, i, rx, ry, rz, fx, fy, fz)
            if _picked(rec, j):
                for i in range(n):
                    a = skin * factor[ra, e0 + i]
                    _record_add(
                        rec, j, i, _skin_at(S, i, ox, oy, oz, bx, by, bz, fluid, a, friction)
                    )
        j += 1

    tab, normal = samples.flap, flap_now  # control surfaces: normals deflected per env
    for p in range(flap_at[b], flap_at[b + 1]):
        if _skipped(rec, j):  # a recording reads only the samples it picks
            j += 1
            continue
        ox, oy, oz = tab[S_OFFSET, p], tab[S_OFFSET + 1, p], tab[S_OFFSET + 2, p]
        if wake or sea:
            _where_rows(S, n, ox, oy, oz, wake, sea, wprm, prm, tau)
        area, eff, ra, re = (
            tab[S_AREA, p],
            tab[S_EFFICIENCY, p],
            frow[F_AREA, j],
            frow[F_EFFICIENCY, j],
        )
        side, skin = tab[S_ONE_SIDED, p], tab[S_SKIN_AREA, p]
        friction = (tab[S_FRICTION_CF, p], tab[S_FRICTION_ITTC, p], tab[S_FRICTION_LENGTH, p],
                    vmax, fmax)  # fmt: skip
        for i in range(_adding(rec, n)):
            e = e0 + i
            rx, ry, rz, fx, fy, fz, _, nx, ny, nz, _ = _plate_at(
                S, i, ox, oy, oz, normal[0, p, e], normal[1, p, e], normal[2, p, e], fluid,
                area * factor[ra, e], eff * factor[re, e], vmax, fmax, side,
            )  # fmt: skip
            _add_force(S, i, rx, ry, rz, fx, fy, fz)
        if _picked(rec, j):
            for i in range(n):
                e = e0 + i
                _record(rec, j, i, S, _plate_at(
                    S, i, ox, oy, oz, normal[0, p, e], normal[1, p, e], normal[2, p, e], fluid,
                    area * factor[ra, e], eff * factor[re, e], vmax, fmax, side,
                ))  # fmt: skip
            _flush(rec, j, n, S)
        if skin > ZERO:  # skin friction, where the craft has it
            for i in range(_adding(rec, n)):
                e = e0 + i
                rx, ry, rz, fx, fy, fz = _skin_at(
                    S, i, ox, oy, oz, normal[0, p, e], normal[1, p, e], normal[2, p, e], fluid,
                    skin * factor[ra, e], friction,
                )  # fmt: skip
                _add_force(S, i, rx, ry, rz, fx, fy, fz)
            if _picked(rec, j):
                for i in range(n):
                    e = e0 + i
                    _record_add(rec, j, i, _skin_at(
                        S, i, ox, oy, oz, normal[0, p, e], normal[1, p, e], normal[2, p, e],
                        fluid, skin * factor[ra, e], friction,
                    ))  # fmt: skip
        j += 1

    tab, axis = samples.cyl, samples.cyl_axis
    for p in range(cyl_at[b], cyl_at[b + 1]):
        if _skipped(rec, j):  # a recording reads only the samples it picks
            j += 1
            continue
        ox, oy, oz = tab[S_OFFSET, p], tab[S_OFFSET + 1, p], tab[S_OFFSET + 2, p]
        if wake or sea:
            _where_rows(S, n, ox, oy, oz, wake, sea, wprm, prm, tau)
        bx, by, bz = axis[0, p], axis[1, p], axis[2, p]
        area, ra = tab[S_CYL_AREA, p], frow[F_AREA, j]
        for i in range(_adding(rec, n)):
            a = area * factor[ra, e0 + i]
            rx, ry, rz, fx, fy, fz = _cylinder_at(S, i, ox, oy, oz, bx, by, bz, fluid, a, vmax,
                                                  fmax)[:6]  # fmt: skip
            _add_force(S, i, rx, ry, rz, fx, fy, fz)
        if _picked(rec, j):
            for i in range(n):
                a = area * factor[ra, e0 + i]
                _record(rec, j, i, S, _cylinder_at(S, i, ox, oy, oz, bx, by, bz, fluid, a,
                                                    vmax, fmax))  # fmt: skip
            _flush(rec, j, n, S)
        j += 1

    g = prm[P_G]
    tab = samples.buoy
    for p in range(buoy_at[b], buoy_at[b + 1]):  # the water's, never the wake's: no flow
        if _skipped(rec, j):  # a recording reads only the samples it picks
            j += 1
            continue
        ox, oy, oz = tab[S_OFFSET, p], tab[S_OFFSET + 1, p], tab[S_OFFSET + 2, p]
        if sea:
            _swell_rows(S, n, ox, oy, oz, prm, tau)  # the surface only: no flow
        vol, area, ra = tab[S_VOLUME, p], tab[S_BUOY_AREA, p], frow[F_AREA, j]
        for i in range(_adding(rec, n)):
            k = factor[ra, e0 + i]
            rx, ry, rz, _, _, fz = _buoyancy_at(S, i, ox, oy, oz, fluid, g, vol * k, area * k)[:6]
            _add_force(S, i, rx, ry, rz, ZERO, ZERO, fz)
        if _picked(rec, j):
            for i in range(n):
                k = factor[ra, e0 + i]
                _record(rec, j, i, S, _buoyancy_at(S, i, ox, oy, oz, fluid, g, vol * k, area * k))
            _flush(rec, j, n, S)
        j += 1

    tab, direction, channel = samples.thr, samples.thr_dir, samples.thr_channel
    for p in range(thr_at[b], thr_at[b + 1]):  # a point force: no flow, no surface
        if _skipped(rec, j):  # a recording reads only the samples it picks
            j += 1
            continue
        ox, oy, oz = tab[S_OFFSET, p], tab[S_OFFSET + 1, p], tab[S_OFFSET + 2, p]
        bx, by, bz, ch = direction[0, p], direction[1, p], direction[2, p], channel[p]
        lo, hi, rt = tab[S_THRUST_MIN, p], tab[S_THRUST_MAX, p], frow[F_THRUST, j]
        for i in range(n):
            e = e0 + i
            a = ctrl[ch, e] if ch >= 0 else ONE
            thrust = thrust_of(a, lo, hi) * factor[rt, e]
            rx, ry, rz = _arm(S, i, ox, oy, oz)
            dx, dy, dz = _rotate(S, i, bx, by, bz)
            fx, fy, fz = thrust * dx, thrust * dy, thrust * dz
            _add_force(S, i, rx, ry, rz, fx, fy, fz)
            if _picked(rec, j):  # a point force: it senses nothing
                nothing = (ZERO, ZERO, ZERO, ZERO)
                _record(rec, j, i, S, (rx, ry, rz, fx, fy, fz, nothing, dx, dy, dz, ZERO))
        if _picked(rec, j):
            _flush(rec, j, n, S)
        j += 1

    ext = external  # Simulator.set_external_force: world force and torque, held per call
    for k in range(6):
        for i in range(n):
            S[(DERIV + OV + k) * BLOCK + i] += ext[e0 + i, b, k]  # rows OV..OV+2, then OL..OL+2

    for i in range(n):
        inv_m = ONE / S[(BODY + B_MASS) * BLOCK + i]
        for k in range(3):
            S[(DERIV + OV + k) * BLOCK + i] *= inv_m
        S[(DERIV + OV + 2) * BLOCK + i] -= g
    gm = prm[P_GM]
    if gm != ZERO:  # a point mass at the origin: -GM x / |x|^3
        for i in range(n):
            x = S[(STATE + OX) * BLOCK + i]
            y = S[(STATE + OX + 1) * BLOCK + i]
            z = S[(STATE + OX + 2) * BLOCK + i]
            r2 = x * x + y * y + z * z
            k = gm / (r2 * math.sqrt(r2))
            S[(DERIV + OV) * BLOCK + i] -= k * x
            S[(DERIV + OV + 1) * BLOCK + i] -= k * y
            S[(DERIV + OV + 2) * BLOCK + i] -= k * z


@njit(**_INLINE)
def _normalize_quat(S, row, n):
    for i in range(n):
        qw, qx, qy, qz = (
            S[(row) * BLOCK + i],
            S[(row + 1) * BLOCK + i],
            S[(row + 2) * BLOCK + i],
            S[(row + 3) * BLOCK + i],
        )
        s = ONE / math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        S[(row) * BLOCK + i] = qw * s
        S[(row + 1) * BLOCK + i] = qx * s
        S[(row + 2) * BLOCK + i] = qy * s
        S[(row + 3) * BLOCK + i] = qz * s


@njit(**_INLINE)
def _copy(S, dst, src, n):
    """State rows dst = src (all 13 rows)."""
    for k in range(NSTATE):
        for i in range(n):
            S[(dst + k) * BLOCK + i] = S[(src + k) * BLOCK + i]


@njit(**_INLINE)
def _axpy(S, dst, src, h, n):
    """State rows dst = src + h * DERIV (all 13 rows)."""
    for k in range(NSTATE):
        for i in range(n):
            S[(dst + k) * BLOCK + i] = S[(src + k) * BLOCK + i] + h * S[(DERIV + k) * BLOCK + i]


@njit(**_INLINE)
def _rotate_by_omega(S, n, h):
    """Turn q by the angular momentum L over h (explicit midpoint in the orientation):
    w from L at q gives a half-step orientation, w from L there turns q by a full step.
    Second order; a one-stage update (w at the old q only) is explicit Euler for the
    rotation and gains energy steadily (about 4% in 10 s for a body spinning at 2 rad/s,
    dt = 1/100), which the midpoint stage removes."""
    for i in range(n):
        inv_inertia = _inv_inertia(S, i)
        lx, ly, lz = (
            S[(STATE + OL) * BLOCK + i],
            S[(STATE + OL + 1) * BLOCK + i],
            S[(STATE + OL + 2) * BLOCK + i],
        )
        qw, qx = S[(STATE + OQ) * BLOCK + i], S[(STATE + OQ + 1) * BLOCK + i]
        qy, qz = S[(STATE + OQ + 2) * BLOCK + i], S[(STATE + OQ + 3) * BLOCK + i]
        w = world_omega(_matrix(S, i), lx, ly, lz, inv_inertia)
        tw, tx, ty, tz = _midpoint_turn(qw, qx, qy, qz, w, lx, ly, lz, inv_inertia, h)
        S[(STATE + OQ) * BLOCK + i] = tw
        S[(STATE + OQ + 1) * BLOCK + i] = tx
        S[(STATE + OQ + 2) * BLOCK + i] = ty
        S[(STATE + OQ + 3) * BLOCK + i] = tz
    _normalize_quat(S, STATE + OQ, n)


@njit(**_INLINE)
def _midpoint_turn(qw, qx, qy, qz, w, lx, ly, lz, inv_inertia, h):
    """q turned over h by the angular momentum L (world angular velocity w at q): the
    explicit-midpoint rule of :func:`_rotate_by_omega`, unnormalized."""
    dq = quat_rate(qw, qx, qy, qz, w[0], w[1], w[2])
    hh = HALF * h
    m = quat_to_matrix(qw + hh * dq[0], qx + hh * dq[1], qy + hh * dq[2], qz + hh * dq[3])
    w2 = world_omega(m, lx, ly, lz, inv_inertia)
    dq = quat_rate(qw, qx, qy, qz, w2[0], w2[1], w2[2])
    return qw + h * dq[0], qx + h * dq[1], qy + h * dq[2], qz + h * dq[3]


@njit(**_INLINE)
def _rotate_tetra(S, n, h, prm):
    """Turn q as a Verlet tetrahedron (``verlet_tetra``): the four particles matched to the
    body (``reference.tetra.match_inertia``) drift a step along their velocities ``w x r_i``
    (plus the center's), the shape is restored by the rotation that best fits the drifted particles
    (least squares), and the velocities by the rigid field with the particles' own momentum
    and angular momentum, so L (the state) is untouched. The best fit maximizes
    tr(ROT^T A) with ``A = sum m_i d_i r_i^T = (1 + h [w]x) ROT S``, S the body's second moment:
    the particles enter only through it. The rotation is found by the iteration of Mueller
    et al. (2016, "A robust method to extract the rotational part of deformations") from
    the rigid midpoint update's orientation (close: the two differ by O((w h)^2)), a fixed
    number of times, without branches or trigonometry (it still runs 5 times slower than
    the rigid turn: making it vectorize is open).

    Above ``|w| h > prm[P_TETRA_SWITCH]`` the particles' straight drift misrepresents the
    turn (its energy error passes the rigid turn's near |w| h = 0.05-0.1 and then grows
    fast: docs/tetra_spin.png): that body steps with the rigid midpoint
    update instead (:func:`_rotate_by_omega`), continuously in q and exactly in L."""
    limit = prm[P_TETRA_SWITCH]
    k = BODY + B_SECOND_MOMENT
    for i in range(n):
        inv_inertia = _inv_inertia(S, i)
        sxx, syy, szz = S[k * BLOCK + i], S[(k + 1) * BLOCK + i], S[(k + 2) * BLOCK + i]
        sxy, sxz, syz = S[(k + 3) * BLOCK + i], S[(k + 4) * BLOCK + i], S[(k + 5) * BLOCK + i]
        lx, ly, lz = (
            S[(STATE + OL) * BLOCK + i],
            S[(STATE + OL + 1) * BLOCK + i],
            S[(STATE + OL + 2) * BLOCK + i],
        )
        qw, qx = S[(STATE + OQ) * BLOCK + i], S[(STATE + OQ + 1) * BLOCK + i]
        qy, qz = S[(STATE + OQ + 2) * BLOCK + i], S[(STATE + OQ + 3) * BLOCK + i]
        r0, r1, r2, r3, r4, r5, r6, r7, r8 = _matrix(S, i)
        wx, wy, wz = world_omega((r0, r1, r2, r3, r4, r5, r6, r7, r8), lx, ly, lz, inv_inertia)
        # B = ROT S (columns b0, b1, b2), then A = B + h w x B
        b00 = r0 * sxx + r1 * sxy + r2 * sxz
        b10 = r3 * sxx + r4 * sxy + r5 * sxz
        b20 = r6 * sxx + r7 * sxy + r8 * sxz
        b01 = r0 * sxy + r1 * syy + r2 * syz
        b11 = r3 * sxy + r4 * syy + r5 * syz
        b21 = r6 * sxy + r7 * syy + r8 * syz
        b02 = r0 * sxz + r1 * syz + r2 * szz
        b12 = r3 * sxz + r4 * syz + r5 * szz
        b22 = r6 * sxz + r7 * syz + r8 * szz
        a00 = b00 + h * (wy * b20 - wz * b10)
        a10 = b10 + h * (wz * b00 - wx * b20)
        a20 = b20 + h * (wx * b10 - wy * b00)
        a01 = b01 + h * (wy * b21 - wz * b11)
        a11 = b11 + h * (wz * b01 - wx * b21)
        a21 = b21 + h * (wx * b11 - wy * b01)
        a02 = b02 + h * (wy * b22 - wz * b12)
        a12 = b12 + h * (wz * b02 - wx * b22)
        a22 = b22 + h * (wx * b12 - wy * b02)
        # the rigid midpoint update: the answer for fast spins, the first guess otherwise
        gw, gx, gy, gz = _midpoint_turn(qw, qx, qy, qz, (wx, wy, wz), lx, ly, lz, inv_inertia, h)
        g = ONE / math.sqrt(gw * gw + gx * gx + gy * gy + gz * gz)
        pw, px, py, pz = gw * g, gx * g, gy * g, gz * g
        for _ in range(POLAR_ITERATIONS):
            m = quat_to_matrix(pw, px, py, pz)
            # sum over columns c of R_c x A_c, over |sum R_c . A_c|: the corrective turn
            ex = (m[3] * a20 - m[6] * a10) + (m[4] * a21 - m[7] * a11) + (m[5] * a22 - m[8] * a12)
            ey = (m[6] * a00 - m[0] * a20) + (m[7] * a01 - m[1] * a21) + (m[8] * a02 - m[2] * a22)
            ez = (m[0] * a10 - m[3] * a00) + (m[1] * a11 - m[4] * a01) + (m[2] * a12 - m[5] * a02)
            dot = (
                m[0] * a00 + m[3] * a10 + m[6] * a20
                + m[1] * a01 + m[4] * a11 + m[7] * a21
                + m[2] * a02 + m[5] * a12 + m[8] * a22
            )  # fmt: skip
            inv = ONE / (abs(dot) + TINY)
            ex, ey, ez = ex * inv, ey * inv, ez * inv
            # the turn's quaternion (cos(a/2), e sin(a/2)/a), a = |e|, to fourth order in a:
            # the corrections are small (the guess is within O((w h)^2)) and any consistent
            # turn has the same fixed point, so no trigonometry (which would not vectorize)
            a2 = ex * ex + ey * ey + ez * ez
            c = ONE - a2 * EIGHTH + a2 * a2 * INV384
            sn = HALF - a2 * INV48
            dx, dy, dz = ex * sn, ey * sn, ez * sn  # the turn's quaternion (c, d), times p
            pw, px, py, pz = (
                c * pw - dx * px - dy * py - dz * pz,
                c * px + dx * pw + dy * pz - dz * py,
                c * py - dx * pz + dy * pw + dz * px,
                c * pz + dx * py - dy * px + dz * pw,
            )
        rigid = math.sqrt(wx * wx + wy * wy + wz * wz) * h > limit
        S[(STATE + OQ) * BLOCK + i] = gw if rigid else pw
        S[(STATE + OQ + 1) * BLOCK + i] = gx if rigid else px
        S[(STATE + OQ + 2) * BLOCK + i] = gy if rigid else py
        S[(STATE + OQ + 3) * BLOCK + i] = gz if rigid else pz
    _normalize_quat(S, STATE + OQ, n)


@njit(**_INLINE)
def _kick(S, n, h):
    """v += h dv, L += h dL."""
    for k in range(OV, NSTATE):
        for i in range(n):
            S[(STATE + k) * BLOCK + i] += h * S[(DERIV + k) * BLOCK + i]


@njit(**_INLINE)
def _drift(S, n, h):
    """x += h v."""
    for k in range(3):
        for i in range(n):
            S[(STATE + OX + k) * BLOCK + i] += h * S[(STATE + OV + k) * BLOCK + i]


# One time step of every body slot in a block, one function per integrator (stage-synchronous
# across slots, so that forces coupling bodies of one environment can be added per stage);
# each evaluation sees the surface at its stage time, the step's start plus ``tau`` (see the
# module docstring). ``STEPPERS`` maps the ids to them; a step kernel compiled for one id
# holds that integrator only (``_step_block``), which a first step compiles far sooner than a
# kernel holding all six (``_integrate``, the shared kernels').


@njit(**_JIT)
def _explicit_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Explicit Euler: everything from the old state."""
    dt = prm[P_DT]
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        _axpy(scr_blk[b], STATE, STATE, dt, n)
        _normalize_quat(scr_blk[b], STATE + OQ, n)


@njit(**_JIT)
def _symplectic_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Symplectic Euler: velocities first, then positions with new velocities."""
    dt = prm[P_DT]
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _kick(S, n, dt)
        _drift(S, n, dt)
        _rotate_by_omega(S, n, dt)


@njit(**_JIT)
def _velocity_verlet(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Velocity Verlet: half kick, drift, new forces, half kick."""
    dt = prm[P_DT]
    h2 = HALF * dt
    tdt = np.float64(dt)  # stage time offsets, float64 like the clock
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _kick(S, n, h2)
        _drift(S, n, dt)
        _rotate_by_omega(S, n, dt)
    for b in range(nb):  # at the step's end
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, tdt, None)
    for b in range(nb):
        _kick(scr_blk[b], n, h2)


@njit(**_JIT)
def _rk2(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """RK2, explicit midpoint: START keeps the step's start."""
    dt = prm[P_DT]
    h2 = HALF * dt
    tdt = np.float64(dt)  # stage time offsets, float64 like the clock
    th = 0.5 * tdt
    for b in range(nb):
        _copy(scr_blk[b], START, STATE, n)
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        _axpy(scr_blk[b], STATE, START, h2, n)
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, th, None)
    for b in range(nb):
        _axpy(scr_blk[b], STATE, START, dt, n)
        _normalize_quat(scr_blk[b], STATE + OQ, n)


@njit(**_JIT)
def _verlet_tetra(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """verlet_tetra: symplectic kick and drift, the turn as a tetrahedron."""
    dt = prm[P_DT]
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _kick(S, n, dt)
        _drift(S, n, dt)
        _rotate_tetra(S, n, dt, prm)


@njit(**_JIT)
def _rk4(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Classic RK4: RK_SUM sums k1 + 2 k2 + 2 k3 + k4."""
    dt = prm[P_DT]
    h2 = HALF * dt
    tdt = np.float64(dt)  # stage time offsets, float64 like the clock
    th = 0.5 * tdt
    for b in range(nb):
        _copy(scr_blk[b], START, STATE, n)
    for stage in range(4):
        tau = T0 if stage == 0 else (th if stage < 3 else tdt)
        for b in range(nb):
            _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, tau, None)
        for b in range(nb):
            S = scr_blk[b]
            weight = ONE if stage == 0 or stage == 3 else TWO
            for k in range(NSTATE):
                for i in range(n):
                    acc = S[(DERIV + k) * BLOCK + i] * weight
                    S[(RK_SUM + k) * BLOCK + i] = (
                        acc if stage == 0 else S[(RK_SUM + k) * BLOCK + i] + acc
                    )
            if stage < 2:
                _axpy(S, STATE, START, h2, n)
            elif stage == 2:
                _axpy(S, STATE, START, dt, n)
            else:
                h6 = dt / SIX
                for k in range(NSTATE):
                    for i in range(n):
                        S[(STATE + k) * BLOCK + i] = (
                            S[(START + k) * BLOCK + i] + h6 * S[(RK_SUM + k) * BLOCK + i]
                        )
                _normalize_quat(S, STATE + OQ, n)


# --------------------------------------------------------------------------------------------
# the seed's remaining methods (docs/seed_map.md). Three of them carry numbers of their own
# from step to step (rows CARRY, kept between calls in ``Data.memory``); each takes them afresh
# from the state where the state is not the one its last step left (rows END), so that a
# reset, a contact or ``set_state`` never meets a stale memory.


@njit(**_INLINE)
def _kick_spin(S, n, h):
    """L += h dL (the angular half of :func:`_kick`)."""
    for k in range(OL, NSTATE):
        for i in range(n):
            S[(STATE + k) * BLOCK + i] += h * S[(DERIV + k) * BLOCK + i]


@njit(**_INLINE)
def _find_stale(S, n):
    """Row STALE: 1 where the state rows differ from rows END (the state the integrator's last
    step left; NaN before the first step), else 0; returns whether any is 1."""
    stale = False
    for i in range(n):
        same = True
        for k in range(NSTATE):
            same &= S[(STATE + k) * BLOCK + i] == S[(END + k) * BLOCK + i]
        S[STALE * BLOCK + i] = ZERO if same else ONE
        stale |= not same
    return stale


@njit(**_INLINE)
def _mark_end(S, n):
    """Rows END = the state rows: what the next step compares with (:func:`_find_stale`)."""
    for k in range(NSTATE):
        for i in range(n):
            S[(END + k) * BLOCK + i] = S[(STATE + k) * BLOCK + i]


@njit(**_JIT)
def _accurate_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """The seed's "more accurate" Euler: the old state's acceleration carried exactly over the
    step, x += v dt + a dt^2 / 2, then v += a dt (velocity Verlet with one force evaluation,
    at the step's start); L likewise, the turn by the half-kicked L."""
    dt = prm[P_DT]
    h2 = HALF * dt
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _kick(S, n, h2)
        _drift(S, n, dt)
        _rotate_by_omega(S, n, dt)
        _kick(S, n, h2)


@njit(**_JIT)
def _position_verlet(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """The seed's velocity-less Verlet (Stormer's form): the memory keeps the last position,
    the step's displacement is the last one plus a dt^2, ``d = (x - x_old) + a dt^2``, and the
    velocity (what the forces and the user read) is ``d / dt``. Algebraically symplectic
    Euler; it rounds differently (``x - x_old`` cancels where x is large against d). The turn
    is symplectic Euler's (a quaternion has no velocity-less form that stays a rotation)."""
    dt = prm[P_DT]
    dt2 = dt * dt
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _find_stale(S, n)
        for k in range(3):
            for i in range(n):
                x = S[(STATE + OX + k) * BLOCK + i]
                kept = S[(CARRY + k) * BLOCK + i]
                v = S[(STATE + OV + k) * BLOCK + i]
                old = kept if S[STALE * BLOCK + i] == ZERO else x - dt * v
                d = (x - old) + dt2 * S[(DERIV + OV + k) * BLOCK + i]
                S[(CARRY + k) * BLOCK + i] = x
                S[(STATE + OX + k) * BLOCK + i] = x + d
                S[(STATE + OV + k) * BLOCK + i] = d / dt
        _kick_spin(S, n, dt)
        _rotate_by_omega(S, n, dt)
        _mark_end(S, n)


@njit(**_JIT)
def _prescaled_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """The seed's prescaled NSV: the memory keeps the velocity times dt (a displacement per
    step), ``u += a dt^2``, ``x += u``; the velocity is ``u / dt``. Symplectic Euler with one
    multiplication less per step (what made it the seed's choice in fixed point); in floats
    it rounds differently. The turn is symplectic Euler's."""
    dt = prm[P_DT]
    dt2 = dt * dt
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _find_stale(S, n)
        for k in range(3):
            for i in range(n):
                kept = S[(CARRY + k) * BLOCK + i]
                u = kept if S[STALE * BLOCK + i] == ZERO else dt * S[(STATE + OV + k) * BLOCK + i]
                u += dt2 * S[(DERIV + OV + k) * BLOCK + i]
                S[(CARRY + k) * BLOCK + i] = u
                S[(STATE + OX + k) * BLOCK + i] += u
                S[(STATE + OV + k) * BLOCK + i] = u / dt
        _kick_spin(S, n, dt)
        _rotate_by_omega(S, n, dt)
        _mark_end(S, n)


@njit(**_JIT)
def _velocity_verlet_cached(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """The seed's velocity Verlet: :func:`_velocity_verlet` with its first evaluation taken
    from the memory, the acceleration (and dL/dt) its last step ended with: one evaluation
    per step. Where the memory is stale (the first step, a reset, a contact) the block
    evaluates at the step's start first. The cached forces were taken with the last step's
    controls, so a new control reaches the first half kick a step late."""
    dt = prm[P_DT]
    h2 = HALF * dt
    tdt = np.float64(dt)
    stale = False
    for b in range(nb):
        stale |= _find_stale(scr_blk[b], n)
    if stale:  # the forces at the start, where the memory cannot be trusted
        for b in range(nb):
            S = scr_blk[b]
            _evaluate(S, b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
            for k in range(6):
                for i in range(n):
                    kept = S[(CARRY + k) * BLOCK + i]
                    new = S[(DERIV + OV + k) * BLOCK + i]
                    S[(CARRY + k) * BLOCK + i] = kept if S[STALE * BLOCK + i] == ZERO else new
    for b in range(nb):
        S = scr_blk[b]
        for k in range(6):  # DERIV rows OV..OV+2, OL..OL+2: the kick's
            for i in range(n):
                S[(DERIV + OV + k) * BLOCK + i] = S[(CARRY + k) * BLOCK + i]
        _omega_row(S, n)  # ROT for the turn (no evaluation has set it this step)
        _kick(S, n, h2)
        _drift(S, n, dt)
        _rotate_by_omega(S, n, dt)
    for b in range(nb):  # at the step's end
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, tdt, None)
    for b in range(nb):
        S = scr_blk[b]
        for k in range(6):
            for i in range(n):
                S[(CARRY + k) * BLOCK + i] = S[(DERIV + OV + k) * BLOCK + i]
        _kick(S, n, h2)
        _mark_end(S, n)


@njit(**_INLINE)
def _rotate_trapezoid(S, n, h):
    """Turn q by L over h with the trapezoid rule (Heun): the rates at q and at the Euler
    prediction q + h dq, averaged; then normalized."""
    hh = HALF * h
    for i in range(n):
        inv_inertia = _inv_inertia(S, i)
        lx, ly, lz = (
            S[(STATE + OL) * BLOCK + i],
            S[(STATE + OL + 1) * BLOCK + i],
            S[(STATE + OL + 2) * BLOCK + i],
        )
        qw, qx = S[(STATE + OQ) * BLOCK + i], S[(STATE + OQ + 1) * BLOCK + i]
        qy, qz = S[(STATE + OQ + 2) * BLOCK + i], S[(STATE + OQ + 3) * BLOCK + i]
        w = world_omega(_matrix(S, i), lx, ly, lz, inv_inertia)
        d0 = quat_rate(qw, qx, qy, qz, w[0], w[1], w[2])
        pw, px, py, pz = qw + h * d0[0], qx + h * d0[1], qy + h * d0[2], qz + h * d0[3]
        w = world_omega(quat_to_matrix(pw, px, py, pz), lx, ly, lz, inv_inertia)
        d1 = quat_rate(pw, px, py, pz, w[0], w[1], w[2])
        S[(STATE + OQ) * BLOCK + i] = qw + hh * (d0[0] + d1[0])
        S[(STATE + OQ + 1) * BLOCK + i] = qx + hh * (d0[1] + d1[1])
        S[(STATE + OQ + 2) * BLOCK + i] = qy + hh * (d0[2] + d1[2])
        S[(STATE + OQ + 3) * BLOCK + i] = qz + hh * (d0[3] + d1[3])
    _normalize_quat(S, STATE + OQ, n)


@njit(**_JIT)
def _trapezoid_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Symplectic Euler with the turn by the trapezoid rule (:func:`_rotate_trapezoid`): the
    seed's "trapezoid" trick for fast spins. In translation a trapezoid of the old and new
    velocity would be the accurate Euler (a row of its own, and not symplectic), so the
    trapezoid goes where the seed says it helps: the rotation."""
    dt = prm[P_DT]
    for b in range(nb):
        _evaluate(scr_blk[b], b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
    for b in range(nb):
        S = scr_blk[b]
        _kick(S, n, dt)
        _drift(S, n, dt)
        _rotate_trapezoid(S, n, dt)


@njit(**_JIT)
def _implicit_midpoint(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Implicit midpoint, ``y1 = y0 + dt f((y0 + y1) / 2)`` on the whole state, solved by
    fixed-point iteration from ``y1 = y0`` (the first iterate is explicit Euler's). A body
    stops iterating, keeping its iterate whatever its block's neighbours still do, when

    - no number of its state moved by more than ``prm[P_IMPLICIT_TOL]`` of its size
      (``|y0| + |dt f|``), or
    - the iteration has reached round-off: the largest change is no smaller than two
      iterations before (Hairer, Lubich and Wanner, GNI VIII.6: stop when the increments
      stop decreasing; two back, since the largest change of an oscillation's position and
      velocity can grow for one iteration while both shrink over two) and is below
      ``prm[P_IMPLICIT_LOOSE]`` times the largest number of the step ``dt f`` (a force summed
      from large terms that cancel, a body at rest, has a rounding floor far above a few ulp
      of its small net).

    Row ITERATIONS keeps the most iterations a step took; past ``prm[P_IMPLICIT_MAX]`` the
    iteration has failed (it contracts by about dt times the forces' stiffness over 2 per
    pass) and the step is flagged diverged. Rows: START y0, RK_SUM the iterate, STATE the
    midpoint, STALE 1 while a body iterates, CHANGE its largest changes two and one
    iterations ago."""
    dt = prm[P_DT]
    th = 0.5 * np.float64(dt)
    tol, loose, most = prm[P_IMPLICIT_TOL], prm[P_IMPLICIT_LOOSE], int(prm[P_IMPLICIT_MAX])
    for b in range(nb):
        S = scr_blk[b]
        _copy(S, START, STATE, n)
        _copy(S, RK_SUM, STATE, n)
        for i in range(n):
            S[STALE * BLOCK + i] = ONE
            S[CHANGE * BLOCK + i] = np.inf
            S[(CHANGE + 1) * BLOCK + i] = np.inf
    left, it = n * nb, 0
    while left > 0 and it < most:
        it += 1
        for b in range(nb):
            S = scr_blk[b]
            for k in range(NSTATE):
                for i in range(n):
                    S[(STATE + k) * BLOCK + i] = HALF * (
                        S[(START + k) * BLOCK + i] + S[(RK_SUM + k) * BLOCK + i]
                    )
            _evaluate(S, b, n, e0, samples, prm, wprm, ctrl, flap_now, external, th, None)
        left = 0
        for b in range(nb):
            S = scr_blk[b]
            for i in range(n):
                if S[STALE * BLOCK + i] == ZERO:
                    continue
                done = True
                change, size = ZERO * dt, ZERO * dt
                for k in range(NSTATE):
                    y0, step = S[(START + k) * BLOCK + i], dt * S[(DERIV + k) * BLOCK + i]
                    y = y0 + step
                    moved = abs(y - S[(RK_SUM + k) * BLOCK + i])
                    done &= moved <= tol * (abs(y0) + abs(step))
                    change, size = max(change, moved), max(size, abs(step))
                    S[(RK_SUM + k) * BLOCK + i] = y
                done |= change >= S[CHANGE * BLOCK + i] and change <= loose * size
                S[CHANGE * BLOCK + i] = S[(CHANGE + 1) * BLOCK + i]
                S[(CHANGE + 1) * BLOCK + i] = change
                if done:
                    S[STALE * BLOCK + i] = ZERO
                    S[ITERATIONS * BLOCK + i] = max(S[ITERATIONS * BLOCK + i], it)
                else:
                    left += 1
    for b in range(nb):
        S = scr_blk[b]
        for i in range(n):  # not converged: one past the most, which flags it
            if S[STALE * BLOCK + i] != ZERO:
                S[ITERATIONS * BLOCK + i] = most + 1
        _copy(S, STATE, RK_SUM, n)
        _normalize_quat(S, STATE + OQ, n)


# integrator id -> its block step
STEPPERS = {
    EXPLICIT_EULER: _explicit_euler,
    SYMPLECTIC_EULER: _symplectic_euler,
    VELOCITY_VERLET: _velocity_verlet,
    RK2: _rk2,
    RK4: _rk4,
    VERLET_TETRA: _verlet_tetra,
    ACCURATE_EULER: _accurate_euler,
    POSITION_VERLET: _position_verlet,
    PRESCALED_SYMPLECTIC_EULER: _prescaled_euler,
    VELOCITY_VERLET_CACHED: _velocity_verlet_cached,
    TRAPEZOID_SYMPLECTIC_EULER: _trapezoid_euler,
    IMPLICIT_MIDPOINT: _implicit_midpoint,
}
assert sorted(STEPPERS) == sorted(IT.BY_ID), "an integrator of integrators.TABLE has no stepper"


@njit(**_JIT)
def _integrate(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external, method):
    """One time step of a block by integrator id ``method``, chosen at run time: the shared
    kernel, compiled once for every integrator (``Simulator(shared_kernel=True)``)."""
    if method == EXPLICIT_EULER:
        _explicit_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == SYMPLECTIC_EULER:
        _symplectic_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == VELOCITY_VERLET:
        _velocity_verlet(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == RK2:
        _rk2(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == RK4:
        _rk4(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == VERLET_TETRA:
        _verlet_tetra(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == ACCURATE_EULER:
        _accurate_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == POSITION_VERLET:
        _position_verlet(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == PRESCALED_SYMPLECTIC_EULER:
        _prescaled_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == VELOCITY_VERLET_CACHED:
        _velocity_verlet_cached(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == TRAPEZOID_SYMPLECTIC_EULER:
        _trapezoid_euler(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    elif method == IMPLICIT_MIDPOINT:
        _implicit_midpoint(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
    else:  # a new row of integrators.TABLE without its branch would leave the state as it was
        raise ValueError("unknown integrator id: see integrators.TABLE")


def _step_block(method, scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """One time step of a block by integrator id ``method`` (compiled code only)."""
    raise NotImplementedError("compiled code only")


@overload(_step_block, prefer_literal=True, inline="always")  # literal first; no call level
def _step_block_typed(method, scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
    """Chosen while numba types a step kernel: with ``method`` a literal integer
    (``step_serial``, ``step_parallel``: ``literally``), that integrator's block step is the
    only one compiled in; with ``method`` an integer (``step_*_shared``), or a literal without
    a block step, :func:`_integrate` (which refuses an unknown id when it runs)."""
    if isinstance(method, types.IntegerLiteral) and method.literal_value in STEPPERS:
        step = STEPPERS[method.literal_value]

        def one(method, scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
            step(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)

        return one
    if isinstance(method, types.Integer):

        def shared(method, scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external):
            _integrate(scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external, method)

        return shared
    return None


@njit(**_JIT)
def _deflect(e0, n, samples, ctrl, flap_now):
    """Body-frame normals of the control surfaces for this block's environments."""
    tab, normal, hinge, mix = (
        samples.flap,
        samples.flap_normal,
        samples.flap_hinge,
        samples.flap_mix,
    )
    for p in range(tab.shape[1]):
        for i in range(n):
            theta = ZERO * tab[S_OFFSET, p]  # zero in the simulation dtype
            for c in range(mix.shape[1]):
                theta += mix[p, c] * ctrl[c, e0 + i]
            nx, ny, nz = rotate_about_axis(
                normal[0, p],
                normal[1, p],
                normal[2, p],
                hinge[0, p],
                hinge[1, p],
                hinge[2, p],
                math.cos(theta),
                math.sin(theta),
            )
            flap_now[0, p, e0 + i] = nx
            flap_now[1, p, e0 + i] = ny
            flap_now[2, p, e0 + i] = nz


@njit(**_INLINE)
def _actuate(e0, n, actuator, command, ctrl):
    """Move each channel of this block's environments one step toward its command: the
    first-order lag held exactly over the step (``actuator[c, 0]`` = 1 - exp(-dt / tau)),
    then clipped to the rate limit (``actuator[c, 1]``, control units per step)."""
    for c in range(actuator.shape[0]):
        share, most = actuator[c, 0], actuator[c, 1]
        for i in range(n):
            x = ctrl[c, e0 + i]
            move = min(max(share * (command[c, e0 + i] - x), -most), most)
            ctrl[c, e0 + i] = x + move


@njit(**_INLINE)
def _load_block(blk, model, samples, data, deflect=True):
    """Copy a block's state, body constants and fluid (and wake source) into its scratch and,
    with ``deflect``, deflect its control surfaces (``_deflect``: a sine and a cosine from
    libm per surface and environment, a large share of a light craft's step); returns (first
    environment, environments in the block)."""
    st, flow, src, scr = data.st, data.flow, data.src, data.scr
    nb, ne = st.shape[1], st.shape[2]
    e0 = blk * BLOCK
    n = min(BLOCK, ne - e0)
    scr_blk = scr[blk]
    if deflect:
        _deflect(e0, n, samples, data.ctrl, data.flap_now)
    for b in range(nb):
        for k in range(st.shape[0]):
            for i in range(n):
                scr_blk[b, (STATE + k) * BLOCK + i] = st[k, b, e0 + i]
        for k in range(model.body.shape[2]):
            for i in range(n):
                scr_blk[b, (BODY + k) * BLOCK + i] = model.body[e0 + i, b, k]
        for k in range(3):
            for i in range(n):
                air = flow[k, e0 + i]
                scr_blk[b, (FLUID + k) * BLOCK + i] = air
                scr_blk[b, (FLUID + 3 + k) * BLOCK + i] = flow[3 + k, e0 + i] - air
        if model.wprm[W_ON] != 0.0 or model.prm[P_ORBITAL] != 0.0:  # per-sample water
            for k in range(3):
                for i in range(n):
                    scr_blk[b, (OWN_WATER + k) * BLOCK + i] = scr_blk[
                        b, (FLUID + 3 + k) * BLOCK + i
                    ]
        if model.wprm[W_ON] != 0.0:
            for k in range(src.shape[0]):
                for i in range(n):
                    scr_blk[b, (SOURCE + k) * BLOCK + i] = src[k, e0 + i]
        memory = data.memory  # a carrying integrator's (empty for the others)
        for k in range(memory.shape[0]):
            for i in range(n):
                scr_blk[b, (MEMORY + k) * BLOCK + i] = memory[k, b, e0 + i]
        if data.iterations.shape[0] > 0:
            for i in range(n):
                scr_blk[b, ITERATIONS * BLOCK + i] = 0.0
    return e0, n


@njit(**_INLINE)
def _block_may_touch(scr_blk, nb, e0, n, model, data):
    """Whether any environment of the block needs contact.py this step. Tested here, inlined,
    before the call: a call of ``_contact`` counts references to every array of ``model`` and
    ``data``, which cost a flying dart's env physics a sixth of its time when made per block
    and step with nothing near the floor."""
    cbody, cprm, warm = model.contact_body, model.cprm, data.warm
    for i in range(n):
        if may_touch(scr_blk, nb, i, BLOCK, e0 + i, cbody, cprm, warm):
            return True
    return False


@njit(**_JIT)
def _contact(scr_blk, nb, e0, n, model, data, work, pairs):
    """contact.py: scalar per environment, after a step's integration."""
    cbody, cprm, warm = model.contact_body, model.cprm, data.warm
    for i in range(n):
        e = e0 + i
        if may_touch(scr_blk, nb, i, BLOCK, e, cbody, cprm, warm):
            collide(scr_blk, nb, i, BLOCK, model.body[e], model.shape[e], model.shape_at,
                    model.grid, cbody[e], cprm, work, warm[e], data.touch[e], pairs)  # fmt: skip


@njit(**_INLINE)
def _advance_block(blk, model, samples, data, method, steps, contact, pairs):
    actuated = model.actuator.shape[0] > 0
    # with actuators every step moves them and deflects the surfaces before its forces
    e0, n = _load_block(blk, model, samples, data, not actuated)
    st, src, clock, diverged = data.st, data.src, data.clock, data.diverged
    nb = st.shape[1]
    scr_blk = data.scr[blk]
    wake = model.wprm[W_ON] != 0.0
    dt = model.prm[P_DT]
    tdt = np.float64(dt)
    sea = model.swell.shape[0] > 0
    touching = model.cprm[C_ON] != 0.0
    prm, wprm, ctrl, flap_now, external = _forces(model, data)
    work = np.empty((num_pairs(nb) if touching else 0, NW), dtype=data.scr.dtype)  # contact.py
    # the contacts' impulses over this call. Written through a local name: numba 0.68 drops
    # the writes of ``data.touch[...] = 0`` in this loop nest once inlined into the prange
    # of step_parallel (the impulses of the last touchdown stayed, and every dart of a
    # parallel batch "landed" again each step after its first landing; reproduced in
    # tests/physics/test_determinism.py)
    touch = data.touch
    if touching:
        for i in range(n):
            for c in range(touch.shape[1]):
                touch[e0 + i, c] = 0.0
    for _ in range(steps):
        if actuated:  # the actuators move at the step rate, the surfaces with them
            _actuate(e0, n, model.actuator, data.command, data.ctrl)
            _deflect(e0, n, samples, data.ctrl, data.flap_now)
        if sea:  # the waves' time phases at the step's start
            for b in range(nb):
                _phase_rows(scr_blk[b], n, e0, model.swell, clock)
        _step_block(method, scr_blk, nb, n, e0, samples, prm, wprm, ctrl, flap_now, external)
        # resolved when numba compiles: with ``contact`` None (a model without contact) the
        # branch is pruned and contact.py is never compiled (most of the dart's first step)
        if contact is not None and touching:
            if _block_may_touch(scr_blk, nb, e0, n, model, data):
                _contact(scr_blk, nb, e0, n, model, data, work, pairs)
        for i in range(n):  # each environment's clock: its own slots only
            clock[e0 + i] += tdt
        if wake:  # the source moves on at its velocity (rows: pos 0-2, velocity 12-14)
            for b in range(nb):
                for k in range(3):
                    for i in range(n):
                        scr_blk[b, (SOURCE + k) * BLOCK + i] += (
                            dt * scr_blk[b, (SOURCE + 12 + k) * BLOCK + i]
                        )
    if wake:  # the source's new position, so that step(k) then step(m) is step(k + m)
        for k in range(3):
            for i in range(n):
                src[k, e0 + i] = scr_blk[0, (SOURCE + k) * BLOCK + i]
    for i in range(n):
        diverged[e0 + i] = False
    # before st is overwritten: it still holds the call's starting positions
    _flag_runaways(scr_blk, nb, n, e0, st, model.prm, steps, diverged)
    memory, iterations = data.memory, data.iterations  # local names: see touch above
    for b in range(nb):
        for k in range(memory.shape[0]):
            for i in range(n):
                memory[k, b, e0 + i] = scr_blk[b, (MEMORY + k) * BLOCK + i]
    if iterations.shape[0] > 0:  # implicit_midpoint: a step whose iteration failed diverged
        most = model.prm[P_IMPLICIT_MAX]
        for i in range(n):
            it = scr_blk[0, ITERATIONS * BLOCK + i]
            for b in range(1, nb):
                it = max(it, scr_blk[b, ITERATIONS * BLOCK + i])
            iterations[e0 + i] = it
            diverged[e0 + i] |= it > most
    for b in range(nb):
        for k in range(st.shape[0]):
            for i in range(n):
                x = scr_blk[b, (STATE + k) * BLOCK + i]
                st[k, b, e0 + i] = x
                diverged[e0 + i] |= not math.isfinite(x)


@njit(**_INLINE)
def _flag_runaways(scr_blk, nb, n, e0, st, prm, steps, diverged):
    """Flag a finite state that has left the model (docs/study.md, how each method fails): the
    clamps keep every force finite, so an integrator past its stability limit runs away
    without ever producing a NaN. A body is a runaway when, over this call, it

    - ends faster than its craft's runaway speed (``B_RUNAWAY``), or than the fluid
      samples' speed clamp (every sample saturated), whichever is lower;
    - moved farther than that speed allows in the call's time: within a call of several
      steps a body can overshoot and come back below it (rk2's midpoint velocity can be far
      beyond it), the distance it jumped tells;
    - turns faster than its craft's runaway rate, or spins with more rotational energy than
      its mass would hold at the clamp speed, ``L . w > m vmax^2``: its samples then move
      far beyond the clamp from the turn alone.

    ``st`` holds the call's starting state, the block's scratch its end."""
    clamp2 = prm[P_VMAX] * prm[P_VMAX]
    for b in range(nb):
        for i in range(n):
            vmax = min(prm[P_VMAX], scr_blk[b, (BODY + B_RUNAWAY) * BLOCK + i])
            vmax2 = vmax * vmax
            reach = vmax * prm[P_DT] * steps
            reach2 = reach * reach * 1.0001  # that speed's distance, and a rounding beyond
            rate = scr_blk[b, (BODY + B_RUNAWAY + 1) * BLOCK + i]
            vx = scr_blk[b, (STATE + OV) * BLOCK + i]
            vy = scr_blk[b, (STATE + OV + 1) * BLOCK + i]
            vz = scr_blk[b, (STATE + OV + 2) * BLOCK + i]
            dx = scr_blk[b, (STATE + OX) * BLOCK + i] - st[OX, b, e0 + i]
            dy = scr_blk[b, (STATE + OX + 1) * BLOCK + i] - st[OX + 1, b, e0 + i]
            dz = scr_blk[b, (STATE + OX + 2) * BLOCK + i] - st[OX + 2, b, e0 + i]
            lx = scr_blk[b, (STATE + OL) * BLOCK + i]
            ly = scr_blk[b, (STATE + OL + 1) * BLOCK + i]
            lz = scr_blk[b, (STATE + OL + 2) * BLOCK + i]
            rot = quat_to_matrix(
                scr_blk[b, (STATE + OQ) * BLOCK + i],
                scr_blk[b, (STATE + OQ + 1) * BLOCK + i],
                scr_blk[b, (STATE + OQ + 2) * BLOCK + i],
                scr_blk[b, (STATE + OQ + 3) * BLOCK + i],
            )
            inv = (
                scr_blk[b, (BODY + B_INV_INERTIA) * BLOCK + i],
                scr_blk[b, (BODY + B_INV_INERTIA + 1) * BLOCK + i],
                scr_blk[b, (BODY + B_INV_INERTIA + 2) * BLOCK + i],
                scr_blk[b, (BODY + B_INV_INERTIA + 3) * BLOCK + i],
                scr_blk[b, (BODY + B_INV_INERTIA + 4) * BLOCK + i],
                scr_blk[b, (BODY + B_INV_INERTIA + 5) * BLOCK + i],
            )
            w = world_omega(rot, lx, ly, lz, inv)
            spin = lx * w[0] + ly * w[1] + lz * w[2]  # twice the rotational energy
            mass = scr_blk[b, (BODY + B_MASS) * BLOCK + i]
            runaway = vx * vx + vy * vy + vz * vz > vmax2
            runaway |= dx * dx + dy * dy + dz * dz > reach2
            runaway |= spin > mass * clamp2
            runaway |= w[0] * w[0] + w[1] * w[1] + w[2] * w[2] > rate * rate
            diverged[e0 + i] |= runaway


@njit(**_JIT)
def step_serial(model, samples, data, method, steps, contact, pairs):
    """Advance every environment ``steps`` steps on the calling thread (``model``, ``samples``,
    ``data``: ``model.py``'s :class:`Model`, :class:`Samples`, :class:`Data`;
    ``method``: an ``integrators.Integrator.id``, compiled as a literal: the kernel holds that
    integrator's block step only (``_step_block``); ``contact``: None for a model without
    contact (``model.cprm[C_ON] == 0``: the kernel is compiled without contact.py), else True;
    ``pairs``: None where no two bodies can touch (one body per environment: the kernel is
    compiled without the body-pair tests), else True)."""
    literally(method)
    for blk in range(data.scr.shape[0]):
        _advance_block(blk, model, samples, data, method, steps, contact, pairs)


@njit(parallel=True, **_JIT)
def step_parallel(model, samples, data, method, steps, contact, pairs):
    """Advance every environment ``steps`` steps, blocks spread over numba's threads
    (arguments: :func:`step_serial`'s)."""
    literally(method)
    for blk in prange(data.scr.shape[0]):
        _advance_block(blk, model, samples, data, method, steps, contact, pairs)


# The same kernels shared by every integrator (``Simulator(shared_kernel=True)``): ``method``
# an integer, the block step chosen at run time (``_integrate``)


@njit(**_JIT)
def step_serial_shared(model, samples, data, method, steps, contact, pairs):
    """:func:`step_serial` for any integrator (arguments: its)."""
    for blk in range(data.scr.shape[0]):
        _advance_block(blk, model, samples, data, method, steps, contact, pairs)


@njit(parallel=True, **_JIT)
def step_parallel_shared(model, samples, data, method, steps, contact, pairs):
    """:func:`step_parallel` for any integrator (arguments: its)."""
    for blk in prange(data.scr.shape[0]):
        _advance_block(blk, model, samples, data, method, steps, contact, pairs)


@njit(**_JIT)
def wrench(model, samples, data, out):
    """Net force and torque about the center of mass of every body from its samples,
    buoyancy and thrusters (gravity excluded), out[6, B, E], world frame, at each
    environment's clock."""
    g = model.prm[P_G]
    st, scr = data.st, data.scr
    prm, wprm, ctrl, flap_now, external = _forces(model, data)
    for blk in range(scr.shape[0]):
        e0, n = _load_block(blk, model, samples, data)
        for b in range(st.shape[1]):
            S = scr[blk, b]
            if model.swell.shape[0] > 0:
                _phase_rows(S, n, e0, model.swell, data.clock)
            _evaluate(S, b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, None)
            for i in range(n):
                m = model.body[e0 + i, b, B_MASS]
                out[0, b, e0 + i] = m * S[(DERIV + OV) * BLOCK + i]
                out[1, b, e0 + i] = m * S[(DERIV + OV + 1) * BLOCK + i]
                out[2, b, e0 + i] = m * (S[(DERIV + OV + 2) * BLOCK + i] + g)
                for k in range(3):
                    out[3 + k, b, e0 + i] = S[(DERIV + OL + k) * BLOCK + i]


@njit(**_JIT)
def sample_forces(model, samples, data, env, out):
    """Each sample's world application point and force in environment ``env`` at its clock,
    ``out[N, 6]`` (point x, y, z, then force), N the samples of every body in ``_evaluate``'s
    order: ``_evaluate``'s force loops, recorded instead of added up (the same code), so they
    sum to :func:`wrench`."""
    st, scr = data.st, data.scr
    prm, wprm, ctrl, flap_now, external = _forces(model, data)
    blk = env // BLOCK
    e0, n = _load_block(blk, model, samples, data)
    i = env - e0
    rows = np.zeros((out.shape[0], R_FORCE, BLOCK), dtype=scr.dtype)
    rec = (np.arange(out.shape[0]), rows, 0)
    for b in range(st.shape[1]):
        S = scr[blk, b]
        if model.swell.shape[0] > 0:
            _phase_rows(S, n, e0, model.swell, data.clock)
        _evaluate(S, b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, rec)
        for j in range(_first_sample(samples, b), _first_sample(samples, b + 1)):
            for k in range(3):
                out[j, k] = st[OX + k, b, env] + rows[j, k, i]
                out[j, 3 + k] = rows[j, 3 + k, i]


@njit(**_INLINE)
def _sense_block(blk, model, samples, data, slot, bodies, out):
    """``sample_flows`` for one block: ``_evaluate`` of each body in ``bodies`` recording the
    samples that ``slot`` picks into the block's columns of ``out``."""
    prm, wprm, ctrl, flap_now, external = _forces(model, data)
    e0, n = _load_block(blk, model, samples, data)
    rec = (slot, out, e0, True)  # the fourth: record what the samples sense
    for b in bodies:
        S = data.scr[blk, b]
        if model.swell.shape[0] > 0:
            _phase_rows(S, n, e0, model.swell, data.clock)
        _evaluate(S, b, n, e0, samples, prm, wprm, ctrl, flap_now, external, T0, rec)


@njit(**_JIT)
def sample_flows_serial(model, samples, data, slot, bodies, blocks, out):
    """What the samples that ``slot[N]`` picks sense in every environment at its clock:
    ``out[P, R_SENSE, E]`` (rows: ``_record``'s), ``out[slot[j]]`` sample j's; ``bodies``
    the body slots that own them; ``blocks`` the blocks of environments to read (the others'
    columns are left as they were). The state is not changed (scratch only: the next step
    reloads it), so observing them leaves the trajectory bit-identical."""
    for k in range(blocks.size):
        _sense_block(blocks[k], model, samples, data, slot, bodies, out)


@njit(parallel=True, **_JIT)
def sample_flows_parallel(model, samples, data, slot, bodies, blocks, out):
    """:func:`sample_flows_serial`, blocks spread over numba's threads."""
    for k in prange(blocks.size):
        _sense_block(blocks[k], model, samples, data, slot, bodies, out)


@njit(**_JIT)
def body_omega(st, body, out):
    """World angular velocity of every body, out[3, B, E], from st[13, B, E] and the body
    constants body[E, B, NBODY]."""
    for b in range(st.shape[1]):
        for e in range(st.shape[2]):
            w = body_state(st, b, e, env_inv_inertia(body, e, b))[3]
            out[0, b, e] = w[0]
            out[1, b, e] = w[1]
            out[2, b, e] = w[2]


@njit(**_JIT)
def quat_matrices(q):
    """Rotation matrices [N, 3, 3] of quaternions [N, 4] (w, x, y, z)."""
    out = np.empty((q.shape[0], 3, 3), dtype=q.dtype)
    for j in range(q.shape[0]):
        m = quat_to_matrix(q[j, 0], q[j, 1], q[j, 2], q[j, 3])
        for k in range(9):
            out[j, k // 3, k % 3] = m[k]
    return out
