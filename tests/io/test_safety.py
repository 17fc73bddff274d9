"""Safe by construction (issue 19): no output replaces an input, names stay inside the output folder, the
atomic writer cannot be redirected, two runs into one folder do not mix, errors are one short line.

Each reproducer: exit 0/1 with a result or exit 2 with one line under 300 characters, no input changed,
nothing written outside the output folder.
"""

from __future__ import annotations

import fcntl
import os
import shutil
from pathlib import Path

import pytest
from conftest import SAMPLES, file_digest

from camcad.errors import CamcadError
from camcad.io.atomic import write_text_atomic
from camcad.io.output_folder import OutputFolder, safe_name

LAW_TABLE = SAMPLES / "law_table.csv"
DEFAULT_SCENE = """
name = "{name}"
[law]
standard = "cycloidal"
phases = "0:120:rise,120:180:dwell,180:300:return,300:360:dwell"
lift = 25.0
[follower]
type = "roller"
base_radius = 50.0
roller_radius = 10.0
"""


def one_line_error(result) -> None:
    assert result.code == 2, (result.code, result.err)
    lines = result.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error:") and len(lines[0]) < 300, result.err
    assert "Traceback" not in result.err


def tree(root: Path) -> dict[str, str]:
    return {str(p.relative_to(root)): file_digest(p) for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.mark.reference("property", "an output that would replace the input is refused; its digest unchanged")
@pytest.mark.parametrize("how", ["plain", "dotdot", "symlinked folder", "hard link"])
def test_profile_never_replaces_its_input(cli, tmp_path, how):
    folder = tmp_path / "p1"
    folder.mkdir()
    law = folder / "law.csv"
    shutil.copy(LAW_TABLE, law)
    out = folder
    if how == "dotdot":
        out = folder / ".." / "p1"
    elif how == "symlinked folder":
        (tmp_path / "link").symlink_to(folder)
        out = tmp_path / "link"
    elif how == "hard link":
        out = tmp_path / "other"
        out.mkdir()
        os.link(law, out / "law.csv")
    before = file_digest(law)
    result = cli("profile", law, "--lift", "10", "--rb", "50", "--rr", "10", "-o", out, "--no-plots")
    one_line_error(result)
    assert "would replace the input" in result.err
    assert file_digest(law) == before


@pytest.mark.reference("property", "hostile names stay inside the output folder")
def test_scene_and_mechanism_names_cannot_leave_the_output_folder(cli, tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    scene = work / "s.toml"
    scene.write_text(DEFAULT_SCENE.format(name="../../escaped"))
    result = cli("profile", scene, "--no-plots", "--json")
    assert result.code == 0, result.err
    assert not (tmp_path / "escaped").exists() and not (tmp_path.parent / "escaped").exists()
    assert (work / "camcad-out" / "escaped" / "profile.dxf").is_file()
    group = work / "g.toml"
    group.write_text("""
[mechanisms."../../../x".law]
standard = "cycloidal"
phases = "0:120:rise,120:180:dwell,180:300:return,300:360:dwell"
lift = 25.0
[mechanisms."../../../x".follower]
type = "roller"
base_radius = 50.0
roller_radius = 10.0
[mechanisms."/abs/y".law]
standard = "harmonic"
phases = "0:120:rise,120:180:dwell,180:300:return,300:360:dwell"
lift = 10.0
[mechanisms."/abs/y".follower]
type = "roller"
base_radius = 50.0
roller_radius = 10.0
""")
    out = work / "out"
    result = cli("profile", group, "--no-plots", "-o", out, "--json")
    assert result.code == 0, result.err
    written = {Path(p).resolve() for p in result.json()["outputs"]}
    assert all(out.resolve() in p.parents for p in written)
    assert {p.parent.name for p in written if p.name == "profile.dxf"} == {"x", "abs_y"}
    assert not Path("/abs").exists()


@pytest.mark.reference("property", "safe_name maps hostile names to safe ones (.., absolute, device names, 500 "
                                   "characters)")
def test_safe_name_rule():
    assert safe_name("../../etc/passwd") == "etc_passwd"
    assert safe_name("/abs/y") == "abs_y"
    assert safe_name("..") == "_" and safe_name("") == "_" and safe_name(".hidden") == "hidden"
    assert safe_name("nul") == "nul_" and safe_name("COM1.txt") == "COM1.txt_"
    assert len(safe_name("a" * 500)) == 100
    assert all(c.isalnum() or c in "_.-" for c in safe_name("weft returner (1) / Ø 30"))


@pytest.mark.reference("property", "a planted symlink is replaced, the file it points at unchanged")
def test_the_atomic_writer_replaces_a_planted_symlink_instead_of_writing_through_it(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").symlink_to(victim)              # a symlink at the output's own name
    for pid in range(os.getpid() - 2, os.getpid() + 3):   # and at the old predictable temp names
        (out / f".report.json.{pid}.tmp").symlink_to(victim)
    write_text_atomic(out / "report.json", "{}")
    assert victim.read_text() == "precious"
    assert not (out / "report.json").is_symlink() and (out / "report.json").read_text() == "{}"
    assert not [p for p in out.iterdir() if p.name.startswith(".report.json.") and not p.is_symlink()]


@pytest.mark.reference("property", "a symlink leading outside the output folder is refused")
def test_a_symlink_in_the_output_folder_cannot_lead_outside(tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    (out / "mech").symlink_to(outside, target_is_directory=True)
    with OutputFolder(out) as folder, pytest.raises(CamcadError, match="outside the output folder"):
        folder.path("mech", "profile.dxf")


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_output_that_is_an_existing_file_or_unwritable_is_one_line(cli, tmp_path):
    existing = tmp_path / "file.txt"
    existing.write_text("x")
    one_line_error(cli("profile", "--no-plots", "-o", existing))
    assert existing.read_text() == "x"
    one_line_error(cli("profile", "--no-plots", "-o", existing / "below"))


@pytest.mark.reference("property", "a second run into a locked folder is refused")
def test_a_second_run_into_the_same_folder_waits_for_the_first(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    holder = os.open(out, os.O_RDONLY)
    fcntl.flock(holder, fcntl.LOCK_EX)
    try:
        folder = OutputFolder(out)
        with pytest.raises(CamcadError, match="another camcad run"):
            folder.lock(timeout_s=0.3)
    finally:
        os.close(holder)
    with OutputFolder(out) as folder:    # free again
        assert folder.path("a.txt").parent == out


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_huge_value_in_a_scene_gives_a_short_line(cli, tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text(DEFAULT_SCENE.format(name="big").replace("base_radius = 50.0",
                                                              "base_radius = [" + ", ".join(["1.5"] * 100000) + "]"))
    before = tree(tmp_path)
    result = cli("profile", scene, "--no-plots", "-o", tmp_path / "o")
    one_line_error(result)
    assert "100000 items" in result.err
    after = tree(tmp_path)
    assert {k: v for k, v in after.items() if not k.startswith("o/")} == before


@pytest.mark.reference("property", "the original kept by fix reads back vertex for vertex with --layer CAMCAD_ORIGINAL")
def test_the_original_kept_by_fix_is_read_back_exactly(cli, tmp_path):
    # nothing the user drew is lost: the fixed copy keeps the original curve (in a block no reader draws),
    # and --layer CAMCAD_ORIGINAL reads it back, vertex for vertex
    source = tmp_path / "law.dxf"
    shutil.copy(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf", source)
    assert cli("fix", source, "--no-plots").code == 0
    original = cli("check", source, "--json").json()
    kept = cli("check", tmp_path / "law.fixed.dxf", "--layer", "CAMCAD_ORIGINAL", "--json").json()
    for key in ("rise", "return", "displacement_closure"):
        assert kept[key] == original[key]
    assert kept["areas"] == original["areas"]
