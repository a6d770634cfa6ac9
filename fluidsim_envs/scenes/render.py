"""Numpy-only software rasterizer behind ``render_mode="rgb_array"``.

Draws a perspective or orthographic view of 3D line segments, filled triangles (plain, or a
mesh shaded by a sun), shadows and point markers, and 2D text, into an RGB ``uint8`` image, so
that environments can be recorded (e.g. by gymnasium's ``RecordVideo``) without a display or a
graphics library. Triangles are depth-tested against a depth buffer (the nearest surface wins
whatever the order of the calls), or on request painted over what is there (flat drawings
whose later layers go on top). Lines, points, text and filled rows paint over everything and
leave the depth buffer alone.

Conventions: the world frame is right-handed with z up, in meters. The camera frame is x right,
y down, z forward along the view axis. Images are ``[height, width, 3]`` arrays with row 0 at
the top. Pixel coordinates are continuous, x right and y down: pixel ``[row, col]`` covers
``[col, col + 1) x [row, row + 1)``, so the image center is ``(width / 2, height / 2)``.

Primitives that cannot be drawn (NaN or inf coordinates, vertices behind the camera) are skipped
rather than raised on, so that a diverging simulation still renders.

>>> cam = Camera.look_at(eye=(-6.0, 0.0, 2.0), target=(0.0, 0.0, 0.5))
>>> canvas = Canvas(cam.width, cam.height)
>>> canvas.ground_grid(cam, center=(0.0, 0.0), half_size=20.0, spacing=1.0, color=(90, 120, 90))
>>> canvas.lines(cam, [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], color=(220, 40, 40), thickness=2)
>>> canvas.image().shape
(360, 480, 3)
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["SUN", "Camera", "Canvas", "OrthoCamera", "text_size"]

# More grid lines than this is a spacing mistake, and would otherwise exhaust memory.
_MAX_GRID_LINES = 10_000
_RGB = np.dtype((np.void, 3))
# Candidate pixels rasterized at once (bounding-box pixels of a group of triangles): bounds the
# scratch memory of one group to some 100 MB however many large triangles one call holds.
_RASTER_BATCH = 1 << 20
# Toward the sun (world, unit): high, from behind the left shoulder of a camera looking +x.
SUN = np.array([-0.35, 0.45, 0.82]) / np.linalg.norm([-0.35, 0.45, 0.82])


class Camera:
    """Pinhole perspective camera.

    ``rotation`` holds the camera axes (right, down, forward) as rows, in world coordinates.
    The focal length, in pixels, follows from the vertical field of view ``fov_deg``. Points at
    depth ``<= near`` are behind the camera.
    """

    def __init__(
        self,
        eye: ArrayLike,
        rotation: ArrayLike,
        fov_deg: float = 50.0,
        width: int = 480,
        height: int = 360,
        near: float = 0.01,
    ) -> None:
        if int(width) < 1 or int(height) < 1:
            raise ValueError(f"image size must be positive, got {width}x{height}")
        if not 0.0 < fov_deg < 180.0:
            raise ValueError(f"fov_deg must be in (0, 180), got {fov_deg}")
        if not near > 0.0:
            raise ValueError(f"near must be positive, got {near}")
        self.eye = np.asarray(eye, dtype=np.float64).reshape(3)
        self.rotation = np.asarray(rotation, dtype=np.float64).reshape(3, 3)
        self.fov_deg = float(fov_deg)
        self.width = int(width)
        self.height = int(height)
        self.near = float(near)
        self.focal = 0.5 * self.height / math.tan(math.radians(self.fov_deg) / 2.0)
        self.center = np.array([0.5 * self.width, 0.5 * self.height])

    @classmethod
    def look_at(
        cls,
        eye: ArrayLike,
        target: ArrayLike,
        up: ArrayLike = (0.0, 0.0, 1.0),
        fov_deg: float = 50.0,
        width: int = 480,
        height: int = 360,
        near: float = 0.01,
    ) -> Camera:
        """Camera at ``eye`` looking at ``target``, with ``up`` pointing up in the image.

        A non-finite ``eye``, ``target`` or ``up`` gives a camera that draws nothing (a camera
        that follows a diverged craft should not stop the episode).
        """
        eye = np.asarray(eye, dtype=np.float64).reshape(3)
        target = np.asarray(target, dtype=np.float64).reshape(3)
        up = np.asarray(up, dtype=np.float64).reshape(3)
        with np.errstate(over="ignore", invalid="ignore"):
            forward = target - eye
        if not (np.isfinite(eye).all() and np.isfinite(forward).all() and np.isfinite(up).all()):
            return cls(eye, np.full((3, 3), np.nan), fov_deg, width, height, near)
        forward = _unit(forward)
        if not np.isfinite(forward).all():
            raise ValueError("eye and target coincide")
        right = _unit(np.cross(forward, _unit(up)))
        if not (np.isfinite(right).all() and abs(right @ right - 1.0) < 1e-6):
            # Looking along `up` (e.g. straight down), or a zero `up`: any roll will do.
            right = _unit(np.cross(forward, np.eye(3)[np.argmin(np.abs(forward))]))
        down = np.cross(forward, right)
        return cls(eye, np.stack([right, down, forward]), fov_deg, width, height, near)

    def to_camera(self, points: ArrayLike) -> np.ndarray:
        """World points ``[..., 3]`` -> camera-frame points ``[..., 3]`` (x right, y down, z
        forward)."""
        with np.errstate(invalid="ignore", over="ignore"):  # callers test for non-finite
            return (np.asarray(points, dtype=np.float64) - self.eye) @ self.rotation.T

    def project(self, points: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """World points ``[N, 3]`` -> (pixels ``[N, 2]`` float (x right, y down), depth ``[N]``
        along the view axis).

        Depth ``<= near`` means behind the camera; those pixels are NaN, since their projection
        would land mirrored on the image.
        """
        cam = self.to_camera(points)
        depth = cam[..., 2]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            pixels = self.center + self.focal * cam[..., :2] / depth[..., None]
        pixels[~(depth > self.near)] = np.nan
        return pixels, depth

    def _pixels(self, cam: np.ndarray) -> np.ndarray:
        """Camera-frame points in front of the camera -> pixels (non-finite past float range)."""
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return self.center + self.focal * cam[..., :2] / cam[..., 2:3]

    def _depth_key(self, depth: np.ndarray) -> np.ndarray:
        """A key that grows with ``depth`` and is linear across the image, so that it can be
        interpolated between a triangle's corners: -1/depth under perspective."""
        return -1.0 / depth

    def _rays(self, points: np.ndarray) -> np.ndarray:
        """Directions ``[..., 3]`` (world, not normalized) from the eye toward ``points``."""
        return points - self.eye


class OrthoCamera(Camera):
    """Orthographic camera (plans and elevations): ``scale`` pixels per meter, no
    perspective; the eye sits ``distance`` behind the view center along the view axis."""

    def __init__(
        self,
        center: ArrayLike,
        rotation: ArrayLike,
        scale: float,
        width: int = 480,
        height: int = 240,
        distance: float = 1.0e4,
    ) -> None:
        if not 0.0 < scale < math.inf:
            raise ValueError(f"scale must be positive and finite, got {scale}")
        rot = np.asarray(rotation, dtype=np.float64).reshape(3, 3)
        eye = np.asarray(center, dtype=np.float64).reshape(3) - distance * rot[2]
        super().__init__(eye, rot, 50.0, width, height, near=1e-9)
        self.scale = float(scale)
        self.distance = float(distance)

    def project(self, points: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        cam = self.to_camera(points)
        pixels = self._pixels(cam)
        pixels[~(cam[..., 2] > self.near)] = np.nan
        return pixels, cam[..., 2]

    def _pixels(self, cam: np.ndarray) -> np.ndarray:
        with np.errstate(over="ignore", invalid="ignore"):
            return self.center + self.scale * cam[..., :2]

    def _depth_key(self, depth: np.ndarray) -> np.ndarray:
        return depth  # already linear across the image

    def _rays(self, points: np.ndarray) -> np.ndarray:
        return np.broadcast_to(self.rotation[2], np.shape(points))


def _unit(v: np.ndarray) -> np.ndarray:
    """``v`` scaled to length 1 without overflow; NaN where ``v`` is zero."""
    with np.errstate(divide="ignore", invalid="ignore"):
        v = v / np.abs(v).max()
        return v / np.sqrt(v @ v)


def _grid_positions(c: float, h: float, spacing: float) -> np.ndarray:
    """The multiples of ``spacing`` within ``h`` of ``c``.

    Multiples rather than offsets from ``c``, so that the grid stays put in the world while
    ``c`` follows a moving craft (the motion cue).
    """
    with np.errstate(over="ignore"):
        k0, k1 = np.ceil((c - h) / spacing), np.floor((c + h) / spacing)
    if not (np.isfinite(k0) and np.isfinite(k1)):
        return np.empty(0)
    # At huge c, rounding can make k1 - k0 far exceed the 2h / spacing lines that fit.
    n = int(max(min(k1 - k0 + 1.0, 2.0 * (h / spacing) + 1.0), 0.0))
    return spacing * (k0 + np.arange(n))


def _colors(color: ArrayLike, n: int) -> np.ndarray:
    """One color ``(3,)`` or one per primitive ``[n, 3]`` -> ``[n, 3]`` uint8."""
    c = np.asarray(color)
    if c.dtype != np.uint8:
        c = np.clip(np.nan_to_num(c.astype(np.float64)), 0.0, 255.0).round().astype(np.uint8)
    if c.shape == (3,):
        return np.broadcast_to(c, (n, 3))
    if c.shape != (n, 3):
        raise ValueError(f"color must have shape (3,) or ({n}, 3), got {c.shape}")
    return c


def _batches(count: np.ndarray, limit: int) -> list[np.ndarray]:
    """Consecutive groups of the indices of ``count`` whose counts sum to about ``limit`` at
    most (a single count over it makes a group of its own)."""
    if not len(count) or not count.sum():
        return []
    ends = np.cumsum(count)
    group = (ends - count) // limit
    return np.split(np.arange(len(count)), np.flatnonzero(np.diff(group)) + 1)


def _clip_to_rect(p0: np.ndarray, p1: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Liang-Barsky clipping of 2D segments ``p0 -> p1`` ``[N, 2]`` to the box ``[lo, hi]``.

    Returns the clipped endpoints and the mask of segments that touch the box.
    """
    t0 = np.zeros(len(p0))
    t1 = np.ones(len(p0))
    keep = np.ones(len(p0), dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        d = p1 - p0
        for p, q in ((-d, p0 - lo), (d, hi - p0)):
            for axis in range(2):
                pk, qk = p[:, axis], q[:, axis]
                r = qk / pk
                keep &= ~((pk == 0.0) & (qk < 0.0))
                t0 = np.where(pk < 0.0, np.maximum(t0, r), t0)
                t1 = np.where(pk > 0.0, np.minimum(t1, r), t1)
        c0, c1 = p0 + t0[:, None] * d, p0 + t1[:, None] * d
    # Ends beyond float range (inf - inf) come out NaN: skip those segments.
    keep &= (t0 <= t1) & np.isfinite(c0).all(axis=1) & np.isfinite(c1).all(axis=1)
    return c0, c1, keep


class Canvas:
    """An RGB image to draw on, with a depth buffer for its triangles.

    Triangles are depth-tested (:meth:`triangles`, :meth:`mesh`); everything else is painted
    over what is already there.
    """

    def __init__(
        self, width: int = 480, height: int = 360, background: ArrayLike = (200, 225, 245)
    ) -> None:
        self.width = int(width)
        self.height = int(height)
        self.background = _colors(background, 1)[0].copy()
        self._buf = np.empty((self.height, self.width, 3), dtype=np.uint8)
        # the depth key (Camera._depth_key) of the nearest triangle drawn at each pixel, and a
        # scratch buffer (kept at inf) that resolves overlaps within one painted call
        self._depth = np.empty(self.height * self.width)
        self._scratch: np.ndarray | None = None  # made by the first painted call
        self.clear()

    def clear(self, color: ArrayLike | None = None) -> None:
        """Fill the image with ``color``, or with the background color; empty the depth
        buffer."""
        self._fill(0, self.height, self.background if color is None else _colors(color, 1)[0])
        self._depth.fill(np.inf)

    def fill_rows(self, y0: float, y1: float, color: ArrayLike) -> None:
        """Fill rows ``y0`` to ``y1`` (rounded; half-open), clipped to the image: sky and
        ground bands. Infinite bounds clip; a NaN bound fills nothing."""
        if math.isnan(y0) or math.isnan(y1):
            return
        r0 = round(min(max(y0, 0.0), self.height))
        r1 = round(min(max(y1, 0.0), self.height))
        if r1 > r0:
            self._fill(r0, r1, _colors(color, 1)[0])

    def _put(self, flat: np.ndarray, colors: np.ndarray, which: np.ndarray) -> None:
        """Set pixels ``flat`` (row * width + col) to ``colors[which]``."""
        # Whole pixels as 3-byte voids: fancy assignment is ~3x faster than on [H, W, 3].
        pixels = self._buf.view(_RGB).reshape(-1)
        pixels[flat] = np.ascontiguousarray(colors).view(_RGB).reshape(-1)[which]

    def _fill(self, r0: int, r1: int, color: np.ndarray) -> None:
        # Broadcasting a (3,) color over [rows, W, 3] is ~50x slower than copying whole rows.
        self._buf[r0] = color
        self._buf[r0 + 1 : r1] = self._buf[r0]

    def lines(
        self, camera: Camera, a: ArrayLike, b: ArrayLike, color: ArrayLike, thickness: int = 1
    ) -> None:
        """Segments ``a[i] -> b[i]`` (``[N, 3]`` world), ``thickness`` pixels wide.

        The part of a segment behind the camera is cut off at the near plane; projecting it
        as is would wrap it through infinity onto the wrong side of the image.
        """
        self._check(camera)
        a = np.asarray(a, dtype=np.float64).reshape(-1, 3)
        b = np.asarray(b, dtype=np.float64).reshape(-1, 3)
        if a.shape != b.shape:
            raise ValueError(f"a and b differ in shape: {a.shape} and {b.shape}")
        colors = _colors(color, len(a))
        ca, cb = camera.to_camera(a), camera.to_camera(b)
        za, zb = ca[:, 2] - camera.near, cb[:, 2] - camera.near
        keep = np.isfinite(ca).all(axis=1) & np.isfinite(cb).all(axis=1) & ((za > 0) | (zb > 0))
        if not keep.any():
            return
        ca, cb, za, zb, colors = ca[keep], cb[keep], za[keep], zb[keep], colors[keep]
        cut_a, cut_b = za <= 0, zb <= 0
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            t = (za / (za - zb))[:, None]  # only used where one end is behind, so za != zb
            ca[cut_a] += t[cut_a] * (cb[cut_a] - ca[cut_a])
            cb[cut_b] = ca[cut_b] + t[cut_b] * (cb[cut_b] - ca[cut_b])
        pa, pb = camera._pixels(ca), camera._pixels(cb)
        # Cut ends land on the near plane, unless rounding of huge coordinates throws them off.
        keep = (ca[:, 2] > 0) & (cb[:, 2] > 0)
        keep &= np.isfinite(pa).all(axis=1) & np.isfinite(pb).all(axis=1)
        pa, pb, colors = pa[keep], pb[keep], colors[keep]

        thickness = max(int(thickness), 1)
        margin = np.array([thickness, thickness], dtype=np.float64)
        size = np.array([self.width, self.height], dtype=np.float64)
        pa, pb, keep = _clip_to_rect(pa, pb, -margin, size + margin)
        if not keep.any():
            return
        pa, pb, colors = pa[keep], pb[keep], colors[keep]

        # Samples at most 1 px apart along the major axis give a gap-free 8-connected line.
        d = pb - pa
        n = np.ceil(np.abs(d).max(axis=1)).astype(np.intp) + 1
        step = d / np.maximum(n - 1, 1)[:, None]
        # np.repeat of per-segment values is much faster than fancy-indexing them by sample.
        seg = np.repeat(np.arange(len(n)), n)
        k = np.arange(len(seg)) - np.repeat(np.cumsum(n) - n, n)
        ix = np.floor(np.repeat(pa[:, 0], n) + k * np.repeat(step[:, 0], n)).astype(np.intp)
        iy = np.floor(np.repeat(pa[:, 1], n) + k * np.repeat(step[:, 1], n)).astype(np.intp)
        if thickness > 1:
            # Widen across the major axis, as a thick Bresenham line does.
            offsets = np.arange(thickness) - (thickness - 1) // 2
            steep = np.repeat(np.abs(d[:, 1]) > np.abs(d[:, 0]), n)
            ix = (ix + np.where(steep, offsets[:, None], 0)).ravel()
            iy = (iy + np.where(steep, 0, offsets[:, None])).ravel()
            seg = np.tile(seg, thickness)
        inside = (ix >= 0) & (ix < self.width) & (iy >= 0) & (iy < self.height)
        self._put(iy[inside] * self.width + ix[inside], colors, seg[inside])

    def triangles(
        self, camera: Camera, tris: ArrayLike, color: ArrayLike, depth_test: bool = True
    ) -> None:
        """Filled triangles ``[N, 3, 3]`` (world).

        With ``depth_test`` (the default) a pixel takes the nearest triangle's color unless a
        nearer one is already in the depth buffer, which it then updates. Without it, the call
        paints over the image (its own triangles nearest on top) and leaves the depth buffer
        alone: flat drawings (plans, elevations) whose later layers go on top.

        A triangle with any vertex behind the camera is skipped, not clipped.
        """
        self._check(camera)
        tris = np.asarray(tris, dtype=np.float64).reshape(-1, 3, 3)
        colors = _colors(color, len(tris))
        for flat, which in self._raster(camera, tris, depth_test):
            self._put(flat, colors, which)

    def mesh(
        self,
        camera: Camera,
        vertices: ArrayLike,
        triangles: ArrayLike,
        colors: ArrayLike,
        sun: ArrayLike = SUN,
        ambient: float = 0.45,
        closed: ArrayLike | None = None,
    ) -> None:
        """An indexed mesh (world ``vertices [V, 3]``, ``triangles [T, 3]`` indices, a color
        per triangle ``[T, 3]`` or one), depth-tested and Lambert-shaded by a sun in direction
        ``sun`` (toward it): ``color * (ambient + (1 - ambient) * max(0, n . sun))``.

        Faces are lit on the side the camera sees (a normal turned toward the camera): a thin
        sheet such as a paper wing is bright from above in sunlight and dark from below.
        Triangles marked in ``closed`` ``[T]`` (bool) belong to solids wound outward: those
        facing away from the camera are hidden anyway, and are skipped.
        """
        v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
        t = np.asarray(triangles, dtype=np.intp).reshape(-1, 3)
        pix, _ = camera.project(v)
        with np.errstate(invalid="ignore"):  # all on one side of the image: nothing to draw
            if (pix < 0).all(axis=0).any() or (pix > [self.width, self.height]).all(axis=0).any():
                return
        tris = v[t]
        base = _colors(colors, len(t)).astype(np.float64)
        with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
            n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            away = np.einsum("ij,ij->i", n, camera._rays(tris.mean(axis=1))) > 0.0
            n[away] *= -1.0
            light = np.clip(np.nan_to_num(n @ np.asarray(sun, dtype=np.float64)), 0.0, 1.0)
        shaded = base * (ambient + (1.0 - ambient) * light)[:, None]
        if closed is not None:
            seen = ~(np.asarray(closed, dtype=bool).reshape(-1) & away)
            tris, shaded = tris[seen], shaded[seen]
        self.triangles(camera, tris, shaded)

    def shadow(
        self,
        camera: Camera,
        tris: ArrayLike,
        plane_z: float = 0.0,
        light: ArrayLike = (0.0, 0.0, 1.0),
        darken: float = 0.55,
    ) -> None:
        """Darken (times ``darken``) the pixels where triangles ``[N, 3, 3]`` (world) cast
        their shadow on the plane ``z = plane_z``, lit from direction ``light`` (toward the
        light; default straight above). Each pixel is darkened once however many triangles
        cover it; nearer surfaces already in the depth buffer keep their color."""
        tris = np.asarray(tris, dtype=np.float64).reshape(-1, 3, 3)
        d = np.asarray(light, dtype=np.float64)
        if not d[2] > 0.0:
            raise ValueError(f"light must point up (z > 0) to cast a shadow down, got {light}")
        with np.errstate(invalid="ignore", over="ignore"):
            height = np.maximum(tris[..., 2] - plane_z, 0.0)
            flat = tris - (height / d[2])[..., None] * d
        flat[..., 2] = plane_z
        hit = [f for f, _ in self._raster(camera, flat, depth_test=True, write=False)]
        if hit:
            where = np.unique(np.concatenate(hit))
            pixels = self._buf.reshape(-1, 3)
            pixels[where] = (pixels[where] * darken).astype(np.uint8)

    def _raster(self, camera: Camera, tris: np.ndarray, depth_test: bool, write: bool = True):
        """Yield, group by group, the covered pixels (flat indices) of triangles ``[N, 3, 3]``
        (world) that win the depth test, with the triangle covering each."""
        self._check(camera)
        cam = camera.to_camera(tris)
        keep = np.isfinite(cam).all(axis=(1, 2)) & (cam[:, :, 2] > camera.near).all(axis=1)
        if not keep.any():
            return
        pix = camera._pixels(cam)
        keep &= np.isfinite(pix).all(axis=(1, 2))
        idx = np.flatnonzero(keep)
        pix, key = pix[idx], camera._depth_key(cam[idx, :, 2])
        # Pixels whose centers (col + 0.5, row + 0.5) lie in the bounding box, clipped to the
        # image before the integer cast, which large coordinates would overflow.
        lo = np.ceil(pix.min(axis=1) - 0.5).clip(0, [self.width, self.height])
        hi = np.floor(pix.max(axis=1) - 0.5).clip(-1, [self.width - 1, self.height - 1])
        lo, size = lo.astype(np.intp), (hi - lo + 1).clip(0).astype(np.intp)
        # Edge k runs from corner k to k + 1; its edge function, over the signed area, is the
        # barycentric weight of the corner opposite (k + 2): >= 0 inside, whatever the winding.
        # Each weight, and so the depth key, is a plane over the image: a + b dx + c dy at
        # (dx, dy) pixels from the box's first pixel center. One row of coefficients per
        # triangle: one gather per candidate pixel instead of one per coefficient.
        edge = np.roll(pix, -1, axis=1) - pix
        first = lo + 0.5
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            area = edge[:, 0, 1] * edge[:, 2, 0] - edge[:, 0, 0] * edge[:, 2, 1]
            ex, ey = edge[..., 0] / area[:, None], edge[..., 1] / area[:, None]
            at = ex * (first[:, None, 1] - pix[..., 1]) - ey * (first[:, None, 0] - pix[..., 0])
            opposite = np.roll(key, -2, axis=1)  # the key of the corner each weight belongs to
            table = np.concatenate(
                [
                    at,
                    -ey,
                    ex,
                    (at * opposite).sum(axis=1, keepdims=True),
                    (-ey * opposite).sum(axis=1, keepdims=True),
                    (ex * opposite).sum(axis=1, keepdims=True),
                ],
                axis=1,
            )
        ok = (np.abs(area) > 1e-12) & np.isfinite(table).all(axis=1)
        count = np.where(ok, size[:, 0] * size[:, 1], 0)
        # Painted calls go far to near (mean depth), so that a nearer group paints over.
        order = np.argsort(-key.sum(axis=1), kind="stable") if not depth_test else None
        groups = _batches(count if order is None else count[order], _RASTER_BATCH)
        if not depth_test and self._scratch is None:
            self._scratch = np.full(self.height * self.width, np.inf)
        target = self._depth if depth_test else self._scratch
        for sel in groups:
            sel = sel if order is None else order[sel]
            n = count[sel]
            tri = np.repeat(sel, n)
            k = np.arange(len(tri)) - np.repeat(np.cumsum(n) - n, n)
            w = size[tri, 0]
            dx, dy = k % w, k // w
            t = table[tri]
            with np.errstate(invalid="ignore", over="ignore"):
                b = t[:, 0:3] + t[:, 3:6] * dx[:, None] + t[:, 6:9] * dy[:, None]
                z = t[:, 9] + t[:, 10] * dx + t[:, 11] * dy
            inside = (b >= 0.0).all(axis=1)
            col, row = lo[tri, 0] + dx, lo[tri, 1] + dy
            flat, tri, z = (row * self.width + col)[inside], tri[inside], z[inside]
            if not len(flat):
                continue
            if depth_test and not write:  # a test against what is drawn (shadows): no update
                win = z <= self._depth[flat]
            else:  # the nearest candidate of each pixel, against the buffer's or alone
                np.minimum.at(target, flat, z)
                win = z <= target[flat]
                if not depth_test:
                    target[flat] = np.inf
            yield flat[win], idx[tri[win]]

    def points(
        self,
        camera: Camera,
        p: ArrayLike,
        color: ArrayLike,
        radius: int = 3,
        depth_test: bool = False,
    ) -> None:
        """Filled discs of ``radius`` pixels at the projections of points ``[N, 3]`` (world).

        With ``depth_test``, a disc is hidden where a triangle already drawn lies nearer than
        its point (particles behind a hull); the depth buffer is left alone either way.
        """
        self._check(camera)
        p = np.asarray(p, dtype=np.float64).reshape(-1, 3)
        colors = _colors(color, len(p))
        r = max(int(round(radius)), 0)
        pix, depth = camera.project(p)
        lo, hi = -r - 1.0, np.array([self.width, self.height]) + r + 1.0
        # Bounds before the integer cast: a huge pixel coordinate would overflow it.
        keep = np.isfinite(pix).all(axis=1) & (pix > lo).all(axis=1) & (pix < hi).all(axis=1)
        if not keep.any():
            return
        pix, colors, depth = pix[keep], colors[keep], depth[keep]
        oy, ox = np.mgrid[-r : r + 1, -r : r + 1]
        disc = ox**2 + oy**2 <= r * (r + 1)  # r(r+1) rounds the disc better than r^2
        ix = np.floor(pix[:, :1]).astype(np.intp) + ox[disc]
        iy = np.floor(pix[:, 1:]).astype(np.intp) + oy[disc]
        seg = np.broadcast_to(np.arange(len(pix))[:, None], ix.shape)
        inside = (ix >= 0) & (ix < self.width) & (iy >= 0) & (iy < self.height)
        flat, seg = iy[inside] * self.width + ix[inside], seg[inside]
        if depth_test:
            with np.errstate(divide="ignore"):
                front = camera._depth_key(depth)[seg] <= self._depth[flat]
            flat, seg = flat[front], seg[front]
        self._put(flat, colors, seg)

    def ground_grid(
        self,
        camera: Camera,
        center: ArrayLike,
        half_size: float,
        spacing: float,
        color: ArrayLike,
    ) -> None:
        """Grid lines on the plane z = 0, ``spacing`` apart, within ``half_size`` of ``center``
        (x, y) in x and in y."""
        if not 0.0 < spacing < math.inf:
            raise ValueError(f"spacing must be positive and finite, got {spacing}")
        cx, cy = (float(c) for c in np.asarray(center, dtype=np.float64).reshape(-1)[:2])
        h = float(half_size)
        if not (math.isfinite(cx) and math.isfinite(cy) and math.isfinite(h) and h > 0.0):
            return
        if not 2.0 * (h / spacing) <= _MAX_GRID_LINES:
            raise ValueError(f"{2 * (h / spacing):.0f} grid lines per axis; raise spacing")
        xs, ys = _grid_positions(cx, h, spacing), _grid_positions(cy, h, spacing)
        zx, zy = np.zeros_like(xs), np.zeros_like(ys)
        a = np.concatenate(
            [np.stack([xs, zx + cy - h, zx], axis=1), np.stack([zy + cx - h, ys, zy], axis=1)]
        )
        b = np.concatenate(
            [np.stack([xs, zx + cy + h, zx], axis=1), np.stack([zy + cx + h, ys, zy], axis=1)]
        )
        self.lines(camera, a, b, color)

    def rect(self, x0: int, y0: int, x1: int, y1: int, color: ArrayLike, alpha: float = 1.0):
        """Fill columns ``x0:x1`` of rows ``y0:y1`` (pixels, clipped to the image), blending
        ``color`` over the image with opacity ``alpha`` (a readout's backdrop)."""
        if not 0.0 <= alpha <= 1.0:
            raise ValueError(f"alpha must be in [0, 1], got {alpha}")
        x0, x1 = max(int(x0), 0), min(int(x1), self.width)
        y0, y1 = max(int(y0), 0), min(int(y1), self.height)
        if x1 <= x0 or y1 <= y0:
            return
        c = _colors(color, 1)[0].astype(np.float64)
        area = self._buf[y0:y1, x0:x1]
        area[:] = (alpha * c + (1.0 - alpha) * area).round().astype(np.uint8)

    def text(self, x: int, y: int, text: str, color: ArrayLike, scale: int = 1) -> None:
        """Write ``text`` (lines split at ``\\n``) with its top-left corner at pixel
        ``(x, y)``, in the built-in 5 x 7 font enlarged ``scale`` times; clipped to the image.

        Raises ValueError naming a character the font lacks (printable ASCII and the degree
        sign).
        """
        if isinstance(scale, bool) or int(scale) != scale or scale < 1:
            raise ValueError(f"scale must be a positive integer, got {scale!r}")
        missing = sorted(set(text) - set(_FONT) - {"\n"})
        if missing:
            raise ValueError(f"the font has no glyph for {missing[0]!r} in {text!r}")
        scale = int(scale)
        lit = []
        for r, line in enumerate(text.split("\n")):
            for k, ch in enumerate(line):
                rows, cols = _LIT[ch]
                lit.append((rows + r * (GLYPH_H + 2), cols + k * (GLYPH_W + 1)))
        if not lit:
            return
        rows = np.concatenate([a for a, _ in lit])
        cols = np.concatenate([b for _, b in lit])
        sub = np.arange(scale)  # each font cell becomes a scale x scale block
        block = (len(rows), scale, scale)
        iy = np.broadcast_to(y + scale * rows[:, None, None] + sub[:, None], block).ravel()
        ix = np.broadcast_to(x + scale * cols[:, None, None] + sub[None, :], block).ravel()
        inside = (ix >= 0) & (ix < self.width) & (iy >= 0) & (iy < self.height)
        self._buf[iy[inside], ix[inside]] = _colors(color, 1)[0]

    def blit(self, x: int, y: int, image: ArrayLike) -> None:
        """Copy ``image`` ``[h, w, 3]`` onto the image with its top-left corner at pixel
        ``(x, y)``, clipped to the image (a computed background such as a colored slice of a
        field, a color scale, an inset); the depth buffer is left alone."""
        img = np.asarray(image)
        if img.ndim != 3 or img.shape[2] != 3:
            raise ValueError(f"image must have shape [h, w, 3], got {img.shape}")
        x0, y0 = max(int(x), 0), max(int(y), 0)
        x1, y1 = min(int(x) + img.shape[1], self.width), min(int(y) + img.shape[0], self.height)
        if x1 <= x0 or y1 <= y0:
            return
        part = img[y0 - int(y) : y1 - int(y), x0 - int(x) : x1 - int(x)]
        self._buf[y0:y1, x0:x1] = _colors(part.reshape(-1, 3), part.size // 3).reshape(part.shape)

    def image(self) -> np.ndarray:
        """A copy of the ``[height, width, 3]`` uint8 image."""
        return self._buf.copy()

    def _check(self, camera: Camera) -> None:
        if (camera.width, camera.height) != (self.width, self.height):
            raise ValueError(
                f"camera is {camera.width}x{camera.height}, canvas {self.width}x{self.height}"
            )


# ---- text ------------------------------------------------------------------------------------

# A 5 x 7 pixel font for on-screen readouts: each line is a character, then its seven rows
# ('#' lit). Printable ASCII and the degree sign; the space is blank.
_FONT_TABLE = r"""
! ..#.. ..#.. ..#.. ..#.. ..#.. ..... ..#..
" .#.#. .#.#. .#.#. ..... ..... ..... .....
# .#.#. .#.#. ##### .#.#. ##### .#.#. .#.#.
$ ..#.. .#### #.#.. .###. ..#.# ####. ..#..
% ##... ##..# ...#. ..#.. .#... #..## ...##
& .##.. #..#. #.#.. .#... #.#.# #..#. .##.#
' ..#.. ..#.. .#... ..... ..... ..... .....
( ...#. ..#.. .#... .#... .#... ..#.. ...#.
) .#... ..#.. ...#. ...#. ...#. ..#.. .#...
* ..... ..#.. #.#.# .###. #.#.# ..#.. .....
+ ..... ..#.. ..#.. ##### ..#.. ..#.. .....
, ..... ..... ..... ..... .##.. ..#.. .#...
- ..... ..... ..... ##### ..... ..... .....
. ..... ..... ..... ..... ..... .##.. .##..
/ ..... ....# ...#. ..#.. .#... #.... .....
0 .###. #...# #..## #.#.# ##..# #...# .###.
1 ..#.. .##.. ..#.. ..#.. ..#.. ..#.. .###.
2 .###. #...# ....# ...#. ..#.. .#... #####
3 ##### ...#. ..#.. ...#. ....# #...# .###.
4 ...#. ..##. .#.#. #..#. ##### ...#. ...#.
5 ##### #.... ####. ....# ....# #...# .###.
6 ..##. .#... #.... ####. #...# #...# .###.
7 ##### ....# ...#. ..#.. .#... .#... .#...
8 .###. #...# #...# .###. #...# #...# .###.
9 .###. #...# #...# .#### ....# ...#. .##..
: ..... .##.. .##.. ..... .##.. .##.. .....
; ..... .##.. .##.. ..... .##.. ..#.. .#...
< ...#. ..#.. .#... #.... .#... ..#.. ...#.
= ..... ..... ##### ..... ##### ..... .....
> .#... ..#.. ...#. ....# ...#. ..#.. .#...
? .###. #...# ....# ...#. ..#.. ..... ..#..
@ .###. #...# ....# .##.# #.#.# #.#.# .###.
A .###. #...# #...# ##### #...# #...# #...#
B ####. #...# #...# ####. #...# #...# ####.
C .###. #...# #.... #.... #.... #...# .###.
D ###.. #..#. #...# #...# #...# #..#. ###..
E ##### #.... #.... ####. #.... #.... #####
F ##### #.... #.... ####. #.... #.... #....
G .###. #...# #.... #.### #...# #...# .####
H #...# #...# #...# ##### #...# #...# #...#
I .###. ..#.. ..#.. ..#.. ..#.. ..#.. .###.
J ..### ...#. ...#. ...#. ...#. #..#. .##..
K #...# #..#. #.#.. ##... #.#.. #..#. #...#
L #.... #.... #.... #.... #.... #.... #####
M #...# ##.## #.#.# #.#.# #...# #...# #...#
N #...# #...# ##..# #.#.# #..## #...# #...#
O .###. #...# #...# #...# #...# #...# .###.
P ####. #...# #...# ####. #.... #.... #....
Q .###. #...# #...# #...# #.#.# #..#. .##.#
R ####. #...# #...# ####. #.#.. #..#. #...#
S .#### #.... #.... .###. ....# ....# ####.
T ##### ..#.. ..#.. ..#.. ..#.. ..#.. ..#..
U #...# #...# #...# #...# #...# #...# .###.
V #...# #...# #...# #...# #...# .#.#. ..#..
W #...# #...# #...# #.#.# #.#.# #.#.# .#.#.
X #...# #...# .#.#. ..#.. .#.#. #...# #...#
Y #...# #...# .#.#. ..#.. ..#.. ..#.. ..#..
Z ##### ....# ...#. ..#.. .#... #.... #####
[ .###. .#... .#... .#... .#... .#... .###.
\ ..... #.... .#... ..#.. ...#. ....# .....
] .###. ...#. ...#. ...#. ...#. ...#. .###.
^ ..#.. .#.#. #...# ..... ..... ..... .....
_ ..... ..... ..... ..... ..... ..... #####
` .#... ..#.. ...#. ..... ..... ..... .....
a ..... ..... .###. ....# .#### #...# .####
b #.... #.... #.##. ##..# #...# #...# ####.
c ..... ..... .###. #.... #.... #...# .###.
d ....# ....# .##.# #..## #...# #...# .####
e ..... ..... .###. #...# ##### #.... .###.
f ..##. .#..# .#... ###.. .#... .#... .#...
g ..... .#### #...# #...# .#### ....# .###.
h #.... #.... #.##. ##..# #...# #...# #...#
i ..#.. ..... .##.. ..#.. ..#.. ..#.. .###.
j ...#. ..... ..##. ...#. ...#. #..#. .##..
k #.... #.... #..#. #.#.. ##... #.#.. #..#.
l .##.. ..#.. ..#.. ..#.. ..#.. ..#.. .###.
m ..... ..... ##.#. #.#.# #.#.# #...# #...#
n ..... ..... #.##. ##..# #...# #...# #...#
o ..... ..... .###. #...# #...# #...# .###.
p ..... ..... ####. #...# ####. #.... #....
q ..... ..... .##.# #..## .#### ....# ....#
r ..... ..... #.##. ##..# #.... #.... #....
s ..... ..... .###. #.... .###. ....# ####.
t .#... .#... ###.. .#... .#... .#..# ..##.
u ..... ..... #...# #...# #...# #..## .##.#
v ..... ..... #...# #...# #...# .#.#. ..#..
w ..... ..... #...# #...# #.#.# #.#.# .#.#.
x ..... ..... #...# .#.#. ..#.. .#.#. #...#
y ..... ..... #...# #...# .#### ....# .###.
z ..... ..... ##### ...#. ..#.. .#... #####
{ ...#. ..#.. ..#.. .#... ..#.. ..#.. ...#.
| ..#.. ..#.. ..#.. ..#.. ..#.. ..#.. ..#..
} .#... ..#.. ..#.. ...#. ..#.. ..#.. .#...
~ ..... ..... .#... #.#.# ...#. ..... .....
° .##.. #..#. #..#. .##.. ..... ..... .....
"""
GLYPH_W, GLYPH_H = 5, 7  # a glyph's lit cells; characters advance GLYPH_W + 1 columns


def _parse_font(table: str) -> dict[str, np.ndarray]:
    font = {" ": np.zeros((GLYPH_H, GLYPH_W), dtype=bool)}
    for line in table.strip("\n").split("\n"):
        rows = line[2:].split()
        font[line[0]] = np.array([[c == "#" for c in r] for r in rows], dtype=bool)
        assert font[line[0]].shape == (GLYPH_H, GLYPH_W), line
    return font


_FONT = _parse_font(_FONT_TABLE)
_LIT = {ch: np.nonzero(glyph) for ch, glyph in _FONT.items()}  # each glyph's (rows, cols)


def text_size(text: str, scale: int = 1) -> tuple[int, int]:
    """(width, height) in pixels of ``text`` drawn by :meth:`Canvas.text` (lines split at
    ``\\n``): no trailing spacing column or row."""
    lines = text.split("\n")
    cols = max(len(s) for s in lines)
    return (
        max(cols * (GLYPH_W + 1) - 1, 0) * scale,
        (len(lines) * (GLYPH_H + 2) - 2) * scale,
    )
