"""Fly an environment yourself, from the keyboard, in a window (pygame: the ``play`` extra).

    python -m fluidsim_envs.play fluidsim/PaperAirplane-v1 [--env KEY=VALUE ...] [--seed N]
                                 [--rerun FLIGHT.rrd] [--scale 1.5]

The window shows the env's own ``rgb_array`` frames at its action rate (real time), with each
control's position and the episode's return and time in a panel under them (the frame, its own
readout included, stays clear). Each scene maps its three actions to keys (its ``Scene.keys``,
printed at the start): a control surface moves while its key is held and springs back to
neutral when released; a throttle or thruster stays where it was left. R starts a new episode,
P pauses, Esc or closing the window quits. ``--rerun`` records the flight for the Rerun viewer
as ``fluidsim-evaluate --rerun`` records a policy's.

Where there is no display (a server, a container, ssh without X forwarding) it says so and
exits with status 2, naming what works there instead.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

from fluidsim_envs.scenes.keys import Axis

PANEL = (245, 245, 245)  # the background of play's own lines, under the frame
LINE_PX = 20  # their spacing


class NoDisplay(RuntimeError):
    """No window can be opened here; the message says what works instead."""


def keymap(env_id: str) -> tuple[Axis, ...]:
    """The keys of ``env_id``'s scene (``Scene.keys``)."""
    from fluidsim_envs.scenes import SCENES

    if env_id not in SCENES:
        raise ValueError(f"unknown env id {env_id!r}; ours: {sorted(SCENES)}")
    if not SCENES[env_id].keys:
        raise ValueError(f"{env_id}: its scene declares no keyboard controls (Scene.keys)")
    return SCENES[env_id].keys


def describe(axes: tuple[Axis, ...]) -> list[str]:
    return [f"  {a.describe()}" for a in axes] + ["  R new episode, P pause, Esc quit"]


def check_display() -> None:
    """A clear error where no window can open: Linux without X11 or Wayland (SDL's dummy
    driver, set on purpose, is let through: the tests use it)."""
    if os.environ.get("SDL_VIDEODRIVER") == "dummy" or not sys.platform.startswith("linux"):
        return
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise NoDisplay(
            "no display here (neither DISPLAY nor WAYLAND_DISPLAY is set): play opens a "
            "window. Run it on a machine with a screen (or ssh -X); here, watch a trained "
            "pilot with `python -m fluidsim_envs.enjoy zoo/<name> --video FLIGHT.mp4`, or "
            "record episodes with `fluidsim-evaluate RUN --rerun FLIGHT.rrd`"
        )


def make_env(env_id: str, env_kwargs: dict, rerun: str | None):
    """One sub-env drawing ``rgb_array`` frames, recorded to ``rerun`` when given."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)

    env = gym.make_vec(
        env_id,
        num_envs=1,
        vectorization_mode="vector_entry_point",
        render_mode="rgb_array",
        **env_kwargs,
    )
    if rerun is not None:
        from fluidsim_envs.wrappers import RerunLogger

        env = RerunLogger(env, path=rerun, name="played")
    return env


class Flight:
    """The loop's state without pygame: the controls, the episode's return and time, and
    the step that applies the keys held (:meth:`advance`). ``play`` draws it."""

    def __init__(self, env, axes: tuple[Axis, ...]) -> None:
        self.env, self.axes = env, axes
        self.period_s = 1.0 / env.metadata["render_fps"]
        self.values = np.zeros(len(axes))
        self.episode_return, self.steps, self.last = 0.0, 0, ""

    def reset(self, seed: int | None = None) -> None:
        self.env.reset(seed=seed)
        self.values[:] = 0.0
        self.episode_return, self.steps = 0.0, 0

    def advance(self, held: set[str]) -> bool:
        """One action with the keys ``held``; True when the episode ended (and, the env
        resetting itself in the same step, a new one began)."""
        for i, a in enumerate(self.axes):
            self.values[i] = a.step(self.values[i], a.down in held, a.up in held, self.period_s)
        _, reward, terminated, truncated, info = self.env.step(self.values[None].astype(np.float32))
        self.episode_return += float(reward[0])
        self.steps += 1
        if terminated[0] or truncated[0]:
            success = info.get("success")
            won = "" if success is None else (" success" if success[0] else " no success")
            self.last = (
                f"last: {self.episode_return:.2f} in {self.steps * self.period_s:.1f} s{won}"
            )
            self.values[:] = [
                0.0 if a.spring else v for a, v in zip(self.axes, self.values, strict=True)
            ]
            self.episode_return, self.steps = 0.0, 0
            return True
        return False

    def hud(self) -> list[str]:
        controls = "  ".join(
            f"{a.action} {v:+.2f}" for a, v in zip(self.axes, self.values, strict=True)
        )
        return [
            controls,
            f"t {self.steps * self.period_s:5.1f} s  return {self.episode_return:8.2f}",
            self.last,
        ]


def play(
    env_id: str,
    env_kwargs: dict | None = None,
    seed: int | None = None,
    rerun: str | None = None,
    scale: float = 1.0,
    max_steps: int | None = None,
    keys=None,
) -> Flight:
    """Open the window and fly until Esc (or ``max_steps`` actions: tests). ``keys``: a
    function of the step index giving the set of keys held (tests), instead of the
    keyboard."""
    check_display()
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    env = make_env(env_id, env_kwargs or {}, rerun)
    flight = Flight(env, keymap(env_id))
    try:
        pygame.display.init()  # not pygame.init(): no mixer, no audio driver looked for
        pygame.font.init()
        flight.reset(seed)
        frame = env.render()[0]
        # play's own lines in a panel under the frame: the env's HUD stays clear
        panel = 8 + LINE_PX * (len(flight.hud()) + 1)
        size = (int(frame.shape[1] * scale), int(frame.shape[0] * scale) + panel)
        try:
            screen = pygame.display.set_mode(size)
        except pygame.error as e:
            raise NoDisplay(f"pygame could not open a window ({e})") from None
        pygame.display.set_caption(f"{env_id}: Esc quits")
        font, clock = pygame.font.Font(None, 22), pygame.time.Clock()
        _loop(pygame, screen, font, clock, flight, scale, max_steps, keys)
    finally:
        env.close()
        pygame.quit()
    return flight


def _loop(pygame, screen, font, clock, flight: Flight, scale, max_steps, keys) -> None:
    names = {a: pygame.key.key_code(a) for ax in flight.axes for a in (ax.down, ax.up)}
    paused, step = False, 0
    while max_steps is None or step < max_steps:
        for event in pygame.event.get():
            if event.type == pygame.QUIT or (
                event.type == pygame.KEYDOWN and event.key == pygame.K_ESCAPE
            ):
                return
            if event.type == pygame.KEYDOWN and event.key == pygame.K_r:
                flight.reset()
            if event.type == pygame.KEYDOWN and event.key == pygame.K_p:
                paused = not paused
        if not paused:
            if keys is not None:
                held = set(keys(step))
            else:
                pressed = pygame.key.get_pressed()
                held = {name for name, code in names.items() if pressed[code]}
            flight.advance(held)
            step += 1
        _draw(pygame, screen, font, flight, scale, paused)
        clock.tick(0 if keys is not None else 1.0 / flight.period_s)


def _draw(pygame, screen, font, flight: Flight, scale: float, paused: bool) -> None:
    frame = np.ascontiguousarray(flight.env.render()[0][:, :, :3])
    surface = pygame.surfarray.make_surface(frame.swapaxes(0, 1))
    height = int(frame.shape[0] * scale)
    if scale != 1.0:
        surface = pygame.transform.smoothscale(surface, (screen.get_width(), height))
    screen.fill(PANEL)
    screen.blit(surface, (0, 0))
    lines = flight.hud() + (["PAUSED (P)"] if paused else [])
    for i, text in enumerate(line for line in lines if line):
        screen.blit(font.render(text, True, (10, 10, 10), PANEL), (8, height + 4 + LINE_PX * i))
    pygame.display.flip()


def build_parser(prog: str = "python -m fluidsim_envs.play") -> argparse.ArgumentParser:
    """The command line's parser (built without pygame: ``--help`` works without it)."""
    parser = argparse.ArgumentParser(prog=prog, description="Fly an env from the keyboard.")
    parser.add_argument("env_id", help="e.g. fluidsim/PaperAirplane-v1")
    parser.add_argument(
        "--env",
        metavar="KEY=VALUE",
        nargs="+",
        default=[],
        help="env parameters (values read as YAML)",
    )
    parser.add_argument("--seed", type=int, help="the first episode's seed (default: random)")
    parser.add_argument("--rerun", metavar="FILE.rrd", help="record the flight for Rerun")
    parser.add_argument(
        "--scale", type=float, default=1.0, help="window size over the frame's (default 1)"
    )
    return parser


def main(argv: list[str] | None = None, prog: str = "python -m fluidsim_envs.play") -> int:
    from fluidsim_envs.rl.config import ConfigError, parse_assignment
    from fluidsim_envs.rl.extras import require

    args = build_parser(prog).parse_args(argv)
    try:
        kwargs = dict(parse_assignment(item, "--env") for item in args.env)
        if not args.scale > 0:
            raise ValueError(f"--scale must be > 0, got {args.scale}")
        require("play", prog)
        axes = keymap(args.env_id)
        print(f"{args.env_id}: keys\n" + "\n".join(describe(axes)))
        flight = play(args.env_id, kwargs, args.seed, args.rerun, args.scale)
    except (NoDisplay, ValueError, ConfigError, ImportError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    if flight.last:
        print(flight.last)
    if args.rerun:
        print(f"recorded: rerun {args.rerun}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
