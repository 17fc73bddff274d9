"""Sunkuev 1984's worked examples as docs/linkage/examples.md writes them: every ``camcad linkage …`` command
runs, from the repository's root, with the exit code the page states (``# exit N`` after it; 0 otherwise). Only
``-o`` is added (the outputs go to a temporary folder, never into the repository)."""

from __future__ import annotations

import re
import shlex

import pytest
from conftest import ROOT

PAGE = ROOT / "docs" / "linkage" / "examples.md"


def commands() -> list[tuple[str, int]]:
    """(command, exit code) of every command in the page's ```sh blocks."""
    text = PAGE.read_text(encoding="utf-8")
    found = []
    for block in re.findall(r"```sh\n(.*?)```", text, flags=re.S):
        lines = block.replace("\\\n", " ").splitlines()
        for line in lines:
            if not line.strip().startswith("camcad linkage"):
                continue
            command, _, comment = line.partition("  # exit ")
            found.append((command.strip(), int(comment.split()[0]) if comment else 0))
    return found


@pytest.mark.reference("property", "issue 27 item 5: the page names every worked example of Sunkuev 1984 listed")
def test_the_page_has_every_example():
    names = " ".join(c for c, _ in commands())
    for needed in ("adjust --table 2 --task 3", "--task 5", "--task 6", "variator",
                   "path --points samples/linkage/needle", "path --timed samples/linkage/rack_feed",
                   "atlas --links 8 --dof 1 --adjustable 1"):
        assert needed in names, needed


@pytest.mark.reference("property", "each command of docs/linkage/examples.md exits with the code the page states "
                                   "and writes its outputs")
@pytest.mark.parametrize(("command", "code"), commands(), ids=lambda v: str(v)[:60])
def test_every_example_runs_as_written(cli, tmp_path, monkeypatch, command, code):
    monkeypatch.chdir(ROOT)
    args = shlex.split(command)[1:]
    run = cli(*args, "-o", tmp_path / "out")
    assert run.code == code, run.err + run.out[-2000:]
    assert (tmp_path / "out").is_dir() and any((tmp_path / "out").iterdir())
