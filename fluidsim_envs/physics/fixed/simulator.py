"""FixedSimulator: what ``Simulator(..., dtype="fixed32" | "fixed64")`` returns.

The same crafts and world as the float :class:`~fluidsim_envs.physics.Simulator`, stepped in
integer arithmetic (``laws.py``, ``kernel.py``): gravity, fixed plates and control surfaces,
cylinders, buoyancy and thrusters, under ``symplectic_euler`` and
``prescaled_symplectic_euler``. Contact, swell, the wake and central gravity are refused.
What it does not offer beside that: per-environment craft changes
(``set_mass_properties``, ``set_sample_scale``), external forces, per-environment wind and
current (the World's hold), snapshots, ``wrench`` and ``sample_forces``.

Controls enter once per ``step`` call: each value is rounded to ``laws.ANGLE_BITS`` fraction
bits (``fixed_controls``; exact IEEE operations), and from there all is integer: each
control surface's deflection and the cosine and sine of it (``laws.sincos``), its turned
normal and the thrusters' control values (``laws.body_inputs``, at the start of the call),
then the steps. Two machines given the same floats compute the same words.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .. import checks as CK
from .. import contact as CT
from .. import kernels as K
from ..craft import Craft
from ..world import World
from . import format as FM
from . import laws as LW
from .kernel import step_parallel, step_serial


class FixedSimulator:
    """Rigid bodies with fluid samples, stepped in fixed point.

    Args (as :class:`~fluidsim_envs.physics.Simulator`'s, and):
        dtype: ``"fixed32"`` or ``"fixed64"`` (``format.py``).
        integrator: ``"symplectic_euler"`` or ``"prescaled_symplectic_euler"`` (velocity
            stored as the displacement per step: the time unit is dt).
        fraction_bits: 1 to 30 (default 14, the source article's ``1 << 14 == 1.0``).
        units: None (derived from the first craft: ``format.derive_units``) or a dict
            overriding ``length_m``, ``mass_kg``, ``time_s``.
        wake, shared_kernel: a wake is refused; ``shared_kernel`` is accepted and unused.

    State: ``pos``, ``quat``, ``lin_vel``, ``ang_vel`` (float64 ``[E, B, ...]`` converted
    from the words), ``fixed_state`` (the words ``[E, B, 13]``: position, quaternion,
    velocity, angular momentum, in the units and the format), ``diverged`` ``[E]`` (a word
    saturated or a body past the speed clamp during the last call), ``clock`` ``[E]``
    (steps times dt).

    Examples:
        >>> from fluidsim_envs.physics import Craft, Simulator, World
        >>> ball = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4))
        >>> sim = Simulator(ball, World(), num_envs=2, dt=0.01, dtype="fixed64",
        ...                 fraction_bits=24)
        >>> sim.reset(lin_vel=(1.0, 0.0, 0.0))
        >>> sim.step(steps=100)
        >>> [round(float(x), 5) for x in sim.pos[0, 0]]  # float64: 1.0, 0.0, -4.95405
        [1.0, 0.0, -4.95405]
        >>> sim.units  # derived from the ball: its radius of gyration, mass, sqrt(L / g)
        Units(length_m=0.5, mass_kg=1.0, time_s=0.25)
    """

    def __init__(
        self,
        crafts: Craft | Sequence[Craft],
        world: World | None = None,
        num_envs: int = 1,
        dt: float = 1.0 / 120.0,
        integrator: str = "symplectic_euler",
        dtype: str = "fixed32",
        parallel: bool | None = None,
        wake=None,
        shared_kernel: bool | None = None,
        fraction_bits: int = 14,
        units=None,
    ) -> None:
        from ..simulator import PARALLEL_MIN_BODIES, _crafts

        crafts = _crafts(crafts)
        world = World() if world is None else world
        if not isinstance(world, World):
            raise TypeError(f"Simulator: world must be a World, got {CK.show(world)}")
        E = CK.number("Simulator", "num_envs", num_envs, ge=1, integer=True)
        dt = CK.number("Simulator", "dt", dt, gt=0.0)
        fmt = FM.fixed_format(dtype, fraction_bits)
        if integrator not in FM.INTEGRATORS:
            raise ValueError(
                f"Simulator: fixed point ({dtype}) steps with one of {FM.INTEGRATORS}, got "
                f"integrator={CK.show(integrator)}"
            )
        refused = []
        if wake is not None:
            refused.append("the wake (wake=)")
        if world.swell:
            refused.append("swell (World.swell)")
        if world.central_gravity_m3s2 != 0.0:
            refused.append("central gravity (World.central_gravity_m3s2)")
        cprm, _ = CT.params(crafts, world.ground, dt, world.gravity_mps2, world.contact_passes, 1.0)
        if cprm[CT.C_ON]:
            refused.append("contact (crafts with shapes against World.ground or each other)")
        if refused:
            raise ValueError(
                f"Simulator: fixed point ({dtype}) does not simulate {', '.join(refused)}; "
                "use dtype=np.float64 or np.float32 for them"
            )
        if parallel is not None:
            parallel = CK.flag("Simulator", "parallel", parallel)
        prescaled = integrator == "prescaled_symplectic_euler"

        self.crafts = tuple(crafts)
        self.world = world
        self.num_envs, self.num_bodies = int(E), len(crafts)
        self.dt = float(dt)
        self.integrator = integrator
        self.dtype = dtype
        self.format = fmt
        self.fraction_bits = fmt.fraction_bits
        self.wake = None
        derived = FM.derive_units(crafts[0], world, dt, prescaled)
        self.units = FM.coerce_units(units, derived, prescaled, dt)
        self.parallel = E * len(crafts) >= PARALLEL_MIN_BODIES if parallel is None else parallel
        self._kernel = step_parallel if self.parallel else step_serial
        self.control_names = tuple(
            crafts[0].control_names
            if len(crafts) == 1
            else (f"{c.name}.{n}" for c in crafts for n in c.control_names)
        )
        self._model = FM.pack(crafts, world, dt, fmt, self.units, prescaled)
        B = self.num_bodies
        self._st = np.zeros((E, B, LW.NSTATE), dtype=np.int64)
        self._st[:, :, LW.OQ] = 1 << fmt.fraction_bits
        self._inp = np.zeros((E, B, self._model.n_inp), dtype=np.int64)
        self._ctrl = np.zeros((E, len(self.control_names)))
        self._ctrl_words = np.zeros((E, len(self.control_names)), dtype=np.int64)
        self._count = np.zeros(E, dtype=np.int64)
        self._diverged = np.zeros(E, dtype=np.bool_)
        self._inv_inertia = np.stack([np.linalg.inv(c.inertia_tensor) for c in crafts])
        self._inertia = np.stack([c.inertia_tensor for c in crafts])

    # ---- conversions ----------------------------------------------------------------------

    def _scale(self, rows: slice) -> float:
        """The SI size of one word of the state rows ``rows``."""
        dims = {LW.OX: FM.LENGTH, LW.OQ: FM.NONE, LW.OV: FM.SPEED, LW.OL: FM.MOMENTUM}
        return self.units.scale(*dims[rows.start]) / 2.0**self.fraction_bits

    def _words(self, name: str, value: np.ndarray, rows: slice) -> np.ndarray:
        exact = np.asarray(value, dtype=np.float64) / self._scale(rows)
        big = np.abs(exact) > self.format.lim
        if np.any(big):
            worst = np.asarray(value).ravel()[np.argmax(np.abs(exact).ravel())]
            raise ValueError(
                f"reset: {self.format} with units {self.units} cannot hold {name} = {worst:.6g} "
                f"(the largest is {self.format.lim * self._scale(rows):.4g})"
            )
        return np.floor(exact + 0.5).astype(np.int64)

    def _floats(self, rows: slice) -> np.ndarray:
        out = self._st[:, :, rows] * self._scale(rows)
        out.flags.writeable = False
        return out

    # ---- state ----------------------------------------------------------------------------

    @property
    def pos(self) -> np.ndarray:
        """Center-of-mass positions [E, B, 3] (m), float64 from the words."""
        return self._floats(slice(LW.OX, LW.OX + 3))

    @property
    def quat(self) -> np.ndarray:
        """Orientations [E, B, 4] (w, x, y, z), float64 from the words."""
        return self._floats(slice(LW.OQ, LW.OQ + 4))

    @property
    def lin_vel(self) -> np.ndarray:
        """Center-of-mass velocities [E, B, 3] (m/s); under the prescaled integrator the
        words are displacements per step, u / dt."""
        return self._floats(slice(LW.OV, LW.OV + 3))

    @property
    def ang_vel(self) -> np.ndarray:
        """Angular velocities [E, B, 3] (rad/s), world frame: R I^-1 R^T L in float64."""
        L = self._floats(slice(LW.OL, LW.OL + 3))
        q = self.quat
        rot = K.quat_matrices(np.ascontiguousarray(q.reshape(-1, 4))).reshape(*q.shape[:2], 3, 3)
        w = np.einsum("ebij,bjk,eblk,ebl->ebi", rot, self._inv_inertia, rot, L)
        w.flags.writeable = False
        return w

    @property
    def fixed_state(self) -> np.ndarray:
        """The integer state words [E, B, 13] (read-only): int32 for fixed32, int64 for
        fixed64; rows position, quaternion, velocity, angular momentum (``laws.O*``)."""
        if self.format.name == "fixed32":
            out = self._st.astype(np.int32)
        else:
            out = self._st.view()
        out.flags.writeable = False
        return out

    @property
    def fixed_controls(self) -> np.ndarray:
        """The last call's controls as integers [E, C] (read-only, ``laws.ANGLE_BITS``
        fraction bits): what the step is computed from."""
        v = self._ctrl_words.view()
        v.flags.writeable = False
        return v

    @property
    def fixed_inputs(self) -> np.ndarray:
        """The last call's integer inputs [E, B, m] (read-only), made from
        :attr:`fixed_controls`: each control surface's deflected body normal, then each
        thruster's control value."""
        v = self._inp.view()
        v.flags.writeable = False
        return v

    @property
    def fixed_model(self) -> FM.FixedModel:
        """The packed crafts and world (``format.FixedModel``), as the kernel reads them."""
        return self._model

    @property
    def diverged(self) -> np.ndarray:
        """[E] True where a body of the environment had a saturated state word or ran past
        the speed clamp during the last ``step`` call: that env needs a reset."""
        v = self._diverged.view()
        v.flags.writeable = False
        return v

    @property
    def clock(self) -> np.ndarray:
        """Each environment's time [E] (s): its steps times dt."""
        return self._count * self.dt

    @property
    def controls(self) -> np.ndarray:
        """``[E, n_controls]``: the controls of the last :meth:`step` call."""
        v = self._ctrl.view()
        v.flags.writeable = False
        return v

    # ---- reset and step -------------------------------------------------------------------

    def reset(
        self,
        pos=(0.0, 0.0, 0.0),
        quat=(1.0, 0.0, 0.0, 0.0),
        lin_vel=(0.0, 0.0, 0.0),
        ang_vel=(0.0, 0.0, 0.0),
        env_ids=None,
    ) -> None:
        """As ``Simulator.reset``: the floats are converted to words (rounded to nearest); a
        value beyond the format is refused naming it."""
        from ..simulator import Simulator

        ids = CK.env_ids("reset", env_ids, self.num_envs)
        n = ids.size
        p = Simulator._broadcast(self, "pos", pos, 3, n)
        q = Simulator._broadcast(self, "quat", quat, 4, n)
        v = Simulator._broadcast(self, "lin_vel", lin_vel, 3, n)
        w = Simulator._broadcast(self, "ang_vel", ang_vel, 3, n)
        norm = np.linalg.norm(q, axis=-1, keepdims=True)
        if np.any(norm < 1e-12):
            raise ValueError(f"reset: quat must be non-zero (a rotation), got {CK.show(quat)}")
        q = q / norm
        rot = K.quat_matrices(np.ascontiguousarray(q.reshape(-1, 4))).reshape(n, -1, 3, 3)
        L = np.einsum("nbij,bjk,nblk,nbl->nbi", rot, self._inertia, rot, w)
        words = np.concatenate(
            [
                self._words("pos", p, slice(LW.OX, LW.OX + 3)),
                self._words("quat", q, slice(LW.OQ, LW.OQ + 4)),
                self._words("lin_vel", v, slice(LW.OV, LW.OV + 3)),
                self._words("angular momentum (ang_vel)", L, slice(LW.OL, LW.OL + 3)),
            ],
            axis=-1,
        )
        self._st[ids] = words
        self._diverged[ids] = False

    def step(self, controls=None, steps: int = 1) -> None:
        """Advance every environment by ``steps`` steps holding ``controls`` (``[E,
        n_controls]`` in [-1, 1]; None: all 0), as ``Simulator.step``."""
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise ValueError(f"step: steps must be a positive integer, got {CK.show(steps)}")
        self._set_controls(controls)
        m = self._model
        self._kernel(self._st, m.bc, m.tab, m.mix, self._ctrl_words, self._inp, m.prm, int(steps),
                     self._count, self._diverged)  # fmt: skip

    def _set_controls(self, controls) -> None:
        shape = (self.num_envs, len(self.control_names))
        if controls is None:
            c = np.zeros(shape)
        else:
            c = CK.real_array("step", "controls", controls)
            if c.shape != shape:
                raise ValueError(
                    f"controls must have shape {shape} (envs, channels {self.control_names}), "
                    f"got {c.shape}: {CK.show(controls)}"
                )
            if not (np.abs(c) <= 1.0).all():
                raise ValueError(
                    f"controls must be finite and lie in [-1, 1], got {CK.show(controls)}"
                )
        self._ctrl[...] = c
        self._ctrl_words[...] = np.floor(c * 2.0**LW.ANGLE_BITS + 0.5)
