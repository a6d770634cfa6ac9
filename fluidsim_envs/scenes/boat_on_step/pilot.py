"""A scripted pilot for BoatOnStep-v0: throttle and heading PID loops on the observation.

- throttle: full ahead until the boat is close to its target speed (over the hump onto the
  plane), then a PI loop on the speed error around a cruise setting;
- heading: line of sight to the next gate's center, with the approach bent so that the boat
  crosses the gate along its direction of travel; rudder on the heading error with yaw-rate
  damping, and less rudder at speed (the same deflection turns a fast boat harder);
- trim tabs: down while climbing onto the plane (less bow rise), then trimmed to keep the
  running trim near ``trim_deg``, and down further as the trim starts to oscillate
  (porpoising).

The bar a trained policy must beat.

Gains: :class:`HelmGains`' defaults are the hand-set gains (:func:`make_hand_pilot`); the
registry's pilot (:func:`make_pilot`) flies the gains tuned on the env's version
(``HelmGains.for_env``): ``tuned_gains.json`` beside this file for v0, ``tuned_gains_v1.json``
for v1, each found by ``python -m benchmarks.tune_pilots fluidsim/BoatOnStep-vN --write``
searching :data:`SEARCH_SPACE` on episodes no evaluation flies
(``fluidsim_envs.evaluation.TUNING_SEEDS``; v1: their tuning stream).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..gains import TunableGains
from .kernel import OBS


@dataclass(frozen=True)
class HelmGains(TunableGains):
    """The pilot's gains; the defaults are the hand-set ones, :meth:`tuned` the tuned ones."""

    cruise_throttle: float = 0.45  # throttle at the target speed (before the PI correction)
    kp_speed: float = 0.15  # throttle per m/s of speed error
    ki_speed: float = 0.03  # throttle per m/s s
    plane_margin_mps: float = 3.0  # full throttle until this close to the target
    approach: float = 1.0  # how far the aim bends to cross the gate along its direction
    kp_heading: float = 3.0  # rudder per rad of heading error (at 10 m/s)
    kd_yaw: float = 0.6  # rudder per rad/s of yaw rate
    trim_deg: float = 2.0  # running trim the tabs hold
    k_tabs: float = 1.5  # tabs per degree of trim above trim_deg
    k_porpoise: float = 3.0  # more tabs per degree of trim oscillation
    step_s: float = 0.05  # the env's action period


#: the gains class the tuner (benchmarks/tune_pilots.py) builds
GAINS = HelmGains

#: the range the tuner searches for each gain, around the hand-set value (step_s is the env's,
#: not a gain): the loop gains from none (or a third) to about three times the hand-set value,
#: the cruise throttle, the planing margin and the held trim (0.5-5 degrees) each side of it
SEARCH_SPACE: dict[str, tuple[float, float]] = {
    "cruise_throttle": (0.2, 0.8),
    "kp_speed": (0.0, 0.45),
    "ki_speed": (0.0, 0.1),
    "plane_margin_mps": (0.5, 6.0),
    "approach": (0.0, 2.0),
    "kp_heading": (1.0, 7.0),
    "kd_yaw": (0.0, 2.0),
    "trim_deg": (0.5, 5.0),
    "k_tabs": (0.0, 4.0),
    "k_porpoise": (0.0, 8.0),
}


class BoatOnStepPilot:
    """PID autopilot over a batch of observations ``[N, 18]`` (BoatOnStep-v0's layout, read
    by name through ``OBS``).

    Keeps an integrator per env: call :meth:`reset` with a mask of the envs that start a new
    episode (all of them when ``mask`` is None).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.scenes.boat_on_step import BoatOnStepVectorEnv
        >>> envs = BoatOnStepVectorEnv(num_envs=4)
        >>> pilot = BoatOnStepPilot()
        >>> obs, _ = envs.reset(seed=0)
        >>> for _ in range(5):
        ...     obs, reward, terminated, truncated, info = envs.step(pilot(obs))
        ...     pilot.reset(terminated | truncated)
    """

    # its per-episode memory, arrays with the episode first (what a planner copies; sized on
    # the first call)
    memory = ("_integral",)

    def __init__(self, gains: HelmGains = HelmGains()) -> None:
        self.gains = gains
        self._integral = np.zeros(0)

    def reset(self, mask=None) -> None:
        if mask is None:
            self._integral = np.zeros(0)
        elif self._integral.size:
            self._integral[np.asarray(mask, dtype=bool)] = 0.0

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        g = self.gains
        obs = np.asarray(obs, dtype=np.float64)
        if self._integral.shape != (len(obs),):
            self._integral = np.zeros(len(obs))
        u, r = obs[:, OBS["u"]], obs[:, OBS["r"]]
        trim = np.degrees(obs[:, OBS["trim"]])
        err = obs[:, OBS["speed_error"]]
        bearing = np.arctan2(obs[:, OBS["gate_bearing_sin"]], obs[:, OBS["gate_bearing_cos"]])
        gate_heading = np.arctan2(obs[:, OBS["gate_heading_sin"]], obs[:, OBS["gate_heading_cos"]])
        oscillation = np.degrees(obs[:, OBS["pitch_oscillation"]])

        # throttle: over the hump at full power, then PI around the cruise setting
        climbing = err > g.plane_margin_mps
        self._integral = np.where(
            climbing, 0.0, np.clip(self._integral + err * g.step_s, -20.0, 20.0)
        )
        throttle = np.where(
            climbing, 1.0, g.cruise_throttle + g.kp_speed * err + g.ki_speed * self._integral
        )

        # heading: toward the gate, bent to meet it along its direction of travel
        aim = bearing + g.approach * np.clip(bearing - gate_heading, -0.5, 0.5)
        aim = np.arctan2(np.sin(aim), np.cos(aim))
        speed_factor = 10.0 / np.maximum(u, 10.0)
        rudder = -(g.kp_heading * speed_factor * aim) + g.kd_yaw * r  # + rudder turns right

        # tabs: down on the way up, then hold the trim, and down against porpoising
        hold = g.k_tabs * (trim - g.trim_deg) + g.k_porpoise * oscillation
        tabs = np.where(climbing, 1.0, np.clip(hold, -1.0, 1.0))
        return np.clip(np.stack([throttle, rudder, tabs], axis=1), -1.0, 1.0)


def make_pilot(venv, gains: HelmGains | None = None) -> BoatOnStepPilot:
    """The pilot for every sub-env of ``venv`` (it sizes its integrators on first use), with
    ``gains`` (default: the gains tuned on ``venv``'s version, ``HelmGains.for_env``)."""
    return BoatOnStepPilot(HelmGains.for_env(venv) if gains is None else gains)


def make_hand_pilot(venv) -> BoatOnStepPilot:
    """:func:`make_pilot` with the hand-set gains (``HelmGains()``)."""
    return make_pilot(venv, HelmGains())


def demo(num_envs: int = 256, seed: int = 0) -> None:
    """The hand-set pilot (in calm water and in swell), the tuned pilot, a random policy and
    idle controls on ``num_envs`` seeded courses."""
    from ...evaluation import first_episodes, random_policy, zero_policy
    from .env import BoatOnStepVectorEnv

    print(f"\nBoatOnStep-v0: {num_envs} courses (seed {seed}), one episode each, 60 s at most")
    print(
        f"{'policy':>14} {'return':>15} {'gates':>6} {'success':>8} {'porpoise':>9} "
        f"{'crash':>6} {'to plane (s)':>13}"
    )
    swell = ((0.2, 40.0, 45.0),)  # 0.4 m crest to trough, 40 m long
    for name, waves, policy in (
        ("scripted pilot", (), BoatOnStepPilot()),
        ("  (in swell)", swell, BoatOnStepPilot()),
        ("tuned pilot", (), BoatOnStepPilot(HelmGains.tuned())),
        ("random", (), None),
        ("zero controls", (), None),
    ):
        venv = BoatOnStepVectorEnv(num_envs=num_envs, swell=waves)
        if policy is None:
            policy = random_policy(venv, seed) if name == "random" else zero_policy(venv)
        r = first_episodes(venv, policy, seed=seed)
        crash = r["capsized"] | r["bow_stuffed"] | r["left_course"] | r["physics_diverged"]
        planed = r["time_to_plane_s"][r["time_to_plane_s"] >= 0.0]
        to_plane = planed.mean() if planed.size else float("nan")
        print(
            f"{name:>14} {r['return'].mean():7.1f} +- {r['return'].std():5.1f} "
            f"{r['gates_passed'].mean():6.2f} {r['success'].mean():8.1%} "
            f"{r['porpoising_fraction'].mean():9.1%} {crash.mean():6.1%} "
            f"{to_plane:13.1f}"
        )
