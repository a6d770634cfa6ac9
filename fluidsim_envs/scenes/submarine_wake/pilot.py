"""A scripted pilot for SubmarineWake-v0: PD loops on the observation, for a batch of envs.

Three decoupled loops, each from the observation alone:

- speed: thrust = the drag of the nose at the station point's speed (feedforward, from the
  uuv craft's data) + mass x a PD law on the along-track error;
- heading: line-of-sight guidance (the lead's heading plus a turn toward the lateral error),
  then rudder on heading error with yaw-rate damping;
- depth: a pitch command from the vertical error, then dive planes on pitch error with
  pitch-rate damping.

It ignores the wake (the flow sensor is unused): the bar a trained policy must beat.

Gains: :class:`StationGains`' defaults are the hand-set gains (:func:`make_hand_pilot`); the
registry's pilot (:func:`make_pilot`) flies the gains tuned on the env's version
(``StationGains.for_env``): ``tuned_gains.json`` beside this file for v0, ``tuned_gains_v1.json``
for v1, each found by ``python -m benchmarks.tune_pilots fluidsim/SubmarineWake-vN --write``
searching :data:`SEARCH_SPACE` on episodes no evaluation flies
(``fluidsim_envs.evaluation.TUNING_SEEDS``; v1: their tuning stream).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...physics import Craft
from ..gains import TunableGains
from .kernel import OBS


@dataclass(frozen=True)
class StationGains(TunableGains):
    """The pilot's gains; the defaults are the hand-set ones, :meth:`tuned` the tuned ones."""

    kp_along: float = 0.15  # m/s^2 of commanded acceleration per m of along-track error
    kd_along: float = 0.6  # per m/s of closing speed error
    k_los: float = 0.12  # rad of heading correction per m of lateral error
    kd_los: float = 0.3  # per m/s of lateral speed error
    max_correction_rad: float = 0.6
    kp_heading: float = 2.0
    kd_yaw: float = 1.5
    kp_depth: float = 0.08  # rad of pitch per m of vertical error
    kd_depth: float = 0.3
    max_pitch_rad: float = 0.35
    kp_pitch: float = 2.5
    kd_pitch: float = 1.5


#: the gains class the tuner (benchmarks/tune_pilots.py) builds
GAINS = StationGains

#: the range the tuner searches for each gain, around the hand-set value: loop gains from a
#: quarter or a third of it to three to five times it (the lateral and depth damping down to
#: none), the heading-correction and pitch-command limits from half to twice
SEARCH_SPACE: dict[str, tuple[float, float]] = {
    "kp_along": (0.05, 0.5),
    "kd_along": (0.2, 1.5),
    "k_los": (0.03, 0.6),
    "kd_los": (0.0, 1.2),
    "max_correction_rad": (0.3, 1.2),
    "kp_heading": (0.7, 6.0),
    "kd_yaw": (0.5, 4.5),
    "kp_depth": (0.02, 0.3),
    "kd_depth": (0.0, 1.0),
    "max_pitch_rad": (0.15, 0.7),
    "kp_pitch": (0.8, 7.0),
    "kd_pitch": (0.5, 4.5),
}


class SubmarineWakePilot:
    """PD autopilot over a batch of observations ``[N, 22]`` (SubmarineWake-v0's layout, read
    by name through ``OBS``).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.scenes.submarine_wake import SubmarineWakeVectorEnv
        >>> envs = SubmarineWakeVectorEnv(num_envs=4)
        >>> pilot = SubmarineWakePilot()
        >>> obs, _ = envs.reset(seed=0)
        >>> for _ in range(5):
        ...     obs, reward, terminated, truncated, info = envs.step(pilot(obs))
    """

    memory = ()  # no per-episode memory (what a planner copies)

    def __init__(self, gains: StationGains = StationGains()) -> None:
        self.gains = gains
        uuv = Craft.load("uuv")
        (prop,) = uuv.thrusters
        self.mass_kg = uuv.mass_kg
        self.thrust_range = (prop.min_thrust_n, prop.max_thrust_n)
        (nose,) = [p for p in uuv.plates if p.normal == (1.0, 0.0, 0.0)]
        self.drag_per_v2 = 0.5 * 1025.0 * nose.area_m2  # N per (m/s)^2, head-on

    def reset(self, mask=None) -> None:
        """Stateless: nothing to clear (kept for the policy protocol)."""

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        g = self.gains
        obs = np.asarray(obs, dtype=np.float64)
        u, q, r = obs[:, OBS["u"]], obs[:, OBS["q"]], obs[:, OBS["r"]]
        gx = obs[:, OBS["gx"]]
        ex, ey, ez = (obs[:, OBS[k]] for k in ("station_x", "station_y", "station_z"))
        evx, evy, evz = (obs[:, OBS[k]] for k in ("station_vx", "station_vy", "station_vz"))
        heading_err = np.arctan2(obs[:, OBS["heading_sin"]], obs[:, OBS["heading_cos"]])

        # speed: feedforward drag at the station point's speed, plus PD on the error
        target_u = u + evx
        accel = g.kp_along * ex + g.kd_along * evx
        thrust = self.drag_per_v2 * target_u * np.abs(target_u) + self.mass_kg * accel
        lo, hi = self.thrust_range
        a_thrust = 2.0 * (thrust - lo) / (hi - lo) - 1.0

        # heading: the lead's heading, turned toward the lateral error (+ left)
        correction = np.clip(
            g.k_los * ey + g.kd_los * evy, -g.max_correction_rad, g.max_correction_rad
        )
        psi_err = heading_err + correction
        a_rudder = -(g.kp_heading * psi_err) + g.kd_yaw * r  # + rudder turns right

        # depth: pitch toward the vertical error (+ up), planes on pitch error
        pitch = np.arcsin(np.clip(-gx, -1.0, 1.0))  # nose up
        pitch_cmd = np.clip(g.kp_depth * ez + g.kd_depth * evz, -g.max_pitch_rad, g.max_pitch_rad)
        a_planes = g.kp_pitch * (pitch_cmd - pitch) + g.kd_pitch * q  # q + nose down

        return np.clip(np.stack([a_thrust, a_rudder, a_planes], axis=1), -1.0, 1.0)


def make_pilot(venv, gains: StationGains | None = None) -> SubmarineWakePilot:
    """The pilot for every sub-env of ``venv`` (it keeps no per-env state), with ``gains``
    (default: the gains tuned on ``venv``'s version, ``StationGains.for_env``)."""
    return SubmarineWakePilot(StationGains.for_env(venv) if gains is None else gains)


def make_hand_pilot(venv) -> SubmarineWakePilot:
    """:func:`make_pilot` with the hand-set gains (``StationGains()``)."""
    return make_pilot(venv, StationGains())


def demo(num_envs: int = 256, seed: int = 0) -> None:
    """The hand-set pilot (with and without the wake), the tuned pilot, a random policy and
    idle controls on ``num_envs`` seeded episodes."""
    from ...evaluation import first_episodes, random_policy, zero_policy
    from .env import SubmarineWakeVectorEnv

    print(f"\nSubmarineWake-v0: {num_envs} episodes (seed {seed}), one each, 60 s")
    print(f"{'policy':>14} {'return':>17} {'on station':>11} {'success':>8} {'crash':>6}")
    for name, wake, policy in (
        ("scripted pilot", True, SubmarineWakePilot()),
        ("  (no wake)", False, SubmarineWakePilot()),
        ("tuned pilot", True, SubmarineWakePilot(StationGains.tuned())),
        ("random", True, None),
        ("zero controls", True, None),
    ):
        venv = SubmarineWakeVectorEnv(num_envs=num_envs, wake=wake)
        if policy is None:
            policy = random_policy(venv, seed) if name == "random" else zero_policy(venv)
        r = first_episodes(venv, policy, seed=seed)
        crash = 1.0 - r["truncated"].mean()
        print(
            f"{name:>14} {r['return'].mean():8.1f} +- {r['return'].std():5.1f} "
            f"{r['on_station_fraction'].mean():11.1%} {r['success'].mean():8.1%} {crash:6.1%}"
        )
