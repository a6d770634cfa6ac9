"""Render meshes (scenes/mesh.py and each scene's mesh.py) and what the frames draw with them:
hinged parts turn exactly as the physics turns their plates, every scene's meshes can be
drawn and their solids are closed and wound outward, and the dart's frame shows its moving
control surfaces, its shadow and the readout."""

import math

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401
from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics.kernels import quat_matrices
from fluidsim_envs.physics.model import sample_names
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes import drawing as D
from fluidsim_envs.scenes.mesh import Part, RenderMesh, body_commands, panel, revolve
from fluidsim_envs.scenes.paper_airplane import view as PV
from fluidsim_envs.scenes.render import text_size
from fluidsim_envs.scenes.submarine_wake.mesh import lead_mesh

DART = "fluidsim/PaperAirplane-v0"


def scene_meshes():
    """(label, mesh, vector env) for every body of every scene, and the lead submarine."""
    out = []
    for scene in SCENES.values():
        venv = scene.vector_cls(num_envs=1)
        for k, mesh in enumerate(scene.meshes(venv)):
            out.append((f"{scene.id}[{k}]", mesh, venv))
        if hasattr(venv, "lead_craft"):
            out.append((f"{scene.id} lead", lead_mesh(venv.lead_craft, venv.wake), venv))
    return out


MESHES = scene_meshes()


def part_slices(mesh: RenderMesh) -> dict[str, slice]:
    ends = np.cumsum([len(p.vertices_m) for p in mesh.parts])
    return {p.name: slice(e - len(p.vertices_m), e) for p, e in zip(mesh.parts, ends, strict=True)}


def unit_normal(v: np.ndarray, tri) -> np.ndarray:
    n = np.cross(v[tri[1]] - v[tri[0]], v[tri[2]] - v[tri[0]])
    return n / np.linalg.norm(n)


# ---- meshes and the physics -------------------------------------------------------------


@pytest.mark.parametrize("label, mesh, venv", MESHES, ids=[m[0] for m in MESHES])
def test_hinged_parts_turn_as_the_physics_turns_their_plates(label, mesh, venv):
    craft = mesh.craft
    assert mesh.hinged, f"{label}: no control surface is bound to its plate"
    commands = np.linspace(0.9, -0.7, len(craft.control_names))  # every channel nonzero
    sim = Simulator(craft, World(), num_envs=1)
    sim.wrench(commands[None])  # deflects the control surfaces as a step does
    flaps = sample_names(craft)["flap"]
    deflected = sim._data.flap_now[:, :, 0].T  # [n_flaps, 3], body frame (kernels._deflect)
    posed, rest = mesh.posed(commands), mesh.posed(None)
    where = part_slices(mesh)
    for part in mesh.parts:
        if part.sample is None:
            continue
        tri = part.triangles[0]
        now = unit_normal(posed[where[part.name]], tri)
        physics = deflected[flaps.index(part.sample)]
        np.testing.assert_allclose(now, physics, atol=1e-12, err_msg=f"{label}: {part.name}")
        # and the part drawn at rest lies in its plate's plane, facing along its normal
        plate = next(p for p in craft.plates if p.name == part.sample)
        np.testing.assert_allclose(
            unit_normal(rest[where[part.name]], tri), plate.normal, atol=1e-12
        )
        assert not np.allclose(posed[where[part.name]], rest[where[part.name]])


def test_fixed_parts_do_not_move_with_the_commands():
    label, mesh, _ = MESHES[0]
    where = part_slices(mesh)
    posed = mesh.posed(np.ones(len(mesh.craft.control_names)))
    for part in mesh.parts:
        if part.sample is None:
            np.testing.assert_array_equal(posed[where[part.name]], part.vertices_m, label)


@pytest.mark.parametrize("label, mesh, venv", MESHES, ids=[m[0] for m in MESHES])
def test_every_mesh_can_be_drawn(label, mesh, venv):
    v, t, c = mesh.posed(None), mesh.triangles, mesh.colors
    assert len(t) >= 10 and np.isfinite(v).all()
    assert t.min() >= 0 and t.max() < len(v)
    assert c.shape == (len(t), 3) and c.dtype == np.uint8
    assert mesh.closed.shape == (len(t),)
    area = 0.5 * np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)
    assert (area > 0).mean() > 0.8, f"{label}: mostly degenerate triangles"
    # the mesh spans the craft: its samples lie within the mesh's box (a margin of a tenth)
    lo, hi = v.min(axis=0), v.max(axis=0)
    pad = 0.1 * (hi - lo).max()
    for p in (*mesh.craft.plates, *mesh.craft.cylinders):
        assert (np.asarray(p.offset_m) >= lo - pad).all() and (p.offset_m <= hi + pad).all(), p.name


SOLIDS = [m for m in MESHES if m[1].closed.any()]


def test_the_hulls_are_solids():
    assert {m[1].craft.name for m in SOLIDS} == {"speedboat", "uuv", "submarine"}


@pytest.mark.parametrize("label, mesh, venv", SOLIDS, ids=[m[0] for m in SOLIDS])
def test_solids_are_closed_and_wound_outward(label, mesh, venv):
    closed = mesh.triangles[mesh.closed]
    v = mesh.posed(None)
    # weld coincident corners: each edge of a closed, consistently wound surface is met once
    # in each direction
    _, ids = np.unique(np.round(v, 9), axis=0, return_inverse=True)
    tri = ids.reshape(-1)[closed]
    tri = tri[(tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 2] != tri[:, 0])]
    edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    fwd = {tuple(e) for e in edges}
    assert len(fwd) == len(edges), f"{label}: an edge runs the same way twice (a flipped face)"
    assert all((b, a) in fwd for a, b in fwd), f"{label}: a hole in a solid"
    a, b, c = v[closed[:, 0]], v[closed[:, 1]], v[closed[:, 2]]
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0.0  # outward: positive volume


def test_revolve_matches_the_volume_of_its_profile():
    x = np.linspace(-1.0, 1.0, 41)
    r = np.sqrt(1.0 - x**2)  # a unit sphere
    v = revolve("ball", x, r, (1, 2, 3), segments=64)
    a, b, c = (v.vertices_m[v.triangles[:, k]] for k in range(3))
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    assert volume == pytest.approx(4.0 / 3.0 * math.pi, rel=0.01)
    with pytest.raises(ValueError, match="ball"):
        revolve("ball", x, -r, (1, 2, 3))


def test_panel_faces_the_normal_it_is_given():
    square = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    for normal in ((0, 0, 1), (0, 0, -1)):
        p = panel("sq", square, normal=normal)
        np.testing.assert_allclose(unit_normal(p.vertices_m, p.triangles[0]), normal)
        np.testing.assert_allclose(unit_normal(p.vertices_m, p.triangles[1]), normal)


def test_a_part_bound_to_no_hinged_plate_is_refused_by_name():
    craft = Craft.load("paper_airplane")
    bad = Part("flap", np.zeros((3, 3)), [[0, 1, 2]], sample="left_wing")
    with pytest.raises(ValueError, match="'left_wing' is not a hinged plate"):
        RenderMesh(craft, (bad,))
    with pytest.raises(ValueError, match="'tri'.*index"):
        Part("tri", np.zeros((3, 3)), [[0, 1, 3]])


def test_body_commands_split_the_channels_per_body():
    boat, buoy = Craft.load("speedboat"), Craft.load("buoy")
    sim = Simulator([boat, buoy], World(water=True), num_envs=2)
    sim.wrench(np.array([[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]]))
    first, second = body_commands(sim, 1)
    np.testing.assert_array_equal(first, [0.4, 0.5, 0.6])
    assert len(second) == len(buoy.control_names) == 0


# ---- the dart's frames --------------------------------------------------------------------


@pytest.fixture
def dart():
    """A PaperAirplane-v0 vector env of one, reset, flying level at 3 m/s and height z."""
    venv = gym.make_vec(
        DART, num_envs=1, vectorization_mode="vector_entry_point", render_mode="rgb_array"
    )
    venv.reset(seed=1)
    yield venv.unwrapped
    venv.close()


def fly(env, z: float, commands=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Put the dart level at height z heading +x (at 3 m/s), set its commands, render."""
    env.sim.reset(pos=(0.0, 0.0, z), quat=(1.0, 0.0, 0.0, 0.0), lin_vel=(3.0, 0.0, 0.0))
    env.sim.wrench(np.asarray(commands, dtype=np.float64)[None])  # the controls a view reads
    return env.render()[0]


def camera_of(env):
    """The camera the view uses for sub-env 0 (same inputs, same function)."""
    pos = np.array(env.sim.pos[0, 0], dtype=np.float64)
    return PV.chase(env, 0, pos, np.array([*env.target_xy(0), 0.0]))


def hud_rows(env) -> int:
    """The readout box's bottom row."""
    _, h = text_size("\n".join(PV._lines(env, 0, np.zeros(3), np.zeros(3))))
    return 6 + h + 8


def test_frame_changes_where_the_elevators_are_when_the_elevator_command_does(dart):
    before = fly(dart, 2.0)
    after = fly(dart, 2.0, (0.0, 1.0, 0.0))
    changed = (before != after).any(axis=2)
    changed[: hud_rows(dart) + 1] = False  # the readout prints the new command
    assert changed.sum() > 10
    # every changed pixel lies where the elevators are drawn, at rest or deflected
    cam, mesh = camera_of(dart), dart.view.mesh
    where = part_slices(mesh)
    rot = quat_matrices(np.ascontiguousarray(dart.sim.quat[0], dtype=np.float64))[0]
    pos = np.array(dart.sim.pos[0, 0], dtype=np.float64)
    corners = []
    for cmd in ((0.0, 0.0, 0.0), (0.0, 1.0, 0.0)):
        v = D.place(mesh, cmd, pos, rot)
        corners += [v[where[n]] for n in ("left_elevator", "right_elevator")]
    pix, _ = cam.project(np.concatenate(corners))
    lo, hi = pix.min(axis=0) - 2, pix.max(axis=0) + 2
    rows, cols = np.nonzero(changed)
    assert (cols >= lo[0]).all() and (cols <= hi[0]).all()
    assert (rows >= lo[1]).all() and (rows <= hi[1]).all()
    # and the aileron command moves other pixels than the elevator command
    rolled = fly(dart, 2.0, (1.0, 0.0, 0.0))
    other = (before != rolled).any(axis=2)
    other[: hud_rows(dart) + 1] = False
    assert other.sum() > 10 and (other & ~changed).sum() > 0.5 * other.sum()


def test_the_dart_casts_its_shadow_on_the_ground_below_it(dart):
    frame = fly(dart, 0.4)
    shadowed = (np.array(PV.GROUND) * 0.55).astype(np.uint8)
    rows, cols = np.nonzero((frame == shadowed).all(axis=2))
    assert len(rows) > 50
    # centered on the ground point below the dart
    (below,), _ = camera_of(dart).project([[0.0, 0.0, 0.0]])
    assert abs(np.median(cols) - below[0]) < 40 and abs(np.median(rows) - below[1]) < 40
    # higher up, the dart is smaller against the ground but its shadow still lies below it
    high = fly(dart, 3.0)
    (below,), _ = camera_of(dart).project([[0.0, 0.0, 0.0]])
    rows, cols = np.nonzero((high == shadowed).all(axis=2))
    assert len(rows) > 5 and abs(np.median(cols) - below[0]) < 20


def test_the_readout_writes_text_in_its_box(dart):
    frame = fly(dart, 2.0)
    bottom = hud_rows(dart)
    w, _ = text_size("\n".join(PV._lines(dart, 0, np.zeros(3), np.zeros(3))))
    box = frame[6:bottom, 6 : 6 + w + 8]
    text = (box == D.HUD_TEXT).all(axis=2)
    assert text.sum() > 200  # two lines of ~45 characters, ~10 lit pixels each
    assert not (frame[bottom + 2 :] == D.HUD_TEXT).all(axis=2).any()
    # a diverged state still renders, with its readout, the numbers it lacks as '?'
    SCENES[DART].diverge(dart, 0)
    frame = dart.render()[0]
    assert (frame[6:bottom, 6 : 6 + w + 8] == D.HUD_TEXT).all(axis=2).sum() > 100
    assert "?" in PV._lines(dart, 0, np.array(dart.sim.pos[0, 0]), np.zeros(3))[0]


def test_the_target_stays_in_view_from_launch_to_touchdown(dart):
    """The scripted pilot's throw: the target's center is on screen in every frame."""
    pilot = SCENES[DART].pilot(dart)
    obs, _ = dart.reset(seed=0)
    for _ in range(200):
        cam = camera_of(dart)
        (c,), _ = cam.project([[*dart.target_xy(0), 0.0]])
        (d,), _ = cam.project([np.array(dart.sim.pos[0, 0])])
        for p in (c, d):
            assert 0 <= p[0] < cam.width and 0 <= p[1] < cam.height, p
        obs, _, terminated, truncated, _ = dart.step(pilot(obs))
        if terminated[0] or truncated[0]:
            break
    assert terminated[0] or truncated[0]
