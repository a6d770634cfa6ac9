"""The README and docs/ pages: their Python examples run as written, and the README's table of
envs is what ``python -m benchmarks.report`` writes from the registry and docs/envs.csv."""

import re
import warnings
from pathlib import Path

import pytest

from benchmarks import report

ROOT = Path(__file__).parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_python_blocks_run(page):
    """Each example as written; the README's quick start with every warning an error (it
    shows the current envs: no "out of date" notice, nothing deprecated)."""
    if page.name == "zoo.md":
        pytest.skip("tests/training/test_zoo_module.py runs it and checks what it scores")
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
    if page.name == "README.md":
        assert blocks, "README has no python example"
    for block in blocks:
        with warnings.catch_warnings():
            if page.name == "README.md":
                warnings.simplefilter("error")
            exec(compile(block, str(page.relative_to(ROOT)), "exec"), {})


def test_the_envs_table_is_up_to_date(capsys):
    assert report.main(["--check"]) == 0, capsys.readouterr().out


@pytest.mark.parametrize("page", PAGES, ids=[p.name for p in PAGES])
def test_local_links_resolve(page):
    """Every link to a file (not a web address or an anchor) names one that exists, relative
    to the page."""
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text()):
        if not re.match(r"[a-z]+:", target):
            assert (page.parent / target).exists(), f"{page.name}: {target}"


def test_quoted_compile_times_are_the_csvs():
    """The cold first step, wherever a page or a message quotes it, is what
    docs/bench_compile.csv holds (``python -m benchmarks.bench_compile`` rewrites it)."""
    from benchmarks.bench_compile import first_step_range
    from fluidsim_envs import compiling

    expected = first_step_range()
    assert compiling.FIRST_STEP == expected
    for path in ("README.md", "docs/benchmarks.md", "fluidsim_envs/warmup.py"):
        quoted = re.findall(r"(\d+-\d+ s) per env", (ROOT / path).read_text())
        assert quoted and set(quoted) == {expected}, (path, quoted, expected)
