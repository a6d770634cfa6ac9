"""SCENES is the one list of scenes: gym's registry matches it, each scene's description hangs
together, generic code names no scene, layouts are declared once, and the old import paths
still work (for one release)."""

import ast
import dataclasses
import importlib
import re
from pathlib import Path

import gymnasium as gym
import pytest
from gymnasium.envs.registration import load_env_creator

import fluidsim_envs
from fluidsim_envs.scenes import SCENES, Scene
from fluidsim_envs.scenes.layout import index

PACKAGE = Path(fluidsim_envs.__file__).parent


def test_gym_registry_is_scenes():
    registered = sorted(k for k in gym.registry if k.startswith("fluidsim/"))
    assert registered == sorted(SCENES)
    for scene in SCENES.values():
        spec = gym.spec(scene.id)
        assert load_env_creator(spec.entry_point) is scene.env_cls
        assert load_env_creator(spec.vector_entry_point) is scene.vector_cls
        assert spec.entry_point.startswith("fluidsim_envs.scenes.")


def test_every_scene_package_is_registered():
    # a scene package whose SCENE is missing from SCENES would never be registered with gym
    packages = [p.name for p in (PACKAGE / "scenes").iterdir() if (p / "__init__.py").exists()]
    assert packages, "no scene packages found"
    registered = {scene.env_cls.__module__.split(".")[2] for scene in SCENES.values()}
    assert sorted(packages) == sorted(registered)
    for name in packages:
        pkg = importlib.import_module(f"fluidsim_envs.scenes.{name}")
        assert pkg.SCENE in SCENES.values(), name


def test_each_scene_lives_in_its_package():
    for scene in SCENES.values():
        package = scene.env_cls.__module__.rsplit(".", 1)[0]
        for part in (scene.vector_cls, scene.params_cls, scene.view, scene.rerun, scene.pilot):
            assert part.__module__.startswith(package + "."), (scene.id, part)
        pkg = importlib.import_module(package)
        assert scene in (pkg.SCENE, pkg.SCENE_V1)
        assert scene.summary and "\n" not in scene.summary


def test_a_scene_that_does_not_hang_together_is_refused():
    good = SCENES["fluidsim/PaperAirplane-v0"]
    other = SCENES["fluidsim/BoatOnStep-v0"]
    cases = [
        ({"id": "PaperAirplane"}, "the id must read"),
        ({"vector_cls": other.vector_cls}, "vector_cls"),
        ({"params_cls": other.params_cls}, "Params"),
        ({"view": other.view}, "View"),
        ({"observation": good.observation[:-1]}, "obs_dim"),
    ]
    for change, msg in cases:
        with pytest.raises(ValueError, match=msg):
            dataclasses.replace(good, **change)
    assert isinstance(dataclasses.replace(good), Scene)


def _code_names(path: Path, strings: bool) -> set[str]:
    """The identifiers, imported modules and (if ``strings``) string constants of a module's
    code, its docstrings and comments left out (their examples may name a scene)."""
    tree = ast.parse(path.read_text())
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            out.add(node.id)
        elif isinstance(node, ast.Attribute):
            out.add(node.attr)
        elif isinstance(node, ast.alias):
            out |= set(node.name.split("."))
        elif isinstance(node, ast.ImportFrom) and node.module:
            out |= set(node.module.split("."))
        elif strings and isinstance(node, ast.Constant) and isinstance(node.value, str):
            if id(node) not in docstrings:
                out.add(node.value)
    return out


def test_generic_code_names_no_scene():
    """wrappers/, rl/ and the package's generic modules read SCENES, never a scene by name:
    no scene's id, class or package in their code, no ``if env_id == ...`` switch."""
    names = set()
    for scene in SCENES.values():
        names |= {scene.id, scene.id.split("/")[1].split("-")[0]}
        names |= {scene.env_cls.__name__, scene.vector_cls.__name__, scene.params_cls.__name__}
        names.add(scene.env_cls.__module__.split(".")[2])  # the package, e.g. boat_on_step
    generic = [*PACKAGE.glob("wrappers/*.py"), *PACKAGE.glob("rl/*.py")]
    generic += [PACKAGE / "evaluation.py", PACKAGE / "scenes" / "base.py"]
    for path in [*generic, PACKAGE / "demo.py"]:  # the demo throws a paper_airplane *craft*
        found = _code_names(path, strings=path in generic)
        assert not any(n in found or any(n in f for f in found) for n in names), path.name
        assert not re.search(r"env_id\s*==", path.read_text()), path.name
    # and the test can fail: a scene's name in code is found
    assert "SubmarineWakeVectorEnv" in _code_names(PACKAGE / "scenes" / "__init__.py", True) or (
        "submarine_wake" in _code_names(PACKAGE / "scenes" / "__init__.py", True)
    )


def test_layout_index_refuses_duplicates():
    assert dict(index(("a", "b"))) == {"a": 0, "b": 1}
    with pytest.raises(ValueError, match=r"duplicates \['a'\]"):
        index(("a", "b", "a"))


def test_layouts_are_declared_once_per_scene():
    """Each kernel's index maps come from its names tuples, and the env's config vector is
    built from CFG_FIELDS in order."""
    for scene in SCENES.values():
        kernel = importlib.import_module(scene.env_cls.__module__.rsplit(".", 1)[0] + ".kernel")
        # v1 adds columns after the task's (realism.py)
        assert dict(kernel.OBS) == {n: i for i, n in enumerate(scene.obs_names[: len(kernel.OBS)])}
        # a version reports the kernel's terms or a prefix of them (BoatOnStep-v0: v1 adds
        # the ride after v0's terms)
        terms = scene.vector_cls.reward_terms
        assert kernel.REWARD_TERMS[: len(terms)] == terms
        assert terms == kernel.REWARD_TERMS or scene.version == 0
        assert dict(kernel.CFG) == {n: i for i, n in enumerate(kernel.CFG_FIELDS)}
        venv = scene.vector_cls(num_envs=1)
        assert venv._cfg.shape == (len(kernel.CFG_FIELDS),)
        for name in kernel.CFG_FIELDS:
            if hasattr(venv.params, name):
                assert venv._cfg[kernel.CFG[name]] == getattr(venv.params, name), name


def test_old_import_paths_still_work():
    from fluidsim_envs.controllers import BoatOnStepPilot, PaperAirplanePilot, SubmarineWakePilot
    from fluidsim_envs.envs import (
        BoatOnStepVectorEnv,
        PaperAirplaneEnv,
        PaperAirplaneVectorEnv,
        SubmarineWakeVectorEnv,
    )
    from fluidsim_envs.envs.boat_on_step import GATES, OBSERVATION, BoatOnStepEnv
    from fluidsim_envs.envs.paper_airplane import PaperAirplaneParams
    from fluidsim_envs.envs.submarine_wake import LEAD_RADIUS_M, SubmarineWakeParams

    assert PaperAirplaneVectorEnv is SCENES["fluidsim/PaperAirplane-v0"].vector_cls
    assert PaperAirplaneEnv is SCENES["fluidsim/PaperAirplane-v0"].env_cls
    assert BoatOnStepVectorEnv is SCENES["fluidsim/BoatOnStep-v0"].vector_cls
    assert BoatOnStepEnv is SCENES["fluidsim/BoatOnStep-v0"].env_cls
    assert SubmarineWakeVectorEnv is SCENES["fluidsim/SubmarineWake-v0"].vector_cls
    assert PaperAirplaneParams is SCENES["fluidsim/PaperAirplane-v0"].params_cls
    assert SubmarineWakeParams is SCENES["fluidsim/SubmarineWake-v0"].params_cls
    assert OBSERVATION == SCENES["fluidsim/BoatOnStep-v0"].observation
    assert GATES == 6 and LEAD_RADIUS_M == 3.0
    assert {BoatOnStepPilot, PaperAirplanePilot, SubmarineWakePilot}
    for old, new in (
        ("envs.base", "scenes.base"),
        ("envs.render", "scenes.render"),
        ("envs.drawing", "scenes.drawing"),
        ("envs.boat_on_step_kernel", "scenes.boat_on_step.kernel"),
        ("envs.paper_airplane_kernel", "scenes.paper_airplane.kernel"),
        ("envs.submarine_wake_kernel", "scenes.submarine_wake.kernel"),
        ("envs.boat_on_step_render", "scenes.boat_on_step.view"),
        ("envs.submarine_wake_render", "scenes.submarine_wake.view"),
        ("controllers.boat_on_step_pilot", "scenes.boat_on_step.pilot"),
        ("controllers.paper_airplane_pilot", "scenes.paper_airplane.pilot"),
        ("controllers.submarine_wake_pilot", "scenes.submarine_wake.pilot"),
    ):
        a = importlib.import_module(f"fluidsim_envs.{old}")
        b = importlib.import_module(f"fluidsim_envs.{new}")
        public = [k for k in vars(b) if not k.startswith("_")]
        public = getattr(b, "__all__", public)
        for name in public:
            assert getattr(a, name) is getattr(b, name), (old, name)


def test_the_scripted_pilot_comes_from_scenes():
    from fluidsim_envs.rl.evaluate import RunError, scripted_pilot

    for scene in SCENES.values():
        venv = scene.vector_cls(num_envs=2)
        pilot = scripted_pilot(scene.id, venv)
        obs, _ = venv.reset(seed=0)
        assert pilot(obs).shape == (2, len(scene.vector_cls.action_names))
    with pytest.raises(RunError, match="no scripted pilot for CartPole-v1"):
        scripted_pilot("CartPole-v1", None)
