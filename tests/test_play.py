"""python -m fluidsim_envs.play: the keys move each scene's controls as documented, a flight
runs headless on SDL's dummy video driver (and records to Rerun), and where no display
exists it says so and exits with status 2."""

from __future__ import annotations

import gymnasium as gym
import pytest
from gymnasium.envs.registration import load_env_creator

from fluidsim_envs import play
from fluidsim_envs.play import keymap
from fluidsim_envs.scenes.keys import RATE_PER_S, Axis

OURS = sorted(k for k in gym.registry if k.startswith("fluidsim/"))


def test_a_held_key_moves_its_axis_and_a_spring_brings_it_back():
    stick, throttle = Axis("elevator", "up", "down"), Axis("throttle", "s", "w", spring=False)
    dt = 0.1
    assert stick.step(0.0, False, True, dt) == pytest.approx(RATE_PER_S * dt)
    assert stick.step(0.95, False, True, dt) == 1.0  # held at the end of its range
    assert stick.step(0.3, False, False, dt) == pytest.approx(0.1)  # springs toward 0
    assert stick.step(-0.1, False, False, dt) == 0.0  # and stops there
    assert stick.step(0.3, True, True, dt) == pytest.approx(0.1)  # both held: released
    assert throttle.step(0.6, False, False, dt) == 0.6  # a throttle stays where left


@pytest.mark.parametrize("env_id", OURS)
def test_every_env_has_keys_for_its_actions(env_id):
    names = load_env_creator(gym.spec(env_id).vector_entry_point).action_names
    axes = keymap(env_id)
    assert tuple(a.action for a in axes) == names
    keys = [k for a in axes for k in (a.down, a.up)]
    assert len(set(keys)) == len(keys)  # no key drives two controls
    assert not {"r", "p", "escape"} & set(keys)  # nor one of the loop's own


def test_no_display_is_a_clear_error(monkeypatch, capsys):
    monkeypatch.setattr(play.sys, "platform", "linux")
    for var in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(var, raising=False)
    assert play.main(["fluidsim/PaperAirplane-v1"]) == 2
    err = capsys.readouterr().err
    assert "no display here" in err and "fluidsim-evaluate RUN --rerun" in err


def test_bad_input_is_named(capsys):
    assert play.main(["fluidsim/NoSuchEnv-v0"]) == 2
    assert "unknown env id 'fluidsim/NoSuchEnv-v0'" in capsys.readouterr().err
    assert play.main(["fluidsim/BoatOnStep-v1", "--scale", "0"]) == 2
    assert "--scale must be > 0, got 0.0" in capsys.readouterr().err


def test_a_headless_flight_applies_the_keys_and_records(monkeypatch, tmp_path):
    """The boat with W held for the first second: the throttle reaches full and stays there
    after W is let go (a spring-less axis), the rudder pulses with RIGHT and springs back."""
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    rate = 20  # the boat's actions per second

    def keys(step: int) -> set[str]:
        return {"w", "right"} if step < rate // 4 else ({"w"} if step < rate else set())

    rrd = tmp_path / "flight.rrd"
    flight = play.play(
        "fluidsim/BoatOnStep-v1", seed=3, rerun=str(rrd), max_steps=2 * rate, keys=keys
    )
    throttle, rudder, tabs = flight.values
    assert throttle == 1.0 and rudder == 0.0 and tabs == 0.0
    assert flight.steps == 2 * rate and flight.episode_return != 0.0
    assert rrd.stat().st_size > 0


def test_play_s_lines_sit_under_the_frame_not_over_it(monkeypatch):
    """The window is the env's frame, untouched (its own readout included), with play's
    lines in a panel below it."""
    import numpy as np

    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    shown = []
    real = play._draw

    def keep(pygame, screen, font, flight, scale, paused):
        real(pygame, screen, font, flight, scale, paused)
        frame = flight.env.render()[0][:, :, :3]
        shown.append((pygame.surfarray.array3d(screen).swapaxes(0, 1), frame))

    monkeypatch.setattr(play, "_draw", keep)
    play.play("fluidsim/PaperAirplane-v1", seed=3, max_steps=2, keys=lambda step: set())
    window, frame = shown[-1]
    assert window.shape[0] > frame.shape[0] and window.shape[1] == frame.shape[1]
    np.testing.assert_array_equal(window[: frame.shape[0]], frame)
    assert (window[frame.shape[0] :] != play.PANEL).any()  # the lines are drawn there
