"""A scripted pilot for SubmarineWake-v0: PD loops on the observation, for a batch of envs.

Three decoupled loops, each from the observation alone:

- speed: thrust = the drag of the nose at the station point's speed (feedforward, from the
  uuv craft's data) + mass x a PD law on the along-track error;
- heading: line-of-sight guidance (the lead's heading plus a turn toward the lateral error),
  then rudder on heading error with yaw-rate damping;
- depth: a pitch command from the vertical error, then dive planes on pitch error with
  pitch-rate damping.

It ignores the wake (the flow sensor is unused): the bar a trained policy must beat.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics import Craft


@dataclass(frozen=True)
class StationGains:
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


class SubmarineWakePilot:
    """PD autopilot over a batch of observations ``[N, 22]`` (SubmarineWake-v0's layout).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.envs.submarine_wake import SubmarineWakeVectorEnv
        >>> envs = SubmarineWakeVectorEnv(num_envs=4)
        >>> pilot = SubmarineWakePilot()
        >>> obs, _ = envs.reset(seed=0)
        >>> for _ in range(5):
        ...     obs, reward, terminated, truncated, info = envs.step(pilot(obs))
    """

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
        u, q, r = obs[:, 0], obs[:, 4], obs[:, 5]
        gx = obs[:, 6]
        ex, ey, ez = obs[:, 11], obs[:, 12], obs[:, 13]
        evx, evy, evz = obs[:, 17], obs[:, 18], obs[:, 19]
        heading_err = np.arctan2(obs[:, 20], obs[:, 21])

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
