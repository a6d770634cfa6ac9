"""Bad inputs to the physics API (Simulator and its methods, World, Ground, SwellWave,
WakeField, Craft and its parts, craft TOML files, the hull and buoy generators): each is
refused with an error that names the argument and the bad value. And NumPy scalars are
numbers everywhere a number is taken.

The simulators here are built once per worker (:func:`functools.cache`) and shared by the
rows: every row is refused before anything is written, so sharing changes no result, and no
row steps a kernel."""

from __future__ import annotations

import functools
import tempfile
from pathlib import Path

import numpy as np
import pytest

from fluidsim_envs.craft.buoy import MarkerBuoy
from fluidsim_envs.craft.hull import VHull
from fluidsim_envs.physics import (
    Buoyancy,
    Control,
    Craft,
    CraftError,
    Cylinder,
    Ground,
    Plate,
    Shape,
    Simulator,
    SwellWave,
    Thruster,
    WakeField,
    World,
)
from tests.bad_inputs.table import Row, check, params

NAN, INF = float("nan"), float("inf")
BALL = {"name": "ball", "mass_kg": 1.0, "inertia_kgm2": (0.4, 0.4, 0.4)}
PLATE = {"name": "w", "offset_m": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0), "area_m2": 0.5}


@functools.cache
def dart() -> Craft:
    return Craft.load("paper_airplane")


@functools.cache
def sim() -> Simulator:
    """The dart, two environments: one body, three control channels, no thruster."""
    return Simulator(dart(), World(), num_envs=2)


@functools.cache
def pair() -> Simulator:
    """Two balls per environment, two environments: E == B, where [2, 3] is ambiguous."""
    return Simulator([Craft(**BALL), Craft(**BALL)], World(), num_envs=2)


@functools.cache
def three() -> Simulator:
    return Simulator(Craft(**BALL), World(), num_envs=3)


@functools.cache
def sub() -> Simulator:
    """The uuv with a wake and a thruster, two environments."""
    return Simulator(Craft.load("uuv"), World(water=True), num_envs=2, wake=WakeField())


def new_sim(**kwargs) -> Simulator:
    return Simulator(**{"crafts": Craft(**BALL), **kwargs})


def craft(**changes) -> Craft:
    return Craft(**{**BALL, **changes})


def plate(**changes) -> Plate:
    return Plate(**{**PLATE, **changes})


_TMP = Path(tempfile.mkdtemp(prefix="fluidsim-bad-crafts-"))
HEAD = 'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n'
PLATE_TOML = '[[plates]]\nname = "w{i}"\noffset_m = [0, 0, 0]\nnormal = [0, 0, 1]\narea_m2 = 0.5\n'


def toml(text: str, head: str = HEAD) -> Craft:
    """Load ``head + text`` as the craft file ``bad.toml`` (a real file, as users write)."""
    path = _TMP / "bad.toml"
    path.write_text(head + text)
    return Craft.load(path)


def plates_then(text: str, n: int = 2) -> Craft:
    """A file with ``n`` good plates and then ``text`` (a third, bad one: ``plates[n]``)."""
    return toml("".join(PLATE_TOML.format(i=i) for i in range(n)) + text)


def sim_rows() -> list[Row]:
    V = ValueError
    # fmt: off
    return [
        # ---- Simulator(...)
        Row("sim-crafts-int", lambda: Simulator(5), TypeError, ["crafts", "5"]),
        Row("sim-crafts-empty", lambda: Simulator([]), TypeError, ["crafts", "[]"]),
        Row("sim-crafts-name", lambda: Simulator(["uuv"]), TypeError, ["crafts", "'uuv'"]),
        Row("sim-world-str", lambda: new_sim(world="air"), TypeError, ["world", "'air'"]),
        Row("sim-num-envs-0", lambda: new_sim(num_envs=0), V, ["num_envs", "0", "positive"]),
        Row("sim-num-envs-float", lambda: new_sim(num_envs=2.0), V, ["num_envs", "2.0"]),
        Row("sim-num-envs-bool", lambda: new_sim(num_envs=True), V, ["num_envs", "True"]),
        Row("sim-num-envs-npfloat", lambda: new_sim(num_envs=np.float32(2)), V,
            ["num_envs", "2.0"]),
        Row("sim-dt-0", lambda: new_sim(dt=0), V, ["dt", "got 0", "> 0"]),
        Row("sim-dt-neg", lambda: new_sim(dt=-0.01), V, ["dt", "-0.01"]),
        Row("sim-dt-nan", lambda: new_sim(dt=NAN), V, ["dt", "nan"]),
        Row("sim-dt-inf", lambda: new_sim(dt=INF), V, ["dt", "inf"]),
        Row("sim-dt-bool", lambda: new_sim(dt=True), V, ["dt", "True"]),
        Row("sim-dt-str", lambda: new_sim(dt="0.01"), V, ["dt", "'0.01'"]),
        Row("sim-dt-np-nan", lambda: new_sim(dt=np.float32(NAN)), V, ["dt", "nan"]),
        Row("sim-integrator-name", lambda: new_sim(integrator="leapfrog"), V,
            ["integrator", "'leapfrog'", "rk4"]),
        Row("sim-integrator-int", lambda: new_sim(integrator=3), V, ["integrator", "3", "rk2"]),
        Row("sim-dtype-int", lambda: new_sim(dtype=np.int32), V, ["dtype", "int32", "float64"]),
        Row("sim-dtype-f16", lambda: new_sim(dtype="float16"), V, ["dtype", "'float16'"]),
        Row("sim-dtype-word", lambda: new_sim(dtype="fast"), V, ["dtype", "'fast'"]),
        Row("sim-parallel-str", lambda: new_sim(parallel="yes"), V, ["parallel", "'yes'"]),
        Row("sim-wake-int", lambda: new_sim(wake=5), TypeError, ["wake", "5", "WakeField"]),
        Row("sim-shared-kernel-int", lambda: new_sim(shared_kernel=1), TypeError,
            ["shared_kernel", "1"]),
        # ---- reset
        Row("reset-pos-str", lambda: sim().reset(pos="a"), V, ["pos", "'a'", "numbers"]),
        Row("reset-pos-nan", lambda: sim().reset(pos=[0, NAN, 0]), V, ["pos", "nan"]),
        Row("reset-pos-short", lambda: sim().reset(pos=[0, 0]), V,
            ["pos", "[0, 0]", "does not broadcast", "[2, 1, 3]"]),
        Row("reset-pos-bool", lambda: sim().reset(pos=True), V, ["pos", "True"]),
        Row("reset-quat-zero", lambda: sim().reset(quat=(0, 0, 0, 0)), V,
            ["quat", "(0, 0, 0, 0)", "non-zero"]),
        Row("reset-quat-short", lambda: sim().reset(quat=[1, 0, 0]), V, ["quat", "[1, 0, 0]"]),
        Row("reset-lin-vel-inf", lambda: sim().reset(lin_vel=[INF, 0, 0]), V, ["lin_vel", "inf"]),
        Row("reset-ang-vel-none", lambda: sim().reset(ang_vel=None), V, ["ang_vel", "None"]),
        Row("reset-ang-vel-ragged", lambda: sim().reset(ang_vel=[[0, 0], [0]]), V,
            ["ang_vel", "ragged", "[[0, 0], [0]]"]),
        Row("reset-ids-half", lambda: sim().reset(env_ids=[0.5]), V, ["env_ids", "0.5", "[0, 2)"]),
        Row("reset-ids-10", lambda: sim().reset(env_ids=[10]), V,
            ["env_ids", "[10]", "out of range", "[0, 2)"]),
        Row("reset-ids-neg", lambda: sim().reset(env_ids=[-1]), V, ["env_ids", "-1", "[0, 2)"]),
        Row("reset-ids-mask-len", lambda: sim().reset(env_ids=np.array([True])), V,
            ["env_ids", "boolean mask", "(2,)", "(1,)"]),
        Row("reset-ids-scalar", lambda: sim().reset(env_ids=0), V, ["env_ids", "got 0", "list"]),
        Row("reset-ids-str", lambda: sim().reset(env_ids="0"), V, ["env_ids", "'0'"]),
        Row("reset-ids-2d", lambda: sim().reset(env_ids=[[0, 1]]), V, ["env_ids", "[[0, 1]]"]),
        Row("reset-ids-ragged", lambda: sim().reset(env_ids=[[0], [0, 1]]), V,
            ["env_ids", "[[0], [0, 1]]"]),
        # ---- per-body arguments: [2, 3] with 2 environments of 2 bodies could be either
        Row("pair-pos", lambda: pair().reset(pos=np.zeros((2, 3))), V,
            ["pos", "[2, 3]", "ambiguous", "[2, 2, 3]", "[1, 2, 3]"]),
        Row("pair-quat", lambda: pair().reset(quat=np.tile([1.0, 0, 0, 0], (2, 1))), V,
            ["quat", "[2, 4]", "ambiguous", "[2, 2, 4]"]),
        Row("pair-lin-vel", lambda: pair().reset(lin_vel=[[1, 0, 0], [2, 0, 0]]), V,
            ["lin_vel", "[2, 3]", "ambiguous"]),
        Row("pair-ang-vel", lambda: pair().reset(ang_vel=np.ones((2, 3))), V,
            ["ang_vel", "ambiguous", "[2, 2, 3]"]),
        Row("pair-pos-one-env", lambda: pair().reset(pos=np.zeros((2, 3)), env_ids=[0]), V,
            ["pos", "[2, 3]", "ambiguous", "[1, 2, 3]"]),
        Row("pair-force", lambda: pair().set_external_force(np.zeros((2, 3))), V,
            ["force_n", "ambiguous", "[2, 2, 3]"]),
        Row("pair-torque", lambda: pair().set_external_force(0.0, np.zeros((2, 3))), V,
            ["torque_nm", "ambiguous"]),
        Row("pair-pos-3-rows", lambda: pair().reset(pos=np.zeros((3, 3))), V,
            ["pos", "(3, 3)", "does not broadcast", "[2, 2, 3]"]),
        Row("three-inertia-tensor", lambda: three().set_mass_properties(inertia_kgm2=np.eye(3)),
            V, ["inertia_kgm2", "[3, 3]", "ambiguous", "[1, 3, 3]"]),
        # ---- step
        Row("step-controls-str", lambda: sim().step("a"), V, ["controls", "'a'"]),
        Row("step-controls-shape", lambda: sim().step(np.zeros((2, 2))), V,
            ["controls", "(2, 3)", "(2, 2)"]),
        Row("step-controls-nan", lambda: sim().step(np.full((2, 3), NAN)), V,
            ["controls", "nan", "NaN"]),
        Row("step-controls-big", lambda: sim().step(np.full((2, 3), 1.5)), V,
            ["controls", "1.5", "[-1, 1]"]),
        Row("step-controls-object", lambda: sim().step(np.zeros((2, 3), dtype=object)), V,
            ["controls", "object"]),
        Row("step-controls-ragged", lambda: sim().step([[0, 0, 0], [0]]), V,
            ["controls", "ragged", "[[0, 0, 0], [0]]"]),
        Row("step-controls-bool", lambda: sim().step(np.zeros((2, 3), dtype=bool)), V,
            ["controls", "bools"]),
        Row("step-steps-0", lambda: sim().step(steps=0), V, ["steps", "0", "positive"]),
        Row("step-steps-float", lambda: sim().step(steps=1.5), V, ["steps", "1.5"]),
        Row("step-steps-bool", lambda: sim().step(steps=True), V, ["steps", "True"]),
        Row("step-steps-npfloat", lambda: sim().step(steps=np.float64(2)), V, ["steps", "2.0"]),
        # ---- set_external_force, set_wind, set_current, set_clock
        Row("force-str", lambda: sim().set_external_force("x"), V, ["force_n", "'x'"]),
        Row("force-nan", lambda: sim().set_external_force([NAN, 0, 0]), V, ["force_n", "nan"]),
        Row("torque-short", lambda: sim().set_external_force(0.0, [0, 0]), V,
            ["torque_nm", "[0, 0]", "does not broadcast"]),
        Row("force-ids", lambda: sim().set_external_force(0.0, env_ids=[5]), V,
            ["set_external_force", "env_ids", "[5]"]),
        Row("wind-str", lambda: sim().set_wind("x"), V, ["set_wind", "wind_mps", "'x'"]),
        Row("wind-inf", lambda: sim().set_wind([0, INF, 0]), V, ["wind_mps", "inf"]),
        Row("current-short", lambda: sim().set_current([0, 0]), V,
            ["set_current", "current_mps", "[0, 0]"]),
        Row("current-ids", lambda: sim().set_current(0.0, env_ids=[2]), V,
            ["set_current", "env_ids", "[2]"]),
        Row("clock-nan", lambda: sim().set_clock(NAN), V, ["set_clock", "t", "nan"]),
        Row("clock-str", lambda: sim().set_clock("now"), V, ["set_clock", "'now'"]),
        Row("clock-3", lambda: sim().set_clock([0, 1, 2]), V, ["t", "[0, 1, 2]", "[2]"]),
        # ---- set_mass_properties
        Row("mass-neg", lambda: sim().set_mass_properties(mass_kg=-1), V, ["mass_kg", "-1"]),
        Row("mass-0", lambda: sim().set_mass_properties(mass_kg=0.0), V, ["mass_kg", "0.0"]),
        Row("mass-nan", lambda: sim().set_mass_properties(mass_kg=NAN), V, ["mass_kg", "nan"]),
        Row("mass-bool", lambda: sim().set_mass_properties(mass_kg=True), V,
            ["mass_kg", "True"]),
        Row("mass-str", lambda: sim().set_mass_properties(mass_kg="1"), V, ["mass_kg", "'1'"]),
        Row("inertia-triangle", lambda: sim().set_mass_properties(inertia_kgm2=(1, 1, 3)), V,
            ["inertia_kgm2", "triangle", "3.0"]),
        Row("inertia-negative", lambda: sim().set_mass_properties(inertia_kgm2=(1, -1, 1)), V,
            ["inertia_kgm2", "positive definite", "-1"]),
        Row("inertia-asymmetric",
            lambda: sim().set_mass_properties(inertia_kgm2=[[1, 2, 0], [0, 1, 0], [0, 0, 1]]),
            V, ["inertia_kgm2", "symmetric", "[[1, 2, 0]"]),
        Row("com-short", lambda: sim().set_mass_properties(center_of_mass_m=(0, 0)), V,
            ["center_of_mass_m", "(0, 0)", "does not broadcast"]),
        Row("com-nan", lambda: sim().set_mass_properties(center_of_mass_m=[NAN, 0, 0]), V,
            ["center_of_mass_m", "nan"]),
        Row("mass-body-1", lambda: sim().set_mass_properties(mass_kg=1.0, body=1), V,
            ["body", "1", "[0, 1)"]),
        Row("mass-body-float", lambda: sim().set_mass_properties(mass_kg=1.0, body=0.0), V,
            ["body", "0.0"]),
        Row("mass-body-bool", lambda: sim().set_mass_properties(mass_kg=1.0, body=True), V,
            ["body", "True"]),
        Row("mass-ids", lambda: sim().set_mass_properties(mass_kg=1.0, env_ids=[5]), V,
            ["set_mass_properties", "env_ids", "[5]"]),
        # ---- set_sample_scale, set_thrust_scale
        Row("scale-group-unknown", lambda: sim().set_sample_scale("wing", area=2.0), V,
            ["group", "'wing'", "wings"]),
        Row("scale-group-list", lambda: sim().set_sample_scale(["all"], area=2.0), V,
            ["group", "['all']"]),
        Row("scale-area-0", lambda: sim().set_sample_scale("all", area=0), V, ["area", "0"]),
        Row("scale-area-neg", lambda: sim().set_sample_scale("all", area=-1.0), V,
            ["area", "-1.0", "positive"]),
        Row("scale-area-nan", lambda: sim().set_sample_scale("all", area=NAN), V,
            ["area", "nan"]),
        Row("scale-area-str", lambda: sim().set_sample_scale("all", area="big"), V,
            ["area", "'big'"]),
        Row("scale-efficiency-5", lambda: sim().set_sample_scale("all", efficiency=5), V,
            ["efficiency", "5", "[0, 1]"]),
        Row("scale-efficiency-neg", lambda: sim().set_sample_scale("all", efficiency=-1), V,
            ["efficiency", "-1"]),
        Row("scale-efficiency-nan", lambda: sim().set_sample_scale("all", efficiency=NAN), V,
            ["efficiency", "nan"]),
        Row("scale-body-2", lambda: sim().set_sample_scale("all", area=1.0, body=2), V,
            ["body", "2"]),
        Row("thrust-neg", lambda: sub().set_thrust_scale(-1.0), V, ["scale", "-1.0", ">= 0"]),
        Row("thrust-nan", lambda: sub().set_thrust_scale(NAN), V, ["scale", "nan"]),
        Row("thrust-str", lambda: sub().set_thrust_scale("x"), V, ["scale", "'x'"]),
        Row("thrust-none-here", lambda: sim().set_thrust_scale(2.0), V,
            ["paper_airplane", "no thruster"]),
        # ---- set_wake_source
        Row("wake-none-here", lambda: sim().set_wake_source(0, (1, 0, 0, 0), 0), V,
            ["set_wake_source", "no wake"]),
        Row("wake-pos-short", lambda: sub().set_wake_source([0, 0], (1, 0, 0, 0), 0), V,
            ["pos", "[0, 0]", "does not broadcast"]),
        Row("wake-quat-zero", lambda: sub().set_wake_source(0, (0, 0, 0, 0), 0), V,
            ["quat", "(0, 0, 0, 0)", "non-zero"]),
        Row("wake-vel-nan", lambda: sub().set_wake_source(0, (1, 0, 0, 0), [NAN, 0, 0]), V,
            ["lin_vel", "nan"]),
        Row("wake-noise-str", lambda: sub().set_wake_source(0, (1, 0, 0, 0), 0, "x"), V,
            ["noise_offset", "'x'"]),
        Row("wake-ids", lambda: sub().set_wake_source(0, (1, 0, 0, 0), 0, env_ids=[3]), V,
            ["env_ids", "[3]"]),
        # ---- sample_forces, surface_height, get_state / set_state
        Row("forces-env-2", lambda: sim().sample_forces(env_index=2), V,
            ["env_index", "got 2", "[0, 2)"]),
        Row("forces-env-half", lambda: sim().sample_forces(env_index=0.5), V,
            ["env_index", "0.5"]),
        Row("forces-env-neg", lambda: sim().sample_forces(env_index=-1), V, ["env_index", "-1"]),
        Row("forces-controls-short", lambda: sim().sample_forces(np.zeros(2)), V,
            ["controls", "(2,)", "(3,)"]),
        Row("forces-controls-str", lambda: sim().sample_forces("up"), V, ["controls", "'up'"]),
        Row("surface-x-str", lambda: sim().surface_height("a", 0.0), V, ["x", "'a'"]),
        Row("get-state-ids", lambda: sim().get_state(env_ids=[9]), V,
            ["get_state", "env_ids", "[9]"]),
        Row("set-state-int", lambda: sim().set_state(5), V, ["set_state", "snapshot", "int"]),
        Row("set-state-repeat", lambda: sim().set_state(sim().get_state([0, 0]), [0, 0]), V,
            ["set_state", "env_ids", "repeat", "[0, 0]"]),
        Row("set-state-other-layout", lambda: sim().set_state(pair().get_state()), V,
            ["set_state", "snapshot", "st"]),
    ]
    # fmt: on


def world_rows() -> list[Row]:
    V = ValueError
    # fmt: off
    return [
        Row("world-gravity-neg", lambda: World(gravity_mps2=-9.81), V, ["gravity_mps2", "-9.81"]),
        Row("world-gravity-nan", lambda: World(gravity_mps2=NAN), V, ["gravity_mps2", "nan"]),
        Row("world-gravity-str", lambda: World(gravity_mps2="9.81"), V,
            ["gravity_mps2", "'9.81'"]),
        Row("world-gravity-bool", lambda: World(gravity_mps2=True), V, ["gravity_mps2", "True"]),
        Row("world-gm-neg", lambda: World(central_gravity_m3s2=-1.0), V,
            ["central_gravity_m3s2", "-1.0"]),
        Row("world-air-0", lambda: World(air_density_kgm3=0.0), V,
            ["air_density_kgm3", "0.0", "> 0"]),
        Row("world-water-density-neg", lambda: World(water_density_kgm3=-1), V,
            ["water_density_kgm3", "-1"]),
        Row("world-water-int", lambda: World(water=1), V, ["water", "got 1", "True or False"]),
        Row("world-water-str", lambda: World(water="yes"), V, ["water", "'yes'"]),
        Row("world-wind-short", lambda: World(wind_mps=(1, 2)), V, ["wind_mps", "(1, 2)"]),
        Row("world-wind-nan", lambda: World(wind_mps=(NAN, 0, 0)), V, ["wind_mps[0]", "nan"]),
        Row("world-current-str", lambda: World(current_mps="fast"), V,
            ["current_mps", "'fast'"]),
        Row("world-blend-neg", lambda: World(surface_blend_m=-0.1), V,
            ["surface_blend_m", "-0.1"]),
        Row("world-vmax-0", lambda: World(max_fluid_speed_mps=0), V,
            ["max_fluid_speed_mps", "0"]),
        Row("world-fmax-inf", lambda: World(max_sample_force_n=INF), V,
            ["max_sample_force_n", "inf"]),
        Row("world-spin-0", lambda: World(tetra_rigid_spin_rad=0), V,
            ["tetra_rigid_spin_rad", "0"]),
        Row("world-spin-nan", lambda: World(tetra_rigid_spin_rad=NAN), V,
            ["tetra_rigid_spin_rad", "nan"]),
        Row("world-passes-0", lambda: World(contact_passes=0), V, ["contact_passes", "0"]),
        Row("world-passes-float", lambda: World(contact_passes=1.5), V,
            ["contact_passes", "1.5", "integer"]),
        Row("world-ground-str", lambda: World(ground="flat"), V, ["ground", "'flat'"]),
        Row("world-swell-dry", lambda: World(swell=[(0.5, 40.0)]), V,
            ["swell", "water=True", "water=False"]),
        Row("world-swell-int", lambda: World(water=True, swell=5), V, ["swell", "5"]),
        Row("world-swell-steep", lambda: World(water=True, swell=[(1.0, 2.0)]), V,
            ["steepness", "amplitude_m=1.0", "wavelength_m=2.0"]),
        Row("world-swell-missing", lambda: World(water=True, swell=[{"amplitude_m": 0.5}]), V,
            ["swell[0]", "wavelength_m", "missing"]),
        Row("world-swell-5-tuple", lambda: World(water=True, swell=[(0.5, 40, 90, 0, 7)]), V,
            ["swell[0]", "(0.5, 40, 90, 0, 7)"]),
        Row("world-swell-5-waves", lambda: World(water=True, swell=[(0.1, 40.0)] * 5), V,
            ["swell", "5 waves", "4"]),
        Row("world-swell-key", lambda: World(water=True, swell=[{"amp": 1, "wavelength_m": 9}]),
            V, ["swell[0]", "'amp'", "amplitude_m"]),
        # ---- Ground
        Row("ground-height-nan", lambda: Ground(height_m=NAN), V, ["Ground", "height_m", "nan"]),
        Row("ground-height-str", lambda: Ground(height_m="0"), V, ["height_m", "'0'"]),
        Row("ground-restitution", lambda: Ground(restitution=1.5), V,
            ["restitution", "1.5", "[0, 1]"]),
        Row("ground-restitution-bool", lambda: Ground(restitution=True), V,
            ["restitution", "True"]),
        Row("ground-friction-neg", lambda: Ground(friction=-0.1), V, ["friction", "-0.1"]),
        Row("ground-spacing-0", lambda: Ground(spacing_m=0), V, ["spacing_m", "0", "> 0"]),
        Row("ground-origin-short", lambda: Ground(origin_m=(0,)), V, ["origin_m", "(0,)"]),
        Row("ground-origin-nan", lambda: Ground(origin_m=(0, NAN)), V, ["origin_m[1]", "nan"]),
        Row("ground-heights-row", lambda: Ground(heights_m=[[0, 1]]), V,
            ["heights_m", "(1, 2)", ">= 2"]),
        Row("ground-heights-nan", lambda: Ground(heights_m=[[0, NAN], [0, 0]]), V,
            ["heights_m", "nan"]),
        Row("ground-heights-str", lambda: Ground(heights_m="hills"), V,
            ["heights_m", "'hills'"]),
        # ---- SwellWave
        Row("swell-amplitude-neg", lambda: SwellWave(-1.0, 40.0), V, ["amplitude_m", "-1.0"]),
        Row("swell-wavelength-0", lambda: SwellWave(0.5, 0.0), V, ["wavelength_m", "0.0"]),
        Row("swell-direction-nan", lambda: SwellWave(0.5, 40.0, NAN), V,
            ["direction_deg", "nan"]),
        Row("swell-phase-str", lambda: SwellWave(0.5, 40.0, 0.0, "0"), V, ["phase_rad", "'0'"]),
        Row("swell-amplitude-bool", lambda: SwellWave(True, 40.0), V, ["amplitude_m", "True"]),
        Row("swell-steep", lambda: SwellWave(5.0, 10.0), V,
            ["steepness", "amplitude_m=5.0", "wavelength_m=10.0"]),
        # ---- WakeField
        Row("wake-length-0", lambda: WakeField(length_m=0), V, ["length_m", "0"]),
        Row("wake-radius-neg", lambda: WakeField(radius_m=-1.0), V, ["radius_m", "-1.0"]),
        Row("wake-squat", lambda: WakeField(length_m=4.0, radius_m=3.0), V,
            ["length_m", "4.0", "radius_m", "3.0"]),
        Row("wake-screws-3", lambda: WakeField(screws=3), V, ["screws", "3", "[1, 2]"]),
        Row("wake-screws-float", lambda: WakeField(screws=1.0), V, ["screws", "1.0"]),
        Row("wake-sense-0", lambda: WakeField(pair_sense=0), V, ["pair_sense", "0", "-1"]),
        Row("wake-sense-bool", lambda: WakeField(pair_sense=True), V, ["pair_sense", "True"]),
        Row("wake-sense-float", lambda: WakeField(pair_sense=1.0), V, ["pair_sense", "1.0"]),
        Row("wake-noise-neg", lambda: WakeField(noise=-0.1), V, ["noise", "-0.1"]),
        Row("wake-dipoles-0", lambda: WakeField(dipoles=0), V, ["dipoles", "0", "[1, 32]"]),
        Row("wake-dipoles-64", lambda: WakeField(dipoles=64), V, ["dipoles", "64"]),
        Row("wake-displacement-int", lambda: WakeField(displacement=1), V,
            ["displacement", "1", "True or False"]),
        Row("wake-circulation-nan", lambda: WakeField(circulation=NAN), V,
            ["circulation", "nan"]),
        Row("wake-core-0", lambda: WakeField(core_radius_m=0.0), V, ["core_radius_m", "0.0"]),
        Row("wake-replace-unknown", lambda: WakeField().replace(speed=1), V,
            ["unknown", "speed", "length_m"]),
        Row("wake-points-str",
            lambda: WakeField().velocity("a", (0, 0, 0), (1, 0, 0, 0), (1, 0, 0)), V,
            ["points", "'a'"]),
        Row("wake-points-shape",
            lambda: WakeField().velocity([[0, 0]], (0, 0, 0), (1, 0, 0, 0), (1, 0, 0)), V,
            ["points", "[N, 3]", "[1, 2]"]),
        Row("wake-sub-quat-zero",
            lambda: WakeField().velocity([0, 0, 0], (0, 0, 0), (0, 0, 0, 0), (1, 0, 0)), V,
            ["sub_quat", "(0, 0, 0, 0)"]),
        Row("wake-sub-pos-nan",
            lambda: WakeField().velocity([0, 0, 0], (NAN, 0, 0), (1, 0, 0, 0), (1, 0, 0)), V,
            ["sub_pos", "nan"]),
        Row("wake-sub-vel-str",
            lambda: WakeField().velocity([0, 0, 0], (0, 0, 0), (1, 0, 0, 0), "fast"), V,
            ["sub_lin_vel", "'fast'"]),
    ]
    # fmt: on


def craft_rows() -> list[Row]:
    C = CraftError
    # fmt: off
    return [
        # ---- Craft(...) and its parts, in code
        Row("craft-name-int", lambda: craft(name=5), C, ["name", "5", "string"]),
        Row("craft-mass-0", lambda: craft(mass_kg=0), C, ["mass_kg", "0", "> 0"]),
        Row("craft-mass-nan", lambda: craft(mass_kg=NAN), C, ["mass_kg", "nan"]),
        Row("craft-mass-str", lambda: craft(mass_kg="1"), C, ["mass_kg", "'1'"]),
        Row("craft-mass-bool", lambda: craft(mass_kg=True), C, ["mass_kg", "True"]),
        Row("craft-inertia-str", lambda: craft(inertia_kgm2="abc"), C, ["inertia_kgm2", "'abc'"]),
        Row("craft-inertia-triangle", lambda: craft(inertia_kgm2=(1, 1, 3)), C,
            ["inertia_kgm2", "triangle", "3.0"]),
        Row("craft-inertia-short", lambda: craft(inertia_kgm2=(1, 2)), C,
            ["inertia_kgm2", "(1, 2)"]),
        Row("craft-inertia-bools", lambda: craft(inertia_kgm2=(True, True, True)), C,
            ["inertia_kgm2", "(True, True, True)"]),
        Row("craft-plates-int", lambda: craft(plates=5), C, ["plates", "5", "list"]),
        Row("craft-plates-item", lambda: craft(plates=[5]), C, ["plates[0]", "5", "table"]),
        Row("craft-restitution", lambda: craft(restitution=2), C, ["restitution", "2"]),
        Row("craft-friction-neg", lambda: craft(friction=-1), C, ["friction", "-1"]),
        Row("craft-runaway-speed-0", lambda: craft(runaway_speed_mps=0.0), C,
            ["runaway_speed_mps", "0.0", "> 0"]),
        Row("craft-runaway-rate-word", lambda: craft(runaway_rate_dps="fast"), C,
            ["runaway_rate_dps", "'fast'", "> 0"]),
        Row("craft-runaway-speed-nan", lambda: craft(runaway_speed_mps=float("nan")), C,
            ["runaway_speed_mps", "nan"]),
        Row("craft-groups-int", lambda: craft(groups=5), C, ["groups", "5"]),
        Row("craft-groups-str", lambda: craft(plates=[plate()], groups={"g": "w"}), C,
            ["groups.g", "'w'"]),
        Row("craft-groups-unknown", lambda: craft(plates=[plate()], groups={"g": ["v"]}), C,
            ["group 'g'", "['v']"]),
        Row("craft-description-int", lambda: craft(description=3), C, ["description", "3"]),
        Row("craft-com-str", lambda: craft().with_center_of_mass("x"), C, ["offset_m", "'x'"]),
        Row("plate-area-neg", lambda: plate(area_m2=-1), C, ["plate 'w'", "area_m2", "-1"]),
        Row("plate-normal-zero", lambda: plate(normal=(0, 0, 0)), C,
            ["normal", "(0, 0, 0)", "non-zero"]),
        Row("plate-efficiency-2", lambda: plate(efficiency=2), C, ["efficiency", "2", "[0, 1]"]),
        Row("plate-name-int", lambda: plate(name=3), C, ["name", "3"]),
        Row("plate-offset-nan", lambda: plate(offset_m=(0, NAN, 0)), C, ["offset_m[1]", "nan"]),
        # one-sided plates and skin friction (issue 20)
        Row("plate-one-sided-int", lambda: plate(one_sided=1), C,
            ["plate 'w'", "one_sided", "1", "true or false"]),
        Row("plate-friction-cf-neg", lambda: plate(friction_coefficient=-0.003), C,
            ["friction_coefficient", "-0.003", "[0, 0.1]"]),
        Row("plate-friction-cf-big", lambda: plate(friction_coefficient=0.5), C,
            ["friction_coefficient", "0.5", "[0, 0.1]"]),
        Row("plate-friction-cf-nan", lambda: plate(friction_coefficient=NAN), C,
            ["friction_coefficient", "nan"]),
        Row("plate-friction-line", lambda: plate(friction_line="prandtl", friction_length_m=1.0),
            C, ["friction_line", "'prandtl'", "ittc1957"]),
        Row("plate-friction-line-no-length", lambda: plate(friction_line="ittc1957"), C,
            ["friction_line", "'ittc1957'", "needs friction_length_m"]),
        Row("plate-friction-length-alone", lambda: plate(friction_length_m=2.0), C,
            ["friction_length_m", "2.0", "friction_line"]),
        Row("plate-friction-length-0",
            lambda: plate(friction_line="ittc1957", friction_length_m=0.0), C,
            ["friction_length_m", "0.0", "[0.0001, 1000]"]),
        Row("plate-friction-area-alone", lambda: plate(friction_area_m2=1.0), C,
            ["friction_area_m2", "1.0", "friction_coefficient"]),
        Row("plate-friction-area-neg",
            lambda: plate(friction_coefficient=0.003, friction_area_m2=-1.0), C,
            ["friction_area_m2", "-1.0", "> 0"]),
        Row("cylinder-axis-str", lambda: Cylinder("c", (0, 0, 0), "x", 0.1), C,
            ["cylinder 'c'", "axis", "'x'"]),
        Row("buoyancy-kind", lambda: Buoyancy("b", (0, 0, 0), "balloon", volume_m3=1.0), C,
            ["kind", "'balloon'", "'volume'"]),
        Row("thruster-max-nan", lambda: Thruster("t", (0, 0, 0), (1, 0, 0), NAN), C,
            ["thruster 't'", "max_thrust_n", "nan"]),
        Row("thruster-control-int", lambda: Thruster("t", (0, 0, 0), (1, 0, 0), 5.0, 0.0, 3), C,
            ["control", "3", "string"]),
        Row("shape-half-neg", lambda: Shape("s", "box", half_extents_m=(1, -1, 1)), C,
            ["half_extents_m[1]", "-1"]),
        Row("shape-radius-0", lambda: Shape("s", "sphere", radius_m=0), C, ["radius_m", "0"]),
        Row("control-deflection", lambda: Control("c", max_deflection_deg=120), C,
            ["max_deflection_deg", "120", "[0, 90]"]),
        Row("control-surfaces-int", lambda: Control("c", surfaces=5), C, ["surfaces", "5"]),
        Row("control-gain-str", lambda: Control("c", surfaces=[{"sample": "w", "gain": "x"}]),
            C, ["surfaces[0].gain", "'x'"]),
        # ---- craft files: the file, the table path and the value
        Row("toml-plates-int", lambda: toml("plates = 5\n"), C,
            ["bad.toml", "plates", "5", "[[plates]]"]),
        Row("toml-plates-str", lambda: toml('plates = "wing"\n'), C,
            ["bad.toml", "plates", "'wing'"]),
        Row("toml-plates-table", lambda: toml('[plates]\nname = "w"\n'), C,
            ["bad.toml", "plates", "{'name': 'w'}", "[[plates]]"]),
        Row("toml-area-str",
            lambda: plates_then('[[plates]]\nname = "w"\noffset_m = [0, 0, 0]\n'
                                'normal = [0, 0, 1]\narea_m2 = "big"\n'),
            C, ["bad.toml", "plates[2].area_m2", "'big'"]),
        Row("toml-area-bool",
            lambda: toml('[[plates]]\nname = "w"\noffset_m = [0, 0, 0]\nnormal = [0, 0, 1]\n'
                         "area_m2 = true\n"),
            C, ["bad.toml", "plates[0].area_m2", "True", "number"]),
        Row("toml-area-neg",
            lambda: plates_then('[[plates]]\nname = "w"\noffset_m = [0, 0, 0]\n'
                                "normal = [0, 0, 1]\narea_m2 = -0.5\n"),
            C, ["bad.toml", "plates[2]", "area_m2", "-0.5"]),
        Row("toml-offset-short",
            lambda: toml('[[plates]]\nname = "w"\noffset_m = [0, 0]\nnormal = [0, 0, 1]\n'
                         "area_m2 = 0.5\n"),
            C, ["bad.toml", "plates[0].offset_m", "[0, 0]", "3 numbers"]),
        Row("toml-normal-str",
            lambda: toml('[[plates]]\nname = "w"\noffset_m = [0, 0, 0]\nnormal = "up"\n'
                         "area_m2 = 0.5\n"),
            C, ["bad.toml", "plates[0].normal", "'up'"]),
        Row("toml-plate-name-int",
            lambda: toml("[[plates]]\nname = 3\noffset_m = [0, 0, 0]\nnormal = [0, 0, 1]\n"
                         "area_m2 = 0.5\n"),
            C, ["bad.toml", "plates[0].name", "3", "string"]),
        Row("toml-plate-unknown", lambda: toml(PLATE_TOML.format(i=0) + "span = 2\n"), C,
            ["bad.toml", "plates[0].span", "2", "unknown key"]),
        Row("toml-one-sided-str", lambda: toml(PLATE_TOML.format(i=0) + 'one_sided = "yes"\n'),
            C, ["bad.toml", "plates[0].one_sided", "'yes'", "true or false"]),
        Row("toml-friction-line-int", lambda: plates_then(
            PLATE_TOML.format(i=2) + "friction_line = 1957\nfriction_length_m = 3.0\n"),
            C, ["bad.toml", "plates[2].friction_line", "1957", "string"]),
        Row("toml-friction-cf-neg",
            lambda: plates_then(PLATE_TOML.format(i=2) + "friction_coefficient = -1.0\n"),
            C, ["bad.toml", "plates[2]", "friction_coefficient", "-1.0"]),
        Row("toml-plate-missing",
            lambda: toml('[[plates]]\nname = "w"\noffset_m = [0, 0, 0]\narea_m2 = 0.5\n'), C,
            ["bad.toml", "plates[0]", "missing", "normal"]),
        Row("toml-mass-str", lambda: toml('mass_kg = "heavy"\n', head='name = "x"\n'
                                          "inertia_kgm2 = [1, 1, 1]\n"),
            C, ["bad.toml", "mass_kg", "'heavy'"]),
        Row("toml-mass-bool", lambda: toml("mass_kg = true\n", head='name = "x"\n'
                                           "inertia_kgm2 = [1, 1, 1]\n"),
            C, ["bad.toml", "mass_kg", "True"]),
        Row("toml-inertia-short", lambda: toml("inertia_kgm2 = [1, 2]\n",
                                               head='name = "x"\nmass_kg = 1.0\n'),
            C, ["bad.toml", "inertia_kgm2", "[1, 2]"]),
        Row("toml-inertia-str", lambda: toml('inertia_kgm2 = "big"\n',
                                             head='name = "x"\nmass_kg = 1.0\n'),
            C, ["bad.toml", "inertia_kgm2", "'big'"]),
        Row("toml-unknown-top", lambda: toml('colour = "red"\n'), C,
            ["bad.toml", "colour", "valid keys"]),
        Row("toml-missing-mass", lambda: toml("", head='name = "x"\ninertia_kgm2 = [1, 1, 1]\n'),
            C, ["bad.toml", "missing", "mass_kg"]),
        Row("toml-name-int", lambda: toml("", head="name = 5\nmass_kg = 1.0\n"
                                          "inertia_kgm2 = [1, 1, 1]\n"),
            C, ["bad.toml", "name", "5", "string"]),
        Row("toml-surfaces-int", lambda: toml('[[controls]]\nname = "c"\nsurfaces = 5\n'), C,
            ["bad.toml", "controls[0].surfaces", "5"]),
        Row("toml-gain-str",
            lambda: toml('[[controls]]\nname = "c"\nsurfaces = [{sample = "w", gain = "x"}]\n'),
            C, ["bad.toml", "controls[0].surfaces[0].gain", "'x'"]),
        Row("toml-surface-sample-int",
            lambda: toml('[[controls]]\nname = "c"\nsurfaces = [{sample = 3}]\n'), C,
            ["bad.toml", "controls[0].surfaces[0].sample", "3"]),
        Row("toml-surface-int", lambda: toml('[[controls]]\nname = "c"\nsurfaces = [4]\n'), C,
            ["bad.toml", "controls[0].surfaces[0]", "4", "table"]),
        Row("toml-deflection-str",
            lambda: toml('[[controls]]\nname = "c"\nmax_deflection_deg = "x"\n'), C,
            ["bad.toml", "controls[0].max_deflection_deg", "'x'"]),
        Row("toml-thruster-control-int",
            lambda: toml('[[thrusters]]\nname = "p"\noffset_m = [0, 0, 0]\n'
                         "direction = [1, 0, 0]\nmax_thrust_n = 5\ncontrol = 5\n"),
            C, ["bad.toml", "thrusters[0].control", "5"]),
        Row("toml-volume-str",
            lambda: toml('[[buoyancy]]\nname = "b"\noffset_m = [0, 0, 0]\nkind = "volume"\n'
                         'volume_m3 = "x"\n'),
            C, ["bad.toml", "buoyancy[0].volume_m3", "'x'"]),
        Row("toml-radius-bool",
            lambda: toml('[[shapes]]\nname = "s"\nkind = "sphere"\nradius_m = true\n'), C,
            ["bad.toml", "shapes[0].radius_m", "True"]),
        Row("toml-half-extents-short",
            lambda: toml('[[shapes]]\nname = "s"\nkind = "box"\nhalf_extents_m = [1, 1]\n'), C,
            ["bad.toml", "shapes[0].half_extents_m", "[1, 1]"]),
        Row("toml-cylinder-area-neg",
            lambda: toml('[[cylinders]]\nname = "c0"\noffset_m = [0, 0, 0]\naxis = [1, 0, 0]\n'
                         'area_m2 = 0.1\n[[cylinders]]\nname = "c1"\noffset_m = [0, 0, 0]\n'
                         "axis = [1, 0, 0]\narea_m2 = -1\n"),
            C, ["bad.toml", "cylinders[1]", "area_m2", "-1"]),
        Row("toml-groups-int", lambda: toml("groups = 5\n"), C, ["bad.toml", "groups", "5"]),
        Row("toml-groups-str", lambda: toml(PLATE_TOML.format(i=0), head=HEAD
                                            + 'groups = { g = "w0" }\n'),
            C, ["bad.toml", "groups.g", "'w0'"]),
        Row("toml-invalid", lambda: toml("mass_kg = = 1\n"), C, ["bad.toml", "not valid TOML"]),
        Row("toml-no-file", lambda: Craft.load(_TMP / "none.toml"), C,
            ["none.toml", "does not exist"]),
        Row("craft-unknown-name", lambda: Craft.load("zeppelin"), C,
            ["'zeppelin'", "paper_airplane"]),
        # ---- the generators of shipped crafts
        Row("hull-stations-float", lambda: VHull(stations=1.5), ValueError,
            ["VHull", "stations", "1.5"]),
        Row("hull-length-nan", lambda: VHull(length_m=NAN), ValueError, ["length_m", "nan"]),
        Row("hull-astern-positive", lambda: VHull(min_thrust_n=100.0), ValueError,
            ["min_thrust_n", "100.0", "<= 0"]),
        Row("hull-gyradius-short", lambda: VHull(gyradius_m=(1.0, 2.0)), ValueError,
            ["gyradius_m", "(1.0, 2.0)"]),
        Row("hull-deadrise-90", lambda: VHull(deadrise_deg=90), ValueError,
            ["deadrise_deg", "90"]),
        Row("buoy-radius-str", lambda: MarkerBuoy(radius_m="x"), ValueError,
            ["MarkerBuoy", "radius_m", "'x'"]),
        Row("buoy-mass-nan", lambda: MarkerBuoy(mass_kg=NAN), ValueError, ["mass_kg", "nan"]),
        Row("buoy-restitution", lambda: MarkerBuoy(restitution=2.0), ValueError,
            ["restitution", "2.0", "[0, 1]"]),
    ]
    # fmt: on


ROWS = sim_rows() + world_rows() + craft_rows()


@pytest.mark.parametrize("row", params(ROWS))
def test_bad_physics_input_is_named(row):
    check(row)


# --------------------------------------------------------------------------------------------
# NumPy scalars are numbers wherever a number is taken

f32, f64, i64, i32 = np.float32, np.float64, np.int64, np.int32


def _simulator_steps():
    """A simulator built, reset, changed and stepped with NumPy scalars throughout. The
    dart over a ground at rk2: the kernel PaperAirplane-v0 compiles, so no new compile."""
    world = World(
        gravity_mps2=f32(9.81),
        air_density_kgm3=f64(1.225),
        ground=Ground(height_m=i64(0), restitution=f32(0.5), friction=f64(0.5)),
    )
    s = Simulator(
        dart(),
        world,
        num_envs=i64(2),
        dt=f32(1 / 120),
        integrator="rk2",
        dtype="float64",
        parallel=np.bool_(False),
    )
    s.reset(
        pos=np.array([0, 0, 5], f32),
        lin_vel=(f32(5.0), i64(0), f64(0)),
        env_ids=np.array([0, 1], i32),
    )
    s.reset(pos=(i64(1), i64(0), f32(6.0)), env_ids=np.array([False, True]))
    s.set_wind((f32(1.0), 0, 0), env_ids=[i64(0)])
    s.set_clock(f32(3.0))
    s.set_external_force(f32(0.0), torque_nm=(f64(0), 0, 0))
    s.set_mass_properties(
        mass_kg=f32(0.005), center_of_mass_m=(f32(0.001), 0, 0), env_ids=[i64(1)], body=i64(0)
    )
    s.set_sample_scale("wings", area=f32(1.1), efficiency=f64(1.0), env_ids=np.array([1], i32))
    s.step(np.full((2, 3), f32(0.1)), steps=i64(2))
    s.sample_forces(np.zeros(3, f32), env_index=i64(1))
    s.set_state(s.get_state(np.array([0], i64)), env_ids=[i32(1)])
    assert s.dt == float(f32(1 / 120)) and np.isfinite(s.pos).all()


def _craft_from_numbers():
    c = Craft(
        name="np",
        mass_kg=f32(1.0),
        inertia_kgm2=np.array([1, 2, 3], f32),
        plates=[
            Plate(
                "w",
                (f32(0), i64(0), 0.0),
                np.array([0, 0, 1], f64),
                f32(0.5),
                efficiency=f64(0.5),
                hinge_axis=(i32(0), 1, 0),
            )
        ],
        cylinders=[
            {"name": "c", "offset_m": (0, 0, 0), "axis": (i64(1), 0, 0), "area_m2": f32(0.1)}
        ],
        thrusters=[
            Thruster("t", (0, 0, 0), (1, 0, 0), f32(5.0), min_thrust_n=i64(-1), control="c")
        ],
        controls=[
            Control("c", max_deflection_deg=i64(20), surfaces=[{"sample": "w", "gain": f32(-1.0)}])
        ],
        shapes=[Shape("s", "box", center_m=(f32(0), 0, 0), half_extents_m=(f32(1), i64(1), 1))],
        restitution=f32(0.3),
        friction=i64(1),
    )
    assert c.mass_kg == 1.0 and c.plates[0].area_m2 == 0.5
    return c.with_center_of_mass((f32(0.01), 0, 0))


def _world_stores_floats():
    """A NumPy scalar is checked and stored as the Python number: numba then compiles one
    type per parameter."""
    world = World(gravity_mps2=f32(9.81), contact_passes=i64(2), water=np.bool_(True))
    assert type(world.gravity_mps2) is float and type(world.contact_passes) is int
    assert type(world.water) is bool


# fmt: off
GOOD = {
    "world": lambda: World(gravity_mps2=f32(9.81), central_gravity_m3s2=i64(0),
                           water=np.bool_(True), water_density_kgm3=f64(1000),
                           wind_mps=np.array([1, 0, 0], f32),
                           current_mps=(i32(0), f32(0.5), 0), surface_blend_m=f32(0.1),
                           max_fluid_speed_mps=i64(100), tetra_rigid_spin_rad=f32(0.1),
                           contact_passes=i64(2), swell=[(f32(0.5), i64(40), f64(90))]),
    "world-stores-floats": _world_stores_floats,
    "ground": lambda: Ground(height_m=i64(0), heights_m=np.ones((2, 2), f32), spacing_m=f32(2),
                             origin_m=(i64(0), f32(1)), restitution=f32(0.5), friction=i32(1)),
    "swell-wave": lambda: SwellWave(f32(0.5), i64(40), direction_deg=i32(90), phase_rad=f64(1)),
    "wake-field": lambda: WakeField(length_m=f32(40), radius_m=i64(3), screws=i64(2),
                                    pair_sense=i64(-1), dipoles=i32(8), noise=f32(0.1),
                                    displacement=np.bool_(True), screw_x_m=f64(-20)),
    "wake-velocity": lambda: WakeField().velocity(np.zeros((2, 3), f32), (f32(0), 0, 0),
                                                  np.array([1, 0, 0, 0], i64), (f32(2), 0, 0)),
    "craft": _craft_from_numbers,
    "craft-from-dict": lambda: Craft.from_dict({"name": "d", "mass_kg": i64(2),
                                                "inertia_kgm2": [f32(1), f32(1), f32(1)]}),
    "hull": lambda: VHull(length_m=f32(5.0), stations=i64(8), strips=i32(2)),
    "buoy": lambda: MarkerBuoy(radius_m=f32(0.4), mass_kg=i64(40)),
    "simulator": _simulator_steps,
}
# fmt: on


@pytest.mark.parametrize("name", sorted(GOOD))
def test_numpy_scalars_are_numbers_to_the_physics(name):
    GOOD[name]()
