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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class HelmGains:
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


class BoatOnStepPilot:
    """PID autopilot over a batch of observations ``[N, 18]`` (BoatOnStep-v0's layout).

    Keeps an integrator per env: call :meth:`reset` with a mask of the envs that start a new
    episode (all of them when ``mask`` is None).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.envs.boat_on_step import BoatOnStepVectorEnv
        >>> envs = BoatOnStepVectorEnv(num_envs=4)
        >>> pilot = BoatOnStepPilot()
        >>> obs, _ = envs.reset(seed=0)
        >>> for _ in range(5):
        ...     obs, reward, terminated, truncated, info = envs.step(pilot(obs))
        ...     pilot.reset(terminated | truncated)
    """

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
        u, r = obs[:, 0], obs[:, 5]
        trim = np.degrees(obs[:, 6])
        err = obs[:, 9]
        bearing = np.arctan2(obs[:, 10], obs[:, 11])
        gate_heading = np.arctan2(obs[:, 14], obs[:, 15])
        oscillation = np.degrees(obs[:, 17])

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
