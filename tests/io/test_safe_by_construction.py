"""Safe by construction II (issue 34) and no output over an input, limits on the whole (issue 25 items 4–5).

Each reproducer of the independent attack runs as its own ``camcad`` process in a fresh folder, and must:
exit 0/1 with a result, or exit 2 with one line under 300 characters; use under 10 s of CPU (the child's own
user + system time, not wall time); change no file outside its output folder; leave every input
byte-identical. Cases are named after the findings (F1 … F16) and written out here, not drawn from the fuzz
generator, so each stays pinned whatever the generator does.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import ezdxf
import pytest
from conftest import ROOT, SAMPLES, file_digest

from camcad.errors import CamcadError
from camcad.io.output_folder import INCOMPLETE_MARK, OutputFolder, check_outputs, confined_path, distinct_names

CPU_LIMIT_S = 10.0
FIG2 = SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf"
STANDARD_MECHANISM = """
[mechanisms."{name}".law]
standard = "cycloidal"
phases = "0:120:rise,120:180:dwell,180:300:return,300:360:dwell"
lift = 20.0
[mechanisms."{name}".follower]
type = "roller"
base_radius = 50.0
roller_radius = 10.0
"""

pytestmark = pytest.mark.reference("property", "issue 34's reproducers F1-F16: exit 0/1 or one line, inputs "
                                               "byte-identical, nothing written outside the output folder")


class Run:
    def __init__(self, code: int, out: str, err: str, cpu: float):
        self.code, self.out, self.err, self.cpu = code, out, err, cpu

    def json(self) -> dict:
        return json.loads(self.out)


def camcad(*args, cwd: Path, wall_s: float = 300.0) -> Run:
    """``camcad ARGS`` as a child process in ``cwd``; its CPU time from the kernel (wait4), a CPU limit as a
    backstop (a hang is a failure, not a stuck test)."""
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_CPU, (int(CPU_LIMIT_S * 3), int(CPU_LIMIT_S * 3) + 5))

    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    child = subprocess.Popen([sys.executable, "-m", "camcad", *map(str, args)], cwd=cwd, env=env,
                             stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             preexec_fn=limit)
    try:
        out, err = child.communicate(timeout=wall_s)
    except subprocess.TimeoutExpired:
        child.kill()
        out, err = child.communicate()
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)  # cumulative: the difference is taken by the caller
    return Run(child.returncode, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"),
               usage.ru_utime + usage.ru_stime)


def snapshot(root: Path) -> dict[str, str]:
    return {str(p.relative_to(root)): file_digest(p) for p in sorted(root.rglob("*"))
            if p.is_file() and not p.is_symlink()}


def bounded(args, cwd: Path, root: Path, output: Path | None = None) -> Run:
    """Run a reproducer and check the contract: exit 0/1, or 2 with one short line; under 10 s of CPU; no file
    under ``root`` changed or added outside ``output`` (a folder or a file; None: nothing may change)."""
    before = snapshot(root)
    cpu_before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = camcad(*args, cwd=cwd)
    cpu = run.cpu - (cpu_before.ru_utime + cpu_before.ru_stime)
    assert run.code in (0, 1, 2), (run.code, run.err)
    assert "Traceback" not in run.err and "internal error" not in run.err, run.err
    if run.code == 2:
        lines = run.err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("camcad: error: ") and len(lines[0]) < 300, run.err
    assert cpu < CPU_LIMIT_S, (cpu, args)
    after = snapshot(root)
    prefix = None if output is None else str(output.relative_to(root))

    def outside(name: str) -> bool:
        return prefix is None or not (name == prefix or name.startswith(prefix + os.sep))

    changed = {k for k in before.keys() | after.keys() if before.get(k) != after.get(k) and outside(k)}
    assert not changed, (changed, run.err)
    run.cpu = cpu
    return run


@pytest.fixture
def place(tmp_path):
    """A work folder with the law, a victim folder beside it (never to be touched)."""
    work = tmp_path / "work"
    victim = tmp_path / "victim"
    work.mkdir()
    victim.mkdir()
    (victim / "notes.txt").write_text("precious\n")
    shutil.copy(FIG2, work / "law.dxf")
    return tmp_path


def script(folder: Path, ops, name: str = "edits.json") -> Path:
    path = folder / name
    path.write_text(json.dumps(ops))
    return path


# ---------------------------------------------------------------------------------------------
# F1: an edit script writes anywhere
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("target, words", [
    ("../../victim/notes.txt", "climbs out of the output folder"),
    ("../victim/notes.txt", "climbs out of the output folder"),
    ("{victim}/notes.txt", "is absolute"),
    ("~/notes.txt", "home folder"),
    ("edits.json", "would replace the input"),           # the script itself
    ("law.dxf", "would replace the input"),              # the law
    ("link.dxf", "would replace the input"),             # a symlink to the law
    ("sub/../../victim/notes.txt", "climbs out of the output folder"),
])
def test_f1_an_edit_script_saves_only_inside_the_output_folder(place, target, words):
    work = place / "work"
    (work / "link.dxf").symlink_to(work / "law.dxf")
    target = target.replace("{victim}", str(place / "victim"))
    path = script(work, [{"op": "correct", "mode": "min-change"}, {"op": "save", "path": "ok.dxf"},
                         {"op": "save", "path": target}])
    run = bounded(["edit", "law.dxf", "--script", path.name], work, place)
    assert run.code == 2 and words in run.err, run.err
    assert not (work / "ok.dxf").exists()              # nothing written: every save is checked first


def test_f1_the_output_may_not_be_the_script_nor_another_output(place):
    work = place / "work"
    path = script(work, [{"op": "correct", "mode": "min-change"}])
    run = bounded(["edit", "law.dxf", "--script", path.name, "-o", path.name], work, place)
    assert run.code == 2 and "would replace the input" in run.err and "(the script)" in run.err
    path = script(work, [{"op": "save", "path": "a.dxf"}, {"op": "correct", "mode": "min-change"},
                         {"op": "save", "path": "./a.dxf"}], "twice.json")
    run = bounded(["edit", "law.dxf", "--script", path.name], work, place)
    assert run.code == 2 and "operation 0 (save)" in run.err and "operation 2 (save)" in run.err
    path = script(work, [{"op": "save", "path": "fixed.dxf"}], "with_o.json")
    run = bounded(["edit", "law.dxf", "--script", path.name, "-o", "fixed.dxf"], work, place)
    assert run.code == 2 and "are the same file" in run.err


def test_f1_save_paths_are_relative_to_the_output_folder(place):
    work = place / "work"
    out = place / "out"
    out.mkdir()
    (work / "scripts").mkdir()
    path = script(work / "scripts", [{"op": "correct", "mode": "min-change"},
                                     {"op": "save", "path": "sub/fixed.csv"}])
    run = bounded(["edit", "law.dxf", "--script", path, "-o", out / "final.dxf", "--json"], work, place, out)
    assert run.code == 0, run.err
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()) == ["final.dxf", "sub/fixed.csv"]
    # -o an existing folder: the final law under its default name there
    run = bounded(["edit", "law.dxf", "--script", path, "-o", out, "--json"], work, place, out)
    assert run.code == 0 and (out / "law.edited.dxf").is_file(), run.err


def test_f1_a_symlink_in_the_output_folder_cannot_lead_a_save_outside(place):
    work = place / "work"
    (work / "escape").symlink_to(place / "victim", target_is_directory=True)
    path = script(work, [{"op": "correct", "mode": "min-change"}, {"op": "save", "path": "escape/notes.txt"}])
    run = bounded(["edit", "law.dxf", "--script", path.name], work, place)
    assert run.code == 2 and "through a symlink" in run.err


# ---------------------------------------------------------------------------------------------
# F2, F6: block references counted before they are expanded; non-finite transformations
# ---------------------------------------------------------------------------------------------

def _law_drawing(path: Path, build) -> Path:
    doc = ezdxf.new("R2000")
    msp = doc.modelspace()
    rows = [(0, 0), (60, 0), (90, 1), (120, 0), (150, -1), (180, 0), (240, 0), (270, -1), (300, 0), (330, 1),
            (360, 0)]
    msp.add_lwpolyline(rows, dxfattribs={"layer": "ACCEL"})
    block = doc.blocks.new("B")
    block.add_line((0, 0), (1000, 1))
    build(doc, msp)
    doc.saveas(path)
    return path


def _minsert(rows: int, cols: int):
    def build(doc, msp):
        msp.add_blockref("B", (0, 0)).grid(size=(rows, cols), spacing=(1, 1))
    return build


def _nested_minsert(doc, msp):
    inner = doc.blocks.new("C")
    inner.add_blockref("B", (0, 0)).grid(size=(32767, 32767), spacing=(1, 1))
    msp.add_blockref("C", (0, 0))


def _empty_fan_out(doc, msp):
    # no curve at all, but 1000 x 1000 placements: counted too
    doc.blocks.new("E")
    fan = doc.blocks.new("F")
    for k in range(1000):
        fan.add_blockref("E", (k, 0))
    top = doc.blocks.new("G")
    for k in range(1000):
        top.add_blockref("F", (0, k))
    msp.add_blockref("G", (0, 0))


def _scaled(scale: float):
    def build(doc, msp):
        ref = msp.add_blockref("B", (0, 0))
        ref.dxf.xscale = scale
    return build


def _nan_point(doc, msp):
    msp.add_blockref("B", (float("nan"), 0.0))


@pytest.mark.parametrize("name, build, words", [
    ("minsert_32767", _minsert(32767, 32767), "MINSERT of 32767 rows x 32767 columns"),
    ("minsert_3000", _minsert(3000, 3000), "9,000,000"),
    ("nested_minsert", _nested_minsert, "more than 10000 curves"),
    ("empty_fan_out", _empty_fan_out, "placed more than 100000 times"),
    ("scale_1e308", _scaled(1e308), "not finite or out of range"),
    ("scale_1e99", _scaled(1e99), "out-of-range coordinate"),
    ("nan_insert", _nan_point, "INSERT"),
])
@pytest.mark.parametrize("command", ["check", "fix", "profile"])
def test_f2_f6_block_references_are_bounded_and_checked(place, name, build, words, command):
    work = place / "work"
    drawing = _law_drawing(work / f"{name}.dxf", build)
    digest = file_digest(drawing)
    extra = {"check": [], "fix": ["-o", "out/fixed.dxf"], "profile": ["--lift", "10", "--rb", "50", "--rr", "10",
                                                                      "--no-plots", "-o", "out"]}[command]
    run = bounded([command, drawing.name, *extra], work, place, work / "out")
    assert run.code == 2 and words in run.err, run.err
    assert "INSERT" in run.err
    assert file_digest(drawing) == digest and not (work / "out").exists()


# ---------------------------------------------------------------------------------------------
# F3 and issue 25 item 5: limits on the whole, checked before the work
# ---------------------------------------------------------------------------------------------

def test_f3_a_sweep_of_a_hundred_million_designs_is_refused_before_any_value_is_made(place):
    pytest.importorskip("pyarrow")
    work = place / "work"
    run = bounded(["sweep", "--vary", "follower.base_radius=1:1e8:1", "-o", "out"], work, place, work / "out")
    assert run.code == 2 and "1e+08 values" in run.err and "1,000,000" in run.err
    run = bounded(["sweep", "--vary", "follower.base_radius=30:80:0.0001", "--vary",
                   "follower.roller_radius=5:15:0.5", "-o", "out"], work, place, work / "out")
    assert run.code == 2 and "designs" in run.err
    assert not (work / "out").exists()


def test_issue25_profile_rb_1e9_is_refused_with_the_whole_point_count(place):
    work = place / "work"
    run = bounded(["profile", "--rb", "1e9", "-o", "out"], work, place, work / "out")
    assert run.code == 2 and "points" in run.err and "1,000,000" in run.err, run.err
    assert "profile" in run.err and "pitch" in run.err            # every written curve counted
    assert run.cpu < 5.0 and not (work / "out").exists()


def test_limits_on_script_operations_and_table_lines(place):
    work = place / "work"
    path = script(work, [{"op": "detect_phases"}] * 2_001, "long.json")
    run = bounded(["edit", "law.dxf", "--script", path.name], work, place)
    assert run.code == 2 and "2001 operations" in run.err
    table = work / "long.csv"
    table.write_text("".join(f"{i * 360 / 600_000:.6f},0\n" for i in range(600_001)))
    run = bounded(["check", table.name, "--lift", "10"], work, place)
    assert run.code == 2 and "600,001 lines" in run.err   # 600,001 rows, each ended by a newline


# ---------------------------------------------------------------------------------------------
# F7: names that cannot collide
# ---------------------------------------------------------------------------------------------

def test_f7_mechanisms_whose_file_names_collide_are_refused_naming_both(place):
    work = place / "work"
    scene = work / "group.toml"
    scene.write_text(STANDARD_MECHANISM.format(name="lift 1") + STANDARD_MECHANISM.format(name="lift_1"))
    run = bounded(["profile", scene.name, "--no-plots", "-o", "out"], work, place, work / "out")
    assert run.code == 2 and "'lift 1'" in run.err and "'lift_1'" in run.err, run.err
    assert not any(p.is_file() for p in (work / "out").rglob("*"))
    scene.write_text(STANDARD_MECHANISM.format(name="Feed") + STANDARD_MECHANISM.format(name="feed"))
    run = bounded(["profile", scene.name, "--no-plots", "-o", "out"], work, place, work / "out")
    assert run.code == 2 and "'Feed'" in run.err and "'feed'" in run.err   # apart on a case-blind disk too


def test_distinct_names_and_the_guard_directly(tmp_path):
    assert distinct_names(["lift", "feed 1", "feed-2"]) == {"lift": "lift", "feed 1": "feed_1", "feed-2": "feed-2"}
    with pytest.raises(CamcadError, match="'a/b' and 'a b'"):
        distinct_names(["a/b", "a b"])
    law = tmp_path / "law.dxf"
    law.write_text("0\nEOF\n")
    (tmp_path / "hard.dxf").hardlink_to(law)
    for output in (law, tmp_path / "hard.dxf", tmp_path / "." / "law.dxf"):
        with pytest.raises(CamcadError, match="would replace the input"):
            check_outputs([(output, "-o")], [(law, "the law")])
    with pytest.raises(CamcadError, match="lie inside the output"):
        check_outputs([tmp_path / "a.json", tmp_path / "a.json" / "b.png"])
    with pytest.raises(CamcadError, match="is also the folder of the output"):
        check_outputs([tmp_path / "a" / "b.png", tmp_path / "a"])
    with pytest.raises(CamcadError, match="existing folder"):
        check_outputs([tmp_path])
    with pytest.raises(CamcadError, match="NUL"):
        check_outputs([tmp_path / "a\x00b"])
    for bad in ("/etc/passwd", "~/x", "..", "a/../../b", "", "a//b", "C:\\x", "a\nb"):
        with pytest.raises(CamcadError):
            confined_path(bad, tmp_path, "script")
    assert confined_path("./a/./b.csv", tmp_path, "script") == tmp_path / "a" / "b.csv"


# ---------------------------------------------------------------------------------------------
# F9, F10 and issue 25 item 4: no output over an input or over another output, checked before writing
# ---------------------------------------------------------------------------------------------

def test_f9_issue25_check_plot_over_the_law_is_refused(place):
    work = place / "work"
    shutil.copy(FIG2, work / "mylaw.dxf")
    run = bounded(["check", "mylaw.dxf", "--plot", "mylaw.dxf"], work, place)
    assert run.code == 2 and "--plot" in run.err and "would replace the input mylaw.dxf (the law)" in run.err
    run = bounded(["check", "mylaw.dxf", "--plot", "out/plot.png"], work, place, work / "out")
    assert run.code == 1 and (work / "out" / "plot.png").is_file()


@pytest.mark.parametrize("law, output, words", [
    ("law.dxf", "out.png", "are the same file"),                       # the corrected law, then its plot
    ("X.png", "X.dxf", "would replace the input X.png (the law)"),     # the plot beside -o is the input
    ("law.dxf", "law.dxf", "would replace the input law.dxf (the law)"),
])
def test_f9_issue25_fix_outputs_are_checked_as_a_set(place, law, output, words):
    work = place / "work"
    if law != "law.dxf":
        shutil.copy(FIG2, work / law)
    run = bounded(["fix", law, "-o", output], work, place)
    assert run.code == 2 and words in run.err, run.err
    run = bounded(["fix", law, "-o", f"out/{Path(output).stem}.dxf"], work, place, work / "out")
    assert run.code == 0 and len(list((work / "out").iterdir())) == 2   # the drawing and its plot


def test_f10_a_group_scene_writes_nothing_when_a_later_output_would_replace_an_input(place):
    work = place / "work"
    (work / "out" / "second").mkdir(parents=True)
    shutil.copy(SAMPLES / "law_table.csv", work / "out" / "second" / "law.csv")   # the 2nd mechanism's law
    scene = work / "group.toml"
    scene.write_text(STANDARD_MECHANISM.format(name="first") + """
[mechanisms.second.law]
file = "out/second/law.csv"
lift = 10.0
[mechanisms.second.follower]
type = "roller"
base_radius = 50.0
roller_radius = 10.0
""")
    run = bounded(["profile", scene.name, "-o", "out"], work, place, work / "out" / "first")
    assert run.code == 2 and "would replace the input" in run.err and "law.csv of second" in run.err, run.err
    assert not (work / "out" / "first").exists()                      # the first mechanism: nothing written
    assert not (work / "out" / INCOMPLETE_MARK).exists()


def test_f10_a_sweep_refuses_an_input_inside_the_folders_it_fills(place):
    pytest.importorskip("pyarrow")
    work = place / "work"
    (work / "out" / "results").mkdir(parents=True)
    scene = work / "out" / "results" / "scene.toml"
    scene.write_text(STANDARD_MECHANISM.replace('mechanisms."{name}".', ""))
    run = bounded(["sweep", scene, "--vary", "follower.base_radius=40,50", "-o", "out"], work, place)
    assert run.code == 2 and "a folder the run writes" in run.err, run.err


# ---------------------------------------------------------------------------------------------
# F11, F12: file guards and nesting
# ---------------------------------------------------------------------------------------------

def test_f11_a_script_that_is_a_fifo_or_a_device_is_refused_without_reading(place):
    work = place / "work"
    os.mkfifo(work / "script.json")
    run = bounded(["edit", "law.dxf", "--script", "script.json"], work, place)
    assert run.code == 2 and "FIFO" in run.err
    run = bounded(["edit", "law.dxf", "--script", "/dev/zero"], work, place)
    assert run.code == 2 and "device" in run.err
    big = work / "big.json"
    with open(big, "wb") as stream:
        stream.truncate(11 * 1024 * 1024)
    run = bounded(["edit", "law.dxf", "--script", big.name], work, place)
    assert run.code == 2 and "MB" in run.err


def test_f12_deep_nesting_and_unicode_digits_exit_2(place):
    work = place / "work"
    (work / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    run = bounded(["edit", "law.dxf", "--script", "deep.json"], work, place)
    assert run.code == 2 and "nest" in run.err
    (work / "deep.toml").write_text('name = "x"\na = ' + "[" * 5000 + "]" * 5000 + "\n")
    run = bounded(["profile", "deep.toml", "-o", "out"], work, place, work / "out")
    assert run.code == 2 and "nest" in run.err
    (work / "dotted.toml").write_text('name = "x"\n' + "a." * 3000 + "b = 1\n")
    run = bounded(["profile", "dotted.toml", "-o", "out"], work, place, work / "out")
    assert run.code == 2
    for text in ("x*²", "x+١", "２*x"):
        run = bounded(["linkage", "fgen", "--function", text, "--x", "1:2", "--input-range", "60",
                       "--output-range", "60", "-o", "out"], work, place, work / "out")
        assert run.code == 2 and "--function" in run.err, (text, run.err)


# ---------------------------------------------------------------------------------------------
# F15: an R12 copy keeps what R12 can hold and says what it cannot
# ---------------------------------------------------------------------------------------------

def test_f15_an_r12_copy_names_the_r2000_header_variables_it_cannot_hold(place):
    work = place / "work"
    lines = (SAMPLES / "dxf" / "r12_polyline_harmonic.dxf").read_text().split("\n")
    at = lines.index("$INSBASE") - 1
    lines[at:at] = ["  9", "$INSUNITS", " 70", "     4", "  9", "$LWDISPLAY", "290", "     1",
                    "  9", "$CELWEIGHT", "370", "    -1", "  9", "$PROJECTNAME", "  1", "CAMS"]
    source = work / "r12.dxf"
    source.write_text("\n".join(lines))
    run = bounded(["fix", source.name, "-o", "out/r12.fixed.dxf", "--force", "--no-plots", "--json"], work, place,
                  work / "out")
    assert run.code == 0, run.err
    notes = " ".join(run.json()["notes"] + run.json().get("write_notes", []) + [run.out])
    assert "$LWDISPLAY, $CELWEIGHT" in notes and "R12" in notes
    written = (work / "out" / "r12.fixed.dxf").read_text()
    assert "AC1009" in written and "$INSUNITS" in written and "$PROJECTNAME" in written
    assert "$LWDISPLAY" not in written and "$CELWEIGHT" not in written
    assert "\n290\n" not in written.replace("\r", "") and "\n370\n" not in written.replace("\r", "")
    back = camcad("check", work / "out" / "r12.fixed.dxf", "--json", cwd=work)
    assert back.code == 0 and back.json()["balanced"]


# ---------------------------------------------------------------------------------------------
# F16: an interrupted run leaves a marked folder; the next run cleans up
# ---------------------------------------------------------------------------------------------

def test_f16_the_mark_stays_while_a_run_writes_and_when_it_fails(tmp_path):
    out = tmp_path / "out"
    with OutputFolder(out) as folder:
        folder.plan(["a.txt"])
        assert not (out / INCOMPLETE_MARK).exists()          # planning writes nothing
        (folder.path("a.txt")).write_text("x")
        assert folder.incomplete and "camcad run" in (out / INCOMPLETE_MARK).read_text()
    assert not (out / INCOMPLETE_MARK).exists()
    with pytest.raises(RuntimeError), OutputFolder(out) as folder:
        folder.path("b.txt").write_text("half")
        raise RuntimeError("killed half way")
    assert (out / INCOMPLETE_MARK).exists()                  # the folder says it is a mix


def test_f16_stray_temporary_files_are_removed_by_the_next_run(place):
    work = place / "work"
    out = work / "out"
    (out / "sub").mkdir(parents=True)
    strays = [out / ".profile.dxf.a1b2c3d4.tmp", out / ".report.json.zz_9y8x7.tmp",
              out / "sub" / ".law.csv.qwertyui.tmp"]
    for stray in strays:
        stray.write_text("half a file")
    (out / INCOMPLETE_MARK).write_text("a run was killed")
    keep = out / ".hidden-notes.tmp"                          # not an atomic write's name: kept
    keep.write_text("mine")
    run = bounded(["profile", "--no-plots", "-o", "out"], work, place, out)
    assert run.code == 0, run.err
    assert not any(p.exists() for p in strays) and keep.read_text() == "mine"
    assert not (out / INCOMPLETE_MARK).exists() and (out / "profile.dxf").is_file()


# ---------------------------------------------------------------------------------------------
# F8, F13: sweeps survive their own death; report.json is the same bytes
# ---------------------------------------------------------------------------------------------

def _children(pid: int) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.append(int(entry.name))
    return found


def _alive(pid: int) -> bool:
    try:
        state = (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc to find the pool's workers")
@pytest.mark.parametrize("victim", ["the run", "a worker"])
def test_f8_after_kill_9_of_any_process_of_a_sweep_resume_completes_it(place, victim):
    pytest.importorskip("pyarrow")
    work = place / "work"
    vary = ["--vary", "follower.base_radius=30:70:0.1", "--workers", "2", "--chunk", "2", "--no-plots",
            "--no-best", "-o", "out"]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    main = subprocess.Popen([sys.executable, "-m", "camcad", "sweep", *vary], cwd=work, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    results = work / "out" / "results"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list(results.glob("chunk-*.parquet"))) < 3:
        time.sleep(0.2)
    workers = _children(main.pid)
    assert len(workers) >= 2 and main.poll() is None
    if victim == "a worker":   # the run stops with one line saying to resume; the other workers end with it
        os.kill(workers[0], signal.SIGKILL)
        main.wait(timeout=120)
        assert main.returncode == 2
    else:
        main.send_signal(signal.SIGKILL)
        main.wait()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.1)
    assert not any(_alive(w) for w in workers)               # no orphan holds the folder or the CPU
    assert (work / "out" / INCOMPLETE_MARK).exists()           # the folder says it is not complete
    done = list(results.glob("chunk-*.parquet"))
    resumed = bounded(["sweep", *vary, "--resume", "--json"], work, place, work / "out")
    assert resumed.code == 0, resumed.err
    assert resumed.json()["throughput"]["chunks_on_disk_before"] >= len(done) - 1
    assert not (work / "out" / INCOMPLETE_MARK).exists()
    from camcad.sweep.store import read_results

    assert read_results(work / "out").column("design").to_pylist() == list(range(401))


def test_f13_report_json_is_the_same_bytes_whatever_the_engine_and_chunking(place):
    pytest.importorskip("pyarrow")
    work = place / "work"
    vary = ["--vary", "follower.base_radius=30:50:5", "--vary", "law.standard=cycloidal,poly345"]
    first = bounded(["sweep", *vary, "--workers", "2", "-o", "a"], work, place, work / "a")
    second = bounded(["sweep", *vary, "--workers", "1", "--chunk", "3", "-o", "a2"], work, place, work / "a2")
    assert first.code == second.code == 0
    one = (work / "a" / "report.json").read_text()
    two = (work / "a2" / "report.json").read_text()
    assert one.replace(str(work / "a2"), str(work / "a")).replace('"a2/', '"a/') == \
        two.replace(str(work / "a2"), str(work / "a")).replace('"a2/', '"a/')
    shutil.rmtree(work / "a")
    again = bounded(["sweep", *vary, "--workers", "2", "--chunk", "4", "-o", "a"], work, place, work / "a")
    assert again.code == 0 and (work / "a" / "report.json").read_text() == one
    timing = json.loads((work / "a" / "throughput.json").read_text())
    assert timing["chunk_designs"] == 4 and "wall_s" in timing["throughput"]


def test_inputs_are_never_changed_by_any_reproducer(place):
    # the reading side: every command that reads the law leaves its bytes alone (also when it refuses)
    work = place / "work"
    digest = file_digest(work / "law.dxf")
    shutil.copy(SAMPLES / "law_table.csv", work / "law.csv")
    shutil.copy(SAMPLES / "law_table.csv", work / "spectrum.csv")
    table = file_digest(work / "law.csv")
    for args in (["check", "law.dxf", "--plot", "law.dxf"], ["fix", "law.dxf", "-o", "law.dxf"],
                 ["edit", "law.dxf", "--script", script(work, [{"op": "save", "path": "law.dxf"}]).name],
                 ["profile", "law.csv", "--lift", "10", "--rb", "50", "--rr", "10", "--no-plots", "-o", "."],
                 ["spectrum", "spectrum.csv", "--lift", "10", "-o", "."]):
        run = bounded(args, work, place)
        assert run.code == 2 and "would replace the input" in run.err, (args, run.err)
    assert file_digest(work / "law.dxf") == digest
    assert file_digest(work / "law.csv") == file_digest(work / "spectrum.csv") == table


@pytest.mark.reference("second method", "ezdxf's Insert.multi_insert, cell by cell")
def test_minsert_cells_by_their_linear_rule_equal_ezdxf_s_own_cells():
    # camcad places a MINSERT's cells as cell (0, 0) moved by whole row and column steps (no virtual entity per
    # cell); ezdxf's multi_insert builds every cell: they agree to round-off for rotated, scaled, mirrored and
    # tilted (OCS) grids
    from camcad.io.dxf_read import _matrices

    doc = ezdxf.new("R2000")
    doc.blocks.new("B").add_line((0, 0), (1, 0))
    msp = doc.modelspace()
    for rotation in (0.0, 30.0, 217.5):
        for sx, sy in ((1, 1), (2.5, -0.5), (-3, 2)):
            for extrusion in ((0, 0, 1), (0, 0, -1), (0.3, 0.4, 0.866)):
                ref = msp.add_blockref("B", (5, -3, 2), dxfattribs={"rotation": rotation, "xscale": sx,
                                                                   "yscale": sy, "extrusion": extrusion})
                ref.grid(size=(4, 5), spacing=(7.5, -2.25))
                mine = _matrices(ref)
                theirs = [[list(cell.matrix44().get_row(k)) for k in range(4)] for cell in ref.multi_insert()]
                assert len(mine) == len(theirs) == 20
                for a, b in zip(mine, theirs):
                    assert a.ravel().tolist() == pytest.approx([v for row in b for v in row], abs=1e-10)


def test_f16_a_stray_temporary_file_beside_a_single_output_is_removed_when_old(place):
    work = place / "work"
    (work / "out").mkdir()
    old, fresh = work / "out" / ".fixed.dxf.k1ll3d99.tmp", work / "out" / ".fixed.dxf.wr1t1ng0.tmp"
    for stray in (old, fresh):
        stray.write_text("half a file")
    os.utime(old, (time.time() - 3600, time.time() - 3600))    # left by a run killed an hour ago
    run = bounded(["fix", "law.dxf", "-o", "out/fixed.dxf", "--no-plots"], work, place, work / "out")
    assert run.code == 0, run.err
    assert not old.exists() and fresh.exists()                  # a young one may be another writer's
