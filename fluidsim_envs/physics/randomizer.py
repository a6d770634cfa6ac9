"""A craft drawn anew at each episode start, written at the cost of a reset.

``Simulator.set_mass_properties`` and ``set_sample_scale`` check everything they are given:
shapes, symmetry and definiteness of a tensor (an eigen decomposition), a group's name and
its plates' efficiencies, each on every call. A v1 scene (``scenes/realism.py``) calls them
once per sub-env reset, usually for one sub-env at a time, and at 256 sub-envs those checks
were a third of the dart's env step. :class:`Randomizer` is the same writes for draws that are
scales of the craft's own values: the groups are resolved once, a positive scale of a valid
inertia tensor is valid (no eigen decomposition), and what is left to check is a sign per
array. The numbers written are the checked setters', bit for bit.
"""

from __future__ import annotations

import numpy as np

from . import checks as CK
from . import model as M


class Randomizer:
    """Writes the episode's craft of body slot ``body`` of ``sim`` (a ``Simulator``): its mass,
    inertia and center of mass, the fluid's density on every sample with a size, and each of
    ``groups``' sizes and plate efficiencies (``Simulator.set_sample_scale``'s groups; a sample
    in several takes the last one's), and, where the craft has thrusters, their thrust."""

    def __init__(self, sim, groups, body: int = 0) -> None:
        bd = sim._body("Randomizer", body)
        self.sim, self.body, self.bodies = sim, body, bd
        self.groups = tuple(groups)
        for g in self.groups:  # the checked setter's errors for a group unknown or plateless
            sim.set_sample_scale(g, area=1.0, efficiency=1.0, body=body)
        sized = {g: [(k, i) for k, i in bd.groups[g] if M.KIND[k].area] for g in self.groups}
        grouped = {s for g in self.groups for s in sized[g]}
        rest = [(k, i) for k, i in bd.groups["all"] if M.KIND[k].area and (k, i) not in grouped]
        self.rest = bd.numbers(rest)
        self.area = [bd.numbers(sized[g]) for g in self.groups]
        plates = [[(k, i) for k, i in sized[g] if M.KIND[k].efficiency] for g in self.groups]
        self.plates = [bd.numbers(p) for p in plates]
        self.top = np.array([max(bd.rows[k][i, M.S_EFFICIENCY] for k, i in p) for p in plates])
        self.thrusters = bd.index["thr"] if bd.names["thr"] else None

    def set(self, ids, mass_scale, inertia_scale, com_shift_m, density, area, efficiency,
            thrust=None) -> None:  # fmt: skip
        """Sub-envs ``ids`` [n] get the craft's mass times ``mass_scale`` [n], its inertia
        tensor times ``mass_scale * inertia_scale`` [n], its center of mass moved by
        ``com_shift_m`` [n, 3] (body frame), every sized sample's size times ``density`` [n]
        and each group's times ``area`` [n, groups] too, each group's plate efficiencies times
        ``efficiency`` [n, groups], and thrust times ``thrust`` [n] (None: left as it is)."""
        what = "Randomizer.set"
        for name, x in (("mass_scale", mass_scale), ("inertia_scale", inertia_scale),
                        ("density", density), ("area", area)):  # fmt: skip
            if not np.all(x > 0.0):
                raise ValueError(f"{what}: {name} must be positive, got {CK.show(x)}")
        if not np.all((efficiency >= 0.0) & (efficiency * self.top <= 1.0)):
            raise ValueError(
                f"{what}: efficiency {CK.show(efficiency)} takes a plate of {self.groups} "
                f"(efficiency up to {self.top}) outside [0, 1]"
            )
        sim, bd, craft = self.sim, self.bodies, self.bodies.craft
        bd.mass_kg[ids] = craft.mass_kg * mass_scale
        bd.inertia[ids] = (mass_scale * inertia_scale)[:, None, None] * craft.inertia_tensor
        bd.com_m[ids] = com_shift_m
        sim._write(self.body, ids)
        sim._set_factor(M.F_AREA, self.rest, ids, density)
        for j in range(len(self.groups)):
            sim._set_factor(M.F_AREA, self.area[j], ids, area[:, j] * density)
            sim._set_factor(M.F_EFFICIENCY, self.plates[j], ids, efficiency[:, j])
        if thrust is not None:
            if self.thrusters is None:
                raise ValueError(f"{what}: craft {craft.name!r} has no thruster")
            if not np.all(thrust >= 0.0):
                raise ValueError(f"{what}: thrust must be >= 0, got {CK.show(thrust)}")
            sim._set_factor(M.F_THRUST, self.thrusters, ids, thrust)
