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

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

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


# what a column reads, as the kernel's codes (READS' order)
_CODE = {read: k for k, read in enumerate(READS)}
AOA, Q, WETTED, PRESSURE, FLOW_X, FLOW_Y, FLOW_Z = (_CODE[r] for r in READS)


class ProbeArray:
    """A scene's probes on one simulator: :meth:`read` writes their columns for every
    sub-env from one ``sample_flows`` call."""

    def __init__(self, sim, probes) -> None:
        self.sim, self.probes = sim, tuple(probes)
        self.samples = list(dict.fromkeys(s for p in self.probes for s in p.samples))
        at = {s: j for j, s in enumerate(self.samples)}
        self.at = [[at[s] for s in p.samples] for p in self.probes]  # each probe's samples
        self.columns = [(p.name, r) for p in self.probes for r in p.reads]
        # the kernel's tables: probe k averages samples members[first[k]:first[k + 1]];
        # column c reads READS' code[c] of probe owner[c]
        self.first = np.cumsum([0] + [len(a) for a in self.at]).astype(np.int64)
        self.members = np.array([j for a in self.at for j in a], dtype=np.int64)
        self.owner = np.array([k for k, p in enumerate(self.probes) for _ in p.reads],
                              dtype=np.int64)  # fmt: skip
        self.code = np.array([_CODE[r] for p in self.probes for r in p.reads], dtype=np.int64)
        w = sim.world
        self.rho_air, self.rho_water = w.air_density_kgm3, w.water_density_kgm3
        self.gravity_mps2 = w.gravity_mps2
        self.fluid = np.array([self.rho_air, self.rho_water, self.gravity_mps2])

    def read(self, density_scale: np.ndarray, env_ids=None) -> np.ndarray:
        """The probe columns [n, len(columns)] (float64) of sub-envs ``env_ids`` (None: all),
        at the current state. ``density_scale`` [n]: each one's fluid density factor (a v1
        episode's draw): the physics scales the samples' areas by it, so q and pressure are
        scaled here."""
        return self._columns(self.sim.sample_flows(self.samples, env_ids=env_ids),
                             density_scale)  # fmt: skip

    def _columns(self, flows: np.ndarray, density_scale: np.ndarray) -> np.ndarray:
        """The probe columns from ``sample_flows``' [n, samples, fields] (one compiled call:
        a numpy expression per column and probe cost a small batch more than the physics)."""
        out = np.empty((flows.shape[0], len(self.columns)))
        columns(flows, np.asarray(density_scale, dtype=np.float64), self.first, self.members,
                self.owner, self.code, self.fluid, out)  # fmt: skip
        return out


_INFLOW = _F["inflow_x_mps"]
_NORMAL, _DENSITY = _F["inflow_normal_mps"], _F["density_kgm3"]
_HEIGHT, _PRESSURE = _F["height_m"], _F["pressure_pa"]
assert _AXIS == {"flow_x": _INFLOW, "flow_y": _INFLOW + 1, "flow_z": _INFLOW + 2}


@njit(cache=True, error_model="numpy")
def columns(flows, density_scale, first, members, owner, code, fluid, out):
    """:meth:`ProbeArray._columns`, compiled: for each sub-env (row of ``flows`` [n, P,
    fields]) and column, its probe's mean sensed fields (its samples summed in order, then
    divided by their count, as numpy's mean over them) and the reading of them. The same
    operations in the same order as the readings' formulas in the module docstring, so the
    columns are the numpy expressions' to the bit; a diverged row gives NaN (masked after)."""
    m = np.empty(flows.shape[2])
    rho_air, rho_water, g = fluid[0], fluid[1], fluid[2]
    for e in range(flows.shape[0]):
        for c in range(code.size):
            k = owner[c]
            lo, hi = first[k], first[k + 1]
            for f in range(m.size):
                m[f] = flows[e, members[lo], f]
            for s in range(lo + 1, hi):
                for f in range(m.size):
                    m[f] += flows[e, members[s], f]
            if hi - lo > 1:
                for f in range(m.size):
                    m[f] /= hi - lo
            out[e, c] = _reading(code[c], m, density_scale[e], rho_air, rho_water, g)


@njit(cache=True, inline="always", error_model="numpy")
def _reading(read, m, density_scale, rho_air, rho_water, g):
    """One reading (a code of READS) from a probe's mean sensed fields ``m``."""
    u0, u1, u2 = m[_INFLOW], m[_INFLOW + 1], m[_INFLOW + 2]
    speed = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    if read == AOA:  # 0 where the sample does not move through the fluid
        ratio = m[_NORMAL] / speed if speed > 1e-9 else 0.0
        return math.asin(min(max(ratio, -1.0), 1.0))  # |ratio| <= 1 but for rounding
    if read == Q:
        return 0.5 * m[_DENSITY] * speed * speed * density_scale
    if read == WETTED:
        return (m[_DENSITY] - rho_air) / (rho_water - rho_air)
    if read == PRESSURE:
        static = rho_water * g * max(-m[_HEIGHT], 0.0)
        return 1e-3 * (m[_PRESSURE] + static) * density_scale
    return m[_INFLOW + read - FLOW_X]


__all__ = ["READS", "Probe", "ProbeArray", "probe_columns"]
