"""Start-up: each command imports only what it needs (structural checks, not timings).

Each case runs ``camcad ...`` in a fresh interpreter and lists the top-level packages it imported
(``sys.modules`` at exit). Timings are measured by benchmarks/bench_cli.py, not here.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
import json, sys
from camcad.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
SUB = ('scipy.', 'camcad.', 'numpy.ma', 'numpy.polynomial', 'rich.')
print("\\nMODULES" + json.dumps(sorted({name.split('.')[0] for name in sys.modules} |
                                      {name for name in sys.modules if name.startswith(SUB)})))
"""


def imported(*args: str, cwd: Path) -> set[str]:
    done = subprocess.run([sys.executable, "-c", PROBE, *args], capture_output=True, text=True, cwd=cwd,
                          timeout=120)
    marker = done.stdout.rsplit("\nMODULES", 1)
    assert len(marker) == 2, done.stderr
    return set(json.loads(marker[1]))


def test_help_and_version_import_no_numerical_library(tmp_path):
    for args in (["--help"], ["--version"], ["profile", "--help"], ["check", "--help"]):
        modules = imported(*args, cwd=tmp_path)
        for heavy in ("numpy", "scipy", "matplotlib", "ezdxf", "shapely", "rich", "pydantic"):
            assert heavy not in modules, (args, heavy)


def test_the_default_profile_without_plots_needs_no_optimiser_and_no_plotting(tmp_path):
    modules = imported("profile", "--no-plots", "-o", str(tmp_path / "out"), cwd=tmp_path)
    assert "numpy" in modules and "ezdxf" in modules
    for unneeded in ("scipy.optimize", "matplotlib", "pydantic", "rich", "camcad.fourier", "camcad.dynamics",
                     "camcad.cyclogram.lp", "scipy.sparse", "numpy.ma", "numpy.polynomial", "shapely"):
        assert unneeded not in modules, unneeded


def test_a_command_imports_only_its_own_command_module(tmp_path):
    modules = imported("check", "--help", cwd=tmp_path)
    commands = {m for m in modules if m.startswith("camcad.cli.") and m != "camcad.cli.common"}
    assert commands == {"camcad.cli.check"}


def test_the_command_list_in_help_is_each_command_s_own_first_line():
    import typer

    from camcad.cli import COMMANDS, app, register_all

    register_all()
    group = typer.main.get_group(app)
    for name, (_, line) in COMMANDS.items():
        command = group.commands[name]
        first = " ".join((command.help or "").split("\n\n")[0].split())
        # the one-line summary opens as the command's own help does (same first words)
        assert first.split()[:2] == line.split()[:2], (name, first, line)


def _law_drawing(folder: Path) -> Path:
    from camcad.bench.startup import write_law

    return write_law(folder / "law.dxf")


def test_check_fix_and_spectrum_import_no_scipy(tmp_path):
    # issue 35: pieces joined by sorting (no scipy.spatial), the min-change solve by cyclic reduction (no
    # scipy.sparse), the Hurwitz zeta by Euler-Maclaurin (no scipy.special), rich.progress only with a bar
    law = _law_drawing(tmp_path)
    for args in (["check", str(law)], ["fix", str(law), "-o", str(tmp_path / "fixed.dxf"), "--no-plots"],
                 ["spectrum", str(law), "--no-plots", "-o", str(tmp_path / "spectrum")],
                 ["profile", "--no-plots", "-o", str(tmp_path / "profile")]):
        modules = imported(*args, cwd=tmp_path)
        assert "numpy" in modules, args
        for unneeded in ("scipy", "matplotlib", "rich.progress", "shapely"):
            assert unneeded not in modules, (args, unneeded)


def test_a_dynamics_run_of_one_speed_shows_no_bar_and_imports_no_rich_progress(tmp_path):
    law = _law_drawing(tmp_path)
    modules = imported("dynamics", str(law), "--rpm", "300", "--fn", "40", "--zeta", "0.05", "--lift", "25",
                       "--no-plots", "-o", str(tmp_path / "dyn"), cwd=tmp_path)
    assert "rich.progress" not in modules
