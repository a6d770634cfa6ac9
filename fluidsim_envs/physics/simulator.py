"""Simulator: E environments of B rigid bodies each, advanced by one compiled call per step."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Sequence

import numpy as np

from . import checks as CK
from . import contact as CT
from . import integrators as IT
from . import kernels as K
from . import model as M
from . import wake as WK
from .craft import Craft, CraftError, check_inertia, shape_reach, shift_offsets
from .factors import FactorTable
from .randomizer import Randomizer
from .state import BLOCK, NMEMORY, NSTATE, OL, OQ, OV, OX, ROWS
from .world import World

PARALLEL_MIN_BODIES = 1024  # below this many bodies the serial kernel wins (thread start-up)
# groups every craft has for Simulator.set_sample_scale, beside its samples' names and its own
BUILTIN_GROUPS = ("all", "plates", "control_surfaces", "cylinders", "buoyancy")
_METHOD_ARG = 3  # the step kernels' integrator id: (model, samples, data, method, ...)
FIXED = ("fixed32", "fixed64")  # dtypes that Simulator hands to physics/fixed/


def _entry_point(kernel, args, literal=()):
    """The compiled function ``kernel`` runs for ``args``, called without the dispatcher's
    typing of every argument: half of a one-environment step's round trip through Python
    (``benchmarks/compare_revisions.py``). The Simulator's buffers keep their types for its
    life, so the types resolved once hold; the arguments at the positions ``literal`` are
    compiled as literals (the integrator id: ``kernels.step_serial``).

    Compiled (or loaded from the cache) for exactly those types: called through the
    dispatcher, a kernel with ``literally`` is first typed with a plain integer, which types
    most of it before asking for the literal, then typed again (measured on the dart's rk4
    kernel, cold: 62 against 142 s and 74 against 87 s on a loaded 2-core machine)."""
    import numba

    key = tuple(
        numba.types.literal(a) if i in literal else numba.typeof(a) for i, a in enumerate(args)
    )
    if key not in kernel.overloads:
        kernel.compile(key)
    return kernel.overloads[key].entry_point


def _world_params(world: World, dt: float, swell: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """The kernels' ``prm[NPRM]`` (float64): the world and the step (``kernels.P_*``)."""
    prm = np.zeros(K.NPRM)
    prm[K.P_IMPLICIT_TOL] = IT.IMPLICIT_TOLERANCE_ULP * np.finfo(dtype).eps
    prm[K.P_IMPLICIT_MAX] = IT.IMPLICIT_MAX_ITERATIONS
    prm[K.P_IMPLICIT_LOOSE] = np.finfo(dtype).eps ** 0.75
    prm[K.P_G] = world.gravity_mps2
    prm[K.P_GM] = world.central_gravity_m3s2
    prm[K.P_RHO_AIR] = world.air_density_kgm3
    prm[K.P_RHO_WATER] = world.water_density_kgm3
    prm[K.P_WATER] = 1.0 if world.water else 0.0
    prm[K.P_WIND : K.P_WIND + 3] = world.wind_mps
    prm[K.P_CURRENT : K.P_CURRENT + 3] = world.current_mps
    # a sharp surface is a layer thin enough that the blend is a step
    prm[K.P_INV_BLEND] = 1.0 / world.surface_blend_m if world.surface_blend_m > 0 else 1e30
    prm[K.P_VMAX] = world.max_fluid_speed_mps
    prm[K.P_FMAX] = world.max_sample_force_n
    prm[K.P_DT] = dt
    prm[K.P_TETRA_SWITCH] = world.tetra_rigid_spin_rad
    prm[K.P_NWAVES] = len(swell)
    prm[K.P_ORBITAL] = 1.0 if world.wave_orbital_velocity and len(swell) else 0.0
    for j, (a, kx, ky, omega, _) in enumerate(swell):
        prm[K.P_SWELL + 4 * j : K.P_SWELL + 4 * j + 4] = (a, kx, ky, omega)
    return prm


def _crafts(crafts) -> list[Craft]:
    """One Craft or a non-empty list of them, as a list."""
    if isinstance(crafts, Craft):
        return [crafts]
    if isinstance(crafts, (list, tuple)) and crafts and all(isinstance(c, Craft) for c in crafts):
        return list(crafts)
    raise TypeError(
        f"Simulator: crafts must be a Craft or a non-empty list of Crafts, got {CK.show(crafts)}"
    )


def _dtype(value) -> np.dtype:
    """float32 or float64, from a NumPy type, a dtype or its name."""
    try:
        dtype = np.dtype(value) if value is not None else None
    except TypeError:
        dtype = None
    if dtype not in (np.float32, np.float64):
        raise ValueError(
            f"Simulator: dtype must be np.float32 or np.float64 (or their names), or a "
            f"fixed-point format {FIXED}, got {CK.show(value)}"
        )
    return dtype


class _Body:
    """One body slot's nominal craft, its samples and groups, and each environment's mass
    properties (what ``set_mass_properties`` holds until changed; the sample factors are in
    the simulator's :class:`FactorTable`)."""

    def __init__(self, craft: Craft, num_envs: int, first: int) -> None:
        self.craft = craft
        self.names = M.sample_names(craft)
        self.rows = {k: np.asarray(r, dtype=np.float64) for k, r in M.sample_rows(craft).items()}
        self.mass_kg = np.full(num_envs, craft.mass_kg)
        self.inertia = np.repeat(craft.inertia_tensor[None], num_envs, axis=0)
        self.com_m = np.zeros((num_envs, 3))  # shift of the center of mass from the craft's
        self.shapes = np.asarray(CT.shape_rows(craft), dtype=np.float64)  # SH_* rows
        self.extents = np.array([s.extent_m for s in craft.shapes])
        self.index = {}  # each kind's samples' numbers among all bodies' (Samples.factor_row)
        for kind, names in self.names.items():
            self.index[kind] = first + np.arange(len(names))
            first += len(names)

        def of(*kinds):
            return [(k, i) for k in kinds for i in range(len(self.names[k]))]

        groups = {
            "all": of(*self.names),
            "plates": of("plate", "flap"),
            "control_surfaces": of("flap"),
            "cylinders": of("cyl"),
            "buoyancy": of("buoy"),
        }
        where = {n: (k, i) for k, names in self.names.items() for i, n in enumerate(names)}
        groups.update({n: [ki] for n, ki in where.items()})
        groups.update({g: [where[n] for n in members] for g, members in craft.groups})
        self.groups = groups

    def numbers(self, members) -> np.ndarray:
        """The sample numbers (``Samples.factor_row``'s columns) of ``(kind, i)`` pairs."""
        return np.asarray([self.index[k][i] for k, i in members], dtype=np.int64)


class Simulator:
    """Rigid bodies with fluid samples, stepped in batches.

    Args:
        crafts: one :class:`Craft`, or a list of them: the bodies of every environment.
        world: the :class:`World` (gravity, fluids, surface, clamps); default ``World()``.
        num_envs: E, the number of independent environments.
        dt: time step (s); ``step(steps=k)`` advances k of them.
        integrator: the time-stepping method (force evaluations per step in brackets):

            - ``explicit_euler`` [1]: first order; everything from the old state. Gains
              energy every step on oscillations and spins (a spring's energy grows by
              ``1 + (omega dt)^2`` per step): for comparison only.
            - ``symplectic_euler`` [1] (default): velocity and angular momentum first, then
              position with the new velocity; orientation by an explicit-midpoint step of the
              new angular momentum. First order, symplectic in translation: energy errors stay
              bounded (O(omega dt)) instead of drifting. Unstable above ``omega dt = 2`` for
              a spring; velocity-dependent forces are taken at the old velocity, so very
              fast damping (light plates at large dt) can overshoot.
            - ``velocity_verlet`` [2]: half kick, drift, new forces, half kick. Second order
              and symplectic for position-only forces; with velocity-dependent forces the
              second evaluation uses the half-step velocity, which makes it first order: on
              the shipped crafts (fluid drag everywhere) rk2 is 50-130 times more accurate
              at the same cost (``docs/study.md``).
            - ``rk2`` [2]: explicit midpoint. Second order, not symplectic: a spring slowly
              gains energy (``|1 + i h - h^2/2| > 1``).
            - ``rk4`` [4]: classic Runge-Kutta. Fourth order; slowly loses energy on
              oscillations; the most accurate per step, the costliest.
            - ``verlet_tetra`` [1]: the body as four particles matched to its mass and
              inertia (``reference.tetra.match_inertia``): velocities and positions as symplectic
              Euler, the turn as the particles' drift with the shape restored by the
              best-fitting rotation and the momenta kept. Above ``World.tetra_rigid_spin_rad``
              per step a body turns rigidly instead.

            The seed's remaining methods (docs/seed_map.md; docs/study.md charts each):

            - ``accurate_euler`` [1]: the seed's "more accurate" Euler, ``x += v dt + a dt^2
              / 2``, ``v += a dt``, all from the old state. Exact for a constant force, first
              order otherwise; not symplectic: a spring gains energy every step (its map's
              determinant is ``1 + (omega dt)^2 / 2``), like explicit Euler but slower.
            - ``position_verlet`` [1]: velocity-less (Stormer) Verlet: it keeps the last
              position, steps by the last displacement plus ``a dt^2`` and reads velocity as
              displacement over dt. Symplectic Euler's trajectory, rounded differently:
              ``x - x_old`` loses digits where positions are large against a step.
            - ``prescaled_symplectic_euler`` [1]: symplectic Euler with the velocity stored
              times dt (the seed's fixed-point form): one product less per step, other
              rounding.
            - ``velocity_verlet_cached`` [1]: the seed's velocity Verlet: ``velocity_verlet``
              with its first evaluation reused from the last step's end, so one evaluation
              per step (two on a first step, after a reset or a contact). Controls changed
              between calls reach its first half kick a step late.
            - ``trapezoid_symplectic_euler`` [1]: symplectic Euler with the turn by the
              trapezoid rule (the seed's trick for fast spins) instead of the midpoint.
            - ``implicit_midpoint`` [1] per iteration: ``y1 = y0 + dt f((y0 + y1) / 2)``
              solved by fixed-point iteration to a few ulp (:attr:`iterations` counts them).
              Second order and symplectic. The iteration contracts by about dt times the
              forces' stiffness over 2 per pass: past 1 it cannot converge, past about 1/2 it
              needs more than ``integrators.IMPLICIT_MAX_ITERATIONS``; either way the step is
              flagged :attr:`diverged`.

            The carrying methods (``position_verlet``, ``prescaled_symplectic_euler``,
            ``velocity_verlet_cached``) keep their memory per body between calls; wherever
            the state is not what their last step left (reset, contact, :meth:`set_state`
            of a snapshot without it), they take it afresh from the state.

            Every method keeps world angular momentum exact under zero torque (it is the
            state) and renormalizes the quaternion each step. Contact (crafts with
            ``shapes``, against ``World.ground`` and each other: ``contact.py``) runs after
            each step's integration, whichever the method.
        dtype: ``np.float64`` (default) or ``np.float32``; ``"fixed32"`` or ``"fixed64"``
            return a fixed-point simulator (``physics/fixed/``, with ``fraction_bits=14``
            and ``units=``: docs/physics.md).
        parallel: run blocks of environments on numba's threads; default: when E * B >= 1024.
        wake: a :class:`WakeField` whose flow every fluid sample in the water feels (its
            velocity is added to the water's); each environment's source (the submarine's
            pose and velocity) is set with :meth:`set_wake_source` and moves on at its
            velocity (orientation held) while the bodies step. None (default): no wake, and
            no cost.
        shared_kernel: compile one step kernel for every integrator (the method chosen at
            run time) instead of one holding this integrator only. The first step of a
            process compiles its kernel (docs/bench_compile.csv): per integrator is the
            faster first step (the default); shared compiles once for a process that runs
            several integrators (the test suite, the studies). Both give bit-identical
            results (tests/physics/test_integrator_table.py). None (default): shared when
            the environment variable ``FLUIDSIM_SHARED_KERNEL`` is ``1``.

    State (world frame, arrays ``[E, B, ...]``, read-only views): ``pos``, ``quat`` (w, x, y,
    z), ``lin_vel``, ``ang_vel``, and ``diverged`` ``[E]`` (a non-finite state).

    Each environment its own craft: :meth:`set_mass_properties` (mass, inertia, center of
    mass), :meth:`set_sample_scale` (sample sizes and efficiencies by group) and
    :meth:`set_thrust_scale` change environments one by one, until changed again; the
    kernels read every such value per environment (``model.py``). An environment left at
    the craft's values steps bit-identically to a batch of that craft alone.

    Time: every environment has its own clock, ``clock`` ``[E]`` (s, float64, read-only view),
    starting at 0 and advanced by ``dt`` per step; :meth:`set_clock` sets it (a scene sets a
    random clock offset on reset to randomize the swell's phase; :meth:`reset` leaves the
    clock alone). A World with ``swell`` moves each environment's water surface with its
    clock; the surface under each sample is taken at the force evaluation's stage time
    (``kernels.py``). Calm water gives the same results, bit for bit, as a flat surface did
    before swell existed, at the same speed (within measurement noise).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.physics import Craft, Simulator, World
        >>> ball = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4))
        >>> sim = Simulator(ball, World(), num_envs=2, dt=0.01)
        >>> sim.reset(lin_vel=(1.0, 0.0, 0.0))
        >>> sim.step(steps=100)
        >>> np.round(sim.pos[0, 0], 5)          # 1 s of flight: x = 1, z = -g t(t+dt)/2
        array([ 1.     ,  0.     , -4.95405])
    """

    def __new__(cls, *args, **kwargs):
        """``dtype="fixed32"`` or ``"fixed64"`` (the sixth argument) gives a
        :class:`~fluidsim_envs.physics.fixed.FixedSimulator` (``physics/fixed/``), which
        also takes ``fraction_bits`` and ``units``; any other dtype, this class."""
        dtype = kwargs.get("dtype", args[5] if len(args) > 5 else None)
        if isinstance(dtype, str) and dtype in FIXED:
            from .fixed import FixedSimulator

            return FixedSimulator(*args, **kwargs)
        extra = sorted({"fraction_bits", "units"} & set(kwargs))
        if extra:
            raise ValueError(
                f"Simulator: {extra} apply to a fixed-point dtype {FIXED} only, got dtype="
                f"{CK.show(dtype) if dtype is not None else 'np.float64 (the default)'}"
            )
        return super().__new__(cls)

    def __init__(
        self,
        crafts: Craft | Sequence[Craft],
        world: World | None = None,
        num_envs: int = 1,
        dt: float = 1.0 / 120.0,
        integrator: str = "symplectic_euler",
        dtype=np.float64,
        parallel: bool | None = None,
        wake: WK.WakeField | None = None,
        shared_kernel: bool | None = None,
    ) -> None:
        crafts = _crafts(crafts)
        world = World() if world is None else world
        if not isinstance(world, World):
            raise TypeError(f"Simulator: world must be a World, got {CK.show(world)}")
        if (
            isinstance(num_envs, bool)
            or not isinstance(num_envs, (int, np.integer))
            or num_envs < 1
        ):
            raise ValueError(
                f"Simulator: num_envs must be a positive integer, got {CK.show(num_envs)}"
            )
        dt = CK.number("Simulator", "dt", dt, gt=0.0)
        method = IT.get(integrator) if isinstance(integrator, str) else None
        if method is None:
            raise ValueError(
                f"Simulator: integrator must be one of {sorted(IT.BY_NAME)}, got "
                f"{CK.show(integrator)}"
            )
        dtype = _dtype(dtype)
        if wake is not None and not isinstance(wake, WK.WakeField):
            raise TypeError(f"Simulator: wake must be a WakeField or None, got {CK.show(wake)}")
        if parallel is not None:
            parallel = CK.flag("Simulator", "parallel", parallel)

        self.crafts = tuple(crafts)
        self.world = world
        self.num_envs = E = int(num_envs)
        self.num_bodies = B = len(crafts)
        self.dt = float(dt)
        self.integrator = integrator
        self.dtype = dtype
        self.wake = wake
        self.parallel = E * B >= PARALLEL_MIN_BODIES if parallel is None else bool(parallel)
        self._method = method.id
        if shared_kernel is None:
            shared_kernel = os.environ.get("FLUIDSIM_SHARED_KERNEL", "") == "1"
        elif not isinstance(shared_kernel, (bool, np.bool_)):
            raise TypeError(
                "Simulator: shared_kernel must be True, False or None, got "
                f"{CK.show(shared_kernel)}"
            )
        shared_kernel = bool(shared_kernel)
        self.shared_kernel = shared_kernel
        if shared_kernel:
            self._kernel = K.step_parallel_shared if self.parallel else K.step_serial_shared
        else:
            self._kernel = K.step_parallel if self.parallel else K.step_serial
        self.control_names: tuple[str, ...] = tuple(M.control_names(crafts))

        swell = world.swell_table()  # rows (a, kx, ky, omega, phase)
        cprm, grid = CT.params(
            crafts, world.ground, dt, world.gravity_mps2, world.contact_passes, method.drift_share
        )
        self._model, self._samples = M.pack(
            crafts,
            E,
            dtype,
            _world_params(world, dt, swell, dtype),
            wake.params(dtype) if wake is not None else np.zeros(WK.NWPRM, dtype),
            swell,
            cprm,
            grid,
        )
        first = np.cumsum([0] + [c.num_samples for c in crafts])
        self._bodies = [_Body(c, E, int(first[b])) for b, c in enumerate(crafts)]
        self._factors = FactorTable(self._samples.factor_row, self._samples.factor)
        self._probes: dict = {}  # sample_flows' slot maps and outputs, by samples and body
        self._all_blocks = np.arange(-(-E // BLOCK), dtype=np.int64)  # sample_flows' default
        n_pairs = CT.num_pairs(B) if cprm[CT.C_ON] else 0
        # the step kernel compiled without contact.py where nothing can touch (its None
        # is resolved when numba compiles: kernels.step_serial)
        self._contact = True if cprm[CT.C_ON] else None
        self._pairs = True if cprm[CT.C_ON] and B > 1 else None  # likewise the body pairs
        flow = np.zeros((6, E), dtype=dtype)  # air velocity, water velocity per env
        flow[:3] = np.asarray(world.wind_mps)[:, None]
        flow[3:] = np.asarray(world.current_mps)[:, None]
        src = np.zeros((WK.NSRC, E), dtype=dtype)  # the wake source of each env
        src[3:12:4] = 1.0  # identity rotation
        st = np.zeros((NSTATE, B, E), dtype=dtype)
        st[OQ] = 1.0
        # buffers, allocated once; the kernels update them in place, never rebind them
        self._data = M.Data(
            st=st,
            flow=flow,
            src=src,
            # float64 whatever the dtype: wave phases omega t stay exact over long episodes
            clock=np.zeros(E, dtype=np.float64),
            ctrl=np.zeros((len(self.control_names), E), dtype=dtype),
            command=np.zeros((len(self.control_names), E), dtype=dtype),
            flap_now=np.zeros((3, self._samples.flap.shape[1], E), dtype=dtype),
            external=np.zeros((E, B, 6), dtype=dtype),
            warm=np.zeros((E if n_pairs else 0, n_pairs, CT.NWARM), dtype=dtype),
            touch=np.zeros((E if n_pairs else 0, n_pairs), dtype=dtype),
            scr=np.zeros((-(-E // BLOCK), B, ROWS * BLOCK), dtype=dtype),
            diverged=np.zeros(E, dtype=np.bool_),
            memory=np.zeros((NMEMORY if method.carries else 0, B, E), dtype=dtype),
            iterations=np.zeros(E if method.iterative else 0, dtype=dtype),
        )
        # rows END NaN: no step of the integrator's has left this state (state.MEMORY_FIELDS)
        self._data.memory[:NSTATE] = np.nan
        self._entry = None  # the step kernel's compiled entry, once it has run (step)
        self._omega = np.zeros((3, B, E), dtype=dtype)
        self._wrench = np.zeros((6, B, E), dtype=dtype)

    def __getstate__(self) -> dict:
        """Pickled without the compiled entry point (found again at the first step)."""
        return {**self.__dict__, "_entry": None}

    # ---- state ----------------------------------------------------------------------------

    def _view(self, rows: slice) -> np.ndarray:
        v = self._data.st[rows].transpose(2, 1, 0)
        v.flags.writeable = False
        return v

    @property
    def pos(self) -> np.ndarray:
        """Center-of-mass positions [E, B, 3] (m)."""
        return self._view(slice(OX, OX + 3))

    @property
    def quat(self) -> np.ndarray:
        """Orientations [E, B, 4], unit quaternions (w, x, y, z), body -> world."""
        return self._view(slice(OQ, OQ + 4))

    @property
    def lin_vel(self) -> np.ndarray:
        """Center-of-mass velocities [E, B, 3] (m/s)."""
        return self._view(slice(OV, OV + 3))

    @property
    def ang_vel(self) -> np.ndarray:
        """Angular velocities [E, B, 3] (rad/s), world frame (derived from L)."""
        K.body_omega(self._data.st, self._model.body, self._omega)
        v = self._omega.transpose(2, 1, 0)
        v.flags.writeable = False
        return v

    def angular_momentum(self) -> np.ndarray:
        """Angular momentum about each center of mass [E, B, 3] (kg m^2/s), world frame."""
        return self._view(slice(OL, OL + 3)).copy()

    def kinetic_energy(self) -> np.ndarray:
        """Kinetic energy of each body [E, B] (J): 1/2 m v^2 + 1/2 L . w."""
        v, w, L = self.lin_vel, self.ang_vel, self._view(slice(OL, OL + 3))
        kinetic = 0.5 * self.mass_kg * np.einsum("ebk,ebk->eb", v, v)
        return kinetic + 0.5 * np.einsum("ebk,ebk->eb", L, w)

    @property
    def ground_impulse(self) -> np.ndarray:
        """``[E, B]`` (N s, read-only view): the normal impulse the ground gave each body over
        the last :meth:`step` call (0: it did not touch; all zeros without contact). A body
        can touch and bounce clear within one call: this is how a scene sees that it did."""
        if self._data.touch.shape[0] == 0:
            return np.zeros((self.num_envs, self.num_bodies), dtype=self.dtype)
        v = self._data.touch[:, : self.num_bodies]  # rows: contact.num_pairs
        v.flags.writeable = False
        return v

    @property
    def pair_impulse(self) -> np.ndarray:
        """``[E, P]`` (N s, read-only view): the normal impulse between each pair of bodies over
        the last :meth:`step` call, pairs in :attr:`pairs` order (all zeros without contact).
        The pairs of body 0 come first: ``pair_impulse[:, : B - 1]`` is body 0 against the
        others."""
        if self._data.touch.shape[0] == 0:
            return np.zeros((self.num_envs, len(self.pairs)), dtype=self.dtype)
        v = self._data.touch[:, self.num_bodies :]
        v.flags.writeable = False
        return v

    @property
    def pairs(self) -> np.ndarray:
        """``[P, 2]``: the bodies (a, b), a < b, of each column of :attr:`pair_impulse`."""
        return np.stack(np.triu_indices(self.num_bodies, 1), axis=1)  # contact.collide's order

    @property
    def iterations(self) -> np.ndarray:
        """``[E]`` (read-only view): with ``implicit_midpoint``, the most fixed-point
        iterations (force evaluations) any step of the last :meth:`step` call took in each
        environment; past ``integrators.IMPLICIT_MAX_ITERATIONS`` the iteration failed and
        the environment is :attr:`diverged`. Other integrators: a ``ValueError``."""
        if not self._data.iterations.shape[0]:
            raise ValueError(
                f"iterations: {self.integrator!r} does not iterate (implicit_midpoint does)"
            )
        v = self._data.iterations.view()
        v.flags.writeable = False
        return v

    @property
    def diverged(self) -> np.ndarray:
        """[E] True where the last ``step`` call left a non-finite state or a runaway: a body
        faster than ``World.max_fluid_speed_mps``, one that moved farther in the call than
        that speed allows (``max_fluid_speed_mps * dt * steps``), or one spinning with more
        rotational energy than its mass holds at that speed (beyond the fluid model: the
        clamps would keep such a runaway finite, not sane). That env needs a reset."""
        v = self._data.diverged.view()
        v.flags.writeable = False
        return v

    @property
    def wind_mps(self) -> np.ndarray:
        """Air velocity of each environment [E, 3] (m/s), world frame; see :meth:`set_wind`."""
        v = self._data.flow[:3].T
        v.flags.writeable = False
        return v

    @property
    def current_mps(self) -> np.ndarray:
        """Water velocity of each environment [E, 3] (m/s); see :meth:`set_current`."""
        v = self._data.flow[3:].T
        v.flags.writeable = False
        return v

    def set_wind(self, wind_mps, env_ids=None) -> None:
        """Set the uniform air velocity of every environment, or of ``env_ids`` only.

        ``wind_mps`` broadcasts to ``[n, 3]``; it starts at the World's ``wind_mps``.
        """
        self._set_flow("wind_mps", slice(0, 3), wind_mps, env_ids)

    def set_current(self, current_mps, env_ids=None) -> None:
        """Set the uniform water velocity of every environment, or of ``env_ids`` only."""
        self._set_flow("current_mps", slice(3, 6), current_mps, env_ids)

    @property
    def controls(self) -> np.ndarray:
        """``[E, n_controls]`` (read-only view): the controls of the last :meth:`step` or
        :meth:`wrench` call, channels in ``control_names`` order."""
        v = (self._data.command if self.actuated else self._data.ctrl).T
        v.flags.writeable = False
        return v

    @property
    def actuators(self) -> np.ndarray:
        """``[E, n_controls]`` (read-only view): where each control channel is now. With
        :meth:`set_actuators` the channels follow :attr:`controls` with a lag and a rate
        limit; without, they are the controls."""
        v = self._data.ctrl.T
        v.flags.writeable = False
        return v

    @property
    def actuated(self) -> bool:
        """Whether the control channels move through actuators (:meth:`set_actuators`)."""
        return self._model.actuator.shape[0] > 0

    def center_actuators(self, env_ids=None) -> None:
        """Put the actuators of environments ``env_ids`` (None: all) at rest at 0, with a
        command of 0 (what :meth:`reset` does; for a scene that writes its starts into
        :meth:`start_arrays`). Without actuators, the controls at 0: the surfaces centred
        for what is evaluated before the next step sets them (a new episode's first
        :meth:`sample_flows` must not depend on the last one's controls)."""
        ids = self._env_ids("center_actuators", env_ids)
        self._data.ctrl[:, ids] = 0.0
        if self.actuated:
            self._data.command[:, ids] = 0.0

    def set_actuators(self, time_constant_s=None, rate_limit_per_s=None) -> None:
        """Make every control channel follow its command through an actuator: a first-order
        lag of time constant ``time_constant_s`` and a rate limit of ``rate_limit_per_s``
        (control units per second: a surface's deg/s over its deflection limit in degrees),
        each > 0, broadcast over the channels (``control_names`` order). Integrated every
        step inside the kernel, held exactly over a step of constant command (the lag's
        step response is 1 - exp(-t / tau)), and then clipped to the rate. The channels'
        positions (:attr:`actuators`) are state: snapshots keep them and :meth:`reset`
        centres them. ``set_actuators()`` (both None) makes them instant again.
        """
        what = "set_actuators"
        C = len(self.control_names)
        if time_constant_s is None and rate_limit_per_s is None:
            self._model = self._model._replace(actuator=np.zeros((0, 2), dtype=self.dtype))
            return
        if time_constant_s is None or rate_limit_per_s is None:
            raise ValueError(f"{what}: give both time_constant_s and rate_limit_per_s, or neither")
        if C == 0:
            raise ValueError(f"{what}: the crafts have no control channel")
        tau = CK.array(what, "time_constant_s", time_constant_s, (C,))
        rate = CK.array(what, "rate_limit_per_s", rate_limit_per_s, (C,))
        for name, v in (("time_constant_s", tau), ("rate_limit_per_s", rate)):
            if not (np.all(np.isfinite(v)) and np.all(v > 0.0)):
                raise ValueError(f"{what}: {name} must be finite and > 0, got {CK.show(v)}")
        table = np.stack([-np.expm1(-self.dt / tau), rate * self.dt], axis=1)
        if not self.actuated:  # the channels start where the instant controls left them
            self._data.command[...] = self._data.ctrl
        self._model = self._model._replace(actuator=table.astype(self.dtype))

    @property
    def external_force(self) -> tuple[np.ndarray, np.ndarray]:
        """``(force [E, B, 3] (N), torque [E, B, 3] (N m))``, read-only views: what
        :meth:`set_external_force` holds on each body."""
        ext = self._data.external
        f, t = ext[..., :3], ext[..., 3:]
        f.flags.writeable = t.flags.writeable = False
        return f, t

    def set_external_force(self, force_n, torque_nm=(0.0, 0.0, 0.0), env_ids=None) -> None:
        """Hold a force at each body's center of mass and a torque on it (world frame), in
        every step until changed (a reset keeps it): a mooring line, a tow, a push from the
        scene. Each broadcasts to ``[n, B, 3]``, n the number of environments in
        ``env_ids`` (None: all). Being constant over a :meth:`step` call, a spring written
        this way is explicit in time: keep its period well above the call's duration."""
        ids = self._env_ids("set_external_force", env_ids)
        f = self._broadcast("force_n", force_n, 3, ids.size, "set_external_force")
        t = self._broadcast("torque_nm", torque_nm, 3, ids.size, "set_external_force")
        self._data.external[ids, :, :3] = f
        self._data.external[ids, :, 3:] = t

    def _set_flow(self, name: str, rows: slice, value, env_ids) -> None:
        ids = self._env_ids(f"set_{name[:-4]}", env_ids)
        self._data.flow[rows, ids] = CK.array(f"set_{name[:-4]}", name, value, (ids.size, 3)).T

    @property
    def clock(self) -> np.ndarray:
        """Each environment's time [E] (s), float64: advanced by ``dt`` per step (the
        simulation dtype's ``dt``); the swell moves with it. See :meth:`set_clock`."""
        v = self._data.clock.view()
        v.flags.writeable = False
        return v

    def set_clock(self, t, env_ids=None) -> None:
        """Set the clock (s) of every environment, or of ``env_ids`` only; ``t`` broadcasts to
        ``[n]``. The swell's surface at a point is a function of the clock, so a random clock
        offset randomizes the phase of every wave at once."""
        ids = self._env_ids("set_clock", env_ids)
        self._data.clock[ids] = CK.array("set_clock", "t", t, (ids.size,))

    def surface_height(self, x, y) -> np.ndarray:
        """Height of the water surface (m) above z = 0 in every environment at its own clock:
        ``x``, ``y`` broadcast to ``[E, ...]`` (leading axis: environments); the result is
        float64 of that shape (zeros in calm water). See :meth:`World.surface_height`."""
        x = CK.real_array("surface_height", "x", x)
        y = CK.real_array("surface_height", "y", y)
        ndim = max(x.ndim, y.ndim, 1)
        t = self._data.clock.reshape((self.num_envs,) + (1,) * (ndim - 1))
        return self.world.surface_height(x, y, t)

    def surface_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The arrays env kernels read the surface from, without copies: ``(swell [n, 5]``
        (float64 rows ``(a, kx, ky, omega, phase)``, empty in calm water; pass it to
        ``surface.surface_height(x, y, t, swell)``), ``clock [E]`` (float64, s)). Treat them
        as read-only."""
        return self._model.swell, self._data.clock

    def set_wake_source(
        self, pos, quat, lin_vel, noise_offset=(0.0, 0.0, 0.0), env_ids=None
    ) -> None:
        """Place the wake's source (the submarine) in every environment, or in ``env_ids``:
        position [n, 3], orientation [n, 4] (w, x, y, z), velocity through the water [n, 3],
        and the turbulence offset [n, 3] (see :meth:`WakeField.velocity`); each broadcasts."""
        if self.wake is None:
            raise ValueError("set_wake_source: this Simulator has no wake (pass wake=)")
        ids = self._env_ids("set_wake_source", env_ids)
        n = ids.size
        p, q, v, o = (
            CK.array("set_wake_source", name, value, (n, width))
            for name, value, width in (
                ("pos", pos, 3),
                ("quat", quat, 4),
                ("lin_vel", lin_vel, 3),
                ("noise_offset", noise_offset, 3),
            )
        )
        norm = np.linalg.norm(q, axis=1, keepdims=True)
        if np.any(norm < 1e-12):
            raise ValueError(f"set_wake_source: quat must be non-zero, got {CK.show(quat)}")
        rot = K.quat_matrices(q / norm).reshape(n, 9)
        self._data.src[:, ids] = np.concatenate([p, rot, v, o], axis=1).T

    def wake_source_rows(self) -> np.ndarray:
        """The wake source array [NSRC, E] the kernel reads, without a copy, for env kernels
        that move the source every step: rows in the layout of ``wake.source_row``
        (position, row-major rotation body -> world, velocity, noise offset); the kernel
        advances the position rows during a step. Prefer :meth:`set_wake_source` elsewhere."""
        if self.wake is None:
            raise ValueError("wake_source_rows: this Simulator has no wake (pass wake=)")
        return self._data.src

    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The arrays env kernels read the state from, without copies: ``(state [13, B, E]``
        (rows ``state.STATE_FIELDS``), ``flow [6, E]`` (air then water velocity),
        ``body [E, B, NBODY]`` (each environment's mass, inertia and center-of-mass shift,
        ``state.BODY_FIELDS``;
        ``rotation.env_inv_inertia(body, e, b)``)). Treat them as read-only."""
        return self._data.st, self._data.flow, self._model.body

    def start_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The arrays a scene's compiled episode start writes, without copies: ``(state
        [13, B, E], flow [6, E], diverged [E], warm [E or 0, P, NWARM])``: what :meth:`reset`,
        :meth:`set_wind` and :meth:`set_current` write. A start writes a normalized
        quaternion, clears ``diverged`` and zeroes the environment's contact warm starts
        (``warm``, empty without contact), as :meth:`reset` does."""
        d = self._data
        return d.st, d.flow, d.diverged, d.warm

    def wrench(self, controls=None) -> tuple[np.ndarray, np.ndarray]:
        """Net force (N) and torque about the center of mass (N m) on each body from its
        fluid samples, buoyancy and thrusters (not gravity) at the current state, world frame,
        each ``[E, B, 3]``. ``controls`` as in :meth:`step` (None: all channels at 0)."""
        with self._evaluating_at(controls):
            K.wrench(self._model, self._samples, self._data, self._wrench)
        out = self._wrench.transpose(2, 1, 0)
        return out[..., :3].copy(), out[..., 3:].copy()

    def sample_forces(
        self, controls=None, env_index: int = 0
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each sample's world application point and force in environment ``env_index`` at
        the current state: the terms that :meth:`wrench` sums (from the same kernel code).

        Samples are the plates, cylinders, buoyancy samples and thrusters of every body;
        the force held by :meth:`set_external_force` acts at the center of mass and is not
        one. So a body's net force is ``forces[body == b].sum(0)`` (plus the external
        force) and its torque ``sum((points - pos) x forces)`` (plus the external torque).

        Args:
            controls: ``[E, n_controls]`` as in :meth:`step`, or ``[n_controls]``: this
                environment's channels; None: every channel at 0.
            env_index: the environment.

        Returns:
            ``(points [N, 3] (m), forces [N, 3] (N), body [N])``, world frame, float64; N
            the samples of all bodies, body by body (within one: plates without a control,
            control surfaces, cylinders, buoyancy, thrusters); ``body`` each one's body slot.
        """
        e = CK.number("sample_forces", "env_index", env_index, ge=0, lt=self.num_envs, integer=True)
        c = None if controls is None else CK.real_array("sample_forces", "controls", controls)
        if c is not None and c.ndim == 1:
            full = np.zeros((self.num_envs, len(self.control_names)))
            if c.shape != full.shape[1:]:
                raise ValueError(
                    f"sample_forces: controls must have shape {full.shape[1:]} (channels "
                    f"{self.control_names}) or {full.shape}, got {c.shape}"
                )
            full[e] = c
            controls = full
        counts = [c.num_samples for c in self.crafts]
        out = np.zeros((sum(counts), 6))
        with self._evaluating_at(controls):
            K.sample_forces(self._model, self._samples, self._data, int(e), out)
        return out[:, :3], out[:, 3:], np.repeat(np.arange(self.num_bodies), counts)

    def sample_flows(self, samples: Sequence[str], body: int = 0, env_ids=None) -> np.ndarray:
        """What the named samples of body slot ``body`` meet in every environment at the
        current state, from the same kernel code as the forces (``kernels._record``): an
        array of air-data probes, pressure taps and flow sensors wherever the craft has a
        sample. The controls are where they are (with actuators: their current positions).

        Args:
            samples: sample names of the body's craft (``Craft.plates``, ``cylinders``,
                ``buoyancy``; not ``thrusters``: a point force meets no flow), P of them,
                each at most once.
            body: the body slot.
            env_ids: the environments to read (None: all; only their blocks of environments
                are evaluated).

        Returns:
            ``[n, P, len(SENSE_FIELDS)]`` float64 for the n environments ``env_ids``,
            fields :data:`SENSE_FIELDS`: the inflow (the fluid's velocity relative to the
            sample, body frame, m/s; 0 at a buoyancy sample, at rest in the water it
            displaces), its component along the sample's normal (a plate's; a cylinder's
            axis), the density there (kg/m^3: the air's, the water's or their blend across
            the surface), the sample's height above the surface under it (m) and the pressure
            (a plate's or a buoyancy sample's force against its normal per area, Pa: onto a
            hull whose normals point out; 0 where it has no area). Each call evaluates the
            chosen bodies' forces once (a step's cost over its force evaluations); the state
            is untouched. In float64 the array is a view of a buffer that the next call
            with the same samples rewrites: copy it to keep it.
        """
        what = "sample_flows"
        ids, bd = self._env_ids(what, env_ids), self._body(what, body)
        listed = isinstance(samples, Sequence) and not isinstance(samples, str)
        key = (tuple(samples), int(body)) if listed else None
        probe = self._probes.get(key)
        if probe is None:
            probe = self._probe(what, samples, bd, int(body))  # checked: raises if not listed
            self._probes[key] = probe
        slot, bodies, out = probe
        kernel = K.sample_flows_parallel if self.parallel else K.sample_flows_serial
        every = env_ids is None
        blocks = self._all_blocks if every else np.unique(ids // BLOCK)
        kernel(self._model, self._samples, self._data, slot, bodies, blocks, out)
        sensed = out[:, K.R_FORCE :, :] if every else out[:, K.R_FORCE :, ids]
        # in float64 a view of the buffer the next call rewrites (copy to keep it)
        return sensed.transpose(2, 0, 1).astype(np.float64, copy=False)

    def _probe(self, what: str, samples, bd: _Body, body: int):
        """``sample_flows``' slot map, bodies and output rows for these samples (checked)."""
        if isinstance(samples, str) or not isinstance(samples, Sequence) or not samples:
            raise ValueError(f"{what}: samples must be a non-empty list of sample names, got "
                             f"{CK.show(samples)}")  # fmt: skip
        where = {n: (k, i) for k, names in bd.names.items() for i, n in enumerate(names)}
        unknown = [n for n in samples if n not in where]
        if unknown:
            raise ValueError(f"{what}: unknown samples {unknown} of craft {bd.craft.name!r}; "
                             f"its samples are {sorted(where)}")  # fmt: skip
        if len(set(samples)) != len(samples):
            raise ValueError(f"{what}: samples named twice in {list(samples)}")
        thrusters = [n for n in samples if where[n][0] == "thr"]
        if thrusters:
            raise ValueError(f"{what}: {thrusters} are thrusters: a point force meets no flow")
        slot = np.full(self._samples.factor_row.shape[1], -1, dtype=np.int64)
        slot[bd.numbers([where[n] for n in samples])] = np.arange(len(samples))
        out = np.zeros((len(samples), K.R_SENSE, self.num_envs), dtype=self._data.scr.dtype)
        return slot, np.array([body], dtype=np.int64), out

    def _env_ids(self, what: str, env_ids) -> np.ndarray:
        """``env_ids`` as int64 indices (:func:`checks.env_ids`: None, indices or a boolean
        mask of length E); the one check of every method here and of the scenes' vector
        envs, whose sub-envs are these environments."""
        return CK.env_ids(what, env_ids, self.num_envs)

    # ---- snapshots ------------------------------------------------------------------------

    def _env_arrays(self) -> dict[str, tuple[np.ndarray, int]]:
        """Every array that holds something of one environment, and its environment axis:
        what a snapshot copies. ``scr`` is scratch (rewritten before it is read), and the
        samples' factors are in the :class:`FactorTable` (:meth:`get_state`)."""
        d, m = self._data, self._model
        arrays = {
            "st": (d.st, 2),
            "flow": (d.flow, 1),
            "src": (d.src, 1),
            "clock": (d.clock, 0),
            "ctrl": (d.ctrl, 1),
            "command": (d.command, 1),
            "flap_now": (d.flap_now, 2),
            "external": (d.external, 0),
            "warm": (d.warm, 0),
            "touch": (d.touch, 0),
            "diverged": (d.diverged, 0),
            "memory": (d.memory, 2),
            "body": (m.body, 0),
            "shape": (m.shape, 0),
            "contact_body": (m.contact_body, 0),
        }
        for b, bd in enumerate(self._bodies):
            arrays.update(
                {
                    f"mass_kg.{b}": (bd.mass_kg, 0),
                    f"inertia.{b}": (bd.inertia, 0),
                    f"com_m.{b}": (bd.com_m, 0),
                }  # fmt: skip
            )
        if not d.warm.shape[0]:  # no body pairs: no warm starts to keep
            del arrays["warm"], arrays["touch"]
        if not d.memory.shape[0]:  # an integrator that carries nothing between steps
            del arrays["memory"]
        return arrays

    def get_state(self, env_ids=None) -> dict[str, np.ndarray]:
        """A copy of everything that decides the future of environments ``env_ids`` (None:
        all): the state, clocks, flows, wake sources, held forces, contact warm starts and
        each environment's craft (mass properties, sample factors). Arrays with the
        environment first, ``[n, ...]``; :meth:`set_state` puts them back, into these or other
        environments of a Simulator of the same crafts and layout."""
        ids = self._env_ids("get_state", env_ids)
        state = {
            name: np.moveaxis(arr, axis, 0)[ids].copy()
            for name, (arr, axis) in self._env_arrays().items()
        }
        state["factors"] = self._factors.values(ids)
        return state

    def set_state(self, state: dict[str, np.ndarray], env_ids=None) -> None:
        """Restore environments ``env_ids`` (None: all) from ``state`` (:meth:`get_state`'s,
        one row per environment): they then step bit for bit as the ones it was taken from."""
        ids = self._env_ids("set_state", env_ids)
        if np.unique(ids).size != ids.size:
            raise ValueError(f"set_state: env_ids repeat an environment: {env_ids!r}")
        arrays = self._env_arrays()
        expected = {*arrays, "factors"}
        if not isinstance(state, dict) or set(state) != expected:
            got = sorted(state) if isinstance(state, dict) else type(state).__name__
            raise ValueError(
                f"set_state: not a snapshot of this Simulator's layout: expected the arrays "
                f"{sorted(expected)}, got {got}"
            )
        arrays["factors"] = (self._factors.values(ids), 0)  # only its shape is checked here
        for name, (arr, axis) in arrays.items():
            want = (ids.size, *np.delete(arr.shape, axis))
            got = np.asarray(state[name])
            if got.shape != want or got.dtype != arr.dtype:
                raise ValueError(
                    f"set_state: snapshot array {name!r} is {got.dtype}{list(got.shape)}, "
                    f"expected {arr.dtype}{list(want)} ({ids.size} environments of this "
                    "Simulator's layout)"
                )
        for name, (arr, axis) in arrays.items():
            if name != "factors":
                np.moveaxis(arr, axis, 0)[ids] = state[name]
        self._factors.restore(np.asarray(state["factors"]), ids)
        if self._factors.factor is not self._samples.factor:  # the table grew
            self._samples = self._samples._replace(factor=self._factors.factor)

    # ---- each environment's craft ----------------------------------------------------------

    @property
    def mass_kg(self) -> np.ndarray:
        """``[E, B]`` each environment's body masses (kg); see :meth:`set_mass_properties`."""
        return np.stack([bd.mass_kg for bd in self._bodies], axis=1)

    @property
    def inertia_kgm2(self) -> np.ndarray:
        """``[E, B, 3, 3]`` each environment's body inertia tensors about the center of mass."""
        return np.stack([bd.inertia for bd in self._bodies], axis=1)

    @property
    def center_of_mass_m(self) -> np.ndarray:
        """``[E, B, 3]`` each environment's center-of-mass shift from the craft's (body frame)."""
        return np.stack([bd.com_m for bd in self._bodies], axis=1)

    def set_mass_properties(
        self, mass_kg=None, inertia_kgm2=None, center_of_mass_m=None, env_ids=None, body=0
    ) -> None:
        """Give environments their own mass, inertia and center of mass for body slot ``body``
        (until changed; a reset keeps them). None leaves a property as it is.

        Args:
            mass_kg: > 0, broadcasts to ``[n]`` (n: the environments in ``env_ids``).
            inertia_kgm2: body-frame inertia about the center of mass: principal moments
                (a shape ending in 3) or tensors (ending in (3, 3)), broadcast to ``[n, 3]``
                or ``[n, 3, 3]``; each symmetric, positive definite, with I1 + I2 >= I3.
            center_of_mass_m: the center of mass's shift from the craft's, body frame,
                broadcast to ``[n, 3]``: every sample and collision shape keeps its place on
                the airframe, as :meth:`Craft.with_center_of_mass` gives (bit for bit in
                float64; in float32 the kernel subtracts the rounded shift, a last-bit
                difference).
            env_ids: the environments (None: all).
            body: the body slot.

        The body's state (position, velocity, angular momentum) is kept: call :meth:`reset`
        for a start that matches the new inertia.
        """
        what = "set_mass_properties"
        ids, bd = self._env_ids(what, env_ids), self._body(what, body)
        n = ids.size
        if mass_kg is not None:
            m = CK.array(what, "mass_kg", mass_kg, (n,))
            if np.any(m <= 0.0):
                raise ValueError(f"{what}: mass_kg must be positive, got {CK.show(mass_kg)}")
        if inertia_kgm2 is not None:
            arr = CK.array(what, "inertia_kgm2", inertia_kgm2, None)
            tensor = arr.ndim >= 2 and arr.shape[-2:] == (3, 3)
            if arr.shape == (3, 3) and n == 3:
                raise ValueError(
                    f"{what}: inertia_kgm2 of shape [3, 3] is ambiguous with 3 environments "
                    "(one tensor, or principal moments per environment?): pass [1, 3, 3] for "
                    "one tensor, [3, 3, 3] for a tensor each, or [3] for one set of moments"
                )
            if tensor:
                inertia = CK.array(what, "inertia_kgm2", arr, (n, 3, 3))
            else:
                inertia = CK.array(what, "inertia_kgm2", arr, (n, 3))[:, :, None] * np.eye(3)
            try:
                check_inertia(what, inertia, inertia_kgm2)
            except CraftError as err:
                raise ValueError(str(err)) from None
        if center_of_mass_m is not None:
            com = CK.array(what, "center_of_mass_m", center_of_mass_m, (n, 3))
        if mass_kg is not None:
            bd.mass_kg[ids] = m
        if inertia_kgm2 is not None:
            bd.inertia[ids] = inertia
        if center_of_mass_m is not None:
            bd.com_m[ids] = com
        self._write(body, ids)

    def set_sample_scale(self, group, area=None, efficiency=None, env_ids=None, body=0) -> None:
        """Scale the samples of ``group`` in environments ``env_ids`` of body slot ``body``,
        from the craft's values (until changed; a reset keeps them).

        Args:
            group: a sample's name, a group of the craft file (``Craft.groups``), or one of
                ``"all"``, ``"plates"``, ``"control_surfaces"``, ``"cylinders"``,
                ``"buoyancy"``.
            area: > 0, broadcasts to ``[n]``: the factor on each sample's size (plates' and
                cylinders' ``area_m2``, buoyancy's ``volume_m3`` or ``area_m2``); thrusters
                have none (:meth:`set_thrust_scale`).
            efficiency: >= 0, broadcasts to ``[n]``: the factor on each plate's
                ``efficiency``, which must stay within [0, 1].
            env_ids: as in :meth:`set_mass_properties`.
            body: as in :meth:`set_mass_properties`.
        """
        what = "set_sample_scale"
        ids, bd = self._env_ids(what, env_ids), self._body(what, body)
        if not isinstance(group, str) or group not in bd.groups:
            raise ValueError(
                f"{what}: unknown group {group!r} for craft {bd.craft.name!r}; groups are "
                f"{BUILTIN_GROUPS + tuple(g for g, _ in bd.craft.groups)} and its samples"
            )
        members = [(k, i) for k, i in bd.groups[group] if M.KIND[k].area]
        if area is not None:
            a = CK.array(what, "area", area, (ids.size,))
            if np.any(a <= 0.0):
                raise ValueError(f"{what}: area must be a positive factor, got {CK.show(area)}")
            if not members:
                raise ValueError(f"{what}: group {group!r} has no sample with an area")
        plates = [(k, i) for k, i in members if M.KIND[k].efficiency]
        if efficiency is not None:
            f = CK.array(what, "efficiency", efficiency, (ids.size,))
            if not plates:
                raise ValueError(f"{what}: group {group!r} has no plate (efficiency is a plate's)")
            top = max(bd.rows[k][i, M.S_EFFICIENCY] for k, i in plates)
            if np.any(f < 0.0) or np.any(f * top > 1.0):
                raise ValueError(
                    f"{what}: efficiency {CK.show(efficiency)} takes a plate of group {group!r} "
                    f"(efficiency up to {top}) outside [0, 1]"
                )
        if area is not None:
            self._set_factor(M.F_AREA, bd.numbers(members), ids, a)
        if efficiency is not None:
            self._set_factor(M.F_EFFICIENCY, bd.numbers(plates), ids, f)

    def randomizer(self, groups, body: int = 0) -> Randomizer:
        """A :class:`Randomizer` of body slot ``body``: the mass properties and ``groups``'
        sample scales of an episode's drawn craft, written without this class's per-call
        checks (a scene's reset; ``physics/randomizer.py``)."""
        return Randomizer(self, groups, body)

    def set_thrust_scale(self, scale, env_ids=None, body=0) -> None:
        """Scale every thruster of body slot ``body`` (its thrust at every control value) in
        environments ``env_ids``; ``scale`` >= 0 broadcasts to ``[n]``; until changed."""
        what = "set_thrust_scale"
        ids, bd = self._env_ids(what, env_ids), self._body(what, body)
        s = CK.array(what, "scale", scale, (ids.size,))
        if np.any(s < 0.0):
            raise ValueError(f"{what}: scale must be >= 0, got {CK.show(scale)}")
        if not bd.names["thr"]:
            raise ValueError(f"{what}: craft {bd.craft.name!r} has no thruster")
        self._set_factor(M.F_THRUST, bd.index["thr"], ids, s)

    def _set_factor(self, which: int, samples: np.ndarray, ids: np.ndarray, values) -> None:
        self._factors.set(which, samples, ids, values)
        if self._factors.factor is not self._samples.factor:  # the table grew
            self._samples = self._samples._replace(factor=self._factors.factor)

    def _body(self, what: str, body) -> _Body:
        if isinstance(body, bool) or not isinstance(body, (int, np.integer)):
            raise ValueError(
                f"{what}: body must be a body slot index in [0, {self.num_bodies}), got "
                f"{CK.show(body)}"
            )
        if not 0 <= body < self.num_bodies:
            raise ValueError(f"{what}: body {body} is not in [0, {self.num_bodies})")
        return self._bodies[int(body)]

    def _write(self, b: int, ids: np.ndarray) -> None:
        """Pack body slot b's mass properties of environments ``ids`` into the kernels' model
        (the body rows, the collision shapes): the same numbers the craft itself packs where a
        property is at the craft's value."""
        bd, model, dtype = self._bodies[b], self._model, self.dtype
        com = bd.com_m[ids]
        limits = np.tile(bd.craft.runaway, (ids.size, 1))
        model.body[ids, b] = M.body_rows(bd.mass_kg[ids], bd.inertia[ids], com, limits).astype(
            dtype
        )
        com = com[:, None, :]  # [n, 1, 3]
        if bd.craft.shapes:
            table = np.repeat(bd.shapes[None], ids.size, axis=0)
            center = slice(CT.SH_CENTER, CT.SH_CENTER + 3)
            table[..., center] = shift_offsets(table[..., center], com)
            table[..., CT.SH_REACH] = shape_reach(table[..., center], bd.extents)
            s0, s1 = model.shape_at[b], model.shape_at[b + 1]
            model.shape[ids, :, s0:s1] = table.transpose(0, 2, 1).astype(dtype)
            model.contact_body[ids, b, CT.CB_REACH] = table[..., CT.SH_REACH].max(axis=1)

    # ---- reset and step -------------------------------------------------------------------

    def _broadcast(self, name: str, value, width: int, n: int, what="reset") -> np.ndarray:
        """``value`` as ``[n, B, width]``. With one body a 2-D ``[n, width]`` is one row per
        environment; with several, a 2-D ``[B, width]`` is one row per body, and refused
        where its rows could as well be environments (B == n, or B == E: rows for every
        environment passed with ``env_ids``), as the 3-D shapes say which."""
        arr = CK.array(what, name, value, None)
        B, E = self.num_bodies, self.num_envs
        if arr.ndim == 2 and arr.shape[-1] == width:
            if B == 1:
                arr = arr[:, None, :]
            elif arr.shape[0] == B and B in (n, E):
                alike = f", [1, {B}, {width}] (alike in every environment)" if n > 1 else ""
                raise ValueError(
                    f"{what}: {name} of shape {list(arr.shape)} is ambiguous with "
                    f"{n if n == B else E} environments of {B} bodies (a row per environment "
                    f"or per body?): pass [{n}, {B}, {width}] (a row per body in each "
                    f"environment){alike} or [{width}] (one row for all)"
                )
        try:
            return np.broadcast_to(arr, (n, B, width))
        except ValueError:  # say which shapes would do
            per_env = f", [{n}, {width}] (a row per environment)" if B == 1 else ""
            raise ValueError(
                f"{what}: {name} of shape {np.shape(value)} does not broadcast to "
                f"[{n}, {B}, {width}], got {CK.show(value)}; pass [{n}, {B}, {width}], "
                f"[{B}, {width}] (a row per body){per_env} or [{width}]"
            ) from None

    def reset(
        self,
        pos=(0.0, 0.0, 0.0),
        quat=(1.0, 0.0, 0.0, 0.0),
        lin_vel=(0.0, 0.0, 0.0),
        ang_vel=(0.0, 0.0, 0.0),
        env_ids=None,
    ) -> None:
        """Set the state of all environments, or of ``env_ids`` only.

        Each argument broadcasts to ``[n, B, 3]`` (``[n, B, 4]`` for quat), n the number of
        environments being reset; for a one-body craft ``[n, 3]`` (``[n, 4]``) gives each
        environment its own. Quaternions are normalized; ``ang_vel`` is in the world frame.
        """
        ids = self._env_ids("reset", env_ids)
        n = ids.size
        p = self._broadcast("pos", pos, 3, n)
        q = self._broadcast("quat", quat, 4, n)
        v = self._broadcast("lin_vel", lin_vel, 3, n)
        w = self._broadcast("ang_vel", ang_vel, 3, n)
        norm = np.linalg.norm(q, axis=-1, keepdims=True)
        if np.any(norm < 1e-12):
            raise ValueError(f"reset: quat must be non-zero (a rotation), got {CK.show(quat)}")
        q = q / norm
        # L = R I R^T w, per body slot
        rot = K.quat_matrices(q.reshape(-1, 4)).reshape(n, self.num_bodies, 3, 3)
        inertia = np.stack([bd.inertia[ids] for bd in self._bodies], axis=1)  # [n, B, 3, 3]
        iw = rot @ inertia @ np.swapaxes(rot, -1, -2)
        L = np.einsum("nbij,nbj->nbi", iw, w)
        st = self._data.st
        for rows, val in (
            (slice(OX, OX + 3), p),
            (slice(OQ, OQ + 4), q),
            (slice(OV, OV + 3), v),
            (slice(OL, OL + 3), L),
        ):
            st[rows, :, ids] = val.transpose(2, 1, 0)
        self._data.diverged[ids] = False
        if self._data.warm.shape[0]:  # contact warm starts belong to the old state
            self._data.warm[ids] = 0.0
        self.center_actuators(ids)

    def step(self, controls=None, steps: int = 1) -> None:
        """Advance every environment by ``steps`` time steps, holding ``controls``; each
        environment's :attr:`clock` advances by ``dt`` per step.

        Args:
            controls: ``[E, n_controls]`` in [-1, 1], the channels in ``control_names`` order;
                None holds every channel at 0.
            steps: number of time steps of ``dt`` in this call (>= 1).
        """
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise ValueError(f"step: steps must be a positive integer, got {CK.show(steps)}")
        self._set_controls(controls)
        args = (self._model, self._samples, self._data, self._method, int(steps), self._contact,
                self._pairs)  # fmt: skip
        if self._entry is None:  # the first call compiles (or loads) the kernel for its types
            literal = () if self.shared_kernel else (_METHOD_ARG,)
            self._entry = _entry_point(self._kernel, args, literal)
        self._entry(*args)

    @contextlib.contextmanager
    def _evaluating_at(self, controls):
        """Forces evaluated at ``controls`` (as :meth:`step`'s): without actuators they are
        the controls from then on, as before; with actuators the channels are put there for
        the evaluation only (None: where they are) and the actuators' state is kept."""
        if not self.actuated:
            self._set_controls(controls)
            yield
            return
        held, told = self._data.ctrl.copy(), self._data.command.copy()
        if controls is not None:
            self._set_controls(controls)  # checked, into the commands
            self._data.ctrl[...] = self._data.command
        try:
            yield
        finally:
            self._data.ctrl[...] = held
            self._data.command[...] = told

    def _set_controls(self, controls) -> None:
        # with actuators the controls are commands that the channels follow (set_actuators)
        target = self._data.command if self.actuated else self._data.ctrl
        if controls is None:
            target[...] = 0.0
        else:
            a = CK.real_array("step", "controls", controls)
            shape = (self.num_envs, len(self.control_names))
            if a.shape != shape:
                raise ValueError(
                    f"controls must have shape {shape} (envs, channels "
                    f"{self.control_names}), got {a.shape}: {CK.show(controls)}"
                )
            if not (np.abs(a) <= 1.0).all():  # one pass; NaN fails it too
                if not np.isfinite(a).all():
                    bad = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
                    raise ValueError(
                        f"controls must be finite (no NaN or inf), got {a[bad]} at {bad}"
                    )
                raise ValueError(
                    f"controls must lie in [-1, 1], got values up to {np.abs(a).max():.6g}"
                )
            target[...] = a.T
