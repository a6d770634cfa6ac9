"""The docs' pictures (python -m fluidsim_envs.scenes.gallery): the strip's layout and the
refusal of an unknown scene id. Flying whole episodes is left to the command itself."""

import numpy as np
import pytest

from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes import gallery as G


def test_strip_puts_the_frames_side_by_side_over_their_captions():
    frames = [np.full((30, 40, 3), v, dtype=np.uint8) for v in (10, 120, 250)]
    out = G.strip([(f"moment {k}", f) for k, f in enumerate(frames)])
    assert out.shape == (30 + G.CAPTION_H, 3 * 40 + 2 * G.GAP, 3)
    for k, f in enumerate(frames):
        x = k * (40 + G.GAP)
        np.testing.assert_array_equal(out[:30, x : x + 40], f)
        caption = out[30:, x : x + 40]
        assert (caption == G.INK).all(axis=2).sum() > 30  # its text
    assert (out[:30, 40 : 40 + G.GAP] == G.BACK).all()  # the gap


def test_each_scene_has_its_own_file_name():
    names = [G.scene_name(s) for s in SCENES.values()]  # v1's with its version
    assert len(set(names)) == len(names)
    assert "paper_airplane" in names


def test_an_unknown_scene_id_is_refused_by_name(tmp_path):
    with pytest.raises(ValueError, match="'fluidsim/Nope-v0'"):
        G.write(tmp_path, ids=["fluidsim/Nope-v0"])
    assert not list(tmp_path.iterdir())
