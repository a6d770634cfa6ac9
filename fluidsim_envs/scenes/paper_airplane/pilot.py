"""A scripted pilot for PaperAirplane-v0: PID loops on the observation, for a batch of envs.

Guidance: head for the target; while too high for the glide path to it, circle to lose height;
flare just above the ground. Inner loops: bank (aileron, PD), airspeed (elevator, PI with
pitch-rate damping), sideslip and yaw rate (rudder). It is the bar a trained policy must beat.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kernel import OBS


@dataclass(frozen=True)
class PilotGains:
    trim_speed_mps: float = 6.7  # the dart's zero-control glide speed
    glide_slope: float = 0.25  # tan of the glide angle it can fly (trim glide ~ 4:1)
    heading_to_bank: float = 1.2  # rad of bank per rad of heading error
    max_bank_rad: float = 0.75
    orbit_radius_m: float = 4.0  # circle the target at this radius to lose excess height
    orbit_gain: float = 1.0  # rad of heading correction per radius of radial error
    approach_margin_m: float = 0.3  # head in when this little above the glide path
    max_dive_mps: float = 1.0  # fly up to this much faster than trim to steepen the glide
    kp_bank: float = 2.0
    kd_roll: float = 0.25
    kp_speed: float = 0.15
    ki_speed: float = 0.05
    kd_pitch: float = 0.15
    flare_height_m: float = 0.6
    flare_elevator: float = 0.6
    k_sideslip: float = 1.0
    k_yaw_rate: float = 0.2


class PaperAirplanePilot:
    """PID autopilot over a batch of observations ``[N, 15]`` (PaperAirplane-v0's layout,
        read by name through ``OBS``).

        Examples:
            >>> import numpy as np

    from .kernel import OBS
            >>> from fluidsim_envs.scenes.paper_airplane import PaperAirplaneVectorEnv
            >>> envs = PaperAirplaneVectorEnv(num_envs=8)
            >>> pilot = PaperAirplanePilot(num_envs=8, dt=envs.params.dt * envs.params.substeps)
            >>> obs, _ = envs.reset(seed=0)
            >>> for _ in range(5):
            ...     obs, reward, terminated, truncated, info = envs.step(pilot(obs))
            ...     pilot.reset(terminated | truncated)
    """

    def __init__(self, num_envs: int = 1, dt: float = 1.0 / 30.0, gains=PilotGains()) -> None:
        self.gains = gains
        self.dt = dt
        self.speed_integral = np.zeros(num_envs)

    def reset(self, mask=None) -> None:
        """Clear the integrators of the envs in ``mask`` (all when None): a new episode."""
        if mask is None:
            self.speed_integral[:] = 0.0
        else:
            self.speed_integral[np.asarray(mask, dtype=bool)] = 0.0

    def __call__(self, obs) -> np.ndarray:
        g = self.gains
        obs = np.atleast_2d(np.asarray(obs, dtype=np.float64))
        u, v, w = obs[:, OBS["u"]], obs[:, OBS["v"]], obs[:, OBS["w"]]
        p, q, r = obs[:, OBS["p"]], obs[:, OBS["q"]], obs[:, OBS["r"]]
        gy, gz = obs[:, OBS["gy"]], obs[:, OBS["gz"]]
        height = obs[:, OBS["height"]]
        tf, tl = obs[:, OBS["target_forward"]], obs[:, OBS["target_left"]]
        airspeed = np.sqrt(u * u + v * v + w * w)

        # guidance (bank + right wing down): turn toward the target (bearing + is to the
        # left); circle right while far above the glide path to it
        bearing = np.arctan2(tl, tf)
        distance = np.hypot(tf, tl)
        excess = height - g.glide_slope * distance  # height above the glide path to the target
        # circle left around the target (it abeam on the left, 90 deg) while well above
        radial = np.clip((distance - g.orbit_radius_m) / g.orbit_radius_m, -1.0, 1.0)
        orbit_bearing = 0.5 * np.pi - g.orbit_gain * radial
        circling = excess > g.approach_margin_m + g.glide_slope * 2 * np.pi * g.orbit_radius_m
        wanted = np.where(circling, orbit_bearing, 0.0)
        feedforward = np.where(
            circling, np.arctan(g.trim_speed_mps**2 / (9.81 * g.orbit_radius_m)), 0.0
        )
        bank_cmd = -np.clip(
            g.heading_to_bank * (bearing - wanted) + feedforward, -g.max_bank_rad, g.max_bank_rad
        )

        # bank from the body-frame gravity; + aileron and p + both roll right
        bank = np.arctan2(-gy, -gz)
        aileron = g.kp_bank * (bank_cmd - bank) - g.kd_roll * p

        # airspeed by pitch: too fast -> up elevator; q + is nose down -> up elevator damps it
        # on the approach, spend height above the glide path as speed (a steeper glide)
        dive = np.where(circling, 0.0, np.clip(excess, 0.0, g.max_dive_mps))
        error = airspeed - (g.trim_speed_mps + dive)
        self.speed_integral = np.clip(self.speed_integral + error * self.dt, -5.0, 5.0)
        elevator = g.kp_speed * error + g.ki_speed * self.speed_integral + g.kd_pitch * q
        elevator = np.where(height < g.flare_height_m, g.flare_elevator, elevator)

        # rudder: nose into the relative wind (v + : air from the left, yaw left = - rudder);
        # r + is nose left, damped by + (right) rudder
        rudder = -g.k_sideslip * v / np.maximum(airspeed, 1.0) + g.k_yaw_rate * r
        return np.clip(np.stack([aileron, elevator, rudder], axis=1), -1.0, 1.0)


def make_pilot(venv) -> PaperAirplanePilot:
    """The pilot for every sub-env of ``venv`` (a vector env or a wrapper of one), at its
    action period."""
    p = venv.unwrapped.params
    return PaperAirplanePilot(venv.num_envs, dt=p.dt * p.substeps)


def demo(num_envs: int = 256, seed: int = 0) -> None:
    """The pilot, a random policy and idle controls on ``num_envs`` seeded throws."""
    from ...evaluation import first_episodes, random_policy, zero_policy
    from .env import PaperAirplaneVectorEnv

    venv = PaperAirplaneVectorEnv(num_envs=num_envs)
    dt = venv.params.dt * venv.params.substeps
    print(f"\nPaperAirplane-v0: {num_envs} throws (seed {seed}), one episode each")
    print(f"{'policy':>14} {'return':>15} {'landed':>7} {'success':>8} {'miss (m)':>9}")
    for name, policy in (
        ("scripted pilot", PaperAirplanePilot(num_envs, dt=dt)),
        ("random", random_policy(venv, seed)),
        ("zero controls", zero_policy(venv)),
    ):
        r = first_episodes(venv, policy, seed=seed)
        print(
            f"{name:>14} {r['return'].mean():7.2f} +- {r['return'].std():5.2f} "
            f"{r['landed'].mean():7.1%} {r['success'].mean():8.1%} {r['distance_m'].mean():9.2f}"
        )
