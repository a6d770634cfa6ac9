"""The docs site (mkdocs.yml, built by ``make docs``): every page under docs/ is in its nav,
no link on a page leaves docs/ (mkdocs builds only docs/, and no page points outside the
repository), each env's page is what ``python -m benchmarks.report`` writes from the scene
registry, the API reference's docstrings read as Markdown, and the site builds strictly (a
few seconds)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from benchmarks import env_pages, report

ROOT = Path(__file__).parents[2]
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.rglob("*.md"))
PAGE_IDS = [str(p.relative_to(DOCS)) for p in PAGES]


def nav_pages(entry) -> list[str]:
    """Every page a nav (or a part of it) names, in order."""
    if isinstance(entry, str):
        return [entry]
    if isinstance(entry, list):
        return [page for item in entry for page in nav_pages(item)]
    if isinstance(entry, dict):
        return [page for value in entry.values() for page in nav_pages(value)]
    raise TypeError(f"a nav entry is a page, a list or a titled entry, got {entry!r}")


def config() -> dict:
    return yaml.safe_load((ROOT / "mkdocs.yml").read_text())


def links(text: str) -> list[str]:
    """The targets of a page's Markdown links and images (inline and by reference) and of
    its HTML ``src``/``href``, outside code blocks and code spans."""
    text = re.sub(r"^(```|~~~).*?^\1", "", text, flags=re.S | re.M)
    text = re.sub(r"`[^`\n]*`", "", text)
    found = re.findall(r"\]\(\s*<?([^)\s>]+)", text)
    found += re.findall(r"^\s*\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)", text, flags=re.M)
    found += re.findall(r"""(?:src|href)\s*=\s*["']([^"']+)["']""", text)
    return found


def test_the_nav_names_every_page_once_and_only_pages_that_exist():
    cfg = config()
    assert cfg["docs_dir"] == "docs"
    named = nav_pages(cfg["nav"])
    assert len(named) == len(set(named)), sorted({p for p in named if named.count(p) > 1})
    assert sorted(named) == sorted(PAGE_IDS), (
        f"pages missing from mkdocs.yml's nav: {sorted(set(PAGE_IDS) - set(named))}; "
        f"named there but absent: {sorted(set(named) - set(PAGE_IDS))}"
    )


def test_the_link_finder_finds_links_and_skips_code():
    text = (
        '[a](a.md) ![b](img/b.png) [c](c.md#x) <img src="/abs.png">\n'
        "[ref]: ../ref.md\n`[no](in_code.md)`\n```\n[no](fenced.md)\n```\n"
    )
    assert links(text) == ["a.md", "img/b.png", "c.md#x", "../ref.md", "/abs.png"]


@pytest.mark.parametrize("page", PAGES, ids=PAGE_IDS)
def test_no_link_leaves_the_docs(page):
    """A link is a web address, an anchor, or a file under docs/ that exists: never an
    absolute path, nor a relative one out of docs/ (into the repository or beyond it)."""
    bad = []
    for target in links(page.read_text()):
        if re.match(r"[a-z][a-z0-9+.-]*:", target, flags=re.I) or target.startswith("#"):
            continue  # http:, https:, mailto:; an anchor on the page
        path = target.split("#", 1)[0].split("?", 1)[0]
        if path.startswith("/") or re.match(r"[A-Za-z]:[\\/]", path):
            bad.append(f"{target} (an absolute path)")
            continue
        resolved = (page.parent / path).resolve()
        if not resolved.is_relative_to(ROOT.resolve()):
            bad.append(f"{target} (outside the repository)")
        elif not resolved.is_relative_to(DOCS.resolve()):
            bad.append(
                f"{target} (outside docs/: link a page of the site, or name the path as code)"
            )
        elif not resolved.exists():
            bad.append(f"{target} (no such file)")
    assert not bad, f"{page.relative_to(ROOT)}: {bad}"


def test_each_v1_env_has_its_page_as_the_report_writes_it():
    from fluidsim_envs.scenes import SCENES

    written = env_pages.pages()
    expected = {f"docs/envs/{env_pages.name(i)}.md" for i, s in SCENES.items() if s.version == 1}
    assert set(written) == expected
    assert "docs/envs" in report.PAGE_SETS
    for page, text in written.items():
        assert (ROOT / page).read_text() == text, (
            f"{page} is stale: run python -m benchmarks.report"
        )
    assert [p.name for p in report.orphans({ROOT / p: t for p, t in written.items()})] == []


def test_an_env_page_holds_its_scene_s_columns_actions_and_success():
    from fluidsim_envs.scenes import SCENES

    scene = SCENES["fluidsim/BoatOnStep-v1"]
    text = env_pages.page(scene.id)
    for col in scene.obs_names:
        assert f"| `{col}` |" in text
    for channel in scene.vector_cls.action_names:
        assert f"| `{channel}` |" in text
    assert f"| success | {scene.success_text()} |" in text
    assert "| `ride` | `w_ride` |" in text  # v1's own term, with its weight
    assert "../zoo_BoatOnStep-v1-ppo.gif" in text and "../frames_boat_on_step.png" in text


def test_docstring_roles_read_as_code_spans():
    pytest.importorskip("griffe")
    from benchmarks.griffe_docstrings import code_spans

    text = "See :class:`~.planner.Planner`, :meth:`Simulator.set_clock` and :mod:`x.y`."
    assert code_spans(text) == "See `Planner`, `Simulator.set_clock` and `x.y`."


def test_the_site_builds_strictly(tmp_path):
    """What ``make docs`` runs: a broken link or anchor, a page outside the nav or a
    docstring griffe cannot read is an error."""
    pytest.importorskip("mkdocs")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}  # Material's banner, not a warning
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert (tmp_path / "envs" / "BoatOnStep" / "index.html").is_file()


def test_every_file_under_docs_is_reachable_from_the_index():
    """Each page is in the nav (above); each other file (a table, a figure, a script) is
    linked from a page, so that the site reaches it."""
    linked = set()
    for page in PAGES:
        for target in links(page.read_text()):
            path = target.split("#", 1)[0].split("?", 1)[0]
            if path and not re.match(r"[a-z][a-z0-9+.-]*:", path, flags=re.I):
                linked.add((page.parent / path).resolve())
    files = [p for p in DOCS.rglob("*") if p.is_file() and p.suffix != ".md"]
    unreached = sorted(str(p.relative_to(DOCS)) for p in files if p.resolve() not in linked)
    assert not unreached, f"linked from no page: {unreached}"
