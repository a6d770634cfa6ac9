"""Craft files: loading, building in code, and refusal of bad data with a message naming it."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, CraftError, Plate, Simulator, World
from fluidsim_envs.physics.craft import available

BOX = dict(name="box", mass_kg=1.0, inertia_kgm2=[1.0, 2.0, 3.0])


def write(tmp_path, text):
    path = tmp_path / "c.toml"
    path.write_text(text)
    return path


def test_shipped_crafts_load():
    assert "paper_airplane" in available()
    for name in available():
        craft = Craft.load(name)
        assert craft.mass_kg > 0
    plane = Craft.load("paper_airplane")
    assert plane.control_names == ("aileron", "elevator", "rudder")
    assert np.allclose(plane.inertia_tensor, np.diag(plane.inertia_kgm2))


def test_craft_in_code_defaults_to_free_body():
    box = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 2.0, 3.0))
    assert box.num_samples == 0 and box.control_names == ()
    full = Craft(
        name="t", mass_kg=1.0, inertia_kgm2=[[2.0, 0.1, 0.0], [0.1, 2.0, 0.0], [0.0, 0.0, 3.0]]
    )
    assert full.inertia_tensor[0, 1] == 0.1


def test_directions_are_normalized():
    p = Plate("w", (0, 0, 0), (0.0, 0.0, 2.0), 0.1)
    assert p.normal == (0.0, 0.0, 1.0)


@pytest.mark.parametrize(
    "text, message",
    [
        ('name = "x"\nmass_kg = 1.0\n', "missing required key(s) ['inertia_kgm2']"),
        (
            'name = "x"\nmass_kg = -1.0\ninertia_kgm2 = [1, 1, 1]\n',
            "mass_kg must be a finite number > 0, got -1.0",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\ncolour = "red"\n',
            "unknown key(s) ['colour']",
        ),
        ('name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 3]\n', "triangle inequality"),
        ('name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, -1, 1]\n', "positive definite"),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[plates]]\nname = "w"\n'
            "offset_m = [0, 0, 0]\nnormal = [0, 0, 1]\narea_m2 = -0.5\n",
            "area_m2 must be a finite number > 0, got -0.5",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[plates]]\nname = "w"\n'
            "offset_m = [0, 0, 0]\nnormal = [0, 0, 0]\narea_m2 = 0.5\n",
            "normal must be a non-zero",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[plates]]\nname = "w"\n'
            "offset_m = [0, 0, 0]\narea_m2 = 0.5\n",
            "plates[0]: missing required key(s) ['normal']",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[plates]]\nname = "w"\n'
            "offset_m = [0, 0, 0]\nnormal = [0, 0, 1]\narea_m2 = 0.5\nspan = 2\n",
            "unknown key(s) ['span']",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[controls]]\nname = "elevator"\n'
            'surfaces = [{sample = "tail"}]\n',
            "drives 'tail', which is not a plate",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[buoyancy]]\nname = "b"\n'
            'offset_m = [0, 0, 0]\nkind = "balloon"\nvolume_m3 = 1\n',
            "kind must be 'volume' or 'area'",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[thrusters]]\nname = "p"\n'
            'offset_m = [0, 0, 0]\ndirection = [1, 0, 0]\nmax_thrust_n = 5\ncontrol = "gas"\n',
            "bound to unknown control 'gas'",
        ),
        (  # control 0 is no thrust: a range that does not hold 0 has no meaning
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[thrusters]]\nname = "p"\n'
            "offset_m = [0, 0, 0]\ndirection = [1, 0, 0]\nmax_thrust_n = 5\nmin_thrust_n = 1\n",
            "min_thrust_n must be <= 0 (astern; control 0 is no thrust), got 1.0",
        ),
        (
            'name = "x"\nmass_kg = 1.0\ninertia_kgm2 = [1, 1, 1]\n[[thrusters]]\nname = "p"\n'
            "offset_m = [0, 0, 0]\ndirection = [1, 0, 0]\nmax_thrust_n = -5\n",
            "max_thrust_n must be >= 0 (ahead), got -5.0",
        ),
    ],
)
def test_bad_craft_file_is_refused_with_a_clear_message(tmp_path, text, message):
    with pytest.raises(CraftError) as err:
        Craft.load(write(tmp_path, text))
    assert message in str(err.value)
    assert "c.toml" in str(err.value)  # the file is named


def test_unknown_craft_name_lists_shipped_ones():
    with pytest.raises(CraftError, match="paper_airplane"):
        Craft.load("zeppelin")


def test_simulator_refuses_bad_arguments():
    box = Craft(**BOX)
    with pytest.raises(ValueError, match="unknown integrator 'leapfrog'"):
        Simulator(box, World(), integrator="leapfrog")
    with pytest.raises(ValueError, match="num_envs must be a positive integer, got 0"):
        Simulator(box, World(), num_envs=0)
    with pytest.raises(ValueError, match="dt must be"):
        Simulator(box, World(), dt=-0.1)
    with pytest.raises(ValueError, match="dtype"):
        Simulator(box, World(), dtype=np.int32)
    with pytest.raises(ValueError, match="air_density_kgm3 must be a finite number > 0"):
        World(air_density_kgm3=0.0)


def test_simulator_refuses_bad_controls():
    plane = Craft.load("paper_airplane")
    sim = Simulator(plane, World(), num_envs=2)
    with pytest.raises(ValueError, match=r"shape \(2, 3\).*got \(2, 2\)"):
        sim.step(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="NaN"):
        sim.step(np.full((2, 3), np.nan))
    with pytest.raises(ValueError, match=r"\[-1, 1\]"):
        sim.step(np.full((2, 3), 1.5))
    with pytest.raises(ValueError, match="steps must be a positive integer"):
        sim.step(steps=0)
    with pytest.raises(ValueError, match="env_ids"):
        sim.reset(env_ids=[5])
    with pytest.raises(ValueError, match="quat must be non-zero"):
        sim.reset(quat=(0, 0, 0, 0))
