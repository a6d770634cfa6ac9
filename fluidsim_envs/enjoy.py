"""Watch a trained policy fly: a zoo entry (``zoo/<env>-<algo>/``) or any run folder.

    python -m fluidsim_envs.enjoy zoo/PaperAirplane-v1-ppo [--episodes N] [--seed S]
                                  [--env KEY=VALUE ...] [--rerun FILE.rrd] [--video FILE.mp4]
                                  [--stride N] [--width PIXELS] [--speed X] [--allow-pickle]

The policy acts deterministically on observations normalized with the statistics saved
beside it (``fluidsim-evaluate``'s rule), in one env, episode after episode from ``--seed``;
each episode's return, length and success are printed. ``--video`` writes the episodes'
``rgb_array`` frames (every ``--stride``-th, played at ``--speed`` times real time) as an
MP4 (moviepy, the ``play`` extra) or, for a name ending ``.gif``, a GIF (Pillow);
``--rerun`` records them for the Rerun viewer. With neither, the episodes play in a window
(pygame, the ``play`` extra); where no display exists that is an error that names
``--video`` and ``--rerun``.

A zoo entry is a run folder cut to what flying and checking it needs: ``config.yaml``,
``model.safetensors`` (the policy's weights), ``vecnormalize.safetensors`` and
``evaluation.csv`` (the row the README shows, which ``fluidsim-evaluate zoo/<name>`` writes
again). Loading them runs no code from them (:mod:`fluidsim_envs.rl.saved`); a folder that
holds SB3's pickled ``model.zip`` instead flies only with ``--allow-pickle``.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np


class EnjoyError(RuntimeError):
    """A folder or an option that cannot be used; the message names it."""


def load_policy(folder: Path, venv, allow_pickle: bool = False):
    """The folder's final model as a policy of ``venv`` (checked: config, model, statistics;
    SB3's pickles only with ``allow_pickle``)."""
    from fluidsim_envs.rl.evaluate import load_run, model_policy
    from fluidsim_envs.rl.runs import MODEL, PICKLED, STATS

    if not folder.is_dir():
        raise EnjoyError(f"{folder}: no such folder")
    if not (folder / MODEL).is_file() and not (folder / PICKLED[MODEL]).is_file():
        raise EnjoyError(
            f"{folder}: no {MODEL}; a zoo entry (or a finished run folder) holds {MODEL}, "
            f"{STATS} and config.yaml"
        )
    cfg, model = load_run(folder, "final", allow_pickle)
    return cfg, model_policy(cfg, model, folder, venv, "final", allow_pickle)


def make_env(folder: Path, overrides: dict, frames: bool, rerun: str | None):
    """One sub-env of the folder's env with its parameters (and ``overrides``)."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)
    from fluidsim_envs.rl.config import load_config
    from fluidsim_envs.rl.evaluate import env_kwargs_with

    if not (folder / "config.yaml").is_file():
        raise EnjoyError(f"{folder}: no config.yaml (not a zoo entry or run folder)")
    cfg = load_config(folder / "config.yaml")
    kwargs = env_kwargs_with(cfg.env_id, cfg.env_kwargs, overrides)
    venv = gym.make_vec(
        cfg.env_id,
        num_envs=1,
        vectorization_mode="vector_entry_point",
        render_mode="rgb_array" if frames else None,
        **kwargs,
    )
    if rerun is not None:
        from fluidsim_envs.wrappers import RerunLogger

        venv = RerunLogger(venv, path=rerun, name=folder.name)
    return cfg.env_id, venv


def fly(
    venv, policy, episodes: int, seed: int, on_frame=None, say=print, on_end=None
) -> list[dict]:
    """``episodes`` episodes one after another (the first reset seeded), each frame to
    ``on_frame`` (returning False stops): every control step's, an episode's last one drawn
    before the same-step autoreset replaces it, after which ``on_end()`` is called; returns
    each episode's return, length, success. ``venv``: a native vector env of one sub-env
    that resets in the same step (or a wrapper of one)."""
    native, last = venv.unwrapped, []  # the ended episode's frame, drawn before the reset
    if on_frame is not None and not getattr(native, "autoreset", False):
        raise EnjoyError(f"{type(native).__name__}: frames need a vector env that autoresets")
    hook = lambda ended, info, reward: last.append(native.render())  # noqa: E731
    if on_frame is not None:
        native.before_autoreset.append(hook)
    try:
        return _fly(venv, policy, episodes, seed, on_frame, say, on_end, last)
    finally:
        if hook in native.before_autoreset:
            native.before_autoreset.remove(hook)


def _fly(venv, policy, episodes, seed, on_frame, say, on_end, last) -> list[dict]:
    obs, _ = venv.reset(seed=seed)
    results, running, steps = [], 0.0, 0
    if on_frame is not None and on_frame(venv.render()[0]) is False:
        return results
    while len(results) < episodes:
        obs, reward, terminated, truncated, info = venv.step(policy(obs))
        running += float(reward[0])
        steps += 1
        done = bool(terminated[0] or truncated[0])
        if on_frame is not None and on_frame((last.pop() if done else venv.render())[0]) is False:
            break
        if done:
            if on_end is not None:
                on_end()
            if hasattr(policy, "reset"):  # a policy with memory starts the next episode anew
                policy.reset(terminated | truncated)
            success = info.get("final_info", {}).get("success")
            row = {"return": running, "length": steps}
            if success is not None:
                row["success"] = bool(success[0])
            results.append(row)
            won = "" if success is None else ("  success" if success[0] else "  no success")
            say(f"episode {len(results)}: return {running:.3f}, {steps} steps{won}")
            running, steps = 0.0, 0
            more = len(results) < episodes
            if more and on_frame is not None and on_frame(venv.render()[0]) is False:
                break  # the next episode's first frame
    return results


def write_video(
    frames: list[np.ndarray],
    path: str,
    fps: float,
    stride: int = 1,
    width: int | None = None,
    speed: float = 1.0,
    ends: tuple[int, ...] = (),
) -> int:
    """An MP4 (moviepy) or, for ``.gif``, an animated GIF (Pillow) of every ``stride``-th
    frame and each episode's last (``ends``, and the last frame), played at ``speed`` times
    real time (``fps * speed / stride`` frames a second), scaled to ``width`` pixels when
    given; returns how many frames it holds."""
    from PIL import Image

    # every stride-th frame, and each episode's last (``ends``: their indices) and the very
    # last: an episode's end is always shown
    keep = sorted({*range(0, len(frames), stride), *ends, len(frames) - 1})
    frames = [frames[i] for i in keep]
    fps = fps * speed / stride
    if width is not None:
        h, w = frames[0].shape[:2]
        size = (width, max(round(h * width / w), 1))
        frames = [
            np.asarray(Image.fromarray(np.asarray(f[:, :, :3])).resize(size, Image.LANCZOS))
            for f in frames
        ]
    if path.lower().endswith(".gif"):
        images = [Image.fromarray(np.asarray(f[:, :, :3], dtype=np.uint8)) for f in frames]
        images[0].save(
            path,
            save_all=True,
            append_images=images[1:],
            duration=round(1000.0 / fps),
            loop=0,
            optimize=True,
        )
        return len(frames)
    try:
        from moviepy import ImageSequenceClip
    except ImportError as e:
        raise EnjoyError(
            f"--video {path}: needs moviepy (the play extra): pip install "
            '"fluidsim-envs[play]" (or write a .gif)'
        ) from e
    clip = ImageSequenceClip([np.asarray(f[:, :, :3]) for f in frames], fps=fps)
    clip.write_videofile(path, logger=None)
    return len(frames)


def window(env_id: str, fps: float):
    """An ``on_frame`` that shows frames in a pygame window at ``fps`` (Esc or closing stops;
    ``fps`` 0: as fast as they come)."""
    from fluidsim_envs.play import check_display

    check_display()
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    pygame.display.init()  # not pygame.init(): no mixer, no audio driver looked for
    state: dict = {}
    clock = pygame.time.Clock()

    def show(frame: np.ndarray) -> bool:
        if "screen" not in state:
            state["screen"] = pygame.display.set_mode((frame.shape[1], frame.shape[0]))
            pygame.display.set_caption(f"{env_id}: Esc quits")
        for event in pygame.event.get():
            if event.type == pygame.QUIT or (
                event.type == pygame.KEYDOWN and event.key == pygame.K_ESCAPE
            ):
                return False
        surface = pygame.surfarray.make_surface(
            np.ascontiguousarray(frame[:, :, :3]).swapaxes(0, 1)
        )
        state["screen"].blit(surface, (0, 0))
        pygame.display.flip()
        clock.tick(fps)
        return True

    return show


def enjoy(
    folder: Path,
    episodes: int = 1,
    seed: int = 0,
    overrides: dict | None = None,
    rerun: str | None = None,
    video: str | None = None,
    say=print,
    stride: int = 1,
    width: int | None = None,
    realtime: bool = True,
    speed: float = 1.0,
    allow_pickle: bool = False,
) -> list[dict]:
    """Fly the folder's policy (see the module docstring); returns the episodes' results.
    ``folder``: a run folder, a zoo entry's folder, or a zoo entry's name (the package's
    copy: :mod:`fluidsim_envs.zoo`)."""
    from fluidsim_envs import zoo

    try:
        folder = zoo.path(folder)
    except zoo.ZooError:
        pass  # not an entry's name: load_policy names what the folder lacks
    if episodes < 1:
        raise EnjoyError(f"--episodes must be at least 1, got {episodes}")
    if stride < 1 or (width is not None and width < 8):
        raise EnjoyError(f"--stride must be >= 1 and --width >= 8, got {stride} and {width}")
    if not (np.isfinite(speed) and speed > 0):
        raise EnjoyError(f"--speed must be a positive number, got {speed}")
    shown = video is None and rerun is None
    if shown:  # pygame: said before the env is built (the play extra)
        from fluidsim_envs.rl.extras import require

        require("play", "python -m fluidsim_envs.enjoy without --video or --rerun")
    env_id, venv = make_env(folder, overrides or {}, frames=video is not None or shown, rerun=rerun)
    try:
        _, policy = load_policy(folder, venv.unwrapped if rerun else venv, allow_pickle)
        fps = venv.metadata["render_fps"]
        frames: list[np.ndarray] = []
        ends: list[int] = []  # each episode's last frame, kept whatever the stride
        on_frame = on_end = None
        if video is not None:
            on_frame = frames.append
            on_end = lambda: ends.append(len(frames) - 1)  # noqa: E731
        elif shown:
            on_frame = window(env_id, fps if realtime else 0)
        results = fly(venv, policy, episodes, seed, on_frame, say, on_end)
        if video is not None:
            kept = write_video(frames, video, fps, stride, width, speed, tuple(ends))
            say(f"wrote {video} ({kept} frames at {fps * speed / stride:g} per second)")
        if rerun is not None:
            say(f"recorded: rerun {rerun}")
    finally:
        venv.close()
    return results


def build_parser(prog: str = "python -m fluidsim_envs.enjoy") -> argparse.ArgumentParser:
    """The command line's parser (built without the extras: ``--help`` works without them)."""
    parser = argparse.ArgumentParser(prog=prog, description="Watch a trained policy fly.")
    parser.add_argument(
        "folder",
        type=Path,
        help="a zoo entry's name (PaperAirplane-v1-ppo) or folder (zoo/<env>-<algo>), or a run "
        "folder",
    )
    parser.add_argument(
        "--episodes", type=int, default=1, help="episodes to fly, one after another (default 1)"
    )
    parser.add_argument("--seed", type=int, default=0, help="the first episode's seed")
    parser.add_argument(
        "--env",
        metavar="KEY=VALUE",
        nargs="+",
        default=[],
        help="env parameters over the folder's config (values read as YAML)",
    )
    parser.add_argument("--rerun", metavar="FILE.rrd", help="record the episodes for Rerun")
    parser.add_argument(
        "--video",
        metavar="FILE.mp4",
        help="write the episodes as MP4 (moviepy: the play extra) or, for a name ending "
        ".gif, a GIF; without --video or --rerun they play in a window (pygame: the play "
        "extra)",
    )
    parser.add_argument("--stride", type=int, default=1, help="--video keeps every Nth frame")
    parser.add_argument("--width", type=int, help="--video's width in pixels (default: the env's)")
    parser.add_argument(
        "--speed", type=float, default=1.0, help="--video plays at this many times real time"
    )
    parser.add_argument(
        "--allow-pickle",
        action="store_true",
        help="fly SB3's pickled model.zip and vecnormalize.pkl (a folder of an older version): "
        "unpickling runs any code the files carry, so only for files you trust",
    )
    return parser


def main(argv: list[str] | None = None, prog: str = "python -m fluidsim_envs.enjoy") -> int:
    from fluidsim_envs.play import NoDisplay
    from fluidsim_envs.rl.config import ConfigError
    from fluidsim_envs.rl.evaluate import parse_env_overrides
    from fluidsim_envs.rl.extras import require
    from fluidsim_envs.rl.files import RunError

    parser = build_parser(prog)
    args = parser.parse_args(argv)
    try:
        require("train", prog)
        overrides = parse_env_overrides(args.env)
        enjoy(
            args.folder,
            args.episodes,
            args.seed,
            overrides,
            args.rerun,
            args.video,
            stride=args.stride,
            width=args.width,
            speed=args.speed,
            allow_pickle=args.allow_pickle,
        )
    except (EnjoyError, NoDisplay, RunError, ConfigError, ImportError, ValueError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
