"""Software renderer: pinhole projection against its closed form, and rasterization of lines
(with near-plane clipping), triangles (depth-tested per pixel, or painted in order), shaded
meshes, shadows, points, text and the ground grid, including inputs that cannot be drawn."""

import math

import numpy as np
import pytest

from fluidsim_envs.scenes.render import _FONT, GLYPH_H, GLYPH_W, Camera, Canvas, text_size

W, H = 480, 360
BG = np.array([200, 225, 245], dtype=np.uint8)
RED, BLUE, GREEN = (255, 0, 0), (0, 0, 255), (0, 255, 0)


def forward_camera(**kwargs):
    """At the origin looking along +x, z up: camera x right = world -y, y down = world -z."""
    return Camera.look_at((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), **kwargs)


def lit(canvas):
    """Mask [H, W] of pixels that differ from the background."""
    return np.any(canvas.image() != BG, axis=2)


def test_point_straight_ahead_projects_to_the_image_center():
    for eye, target in [((0, 0, 0), (1, 0, 0)), ((1.0, 2.0, 3.0), (-2.0, 5.0, 0.5))]:
        cam = Camera.look_at(eye, target, width=W, height=H)
        axis = np.subtract(target, eye) / np.linalg.norm(np.subtract(target, eye))
        pix, depth = cam.project(np.asarray(eye) + 7.0 * axis[None, :])
        np.testing.assert_allclose(pix, [[W / 2, H / 2]], atol=1e-9)
        np.testing.assert_allclose(depth, [7.0], rtol=1e-12)


def test_right_projects_right_of_center_and_up_projects_above():
    cam = forward_camera()
    (right, above, left, below), _ = cam.project(
        [[5.0, -1.0, 0.0], [5.0, 0.0, 1.0], [5.0, 1.0, 0.0], [5.0, 0.0, -1.0]]
    )
    assert right[0] > W / 2 and right[1] == pytest.approx(H / 2)
    assert above[1] < H / 2 and above[0] == pytest.approx(W / 2)
    assert left[0] < W / 2 and below[1] > H / 2


def test_look_at_gives_an_orthonormal_right_handed_frame():
    for up in [(0.0, 0.0, 1.0), (0.0, 0.0, 5.0)]:
        for target in [(3.0, -1.0, 2.0), (0.0, 0.0, -4.0), (0.0, 0.0, 4.0)]:  # incl. along up
            r = Camera.look_at((0.0, 0.0, 0.0), target, up=up).rotation
            np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
            assert np.linalg.det(r) == pytest.approx(1.0)


@pytest.mark.parametrize(
    "fov_deg, width, height", [(50.0, 480, 360), (90.0, 64, 48), (20.0, 33, 101)]
)
def test_projection_matches_the_pinhole_closed_form(fov_deg, width, height):
    rng = np.random.default_rng(0)
    f = (height / 2) / math.tan(math.radians(fov_deg) / 2)
    eye = np.array([1.0, 2.0, 0.5])
    # Looking along -y with z up: camera (x right, y down, z forward) = (-dx, -dz, -dy).
    cam = Camera.look_at(eye, eye + [0.0, -3.0, 0.0], fov_deg=fov_deg, width=width, height=height)
    world = eye + rng.uniform([-5, -20, -5], [5, -0.5, 5], size=(50, 3))
    d = world - eye
    x_cam, y_cam, z_cam = -d[:, 0], -d[:, 2], -d[:, 1]
    expected = np.stack([width / 2 + f * x_cam / z_cam, height / 2 + f * y_cam / z_cam], axis=1)
    pix, depth = cam.project(world)
    np.testing.assert_allclose(pix, expected, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(depth, z_cam, rtol=1e-12)
    # The vertical field of view spans the image: a point at fov/2 above the axis is at row 0.
    t = math.tan(math.radians(fov_deg) / 2)
    top, _ = cam.project(eye + [[0.0, -2.0, 2.0 * t]])
    np.testing.assert_allclose(top, [[width / 2, 0.0]], atol=1e-9)


def test_points_behind_the_camera_project_to_nan_with_nonpositive_depth():
    pix, depth = forward_camera().project([[-3.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 0.0, 0.0]])
    assert depth[0] < 0 and depth[1] == 0 and depth[2] == pytest.approx(2.0)
    assert np.isnan(pix[:2]).all() and np.isfinite(pix[2]).all()


def test_horizontal_line_lights_pixels_along_it_and_nothing_far_from_it():
    cam, canvas = forward_camera(), Canvas(W, H)
    canvas.lines(cam, [[5.0, 2.0, 0.0]], [[5.0, -2.0, 0.0]], RED)
    f = (H / 2) / math.tan(math.radians(50.0) / 2)
    x0, x1 = W / 2 - f * 2 / 5, W / 2 + f * 2 / 5
    mask = lit(canvas)
    rows, cols = np.nonzero(mask)
    assert np.all(np.abs(rows - H / 2) <= 1)
    assert cols.min() >= math.floor(x0) - 1 and cols.max() <= math.ceil(x1) + 1
    assert mask[:, math.ceil(x0) : math.floor(x1)].any(axis=0).all()  # no gaps
    assert (canvas.image()[mask] == RED).all()


def test_diagonal_line_is_continuous_and_close_to_its_projection():
    cam, canvas = forward_camera(), Canvas(W, H)
    a, b = np.array([4.0, 1.5, 1.0]), np.array([6.0, -2.0, -1.5])
    canvas.lines(cam, a, b, GREEN)
    (pa, pb), _ = cam.project([a, b])
    rows, cols = np.nonzero(lit(canvas))
    centers = np.stack([cols + 0.5, rows + 0.5], axis=1)
    d = (pb - pa) / np.linalg.norm(pb - pa)
    rel = centers - pa
    assert np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]).max() <= 1.0  # distance to the line
    along = rel @ d
    assert along.min() >= -1.0 and along.max() <= np.linalg.norm(pb - pa) + 1.0
    major = int(np.argmax(np.abs(pb - pa)))
    covered = np.unique([cols, rows][major])
    assert len(covered) == covered.max() - covered.min() + 1  # a pixel at every step


def test_thick_line_is_wider_across_its_direction():
    cam = forward_camera()
    widths = []
    for thickness in (1, 3):
        canvas = Canvas(W, H)
        canvas.lines(cam, [[5.0, 2.0, 0.0]], [[5.0, -2.0, 0.0]], RED, thickness=thickness)
        widths.append(lit(canvas)[:, W // 2].sum())
    assert widths == [1, 3]


def test_segment_crossing_behind_the_camera_draws_only_its_visible_part():
    cam, canvas = forward_camera(), Canvas(W, H)
    # From 5 m ahead and 1 m below to 5 m behind. Projected without clipping, the far end would
    # land above the center (mirrored); the visible part runs from the front end down and off
    # the bottom of the image as it nears the camera.
    canvas.lines(cam, [[5.0, 0.0, -1.0]], [[-5.0, 0.0, -1.0]], RED)
    f = (H / 2) / math.tan(math.radians(50.0) / 2)
    y_front = H / 2 + f * 1.0 / 5.0
    rows, cols = np.nonzero(lit(canvas))
    assert np.all(np.abs(cols - W / 2) <= 1)
    assert rows.min() >= math.floor(y_front) - 1
    assert set(range(math.ceil(y_front), H)) <= set(rows.tolist())
    # The same segment given the other way round, and ones wholly behind, draw the same/nothing.
    other = Canvas(W, H)
    other.lines(cam, [[-5.0, 0.0, -1.0]], [[5.0, 0.0, -1.0]], RED)
    np.testing.assert_array_equal(other.image(), canvas.image())
    behind = Canvas(W, H)
    behind.lines(
        cam, [[-1.0, -3.0, 0.0], [0.0, 1.0, 1.0]], [[-5.0, 3.0, 0.0], [-2.0, 1.0, 1.0]], RED
    )
    assert not lit(behind).any()


def test_segment_crossing_the_side_of_the_camera_is_cut_not_wrapped():
    cam, canvas = forward_camera(), Canvas(W, H)
    # Passes beside the camera from ahead-left to behind-right: the visible part goes off the
    # left edge; nothing may appear on the right half.
    canvas.lines(cam, [[5.0, 1.0, 0.0]], [[-5.0, 1.5, 0.0]], RED)
    rows, cols = np.nonzero(lit(canvas))
    assert len(cols) > 0 and cols.max() < W / 2 and cols.min() == 0


def test_nearer_triangle_wins_where_triangles_overlap():
    cam = forward_camera()

    def tri(x, half):  # facing the camera, centered on the view axis
        return [[x, half, -half], [x, -half, -half], [x, 0.0, half]]

    near, far = tri(3.0, 0.5), tri(6.0, 2.0)
    for tris, colors in [([near, far], [RED, BLUE]), ([far, near], [BLUE, RED])]:
        canvas = Canvas(W, H)
        canvas.triangles(cam, tris, colors)
        img = canvas.image()
        assert (img[H // 2, W // 2] == RED).all()
        assert (img[300, W // 2] == BLUE).all()  # below the near one: far one only
        assert (img[5, 5] == BG).all()


def test_triangle_fill_covers_its_inside_either_winding():
    cam = forward_camera()
    t = np.array([[5.0, 1.0, -1.0], [5.0, -1.0, -1.0], [5.0, 0.0, 1.0]])
    masks = []
    for tri in (t, t[::-1]):
        canvas = Canvas(W, H)
        canvas.triangles(cam, [tri], GREEN)
        masks.append(lit(canvas))
    np.testing.assert_array_equal(masks[0], masks[1])
    (p0, p1, p2), _ = cam.project(t)
    area = abs((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1])) / 2
    assert masks[0].sum() == pytest.approx(area, rel=0.02)


def test_triangle_with_a_vertex_behind_the_camera_is_skipped():
    canvas = Canvas(W, H)
    canvas.triangles(forward_camera(), [[[5.0, 1.0, 0.0], [5.0, -1.0, 0.0], [-1.0, 0.0, 1.0]]], RED)
    assert not lit(canvas).any()


def test_points_draw_discs_at_their_projections():
    cam, canvas = forward_camera(), Canvas(W, H)
    canvas.points(cam, [[5.0, 0.0, 0.0], [5.0, 1.0, 1.0]], [RED, BLUE], radius=3)
    img = canvas.image()
    (center, corner), _ = cam.project([[5.0, 0.0, 0.0], [5.0, 1.0, 1.0]])
    assert (img[int(center[1]), int(center[0])] == RED).all()
    assert (img[int(corner[1]), int(corner[0])] == BLUE).all()
    rows, cols = np.nonzero((img == RED).all(axis=2))
    assert np.hypot(rows + 0.5 - center[1], cols + 0.5 - center[0]).max() <= 3 * math.sqrt(2) + 1
    assert 20 <= len(rows) <= 49


def test_ground_grid_lies_below_the_horizon():
    cam = Camera.look_at((0.0, 0.0, 2.0), (10.0, 0.0, 2.0))  # level: horizon at the center row
    canvas = Canvas(W, H)
    canvas.ground_grid(cam, center=(0.0, 0.0), half_size=30.0, spacing=1.0, color=(90, 90, 90))
    rows, _ = np.nonzero(lit(canvas))
    assert len(rows) > 1000 and rows.min() >= H // 2 - 1
    with pytest.raises(ValueError):
        canvas.ground_grid(cam, center=(0.0, 0.0), half_size=30.0, spacing=0.0, color=RED)


@pytest.mark.filterwarnings("error")  # no RuntimeWarning from NaN arithmetic or casts either
def test_nan_and_inf_inputs_draw_nothing_and_do_not_raise():
    cam, canvas = forward_camera(), Canvas(W, H)
    for v in (np.nan, np.inf, -np.inf):
        p = [5.0, v, 0.0]
        canvas.lines(cam, [p, [5.0, 0.0, v]], [[5.0, 0.0, 0.0], [5.0, 1.0, 0.0]], RED, thickness=3)
        canvas.triangles(cam, [[p, [5.0, 1.0, 0.0], [5.0, 0.0, 1.0]]], RED)
        canvas.points(cam, [p], RED)
        canvas.ground_grid(cam, center=(v, 0.0), half_size=10.0, spacing=1.0, color=RED)
        canvas.ground_grid(cam, center=(0.0, 0.0), half_size=v, spacing=1.0, color=RED)
    canvas.fill_rows(np.nan, 10.0, RED)
    canvas.fill_rows(0.0, np.nan, RED)
    nan_cam = Camera.look_at((np.nan, 0.0, 0.0), (1.0, 0.0, 0.0))
    canvas.lines(nan_cam, [[5.0, 0.0, 0.0]], [[5.0, 1.0, 0.0]], RED)
    canvas.triangles(nan_cam, [[[5.0, 1.0, 0.0], [5.0, -1.0, 0.0], [5.0, 0.0, 1.0]]], RED)
    canvas.points(nan_cam, [[5.0, 0.0, 0.0]], RED)
    canvas.lines(cam, np.empty((0, 3)), np.empty((0, 3)), RED)
    canvas.triangles(cam, np.empty((0, 3, 3)), RED)
    assert not lit(canvas).any()
    # Good primitives next to bad ones still draw.
    canvas.points(cam, [[5.0, np.nan, 0.0], [5.0, 0.0, 0.0]], RED)
    canvas.lines(cam, [[5.0, np.inf, 0.5], [5.0, 0.0, 1.0]], [[5.0, 0.0, 0.5]] * 2, [BLUE, GREEN])
    img = canvas.image()
    assert (img[H // 2, W // 2] == RED).all() and (img[120, W // 2] == GREEN).all()
    assert not (img == BLUE).all(axis=2).any()


@pytest.mark.filterwarnings("error")
def test_huge_finite_inputs_do_not_raise():
    cam, canvas = forward_camera(), Canvas(W, H)
    for v in (1e300, -1e300, 1e17, 1.7e308):
        p = [5.0, v, v]
        canvas.lines(cam, [p], [[5.0, -v, -v]], RED)
        canvas.lines(cam, [[-v, -v, 0.0]], [[v, v, 0.0]], RED)
        canvas.lines(cam, [p], [[5.0, 0.0, 0.0]], RED, thickness=3)
        canvas.lines(cam, [p], [[v, 0.0, 0.0]], RED)
        canvas.triangles(cam, [[p, [5.0, 1.0, 0.0], [5.0, 0.0, 1.0]]], RED)
        canvas.points(cam, [p, [v, 0.0, 0.0]], RED)
        canvas.ground_grid(cam, center=(v, v), half_size=10.0, spacing=1.0, color=RED)
    assert canvas.image().dtype == np.uint8


@pytest.mark.filterwarnings("error")
def test_far_off_image_geometry_is_clipped():
    cam, canvas = forward_camera(), Canvas(W, H)
    # Ends just past the near plane project millions of pixels away; only the visible part draws.
    canvas.lines(cam, [[0.0101, 0.0, 0.0]], [[0.0101, -1e3, 0.0]], RED)
    canvas.lines(cam, [[5.0, 1e6, 0.0]], [[5.0, 2e6, 0.0]], RED)  # wholly off to the left
    rows, cols = np.nonzero(lit(canvas))
    assert (rows == H // 2).all() and cols.min() == W // 2 and cols.max() == W - 1
    big = Canvas(W, H)
    big.triangles(cam, [[[0.02, 50.0, -50.0], [0.02, -50.0, -50.0], [0.02, 0.0, 50.0]]], BLUE)
    assert lit(big).all()


def test_image_is_a_uint8_copy_and_fill_rows_clips():
    canvas = Canvas(W, H)
    img = canvas.image()
    assert img.shape == (H, W, 3) and img.dtype == np.uint8 and (img == BG).all()
    img[:] = 0
    assert (canvas.image() == BG).all()
    canvas.fill_rows(-10, 50, GREEN)
    canvas.fill_rows(H - 5, np.inf, BLUE)
    img = canvas.image()
    assert (
        (img[:50] == GREEN).all() and (img[50 : H - 5] == BG).all() and (img[H - 5 :] == BLUE).all()
    )
    canvas.clear(RED)
    assert (canvas.image() == RED).all()
    canvas.clear()
    assert (canvas.image() == BG).all()


def test_camera_and_canvas_sizes_must_agree():
    with pytest.raises(ValueError):
        Canvas(100, 100).points(forward_camera(), [[5.0, 0.0, 0.0]], RED)


@pytest.mark.filterwarnings("error")
def test_random_garbage_never_raises_or_warns():
    rng = np.random.default_rng(7)
    special = np.array([np.nan, np.inf, -np.inf, 0.0, 1e-300, 1e300, -1e300, 1.7e308, 0.01])

    def garbage(*shape):
        x = rng.normal(size=shape) * 10.0 ** rng.uniform(-3, 3, size=shape)
        mask = rng.random(shape) < 0.1
        x[mask] = rng.choice(special, size=mask.sum())
        return x

    for _ in range(300):
        w, h = (int(v) for v in rng.integers(1, 64, size=2))
        cam = Camera.look_at(garbage(3), garbage(3), width=w, height=h)
        canvas = Canvas(w, h)
        n = int(rng.integers(0, 10))
        canvas.lines(cam, garbage(n, 3), garbage(n, 3), RED, thickness=int(rng.integers(1, 4)))
        canvas.triangles(cam, garbage(n, 3, 3), rng.integers(0, 256, size=(n, 3)))
        canvas.points(cam, garbage(n, 3), BLUE, radius=int(rng.integers(0, 5)))
        canvas.ground_grid(cam, garbage(2), float(rng.uniform(0, 50)), 1.0, GREEN)
        canvas.fill_rows(*garbage(2), GREEN)
        assert canvas.image().shape == (h, w, 3)


# ---- depth, shading, shadows, text ----------------------------------------------------------


def facing(x, half=1.0):
    """A triangle in the plane at depth x before forward_camera, covering the view's center."""
    return [[x, half, -half], [x, -half, -half], [x, 0.0, half]]


def test_depth_is_resolved_per_pixel_where_triangles_cross():
    cam = forward_camera()
    flat = facing(5.0, 2.0)
    # tilted: 3 m away on the left of the image (world +y), 7 m on the right
    tilted = [[3.0, 2.0, -2.0], [7.0, -2.0, -2.0], [5.0, 0.0, 2.0]]
    for order in ((flat, tilted), (tilted, flat)):
        canvas = Canvas(W, H)
        for tri, color in zip(order, (RED, BLUE) if order[0] is flat else (BLUE, RED), strict=True):
            canvas.triangles(cam, [tri], color)
        img = canvas.image()
        row = H // 2 + 20
        assert (img[row, W // 2 - 30] == BLUE).all()  # the tilted one is nearer on the left
        assert (img[row, W // 2 + 30] == RED).all()  # and farther on the right


def test_painted_triangles_go_on_top_and_leave_the_depth_buffer_alone():
    cam, canvas = forward_camera(), Canvas(W, H)
    canvas.triangles(cam, [facing(3.0)], RED)
    canvas.triangles(cam, [facing(9.0)], BLUE, depth_test=False)  # painted over, though farther
    assert (canvas.image()[H // 2, W // 2] == BLUE).all()
    canvas.triangles(cam, [facing(6.0)], GREEN)  # depth-tested: still behind the first
    assert (canvas.image()[H // 2, W // 2] == BLUE).all()
    canvas.clear()
    canvas.triangles(cam, [facing(6.0)], GREEN)  # clear() empties the depth buffer
    assert (canvas.image()[H // 2, W // 2] == GREEN).all()


def test_mesh_is_lambert_shaded_by_the_sun_on_the_side_the_camera_sees():
    square = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]])
    tris, base, ambient = [[0, 1, 2], [0, 2, 3]], np.array([200.0, 100.0, 50.0]), 0.4
    tilt = math.radians(60.0)
    cases = [  # camera height, sun: the expected brightness
        (5.0, (0.0, 0.0, 1.0), 1.0),
        (5.0, (math.sin(tilt), 0.0, math.cos(tilt)), ambient + (1 - ambient) * math.cos(tilt)),
        (-5.0, (0.0, 0.0, 1.0), ambient),  # from below: the lit side faces away
    ]
    for z, sun, light in cases:
        cam = Camera.look_at((0.0, 0.0, z), (0.0, 0.0, 0.0), up=(1.0, 0.0, 0.0))
        canvas = Canvas(W, H)
        canvas.mesh(cam, square, tris, base, sun=sun, ambient=ambient)
        np.testing.assert_allclose(canvas.image()[H // 2, W // 2], base * light, atol=0.51)


def test_closed_meshes_skip_the_faces_turned_away():
    cam = forward_camera()
    toward = np.array(facing(5.0))  # right-hand normal toward the camera (-x)
    for tri, drawn in ((toward, True), (toward[::-1], False)):
        canvas = Canvas(W, H)
        canvas.mesh(cam, tri, [[0, 1, 2]], RED, closed=[True])
        assert lit(canvas)[H // 2, W // 2] == drawn
        canvas.mesh(cam, tri, [[0, 1, 2]], RED)  # open: both sides show
        assert lit(canvas)[H // 2, W // 2]


def test_shadow_darkens_the_plane_below_a_triangle_once():
    cam = Camera.look_at((0.0, 0.0, 10.0), (0.0, 0.0, 0.0), up=(1.0, 0.0, 0.0))
    canvas = Canvas(W, H, background=(100, 200, 60))
    tri = [[-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.0]]
    canvas.shadow(cam, [tri, tri], darken=0.5)  # twice over: one darkening
    img = canvas.image()
    dark = (img == [50, 100, 30]).all(axis=2)
    assert dark[H // 2, W // 2] and (dark | (img == [100, 200, 60]).all(axis=2)).all()
    # straight down: the shadow is the triangle flattened onto z = 0
    pix, _ = cam.project(np.array(tri) * [1.0, 1.0, 0.0])
    (ax, ay), (bx, by) = pix[1] - pix[0], pix[2] - pix[0]
    assert dark.sum() == pytest.approx(abs(ax * by - ay * bx) / 2, rel=0.03)
    # a surface already drawn nearer than the plane keeps its color
    canvas = Canvas(W, H, background=(100, 200, 60))
    canvas.triangles(cam, [[[-3.0, -3.0, 2.0], [3.0, -3.0, 2.0], [0.0, 3.0, 2.0]]], BLUE)
    canvas.shadow(cam, [tri])
    assert (canvas.image()[H // 2, W // 2] == BLUE).all()
    with pytest.raises(ValueError, match="light must point up"):
        canvas.shadow(cam, [tri], light=(0.0, 0.0, -1.0))


def test_points_can_hide_behind_drawn_triangles():
    cam = forward_camera()
    for depth_test, shown in ((True, False), (False, True)):
        canvas = Canvas(W, H)
        canvas.triangles(cam, [facing(5.0)], BLUE)
        canvas.points(cam, [[8.0, 0.0, 0.0], [3.0, 0.3, 0.0]], RED, radius=1, depth_test=depth_test)
        img = canvas.image()
        (behind, before), _ = cam.project([[8.0, 0.0, 0.0], [3.0, 0.3, 0.0]])
        assert (img[int(behind[1]), int(behind[0])] == RED).all() == shown
        assert (img[int(before[1]), int(before[0])] == RED).all()


def test_text_draws_the_font_glyphs_and_names_a_missing_one():
    canvas = Canvas(W, H)
    canvas.text(10, 20, "A1", RED)
    img = (canvas.image() == RED).all(axis=2)
    np.testing.assert_array_equal(img[20 : 20 + GLYPH_H, 10 : 10 + GLYPH_W], _FONT["A"])
    np.testing.assert_array_equal(img[20 : 20 + GLYPH_H, 16 : 16 + GLYPH_W], _FONT["1"])
    assert img.sum() == _FONT["A"].sum() + _FONT["1"].sum()
    rows, cols = np.nonzero(img)
    w, h = text_size("A1")
    assert cols.max() - 10 < w and rows.max() - 20 < h
    big = Canvas(W, H)
    big.text(10, 20, "A1\nA1", RED, scale=3)
    assert (big.image() == RED).all(axis=2).sum() == 2 * 9 * img.sum()
    big.text(W - 3, H - 3, "clipped at the corner", RED)  # no error
    with pytest.raises(ValueError, match="'é'"):
        canvas.text(0, 0, "café", RED)
    with pytest.raises(ValueError, match="scale"):
        canvas.text(0, 0, "x", RED, scale=0)


def test_rect_blends_and_blit_copies_an_image_in_clipped():
    canvas = Canvas(W, H, background=(200, 100, 0))
    canvas.rect(-5, 10, 20, 30, (0, 0, 100), alpha=0.5)
    img = canvas.image()
    assert (img[10:30, 0:20] == [100, 50, 50]).all() and (img[30, 0] == [200, 100, 0]).all()
    with pytest.raises(ValueError, match="alpha"):
        canvas.rect(0, 0, 1, 1, RED, alpha=1.5)
    picture = np.random.default_rng(0).integers(0, 256, (H, W, 3), dtype=np.uint8)
    canvas.blit(0, 0, picture)
    np.testing.assert_array_equal(canvas.image(), picture)
    canvas.blit(W - 10, -5, picture[:20, :30] // 2)  # hangs over the top and right edges
    np.testing.assert_array_equal(canvas.image()[:15, W - 10 :], picture[5:20, :10] // 2)
    np.testing.assert_array_equal(canvas.image()[15:], picture[15:])
    with pytest.raises(ValueError, match="shape"):
        canvas.blit(0, 0, picture[..., 0])
