"""Simulator: E environments of B rigid bodies each, advanced by one compiled call per step."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from . import contact as CT
from . import kernels as K
from . import wake as WK
from .craft import Craft
from .world import World

_BATCH_PARALLEL_MIN = 1024  # below this many bodies the serial kernel wins (thread start-up)


def _pack(
    crafts: Sequence[Craft], world: World, dt: float, num_envs: int, dtype, integrator: str
) -> tuple[tuple, np.ndarray, list[str]]:
    """Flatten the crafts' samples into the kernel's tables (field-major, slot ranges)."""
    names: list[str] = []
    offsets = []
    for c in crafts:
        offsets.append(len(names))
        names.extend(
            c.control_names if len(crafts) == 1 else (f"{c.name}.{n}" for n in c.control_names)
        )
    n_ch = len(names)

    body = np.zeros((len(crafts), K.NBODY))
    fpl, cpl, cyl, buo, thr, thr_ch, mix = [], [], [], [], [], [], []
    at = {k: [0] for k in ("fpl", "cpl", "cyl", "buo", "thr")}
    for b, c in enumerate(crafts):
        inv = np.linalg.inv(c.inertia_tensor)
        sec = 0.5 * np.trace(c.inertia_tensor) * np.eye(3) - c.inertia_tensor  # tetra.py
        body[b] = (
            c.mass_kg,
            *(inv[0, 0], inv[1, 1], inv[2, 2], inv[0, 1], inv[0, 2], inv[1, 2]),
            *(sec[0, 0], sec[1, 1], sec[2, 2], sec[0, 1], sec[0, 2], sec[1, 2]),
        )
        drive: dict[str, np.ndarray] = {}
        for j, ctl in enumerate(c.controls):
            for s in ctl.surfaces:
                row = drive.setdefault(s.sample, np.zeros(n_ch))
                row[offsets[b] + j] += s.gain * math.radians(ctl.max_deflection_deg)
        for p in c.plates:
            if p.name in drive:
                cpl.append((*p.offset_m, *p.normal, *p.hinge_axis, p.area_m2, p.efficiency))
                mix.append(drive[p.name])
            else:
                fpl.append((*p.offset_m, *p.normal, p.area_m2, p.efficiency))
        cyl.extend((*s.offset_m, *s.axis, s.area_m2) for s in c.cylinders)
        buo.extend((*s.offset_m, s.volume_m3 or 0.0, s.area_m2 or 0.0) for s in c.buoyancy)
        channels = c.control_names
        for t in c.thrusters:
            thr.append((*t.offset_m, *t.direction, t.min_thrust_n, t.max_thrust_n))
            thr_ch.append(-1 if t.control is None else offsets[b] + channels.index(t.control))
        for key, table in (("fpl", fpl), ("cpl", cpl), ("cyl", cyl), ("buo", buo), ("thr", thr)):
            at[key].append(len(table))

    def table(rows, width):
        return np.ascontiguousarray(np.asarray(rows, dtype=dtype).reshape(-1, width).T)

    def ranges(key):
        return np.asarray(at[key], dtype=np.int64)

    tables = (
        body.astype(dtype),
        table(fpl, 8),
        ranges("fpl"),
        table(cpl, 11),
        ranges("cpl"),
        table(cyl, 7),
        ranges("cyl"),
        table(buo, 5),
        ranges("buo"),
        table(thr, 8),
        np.asarray(thr_ch, dtype=np.int64),
        ranges("thr"),
        *CT.pack(  # tables[12:19]: contact.py
            crafts,
            world.ground,
            dt,
            world.gravity_mps2,
            world.contact_passes,
            num_envs,
            dtype,
            K.DRIFT_SHARE[integrator],
        ),
        # tables[19]: the external force and torque on each body [E, B, 6], world frame
        np.zeros((num_envs, len(crafts), 6), dtype=dtype),
    )
    cmix = np.asarray(mix, dtype=dtype).reshape(len(mix), n_ch)
    return tables, cmix, names


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
              inertia (``tetra.match_inertia``): velocities and positions as symplectic
              Euler, the turn as the particles' drift with the shape restored by the
              best-fitting rotation and the momenta kept. Above ``World.tetra_rigid_spin_rad``
              per step a body turns rigidly instead.

            Every method keeps world angular momentum exact under zero torque (it is the
            state) and renormalizes the quaternion each step. Contact (crafts with
            ``shapes``, against ``World.ground`` and each other: ``contact.py``) runs after
            each step's integration, whichever the method.
        dtype: ``np.float64`` (default) or ``np.float32``.
        parallel: run blocks of environments on numba's threads; default: when E * B >= 1024.
        wake: a :class:`WakeField` whose flow every fluid sample in the water feels (its
            velocity is added to the water's); each environment's source (the submarine's
            pose and velocity) is set with :meth:`set_wake_source` and moves on at its
            velocity (orientation held) while the bodies step. None (default): no wake, and
            no cost.

    State (world frame, arrays ``[E, B, ...]``, read-only views): ``pos``, ``quat`` (w, x, y,
    z), ``lin_vel``, ``ang_vel``, and ``diverged`` ``[E]`` (a non-finite state).

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
    ) -> None:
        crafts = [crafts] if isinstance(crafts, Craft) else list(crafts)
        if not crafts or not all(isinstance(c, Craft) for c in crafts):
            raise TypeError(f"crafts must be a Craft or a non-empty list of Crafts, got {crafts!r}")
        world = World() if world is None else world
        if not isinstance(world, World):
            raise TypeError(f"world must be a World, got {world!r}")
        if (
            isinstance(num_envs, bool)
            or not isinstance(num_envs, (int, np.integer))
            or num_envs < 1
        ):
            raise ValueError(f"num_envs must be a positive integer, got {num_envs!r}")
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
        if integrator not in K.INTEGRATORS:
            raise ValueError(
                f"unknown integrator {integrator!r}; choose one of {sorted(K.INTEGRATORS)}"
            )
        dtype = np.dtype(dtype)
        if dtype not in (np.float32, np.float64):
            raise ValueError(f"dtype must be float32 or float64, got {dtype}")
        if wake is not None and not isinstance(wake, WK.WakeField):
            raise TypeError(f"wake must be a WakeField or None, got {wake!r}")

        self.crafts = tuple(crafts)
        self.world = world
        self.num_envs = E = int(num_envs)
        self.num_bodies = B = len(crafts)
        self.dt = float(dt)
        self.integrator = integrator
        self.dtype = dtype
        self.wake = wake
        self.parallel = E * B >= _BATCH_PARALLEL_MIN if parallel is None else bool(parallel)
        self._method = K.INTEGRATORS[integrator]
        self._kernel = K.step_parallel if self.parallel else K.step_serial

        self._tables, self._cmix, names = _pack(crafts, world, dt, E, dtype, integrator)
        self.control_names: tuple[str, ...] = tuple(names)
        self._mass = np.array([c.mass_kg for c in crafts])

        prm = np.zeros(K.NPRM)
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
        swell = world.swell_table()  # rows (a, kx, ky, omega, phase)
        prm[K.P_NWAVES] = len(swell)
        for j, (a, kx, ky, omega, _) in enumerate(swell):
            prm[K.P_SWELL + 4 * j : K.P_SWELL + 4 * j + 4] = (a, kx, ky, omega)
        self._prm = prm.astype(dtype)

        # buffers, allocated once
        n_blocks = -(-E // K.BLOCK)
        self._st = np.zeros((K.NSTATE, B, E), dtype=dtype)
        self._st[K.OQ] = 1.0
        self._ctrl = np.zeros((len(names), E), dtype=dtype)
        self._cnorm = np.zeros((3, self._cmix.shape[0], E), dtype=dtype)
        self._scr = np.zeros((n_blocks, B, K.ROWS * K.BLOCK), dtype=dtype)
        self._diverged = np.zeros(E, dtype=np.bool_)
        self._omega = np.zeros((3, B, E), dtype=dtype)
        self._flow = np.zeros((6, E), dtype=dtype)  # air velocity, water velocity per env
        self._flow[:3] = np.asarray(world.wind_mps)[:, None]
        self._flow[3:] = np.asarray(world.current_mps)[:, None]
        self._wrench = np.zeros((6, B, E), dtype=dtype)
        self._wprm = wake.params(dtype) if wake is not None else np.zeros(WK.NWPRM, dtype)
        self._src = np.zeros((WK.NSRC, E), dtype=dtype)  # the wake source of each env
        self._src[3:12:4] = 1.0  # identity rotation
        # the surface: swell table [n_waves, 5] (empty: calm water) and each env's clock, both
        # float64 whatever the dtype (wave phases omega t stay exact over long episodes)
        self._swell = np.ascontiguousarray(swell, dtype=np.float64)
        self._clock = np.zeros(E, dtype=np.float64)
        # the kernels' leading arguments: buffers updated in place, never rebound
        self._args = (
            self._st,
            self._flow,
            self._src,
            self._wprm,
            self._swell,
            self._clock,
            self._ctrl,
            self._tables,
            self._cmix,
            self._cnorm,
            self._prm,
        )

    # ---- state ----------------------------------------------------------------------------

    def _view(self, rows: slice) -> np.ndarray:
        v = self._st[rows].transpose(2, 1, 0)
        v.flags.writeable = False
        return v

    @property
    def pos(self) -> np.ndarray:
        """Center-of-mass positions [E, B, 3] (m)."""
        return self._view(slice(K.OX, K.OX + 3))

    @property
    def quat(self) -> np.ndarray:
        """Orientations [E, B, 4], unit quaternions (w, x, y, z), body -> world."""
        return self._view(slice(K.OQ, K.OQ + 4))

    @property
    def lin_vel(self) -> np.ndarray:
        """Center-of-mass velocities [E, B, 3] (m/s)."""
        return self._view(slice(K.OV, K.OV + 3))

    @property
    def ang_vel(self) -> np.ndarray:
        """Angular velocities [E, B, 3] (rad/s), world frame (derived from L)."""
        K.body_omega(self._st, self._tables[0], self._omega)
        v = self._omega.transpose(2, 1, 0)
        v.flags.writeable = False
        return v

    def angular_momentum(self) -> np.ndarray:
        """Angular momentum about each center of mass [E, B, 3] (kg m^2/s), world frame."""
        return self._view(slice(K.OL, K.OL + 3)).copy()

    def kinetic_energy(self) -> np.ndarray:
        """Kinetic energy of each body [E, B] (J): 1/2 m v^2 + 1/2 L . w."""
        v, w, L = self.lin_vel, self.ang_vel, self._view(slice(K.OL, K.OL + 3))
        return 0.5 * self._mass * np.einsum("ebk,ebk->eb", v, v) + 0.5 * np.einsum(
            "ebk,ebk->eb", L, w
        )

    @property
    def ground_impulse(self) -> np.ndarray:
        """``[E, B]`` (N s, read-only view): the normal impulse the ground gave each body over
        the last :meth:`step` call (0: it did not touch; all zeros without contact). A body
        can touch and bounce clear within one call: this is how a scene sees that it did."""
        if self._tables[18].shape[0] == 0:
            return np.zeros((self.num_envs, self.num_bodies), dtype=self.dtype)
        v = self._tables[18][:, : self.num_bodies]  # rows: contact.num_pairs
        v.flags.writeable = False
        return v

    @property
    def pair_impulse(self) -> np.ndarray:
        """``[E, P]`` (N s, read-only view): the normal impulse between each pair of bodies over
        the last :meth:`step` call, pairs in :attr:`pairs` order (all zeros without contact).
        The pairs of body 0 come first: ``pair_impulse[:, : B - 1]`` is body 0 against the
        others."""
        if self._tables[18].shape[0] == 0:
            return np.zeros((self.num_envs, len(self.pairs)), dtype=self.dtype)
        v = self._tables[18][:, self.num_bodies :]
        v.flags.writeable = False
        return v

    @property
    def pairs(self) -> np.ndarray:
        """``[P, 2]``: the bodies (a, b), a < b, of each column of :attr:`pair_impulse`."""
        return np.stack(np.triu_indices(self.num_bodies, 1), axis=1)  # contact.collide's order

    @property
    def diverged(self) -> np.ndarray:
        """[E] True where the last step left a non-finite state, or a body faster than
        ``World.max_fluid_speed_mps`` (beyond the fluid model: the clamps would keep such a
        runaway finite, not sane). That env needs a reset."""
        v = self._diverged.view()
        v.flags.writeable = False
        return v

    @property
    def wind_mps(self) -> np.ndarray:
        """Air velocity of each environment [E, 3] (m/s), world frame; see :meth:`set_wind`."""
        v = self._flow[:3].T
        v.flags.writeable = False
        return v

    @property
    def current_mps(self) -> np.ndarray:
        """Water velocity of each environment [E, 3] (m/s); see :meth:`set_current`."""
        v = self._flow[3:].T
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
        v = self._ctrl.T
        v.flags.writeable = False
        return v

    @property
    def external_force(self) -> tuple[np.ndarray, np.ndarray]:
        """``(force [E, B, 3] (N), torque [E, B, 3] (N m))``, read-only views: what
        :meth:`set_external_force` holds on each body."""
        ext = self._tables[19]
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
        self._tables[19][ids, :, :3] = f
        self._tables[19][ids, :, 3:] = t

    def _set_flow(self, name: str, rows: slice, value, env_ids) -> None:
        ids = self._env_ids(name, env_ids)
        arr = np.asarray(value, dtype=np.float64)
        try:
            arr = np.broadcast_to(arr, (ids.size, 3))
        except ValueError:
            raise ValueError(
                f"{name} of shape {arr.shape} does not broadcast to [{ids.size}, 3]"
            ) from None
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} has non-finite values: {value!r}")
        self._flow[rows, ids] = arr.T

    @property
    def clock(self) -> np.ndarray:
        """Each environment's time [E] (s), float64: advanced by ``dt`` per step (the
        simulation dtype's ``dt``); the swell moves with it. See :meth:`set_clock`."""
        v = self._clock.view()
        v.flags.writeable = False
        return v

    def set_clock(self, t, env_ids=None) -> None:
        """Set the clock (s) of every environment, or of ``env_ids`` only; ``t`` broadcasts to
        ``[n]``. The swell's surface at a point is a function of the clock, so a random clock
        offset randomizes the phase of every wave at once."""
        ids = self._env_ids("set_clock", env_ids)
        arr = np.asarray(t, dtype=np.float64)
        try:
            arr = np.broadcast_to(arr, (ids.size,))
        except ValueError:
            raise ValueError(
                f"set_clock: t of shape {arr.shape} does not broadcast to [{ids.size}]"
            ) from None
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"set_clock: t has non-finite values: {t!r}")
        self._clock[ids] = arr

    def surface_height(self, x, y) -> np.ndarray:
        """Height of the water surface (m) above z = 0 in every environment at its own clock:
        ``x``, ``y`` broadcast to ``[E, ...]`` (leading axis: environments); the result is
        float64 of that shape (zeros in calm water). See :meth:`World.surface_height`."""
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        ndim = max(x.ndim, y.ndim, 1)
        t = self._clock.reshape((self.num_envs,) + (1,) * (ndim - 1))
        return self.world.surface_height(x, y, t)

    def surface_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The arrays env kernels read the surface from, without copies: ``(swell [n, 5]``
        (float64 rows ``(a, kx, ky, omega, phase)``, empty in calm water; pass it to
        ``surface.surface_height(x, y, t, swell)``), ``clock [E]`` (float64, s)). Treat them
        as read-only."""
        return self._swell, self._clock

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
        parts = []
        for name, value, width in (
            ("pos", pos, 3),
            ("quat", quat, 4),
            ("lin_vel", lin_vel, 3),
            ("noise_offset", noise_offset, 3),
        ):
            arr = np.asarray(value, dtype=np.float64)
            try:
                arr = np.broadcast_to(arr, (n, width))
            except ValueError:
                raise ValueError(
                    f"set_wake_source: {name} of shape {arr.shape} does not broadcast to "
                    f"[{n}, {width}]"
                ) from None
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"set_wake_source: {name} has non-finite values: {value!r}")
            parts.append(arr)
        p, q, v, o = parts
        norm = np.linalg.norm(q, axis=1, keepdims=True)
        if np.any(norm < 1e-12):
            raise ValueError("set_wake_source: quat must be non-zero")
        rot = K.quat_matrices(q / norm).reshape(n, 9)
        self._src[:, ids] = np.concatenate([p, rot, v, o], axis=1).T

    def wake_source_rows(self) -> np.ndarray:
        """The wake source array [NSRC, E] the kernel reads, without a copy, for env kernels
        that move the source every step: rows in the layout of ``wake.source_row``
        (position, row-major rotation body -> world, velocity, noise offset); the kernel
        advances the position rows during a step. Prefer :meth:`set_wake_source` elsewhere."""
        if self.wake is None:
            raise ValueError("wake_source_rows: this Simulator has no wake (pass wake=)")
        return self._src

    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The arrays env kernels read the state from, without copies: ``(state [13, B, E]``
        (rows x, q, v, L as in ``kernels.py``), ``flow [6, E]`` (air then water velocity),
        ``body [B, 7]`` (mass, inverse inertia entries)). Treat them as read-only."""
        return self._st, self._flow, self._tables[0]

    def wrench(self, controls=None) -> tuple[np.ndarray, np.ndarray]:
        """Net force (N) and torque about the center of mass (N m) on each body from its
        fluid samples, buoyancy and thrusters (not gravity) at the current state, world frame,
        each ``[E, B, 3]``. ``controls`` as in :meth:`step` (None: all channels at 0)."""
        self._set_controls(controls)
        K.wrench(*self._args, self._scr, self._wrench)
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
        (e,) = self._env_ids("sample_forces", np.asarray([env_index]))
        if controls is not None and np.ndim(controls) == 1:
            full = np.zeros((self.num_envs, len(self.control_names)))
            c = np.asarray(controls, dtype=np.float64)
            if c.shape != full.shape[1:]:
                raise ValueError(
                    f"sample_forces: controls must have shape {full.shape[1:]} (channels "
                    f"{self.control_names}) or {full.shape}, got {c.shape}"
                )
            full[e] = c
            controls = full
        self._set_controls(controls)
        counts = [c.num_samples for c in self.crafts]
        out = np.zeros((sum(counts), 6))
        K.sample_forces(*self._args, self._scr, int(e), out)
        return out[:, :3], out[:, 3:], np.repeat(np.arange(self.num_bodies), counts)

    def _env_ids(self, what: str, env_ids) -> np.ndarray:
        ids = np.arange(self.num_envs) if env_ids is None else np.asarray(env_ids)
        if (
            ids.ndim != 1
            or ids.dtype.kind not in "iu"
            or (ids.size and (ids.min() < 0 or ids.max() >= self.num_envs))
        ):
            raise ValueError(
                f"{what}: env_ids must be integers in [0, {self.num_envs}), got {env_ids!r}"
            )
        return ids

    # ---- reset and step -------------------------------------------------------------------

    def _broadcast(self, name: str, value, width: int, n: int, what="reset") -> np.ndarray:
        arr = np.asarray(value, dtype=np.float64)
        try:
            arr = np.broadcast_to(arr, (n, self.num_bodies, width))
        except ValueError:
            raise ValueError(
                f"{what}: {name} of shape {arr.shape} does not broadcast to "
                f"[{n}, {self.num_bodies}, {width}]"
            ) from None
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{what}: {name} has non-finite values: {value!r}")
        return arr

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
        environments being reset. Quaternions are normalized; ``ang_vel`` is in the world frame.
        """
        ids = self._env_ids("reset", env_ids)
        n = ids.size
        p = self._broadcast("pos", pos, 3, n)
        q = self._broadcast("quat", quat, 4, n)
        v = self._broadcast("lin_vel", lin_vel, 3, n)
        w = self._broadcast("ang_vel", ang_vel, 3, n)
        norm = np.linalg.norm(q, axis=-1, keepdims=True)
        if np.any(norm < 1e-12):
            raise ValueError("reset: quat must be non-zero")
        q = q / norm
        # L = R I R^T w, per body slot
        rot = K.quat_matrices(q.reshape(-1, 4)).reshape(n, self.num_bodies, 3, 3)
        inertia = np.stack([c.inertia_tensor for c in self.crafts])  # [B, 3, 3]
        iw = rot @ inertia[None] @ np.swapaxes(rot, -1, -2)
        L = np.einsum("nbij,nbj->nbi", iw, w)
        st = self._st
        for rows, val in (
            (slice(K.OX, K.OX + 3), p),
            (slice(K.OQ, K.OQ + 4), q),
            (slice(K.OV, K.OV + 3), v),
            (slice(K.OL, K.OL + 3), L),
        ):
            st[rows, :, ids] = val.transpose(2, 1, 0)
        self._diverged[ids] = False
        if self._tables[17].shape[0]:  # contact warm starts belong to the old state
            self._tables[17][ids] = 0.0

    def step(self, controls=None, steps: int = 1) -> None:
        """Advance every environment by ``steps`` time steps, holding ``controls``; each
        environment's :attr:`clock` advances by ``dt`` per step.

        Args:
            controls: ``[E, n_controls]`` in [-1, 1], the channels in ``control_names`` order;
                None holds every channel at 0.
            steps: number of time steps of ``dt`` in this call (>= 1).
        """
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise ValueError(f"steps must be a positive integer, got {steps!r}")
        self._set_controls(controls)
        self._kernel(*self._args, self._method, int(steps), self._scr, self._diverged)

    def _set_controls(self, controls) -> None:
        if controls is None:
            self._ctrl[...] = 0.0
        else:
            a = np.asarray(controls)
            shape = (self.num_envs, len(self.control_names))
            if a.shape != shape:
                raise ValueError(
                    f"controls must have shape {shape} (envs, channels "
                    f"{self.control_names}), got {a.shape}"
                )
            if not (np.abs(a) <= 1.0).all():  # one pass; NaN fails it too
                if not np.isfinite(a).all():
                    raise ValueError("controls contain NaN or inf")
                raise ValueError(
                    f"controls must lie in [-1, 1], got values up to {np.abs(a).max():.6g}"
                )
            self._ctrl[...] = a.T
