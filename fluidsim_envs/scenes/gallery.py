"""The docs' pictures of every scene: ``python -m fluidsim_envs.scenes.gallery [OUT_DIR]``.

Flies each registered scene's scripted pilot through one episode from a fixed seed, rendering
every step (the views keep state from frame to frame: the boat's wake, the submarine's
tracers), and writes ``OUT_DIR/frames_<scene>.png``: three rgb_array frames side by side (the
start, the middle and the last step of the episode), each captioned with its moment, the
episode time and, for the last, how the episode ended; 256 colors, a few tens to ~150 kB.

Options: ``--seed N`` (default 0), ``--ids ID [ID ...]`` (default: every scene).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from . import SCENES, V0_SCENES
from .render import Canvas

CAPTION_H, GAP = 16, 4  # the caption strip under each frame; the gap between frames (px)
BACK, INK = (24, 28, 36), (230, 232, 236)


def episode_frames(scene, seed: int = 0) -> list[tuple[str, np.ndarray]]:
    """(caption, frame) at the start, middle and end of one episode of ``scene`` flown by its
    scripted pilot from ``seed``."""
    venv = scene.vector_cls(num_envs=1, render_mode="rgb_array", autoreset=False)
    pilot = scene.pilot(venv)
    obs, _ = venv.reset(seed=seed)
    period = venv.params.dt * venv.params.substeps
    frames = [venv.render()[0]]
    while True:
        obs, _, terminated, truncated, _ = venv.step(pilot(obs))
        frames.append(venv.render()[0])  # the last one shows the episode's final state
        if terminated[0] or truncated[0]:
            break
    venv.close()
    end = "time limit" if truncated[0] else "terminated"
    picks = [(0, "start"), (len(frames) // 2, "middle"), (len(frames) - 1, f"end ({end})")]
    return [(f"{label}, t = {k * period:.1f} s", frames[k]) for k, label in picks]


def strip(captioned: list[tuple[str, np.ndarray]]) -> np.ndarray:
    """The frames side by side, ``GAP`` px apart, each over its caption."""
    h, w, _ = captioned[0][1].shape
    canvas = Canvas(len(captioned) * (w + GAP) - GAP, h + CAPTION_H, background=BACK)
    for k, (caption, frame) in enumerate(captioned):
        canvas.blit(k * (w + GAP), 0, frame)
        canvas.text(k * (w + GAP) + 4, h + 5, caption, INK)
    return canvas.image()


def scene_name(scene) -> str:
    """The scene's package name (``paper_airplane`` for PaperAirplane-v0), with its version
    after v0 (``paper_airplane_v1``)."""
    name = scene.env_cls.__module__.split(".")[-2]
    return name if scene.version == 0 else f"{name}_v{scene.version}"


def write(out_dir: Path, seed: int = 0, ids=None) -> list[Path]:
    """Write the pictures of the scenes ``ids`` (default each scene's v0: a later version
    flies the same craft) into ``out_dir``; returns the paths written."""
    from PIL import Image  # matplotlib's dependency; only this tool needs it

    ids = list(V0_SCENES) if ids is None else list(ids)
    unknown = [i for i in ids if i not in SCENES]
    if unknown:
        raise ValueError(f"unknown scene id {unknown[0]!r}; registered: {sorted(SCENES)}")
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for i in ids:
        scene = SCENES[i]
        path = out_dir / f"frames_{scene_name(scene)}.png"
        image = Image.fromarray(strip(episode_frames(scene, seed)))
        # 256 colors, not dithered: the wake's smooth shading halves in size, looking the same
        image.quantize(256, Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(
            path, optimize=True
        )
        paths.append(path)
    return paths


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m fluidsim_envs.scenes.gallery", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument(
        "out_dir", nargs="?", default="docs", type=Path, help="where the PNGs go (docs)"
    )
    parser.add_argument("--seed", type=int, default=0, help="the episode's seed (0)")
    parser.add_argument(
        "--ids", nargs="+", default=None, metavar="ID", help="env ids (default: every scene)"
    )
    args = parser.parse_args(argv)
    try:
        paths = write(args.out_dir, args.seed, args.ids)
    except ValueError as err:
        parser.error(str(err))
    for p in paths:
        print(f"{p} ({p.stat().st_size // 1024} kB)")


if __name__ == "__main__":
    main()
