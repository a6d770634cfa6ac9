"""Probes: observations read from the fluid samples (v1's ``observe_samples``).

Every sample of a craft already computes the flow it meets to make its force; a probe reads
it back (``Simulator.sample_flows``, the same kernel code as the forces), the way real craft
carry air-data vanes and pitot tubes, hull pressure taps or a lateral line of flow sensors.
A scene declares its probes as a tuple of :class:`Probe`: the samples a probe averages over
(a tail of two stabilizers, a hull station of four bottom plates) and what it reads of them:

- ``aoa`` (rad): the angle of the inflow to the samples' plane, ``asin(u_n / |u|)`` with
  ``u`` the fluid's velocity relative to the sample and ``u_n`` its part along the plate's
  normal: positive where the fluid meets the plate from the side its normal points away
  from (a wing with its normal up, the air coming from below: a positive angle of attack);
  0 where the sample does not move through the fluid;
- ``q`` (Pa): the inflow's dynamic pressure ``rho |u|^2 / 2``;
- ``wetted`` (1): the fraction of the samples under water, from the density there
  (``(rho - rho_air) / (rho_water - rho_air)``: 0 dry, 1 wet, between across the surface
  blend);
- ``pressure`` (kPa): what a flush pressure tap reads (gauge): the flow's force against
  the plates' normals (which point out of a hull) per unit of their area, plus the water's
  weight above them (``rho_water g depth`` below the surface; the model carries it in
  separate buoyancy samples, so the plates' own forces leave it out);
- ``flow_x``, ``flow_y``, ``flow_z`` (m/s): the inflow along the body's axes.

A probe over several samples averages what they sense before it derives its reading (the
mean inflow's angle, not the mean angle). Readings are the truth; a v1 scene's ``SENSORS``
add the instruments' noise to their columns like to any other.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..physics.kernels import SENSE_FIELDS

_F = {name: j for j, name in enumerate(SENSE_FIELDS)}
_AXIS = {"flow_x": _F["inflow_x_mps"], "flow_y": _F["inflow_y_mps"], "flow_z": _F["inflow_z_mps"]}

# what a probe can read: unit and description (``{}`` the probe's words)
READS = {
    "aoa": ("rad", "angle of attack of the inflow at the {}"),
    "q": ("Pa", "dynamic pressure of the inflow at the {}"),
    "wetted": ("1", "wetted fraction of the {} (0 dry, 1 under water)"),
    "pressure": ("kPa", "gauge pressure on the {} (the flow's and the water's weight)"),
    "flow_x": ("m/s", "inflow at the {} along body x"),
    "flow_y": ("m/s", "inflow at the {} along body y"),
    "flow_z": ("m/s", "inflow at the {} along body z"),
}


@dataclass(frozen=True)
class Probe:
    """One probe of a scene's craft (body 0).

    Attributes:
        name: the prefix of its observation columns (``{name}_{read}``).
        samples: the craft's samples it averages over.
        reads: what it reads of them, in order (keys of :data:`READS`).
        where: the probe in words, for the column descriptions ("left wing").
    """

    name: str
    samples: tuple[str, ...]
    reads: tuple[str, ...]
    where: str

    def __post_init__(self) -> None:
        own = f"Probe {self.name!r}"
        if not self.samples or len(set(self.samples)) != len(self.samples):
            raise ValueError(f"{own}: samples must be distinct names, got {self.samples!r}")
        unknown = [r for r in self.reads if r not in READS]
        if not self.reads or unknown:
            raise ValueError(f"{own}: reads must be some of {sorted(READS)}, got {self.reads!r}")


def probe_columns(probes) -> tuple[tuple[str, str, str], ...]:
    """The observation columns of ``probes``: (name, unit, description) each."""
    return tuple(
        (f"{p.name}_{r}", READS[r][0], READS[r][1].format(p.where)) for p in probes for r in p.reads
    )


class ProbeArray:
    """A scene's probes on one simulator: :meth:`read` writes their columns for every
    sub-env from one ``sample_flows`` call."""

    def __init__(self, sim, probes) -> None:
        self.sim, self.probes = sim, tuple(probes)
        self.samples = list(dict.fromkeys(s for p in self.probes for s in p.samples))
        at = {s: j for j, s in enumerate(self.samples)}
        self.at = [[at[s] for s in p.samples] for p in self.probes]  # each probe's samples
        self.columns = [(p.name, r) for p in self.probes for r in p.reads]
        w = sim.world
        self.rho_air, self.rho_water = w.air_density_kgm3, w.water_density_kgm3
        self.gravity_mps2 = w.gravity_mps2

    def read(self, density_scale: np.ndarray, env_ids=None) -> np.ndarray:
        """The probe columns [n, len(columns)] (float64) of sub-envs ``env_ids`` (None: all),
        at the current state. ``density_scale`` [n]: each one's fluid density factor (a v1
        episode's draw): the physics scales the samples' areas by it, so q and pressure are
        scaled here."""
        with np.errstate(invalid="ignore", over="ignore"):  # diverged rows: masked after
            return self._columns(self.sim.sample_flows(self.samples, env_ids=env_ids),
                                 density_scale)  # fmt: skip

    def _columns(self, flows: np.ndarray, density_scale: np.ndarray) -> np.ndarray:
        """The probe columns from ``sample_flows``' [n, samples, fields]."""
        rows = flows.transpose(1, 2, 0)  # [samples, fields, n]
        out = np.empty((rows.shape[2], len(self.columns)))
        c = 0
        for at, probe in zip(self.at, self.probes, strict=True):
            # the probe's mean sensed fields [fields, E] (no BLAS: its threads would spin
            # beside numba's)
            m = rows[at[0]] if len(at) == 1 else rows[at].mean(axis=0)
            u = m[_F["inflow_x_mps"] : _F["inflow_z_mps"] + 1]
            speed = np.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
            for r in probe.reads:
                out[:, c] = self._reading(r, m, speed, density_scale)
                c += 1
        return out

    def _reading(self, read: str, m, speed, density_scale) -> np.ndarray:
        """One reading of one probe from its mean sensed fields ``m`` [fields, E]."""
        if read == "aoa":
            ratio = np.divide(m[_F["inflow_normal_mps"]], speed, out=np.zeros_like(speed),
                              where=speed > 1e-9)  # fmt: skip
            return np.arcsin(np.clip(ratio, -1.0, 1.0))  # |ratio| <= 1 but for rounding
        if read == "q":
            return 0.5 * m[_F["density_kgm3"]] * speed * speed * density_scale
        if read == "wetted":
            return (m[_F["density_kgm3"]] - self.rho_air) / (self.rho_water - self.rho_air)
        if read == "pressure":
            depth = np.maximum(-m[_F["height_m"]], 0.0)
            static = self.rho_water * self.gravity_mps2 * depth
            return 1e-3 * (m[_F["pressure_pa"]] + static) * density_scale
        return m[_AXIS[read]]


__all__ = ["READS", "Probe", "ProbeArray", "probe_columns"]
