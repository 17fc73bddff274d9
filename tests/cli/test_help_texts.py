"""Help texts in a user's words (issue 32): no command's --help speaks of "the seed", "the source's loop" or the
project's own contract file; the works are named as docs/references.md names them. A group given no command
prints its help as written, not squashed into one error line."""

from __future__ import annotations

import re

import pytest
import typer

from camcad.cli import app, register_all

#: words a user of camcad does not know: the project's own names for the source works and its documents
FORBIDDEN = (r"\bseeds?\b", r"\bseed's\b", r"the source's", r"SPEC\.md", r"STYLE\.md", r"\bwave[ -]?\d")
#: "seed" in its ordinary sense: a random-number seed, and the option that sets it
ALLOWED = (r"--seed\b", r"random-number seed", r"the same seed")


def _commands():
    """(path, help text) of every command and group of camcad, as `camcad ... --help` prints it."""
    from typer._click import Context

    register_all()
    root = typer.main.get_command(app)

    def walk(command, path):
        ctx = Context(command, info_name=" ".join(path))
        yield " ".join(path), command.get_help(ctx)
        if hasattr(command, "list_commands"):
            for name in command.list_commands(ctx):
                sub = command.get_command(ctx, name)
                if sub is not None:
                    yield from walk(sub, [*path, name])

    return list(walk(root, ["camcad"]))


def test_every_help_text_speaks_a_users_words():
    commands = _commands()
    assert len(commands) > 20       # every command and subcommand was walked
    found = []
    for path, text in commands:
        plain = " ".join(text.split())
        for allowed in ALLOWED:
            plain = re.sub(allowed, "", plain, flags=re.IGNORECASE)
        for pattern in FORBIDDEN:
            for match in re.finditer(pattern, plain, flags=re.IGNORECASE):
                found.append(f"{path}: ...{plain[max(0, match.start() - 50):match.end() + 30]}...")
    assert not found, "\n".join(found)


def test_the_source_works_are_named_as_the_references_name_them():
    texts = dict(_commands())
    assert "Sunkuev 1984" in texts["camcad linkage"]
    assert "Dupliak & Kotsiyba 2018" in " ".join(texts["camcad fix"].split())


@pytest.mark.parametrize("group", ["linkage"])
def test_a_group_without_a_command_prints_its_help_as_written(cli, group):
    result = cli(group)
    assert result.code == 0 and result.err == ""
    lines = result.out.splitlines()
    assert lines[0].startswith(f"Usage: camcad {group}")
    assert "Commands:" in lines and len(lines) > 8          # a help page, not one error line
    assert not result.out.startswith("camcad: error")


def test_a_usage_error_is_still_one_line(cli):
    result = cli("linkage", "no-such-command")
    assert result.code == 2 and result.out == ""
    assert len(result.err.strip().splitlines()) == 1 and result.err.startswith("camcad: error:")
