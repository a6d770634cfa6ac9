"""The docs site's page of each env, ``docs/envs/<Name>.md``, written from the scene registry
(:data:`fluidsim_envs.scenes.SCENES`), and the zoo page's tables.

    python -m benchmarks.report            # writes these pages with every other table
    python -m benchmarks.report --check    # exit 1 if one is out of date (the tests run it)

One page per v1 scene (its v0 named on it): the observation's columns (the scene's
``observation`` layout), the actions, the reward terms with their weights, what success
means (``Scene.success``), the difficulty levels and knobs, the instruments, every parameter,
and the pictures (``docs/zoo_<Name>-v1-*.gif``, ``docs/frames_<scene>.png``). The prose
sections (rewards, starting state, episode end) are the env class's docstring, which stays
the full reference. The tables reuse :mod:`benchmarks.report`'s renderers.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re
from pathlib import Path

from .common import DOCS
from .report import WRITER, level_cell, params_table, scene_slug

FOLDER = "docs/envs"  # every page in it is written here


def name(env_id: str) -> str:
    """``fluidsim/PaperAirplane-v1`` -> ``PaperAirplane``."""
    return env_id.split("/")[1].rsplit("-v", 1)[0]


def pages() -> dict[str, str]:
    """Every env page, by path relative to the repository root, as it should read."""
    from fluidsim_envs.scenes import SCENES

    return {
        f"{FOLDER}/{name(env_id)}.md": page(env_id)
        for env_id, scene in SCENES.items()
        if scene.version == 1
    }


def docstring_section(cls: type, title: str) -> str:
    """The ``## title`` section of ``cls``'s docstring (the Gymnasium layout the env classes
    follow) as Markdown: reST roles and double backticks become code spans."""
    doc = (inspect.getdoc(cls) or "").split("\nExamples:", 1)[0]
    parts = re.split(r"^## (.+)$", doc, flags=re.M)
    sections = dict(zip(parts[1::2], parts[2::2], strict=True))
    text = sections.get(title, "").strip()
    text = re.sub(r":[a-z]+:`~?(?:[\w.]+\.)?([\w]+)`", r"`\1`", text)
    return re.sub(r"``([^`]+)``", r"`\1`", text)


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def observation_table(scene, first) -> str:
    """The scene's observation columns (``Scene.observation``), those of its v0 marked."""
    own = set(first.obs_names)
    lines = ["| index | name | unit | description | in v0 |", "|---:|---|---|---|---|"]
    for i, (col, unit, text) in enumerate(scene.observation):
        mark = "yes" if col in own else ""
        lines.append(f"| {i} | `{col}` | {_cell(unit)} | {_cell(text)} | {mark} |")
    return "\n".join(lines)


def action_table(scene) -> str:
    """The action's channels, in order, with the keys ``python -m fluidsim_envs.play`` flies
    them with (``Scene.keys``)."""
    keys = {a.action: a for a in scene.keys}
    lines = ["| index | name | play: - key | play: + key | released |", "|---:|---|---|---|---|"]
    for i, channel in enumerate(scene.vector_cls.action_names):
        a = keys.get(channel)
        if a is None:
            lines.append(f"| {i} | `{channel}` | | | |")
            continue
        released = "springs back to 0" if a.spring else "stays"
        lines.append(f"| {i} | `{channel}` | {a.down} | {a.up} | {released} |")
    return "\n".join(lines)


def reward_table(scene, first) -> str:
    """The reward terms, each with its weight parameter and default (v1's), and whether v0
    has it."""
    p = scene.params_cls()
    old = set(first.vector_cls.reward_terms)
    lines = ["| term | weight | default | in v0 |", "|---|---|---:|---|"]
    for term in scene.vector_cls.reward_terms:
        weight = f"w_{term}"
        value = f"{getattr(p, weight):g}" if hasattr(p, weight) else ""
        shown = f"`{weight}`" if hasattr(p, weight) else ""
        lines.append(f"| `{term}` | {shown} | {value} | {'yes' if term in old else ''} |")
    return "\n".join(lines)


def levels_table(module) -> str:
    """Each knob of the scene at each difficulty level (its ``LEVELS`` over ``KNOBS``)."""
    from fluidsim_envs.scenes.realism import LEVELS

    own = dataclasses.asdict(module.KNOBS())
    lines = ["| knob | " + " | ".join(LEVELS) + " |", "|---" * (len(LEVELS) + 1) + "|"]
    for knob in own:
        cells = [level_cell({**own, **module.LEVELS[lv]}[knob]) for lv in LEVELS]
        lines.append(f"| `{knob}` | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def sensors_table(module) -> str:
    """The scene's instruments (``SENSORS``) at ``sensor_scale`` 1."""
    from fluidsim_envs.scenes.sensors import table_rows

    lines = [
        "| instrument | columns | noise | bias (time) | resolution | hardware |",
        "|---|---|---:|---:|---:|---|",
    ]
    lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in table_rows(module.SENSORS)]
    return "\n".join(lines)


def zoo_rows(env: str) -> str:
    """The zoo table's header and the rows of ``env``'s entries (empty if it has none)."""
    lines = zoo_markdown().rstrip("\n").split("\n")
    rows = [r for r in lines[2:] if f"`zoo/{env}-" in r]
    return "\n".join(lines[:2] + rows) if rows else ""


def pictures(env: str, slug: str, up: str = "") -> list[str]:
    """Markdown images: ``env``'s zoo GIFs and its v0 scene's frames (``up``: the way from
    the page to docs/)."""
    from .zoo import GIF_WIDTH

    lines = [moving(gif, up, GIF_WIDTH) for gif in sorted(DOCS.glob(f"zoo_{env}-*.gif"))]
    frames = DOCS / f"frames_{slug}.png"
    if frames.is_file():
        lines.append(
            f"![{env}-v0 at the start, middle and end of an episode flown by its scripted "
            f"pilot]({up}{frames.name})"
        )
    return lines


def page(env_id: str) -> str:
    """The page of the v1 scene ``env_id``."""
    from fluidsim_envs.scenes import SCENES

    scene = SCENES[env_id]
    first = SCENES[scene.first_id]
    module = importlib.import_module(scene.vector_cls.__module__)
    env = name(env_id)
    p = scene.params_cls()
    period_s = p.dt * p.substeps
    slug = scene_slug(first.id)
    out = [
        f"# {env}",
        "",
        f"<!-- written by `{WRITER}` (benchmarks/env_pages.py) from the scene registry: "
        "do not edit -->",
        "",
        f"`{env_id}`: {scene.summary}. Its first version, `{first.id}`, is the same task "
        "with the nominal craft, exact readings and no actuators. Every table below is written "
        "from the scene's own declarations (`fluidsim_envs.scenes.SCENES`); the full reference "
        f"is the docstring of `{scene.env_cls.__module__}.{scene.env_cls.__qualname__}`.",
        "",
        "| | |",
        "|---|---|",
        f"| single env | `{scene.entry_point}` |",
        f"| vector env | `{scene.vector_entry_point}` |",
        f"| parameters | `{scene.params_cls.__module__}.{scene.params_cls.__qualname__}` |",
        f"| observation | `Box(-inf, inf, ({scene.vector_cls.obs_dim},), float32)` |",
        f"| action | `Box(-1, 1, ({len(scene.vector_cls.action_names)},), float32)` |",
        f"| control rate | {1.0 / period_s:g} Hz |",
        f"| horizon | {p.max_episode_steps} actions ({p.max_episode_steps * period_s:g} s) |",
        f"| success | {scene.success_text(p)} |",
        "",
        *[line + "\n" for line in pictures(env, slug, up="../")],
        "## Description",
        "",
        docstring_section(scene.env_cls, "Description"),
        "",
        "## Observation",
        "",
        f"The columns in order ({len(first.observation)} of them are v0's observation).",
        "",
        observation_table(scene, first),
        "",
        "## Actions",
        "",
        f"**{first.id.split('/')[1]}**: " + docstring_section(first.env_cls, "Action Space"),
        "",
        f"**{env_id.split('/')[1]}**: " + docstring_section(scene.env_cls, "Action Space"),
        "",
        action_table(scene),
        "",
        "## Reward",
        "",
        reward_table(scene, first),
        "",
        docstring_section(scene.env_cls, "Rewards"),
        "",
        "## Starting state",
        "",
        docstring_section(scene.env_cls, "Starting State"),
        "",
        "## Success and episode end",
        "",
        f'Success (`info["success"]` at the episode\'s end): {scene.success_text(p)}.',
        "",
        docstring_section(scene.env_cls, "Episode End"),
        "",
        "## Levels and knobs",
        "",
        '`difficulty="easy"`, `"standard"` (the default) or `"hard"` sets every knob below; '
        "each knob given alone to `gym.make` overrides its level's value. A range is drawn "
        "anew each episode ([environments.md](../environments.md#version-1-a-real-craft-"
        "instruments-and-actuators) says what each does).",
        "",
        levels_table(module),
        "",
        "The instruments (at `sensor_scale` 1; `easy` reads exactly):",
        "",
        sensors_table(module),
        "",
        "## Parameters",
        "",
        f'Every keyword of `gym.make("{env_id}", ...)`: its default and the values it may '
        "take (an unknown one is an error that lists these).",
        "",
        params_table(scene),
        "",
    ]
    zoo = zoo_rows(env)
    if zoo:
        out += [
            "## Trained policies",
            "",
            "Its [zoo](../zoo.md) entries, on fresh episodes beside the best scripted pilot; "
            "every config over its training seeds against every baseline: "
            "[results](../results.md).",
            "",
            zoo,
            "",
        ]
    return "\n".join(out).replace("\n\n\n", "\n\n").rstrip() + "\n"


# ---- the zoo page's blocks ------------------------------------------------------------------


def zoo_markdown() -> str:
    """The README's zoo table (:func:`benchmarks.zoo.markdown`) for a docs page: the entries'
    folders named as code, since a page links nowhere outside docs/."""
    from . import zoo

    return re.sub(r"\[(`zoo/[^`]+`)\]\(zoo/[^)]+\)", r"\1", zoo.markdown())


def moving(gif: Path, up: str, width: int) -> str:
    """A zoo entry's episode: its video (every control step, real time) where there is one,
    with its GIF linked; else the GIF as an image."""
    entry, video = gif.stem[4:], gif.with_suffix(".mp4")
    if not video.is_file():
        return f'![{entry}, flown by its zoo policy]({up}{gif.name}){{ width="{width}" }}'
    return (
        f'<video src="{up}{video.name}" width="{width}" controls loop muted playsinline>'
        f"</video>\n\n{entry}, flown by its zoo policy, every control step in real time "
        f"([GIF]({up}{gif.name}))"
    )


def zoo_gifs_markdown() -> str:
    """Each zoo entry's episode (:func:`moving`)."""
    from .zoo import GIF_WIDTH, ZOO

    gifs = [DOCS / f"zoo_{f.name}.gif" for f in sorted(ZOO.glob("*"))]
    lines = [moving(g, "", GIF_WIDTH) for g in gifs if g.is_file()]
    return "\n\n".join(lines) if lines else "(no zoo GIFs yet: `python -m benchmarks.zoo`)"
