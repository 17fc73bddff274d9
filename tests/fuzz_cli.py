"""The long fuzz campaign: every camcad command on mutated laws and scenes, each case in a forked child.

A case is one command line — ``check``, ``fix``, ``profile LAW``, ``profile SCENE``, ``spectrum``,
``dynamics``, ``impact``, ``contact`` or ``cyclogram``, and the surfaces of issue 34: ``edit --script``
(generated edit scripts: every operation, fields of every type and at extremes, hostile save paths, thousands
of operations, deep nesting), ``minsert`` (``check``/``fix``/``profile`` on drawings with MINSERTs and nested
block references of every size, scale and count), ``fgen`` (``linkage fgen --function`` on generated
expressions: every function and operator, Unicode digits and letters, deep nesting) and ``sweep`` (generated
``--vary`` specs: ranges, lists and distributions at extremes, unknown keys, junk objectives) — with options
drawn from sensible and extreme values, on inputs that are either intact samples or mutated:
- drawings and tables: byte mutations (``fuzz_dxf.mutate``: flips, truncation, shuffled group codes,
  garbage numbers, dropped or repeated lines, huge counts, a hundred thousand vertices);
- scenes: structure-aware mutations of the parsed TOML — numbers at extremes (0, −0, 1e-300, 1e300,
  nan, inf, huge integers), wrong types, huge arrays, hostile path names (``../../x``, absolute paths,
  names with NUL or newlines), cyclic networks, missing and extra sections — or byte mutations.

Each case runs in a child forked from a parent that has imported camcad and its libraries once (far
faster than a new Python per case), two children at a time (both cores). The child runs in the case's
own folder with a limit of 10 s of CPU time (``RLIMIT_CPU``: on a shared machine wall time would count
other people's work) and 600 s of wall time (an alarm) whose default actions kill it even inside C code,
an address-space limit (``RLIMIT_AS``), stdin from /dev/null, stdout and stderr to files, and an audit
hook that records every file the command opens for writing, renames, creates or deletes outside the
case folder.
The parent classifies the outcome:
- ok:       exit 0 or 1, with --json one JSON object on stdout, and nothing on stderr;
- error:    exit 2, one line "camcad: error: ..." under 300 characters, not an internal error;
- memory:   the address-space limit was reached and said so in one line (counted, not a finding);
- FINDING:  anything else — a traceback, an internal error (exit 3), several lines, library noise on
            stderr, more than 10 s of CPU (or 600 s of wall time), a crash, an input file changed, a file
            written outside the case.

Long run:   python tests/fuzz_cli.py --cases 100000 --seed 1 --workers 2
One case:   python tests/fuzz_cli.py --seed 1 --replay 4711      (prints its command and outcome)
Pin a case: python tests/fuzz_cli.py --seed 1 --pin 4711 --finding "what it found"
            (writes its input files and argv to tests/fixtures/fuzz/seed1-case4711/: a regression case that
            stays the same when the corpus or the generator changes, where a case number would not)
The test suite runs a short fixed-seed slice and every pinned case (tests/cli/test_fuzz_cli.py).
"""

from __future__ import annotations

import argparse
import gc
import hashlib
import json
import math
import os
import random
import re
import shutil
import signal
import sys
import tempfile
import time
import tomllib
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"
REAL_DXF = ROOT / "tests" / "fixtures" / "dxf-real"
PINNED = ROOT / "tests" / "fixtures" / "fuzz"
TIME_LIMIT_S = 10                  # CPU seconds a case may use (the machine may be shared: CPU, not wall time)
WALL_LIMIT_S = 600                 # a backstop for a case that waits instead of computing (a loaded machine
                                   # gives a niced child a small share of a core: keep this generous)
MEMORY_HEADROOM = 2 << 30          # bytes of address space a case may add to what the parent holds
COMMANDS = ("check", "fix", "profile-law", "profile-scene", "spectrum", "dynamics", "impact", "contact",
            "cyclogram")
#: the surfaces issue 34 added; ``run`` draws from ``COMMANDS`` unless told (so a case number of the earlier
#: campaigns is the same case), the command line from all of them
NEW_SURFACES = ("edit-script", "minsert", "fgen", "sweep")
ALL_COMMANDS = COMMANDS + NEW_SURFACES
#: small real drawings (fast to read) that join the samples as law inputs
REAL_LAWS = ("camcad__sample_2018.dxf", "camcad__sample_r14.dxf", "ezdxf__duplicate_handles.dxf",
             "camcad__entities_r2000.dxf", "camcad__entities_r12.dxf", "ezdxf__POLI-ALL210_12.DXF",
             "dxfparser__splines.dxf", "gdal__closed_polyline_with_bulge.dxf", "camcad__crlf_inch_polyline.dxf")


# ---------------------------------------------------------------------------------------------
# Inputs
# ---------------------------------------------------------------------------------------------

def law_corpus() -> list[Path]:
    files = sorted((SAMPLES / "dxf").glob("*.dxf")) + sorted(SAMPLES.glob("law_table*"))
    files += [REAL_DXF / name for name in REAL_LAWS]
    return files


def scene_corpus() -> list[Path]:
    """The sample scenes the scene commands take (a machine scene of groups is camcad machine's alone)."""
    return sorted(path for path in (SAMPLES / "scenes").glob("*.toml") if "[groups." not in path.read_text())


#: stands for an absolute folder outside the case (the run's canary folder, watched for strays)
CANARY = "/CAMCAD-FUZZ-CANARY"
EXTREME_NUMBERS = (0, -0.0, 1e-300, -1e-300, 1e300, -1e300, math.nan, math.inf, -math.inf, 2 ** 63 - 1,
                   -(2 ** 63), 10 ** 15, 1, -1, 0.5, 5e-324)
HOSTILE_NAMES = ("../../escape", "../escape.dxf", CANARY + "/abs", "a\x00b", "a\nb", "", " ",
                 "x" * 300, "CON", ".", "..", "~/x", "$HOME/x", "law.dxf/..", "*", "a/b/c", "\\\\server\\x")


def toml_text(data: dict) -> str:
    """``data`` as TOML (tables, arrays of tables, nan/inf, escaped strings): the scene mutator's writer."""
    lines: list[str] = []
    _toml_table(data, [], lines)
    return "\n".join(lines) + "\n"


def _toml_key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else _toml_string(key)


def _toml_string(text: str) -> str:
    out = []
    for ch in text:
        if ch in ('"', "\\"):
            out.append("\\" + ch)
        elif ch == "\n":
            out.append("\\n")
        elif ord(ch) < 32 or ord(ch) == 127:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_toml_key(str(k))} = {_toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return _toml_string(str(value))


def _toml_table(table: dict, path: list[str], lines: list[str]) -> None:
    scalars = {k: v for k, v in table.items() if not _is_table(v) and not _is_table_array(v)}
    for key, value in scalars.items():
        lines.append(f"{_toml_key(str(key))} = {_toml_value(value)}")
    for key, value in table.items():
        if _is_table(value):
            lines.append("")
            lines.append("[" + ".".join(_toml_key(str(p)) for p in path + [key]) + "]")
            _toml_table(value, path + [key], lines)
        elif _is_table_array(value):
            for item in value:
                lines.append("")
                lines.append("[[" + ".".join(_toml_key(str(p)) for p in path + [key]) + "]]")
                _toml_table(item, path + [key], lines)


def _is_table(value) -> bool:
    return isinstance(value, dict)


def _is_table_array(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _leaves(data, path=()):
    """(path, value) of every scalar or list-of-scalars leaf of a TOML document."""
    if isinstance(data, dict):
        for key, value in data.items():
            yield from _leaves(value, path + (key,))
    elif isinstance(data, list) and data and all(isinstance(v, dict) for v in data):
        for index, value in enumerate(data):
            yield from _leaves(value, path + (index,))
    else:
        yield path, data


def _tables(data, path=()):
    if isinstance(data, dict):
        yield path, data
        for key, value in data.items():
            yield from _tables(value, path + (key,))
    elif isinstance(data, list):
        for index, value in enumerate(data):
            if isinstance(value, dict):
                yield from _tables(value, path + (index,))


def _set(data, path, value) -> None:
    for key in path[:-1]:
        if isinstance(data, dict) and key not in data:   # a table the scene lacks (a group has no top-level [law])
            data[key] = {}
        data = data[key]
    data[path[-1]] = value


def lighten(data: dict) -> dict:
    """The scene with one speed and the frequency-domain dynamics where it allows: the same sections and
    code paths in a fraction of the time (an intact sample scene takes 3–30 s, past the case limit)."""
    machine = data.get("machine")
    if isinstance(machine, dict) and "rpm" in machine:
        machine["rpm"] = 350.0
    for path, table in list(_tables(data)):
        if path and path[-1] == "dynamics" and isinstance(table, dict):
            table["samples"] = 256
            table.pop("stiffness_variation", None)
            table["method"] = "frequency"
            table.pop("rtol", None)
            table.pop("solver", None)
    return data


def _bytes_mutation(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    """``fuzz_dxf.mutate``, with its slowest mutation (a hundred thousand vertices) three times rarer."""
    from fuzz_dxf import mutate

    mutated, how = mutate(data, rng)
    if how == "many_vertices" and rng.random() < 0.67:
        mutated, how = mutate(data, rng)
    return mutated, how


def mutate_scene(data: dict, rng: random.Random) -> tuple[dict, str]:
    """One structure-aware mutation of a parsed scene; returns the scene and the mutation's name."""
    kind = rng.choice(["extreme_number", "extreme_number", "wrong_type", "huge_array", "hostile_name",
                       "cyclic_network", "missing_section", "extra_section", "phases_text", "speed_text",
                       "law_file"])
    leaves = list(_leaves(data))
    if kind == "extreme_number":
        numeric = [p for p, v in leaves if isinstance(v, (int, float)) and not isinstance(v, bool)]
        for path in rng.sample(numeric, min(len(numeric), rng.randint(1, 3))):
            _set(data, path, rng.choice(EXTREME_NUMBERS))
    elif kind == "wrong_type" and leaves:
        path, _ = rng.choice(leaves)
        _set(data, path, rng.choice(["text", True, [], [1, "a"], {"x": 1}, 3, -2.5, [[1, 2], [3]]]))
    elif kind == "huge_array" and leaves:
        path, _ = rng.choice(leaves)
        size = rng.choice([10 ** 4, 10 ** 5, 10 ** 6])
        _set(data, path, [rng.random() for _ in range(min(size, 10 ** 5))] * (size // min(size, 10 ** 5)))
    elif kind == "hostile_name":
        strings = [p for p, v in leaves if isinstance(v, str)] or [("name",)]
        path = rng.choice(strings + [("name",)])
        _set(data, path, rng.choice(HOSTILE_NAMES))
    elif kind == "cyclic_network":
        cyclogram = data.setdefault("cyclogram", {"name": "net"})
        operations = cyclogram.setdefault("operations", [])
        events = [1, 2, 3]
        for a, b in zip(events, events[1:] + events[:1]):
            operations.append({"from": a, "to": b, "name": f"loop {a}", "bounds_deg": [rng.choice([0.0, 10.0]),
                                                                                       rng.choice([90.0, math.inf])]})
    elif kind == "missing_section":
        tables = [p for p, _ in _tables(data) if p]
        if tables:
            path = rng.choice(tables)
            parent = data
            for key in path[:-1]:
                parent = parent[key]
            del parent[path[-1]]
    elif kind == "extra_section":
        tables = [p for p, _ in _tables(data)]
        path = rng.choice(tables)
        target = data
        for key in path:
            target = target[key]
        target[rng.choice(["unknown", "extra_key", "dynamics", "stops", "contact", "cyclogram"])] = \
            rng.choice([{"x": 1}, 5, "text", {"natural_frequency_hz": 100.0}])
    elif kind == "phases_text":
        strings = [p for p, v in leaves if p and p[-1] == "phases"] or [("law", "phases")]
        _set(data, rng.choice(strings), rng.choice(["0:100:dwell", "0:360:rise", "0:180:rise,180:360:return",
                                                    "0:90:rise,90:90:dwell,90:360:return", "nan:1:rise",
                                                    "0:1e300:rise", "", ":::", "0:180:rise,180:360:rise"]))
    elif kind == "speed_text":
        strings = [p for p, v in leaves if p and p[-1] in ("rpm", "speeds")] or [("machine", "rpm")]
        _set(data, rng.choice(strings), rng.choice(["1:1e9:1e-9", "0", "-5", "nan", "300:100", "1e308",
                                                    [0.0], [], [1e300], "280:420:0", 280]))
    elif kind == "law_file":
        laws = [t for p, t in _tables(data) if p and p[-1] == "law"] or [data.setdefault("law", {})]
        law = rng.choice(laws)
        law.pop("standard", None)
        law["file"] = rng.choice(["law.dxf", "law.dxf", "law.csv", "missing.dxf", "../../law.dxf",
                                  CANARY + "/law.dxf", "law\x00.dxf", ".", "scene.toml"])
    return data, f"scene:{kind}"


# ---------------------------------------------------------------------------------------------
# Cases
# ---------------------------------------------------------------------------------------------

@dataclass
class Case:
    number: int
    command: str
    argv: list[str]
    files: dict[str, bytes]
    mutation: str


def _value(rng: random.Random, sensible: list) -> str:
    if rng.random() < 0.9:
        return str(rng.choice(sensible))
    return str(rng.choice(["0", "-0", "1e-300", "1e300", "nan", "inf", "-inf", "-1", "1e9", "abc", "",
                           "9" * 30, "1,5"]))


def _options(rng: random.Random, menu: dict, count: tuple[int, int] = (0, 4)) -> list[str]:
    argv: list[str] = []
    for name in rng.sample(sorted(menu), min(len(menu), rng.randint(*count))):
        values = menu[name]
        if values is None:
            argv.append(name)
        else:
            argv += [name, _value(rng, values)]
    return argv


LAW_OPTIONS = {"--lift": [10, 25, 0.421], "--cycle": [360, 180, 120], "--x-deg": None,
               "--phases": ["0:90:dwell,90:180:rise,180:270:dwell,270:360:return",
                            "0:60:dwell,60:180:rise,180:240:dwell,240:360:return", "0:180:rise,180:360:return"],
               "--layer": ["ACCEL", "0", "LAW"], "--handle": ["30", "2F", "91", "ZZ"]}
COMMAND_OPTIONS = {
    "check": {"--tol": [1e-5, 1e-3, 1e-9], "--trapezoid": None, "--step": [0.1, 1, 0.01]},
    "fix": {"--mode": ["min-change", "extrema", "extrema-resample", "keypoints", "segment", "phase",
                       "phase-keypoints"], "--method": ["exact", "iterate"], "--step": [0.1, 1.0, 0.5],
            "--segment": ["60:180", "0:360", "200:300"], "--max-stretch": [0.05, 0.5], "--free-lift": None,
            "--force": None, "--tol": [1e-5, 1e-3], "--move": ["75:5", "120:2", "250:-3", "61:7.5", "30:1"]},
    "profile": {"--rb": [40, 60, 25], "--rr": [8, 10, 0], "--offset": [0, 5], "--follower": ["roller", "flat",
                "oscillating"], "--pivot": [110, 160], "--arm": [80, 120], "--swing": [15, 24],
                "--cw": None, "--auto-rb": None, "--pa-rise": [30, 35], "--tol-mm": [1e-3, 1e-2],
                "--r12": None, "--arcs": None, "--spline": None, "--groove": None},
    "spectrum": {"-N": [20, 50, 5], "--fn": [100, 297], "--rpm": ["280:420:20", "300"], "--filter": None,
                 "--step": [0.5, 1.0]},
    "dynamics": {"--fn": [100, 297], "--zeta": [0.05, 0.1], "--rpm": ["280:420:20", "300"],
                 "--method": ["frequency", "time"], "--samples": [256, 1024]},
    "impact": {"--rpm": ["280:420:20", "300"], "--mass": [0.01, 1], "--f-free": [297], "--f-stop": [768],
               "--restitution": [0.55], "--preload": [0.25], "--stop": ["upper", "lower"]},
    "contact": {"--rpm": ["280:420:20", "300"], "--samples": [360, 90]},
    "cyclogram": {"--rpm": ["280:420:20", "300"], "--samples": [360, 90]},
}


#: options without which a command on a drawn law mostly stops at "… is not given": usually added
REQUIRED_OPTIONS = {
    "profile-law": {"--rb": [40, 60], "--rr": [8, 10]},
    "spectrum": {"--rpm": ["280:420:20", "300"]},
    "dynamics": {"--fn": [100, 297], "--zeta": [0.05], "--rpm": ["280:420:20", "300"]},
    "impact": {"--rpm": ["280:420:20"], "--mass": [0.0076], "--f-free": [297], "--f-stop": [768],
               "--restitution": [0.55]},
}


def make_case(seed: int, number: int, laws: list[Path], scenes: list[Path],
              commands: tuple[str, ...] = COMMANDS) -> Case:
    """Case ``number`` of the campaign ``seed``: the same case every time, whatever ran before it."""
    rng = random.Random(f"{seed}:{number}")
    command = rng.choice(commands)
    if command in NEW_SURFACES:
        return NEW_SURFACE_CASES[command](rng, number, laws)
    files: dict[str, bytes] = {}
    mutation = "intact"
    uses_scene = command in ("profile-scene", "contact", "cyclogram") or \
        (command in ("spectrum", "dynamics", "impact") and rng.random() < 0.5)
    if uses_scene:
        scene_path = rng.choice(scenes)
        law_path = rng.choice([p for p in laws if p.suffix.lower() == ".dxf"])
        files["law.dxf"] = law_path.read_bytes()
        files["law.csv"] = (SAMPLES / "law_table.csv").read_bytes()
        data = tomllib.loads(scene_path.read_text(encoding="utf-8"))
        if rng.random() < 0.9:
            data = lighten(data)
            scene_name = scene_path.stem + "~light"
        else:
            scene_name = scene_path.stem
        roll = rng.random()
        if roll < 0.65:
            data, mutation = mutate_scene(data, rng)
            if rng.random() < 0.3:
                data, second = mutate_scene(data, rng)
                mutation += "+" + second.split(":")[1]
            text = toml_text(data).encode("utf-8")
        elif roll < 0.85:
            text, mutation = _bytes_mutation(scene_path.read_bytes(), rng)
            mutation = "bytes:" + mutation
        else:
            text = toml_text(data).encode("utf-8")
        files["scene.toml"] = text
        source = "scene.toml"
        mutation = f"{scene_name} {mutation}"
    else:
        law_path = rng.choice(laws)
        data = law_path.read_bytes()
        name = "law" + law_path.suffix.lower()
        if rng.random() < 0.6:
            data, how = _bytes_mutation(data, rng)
            mutation = f"{law_path.name} bytes:{how}"
        else:
            mutation = f"{law_path.name} intact"
        files[name] = data
        source = name
    verb = command.split("-")[0]
    argv = [verb, source]
    if not uses_scene:
        argv += _options(rng, LAW_OPTIONS, (0, 2))
    elif verb in ("spectrum", "dynamics", "impact", "contact") and rng.random() < 0.8 and "mechanisms" in data:
        argv += ["--mechanism", rng.choice(sorted(data["mechanisms"]) if isinstance(data["mechanisms"], dict)
                                           else ["x"])]
    argv += _options(rng, COMMAND_OPTIONS.get(verb, {}), (0, 3))
    for option, values in REQUIRED_OPTIONS.get(command, {}).items():
        if option not in argv and rng.random() < 0.85:
            argv += [option, str(rng.choice(values))]
    if verb == "fix":
        argv += ["-o", rng.choice(["out/fixed.dxf", "out/fixed.csv", "out/fixed.txt", "out/sub/fixed.dxf"])]
        for _ in range(rng.choice([0, 0, 1, 2])):
            argv += ["--move", f"{rng.choice([0, 61, 75, 120, 180, 250, 359, 400, -5])}:{rng.choice([0, 1, -3, 7.5])}"]
    elif verb == "check":
        if rng.random() < 0.1:
            argv += ["--plot", "out/check.png"]
    else:
        argv += ["-o", "out"]
    if rng.random() < 0.9 and verb in ("fix", "profile", "spectrum", "dynamics", "impact", "contact", "cyclogram"):
        argv.append("--no-plots")
    if rng.random() < 0.85:
        argv.append("--json")
    return Case(number, command, argv, files, mutation)


def pin(case: Case, folder: Path, finding: str, seed: int | None = None) -> Path:
    """Write ``case`` as a pinned regression case: its input files as they are and ``case.json`` (argv, the
    campaign it came from, what it found). ``load_pinned`` reads it back."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in case.files.items():
        (folder / name).write_bytes(data)
    record = {"campaign": None if seed is None else {"seed": seed, "case": case.number}, "command": case.command,
              "argv": case.argv, "files": sorted(case.files), "mutation": case.mutation, "finding": finding}
    (folder / "case.json").write_text(json.dumps(record, indent=1, ensure_ascii=True) + "\n", encoding="utf-8")
    return folder


def load_pinned(folder: Path) -> tuple[Case, dict]:
    """The pinned case in ``folder`` (see ``pin``) and its record (``case.json``: argv, files, the finding, and
    the outcome expected now, ``expect``: status and a part of its detail)."""
    record = json.loads((folder / "case.json").read_text(encoding="utf-8"))
    files = {name: (folder / name).read_bytes() for name in record["files"]}
    number = (record.get("campaign") or {}).get("case", 0)
    return Case(number, record["command"], list(record["argv"]), files, record["mutation"]), record


def pinned_cases() -> list[Path]:
    """The folders of the pinned regression cases (tests/fixtures/fuzz/*/case.json)."""
    return sorted(path.parent for path in PINNED.glob("*/case.json"))


# ---------------------------------------------------------------------------------------------
# The surfaces of issue 34: edit scripts, MINSERTs, linkage expressions, sweep specs
# ---------------------------------------------------------------------------------------------

HOSTILE_PATHS = ("../../escape.dxf", "../escape.csv", CANARY + "/abs.dxf", "~/x.dxf", "law.dxf", "script.json",
                 "link.dxf", "sub/../../x.dxf", "a\x00b.dxf", "", ".", "..", "out", "x" * 300 + ".dxf", "a\nb.csv",
                 "C:\\x.dxf", "sub/ok.csv", "ok.json", "ok.txt", "ok.png", "ok", "out/../../../x.dxf")
EDIT_VALUES = (0, 1, -1, 75, 90.5, 180, 359.99, 360, 400, -5, 1e-300, 1e300, float("nan"), float("inf"), True, None,
               "75", [1, 2], {"x": 1}, 2 ** 63, "left", "right", "min-change", "phase", "nope", [60, 180],
               [180, 60], [0, 1e300], [float("nan"), 1])


def _edit_op(rng: random.Random, clean: bool = False) -> dict:
    from camcad.edit.session import MODES, OPERATIONS

    name = rng.choice(sorted(OPERATIONS) + ["move", "correct", "save", "bogus"])
    op: dict = {"op": name}
    for key, (kind, required) in OPERATIONS.get(name, {}).items():
        if not required and rng.random() < 0.5:
            continue
        if clean or rng.random() < 0.75:       # a sensible value of its kind
            value = {"number": rng.choice([0, 10, 45, 75, 100, 120, 180, 250, 300, 359]) + rng.random(),
                     "text": rng.choice(list(MODES) + ["exact", "iterate"]) if key != "path" else
                     rng.choice(["ok.dxf", "ok.csv", "sub/ok.csv", "ok.json"]),
                     "pair": sorted(rng.sample(range(0, 361, 15), 2)), "end": rng.choice(["left", "right"])}[kind]
        else:
            value = rng.choice(EDIT_VALUES) if key != "path" else rng.choice(HOSTILE_PATHS)
        op[key] = value
    if not clean and rng.random() < 0.1:
        op[rng.choice(["extra", "op2", "x"])] = rng.choice(EDIT_VALUES)
    return op


def edit_script_case(rng: random.Random, number: int, laws: list[Path]) -> Case:
    """``camcad edit LAW --script script.json`` with a generated script (issue 34 F1, F11, F12)."""
    law_path = rng.choice([p for p in laws if p.parent == SAMPLES / "dxf"] + [SAMPLES / "law_table.csv"])
    law = "law" + law_path.suffix.lower()
    roll = rng.random()
    if roll < 0.05:
        text = "[" * rng.choice([33, 1000, 100000]) + "]" * rng.choice([0, 33, 1000])
        how = "deep"
    elif roll < 0.08:
        text = json.dumps([{"op": "detect_phases"}] * rng.choice([2_000, 2_001, 50_000]))
        how = "long"
    elif roll < 0.12:
        text = rng.choice(["{}", "null", '"x"', "[1, 2]", "[{}]", "not json", "", "\ufeff[]", '[{"op": 1}]'])
        how = "malformed"
    else:
        clean = rng.random() < 0.6
        ops = [_edit_op(rng, clean) for _ in range(rng.randint(1, 8))]
        if rng.random() < 0.5:
            ops.append({"op": "save", "path": rng.choice(HOSTILE_PATHS)})
        text = json.dumps(ops, allow_nan=True)
        how = "ops"
    files = {law: law_path.read_bytes(), "script.json": text.encode("utf-8")}
    argv = ["edit", law, "--script", "script.json"]
    if rng.random() < 0.3:   # -o is the user's own choice of place: odd names, but inside the case folder (and
        # no NUL byte, which no command line can hold: the script's save paths carry it instead)
        inside = tuple(p for p in HOSTILE_PATHS if ".." not in p and CANARY not in p and not p.startswith("C:")
                       and "\x00" not in p)
        argv += ["-o", rng.choice(inside + ("out/final.dxf", "out", "out/final.csv"))]
    argv += _options(rng, {"--tol": [1e-5, 1e-3], "--lift": [10, 25], "--cycle": [360, 180]}, (0, 2))
    if rng.random() < 0.85:
        argv.append("--json")
    return Case(number, "edit-script", argv, files, f"{law_path.name} script:{how}")


def minsert_drawing(rng: random.Random) -> tuple[bytes, str]:
    """A drawing with the law and block references of random sizes: MINSERT cells, nesting, scales."""
    import io

    import ezdxf

    doc = ezdxf.new("R2000")
    msp = doc.modelspace()
    rows = [(0, 0), (60, 0), (90, 1), (120, 0), (150, -1), (180, 0), (240, 0), (270, -1), (300, 0), (330, 1),
            (360, 0)]
    if rng.random() < 0.8:
        msp.add_lwpolyline(rows, dxfattribs={"layer": "ACCEL"})
    depth = rng.choice([1, 1, 2, 3, 17])
    for level in range(depth):
        block = doc.blocks.new(f"B{level}")
        if level == 0:
            for _ in range(rng.choice([0, 1, 3])):
                block.add_line((0, 0), (rng.choice([1, 10, 1000]), 1))
            if rng.random() < 0.3:
                block.add_lwpolyline(rows)
        else:
            ref = block.add_blockref(f"B{level - 1}", (0, 0))
            if rng.random() < 0.5:
                ref.grid(size=(rng.choice([1, 2, 10, 100]), rng.choice([1, 2, 10, 100])), spacing=(1, 1))
    cells = rng.choice([1, 2, 50, 100, 3000, 32767, -5, 0])
    top = msp.add_blockref(f"B{depth - 1}", (rng.choice([0, 1e99, 1e300]) if rng.random() < 0.1 else 0, 0))
    if cells != 1:
        top.grid(size=(max(cells, 1), max(rng.choice([cells, 1, 7]), 1)), spacing=(rng.choice([1, 0, 1e300]), 1))
        if cells <= 0:
            top.dxf.row_count = cells
    if rng.random() < 0.2:
        top.dxf.xscale = rng.choice([1e-300, 1e99, 1e308, -1e308, 0.0])
    if rng.random() < 0.05:
        doc.blocks.get("B0").add_blockref(f"B{depth - 1}", (0, 0))      # a block that inserts itself
    stream = io.StringIO()
    doc.write(stream)     # not camcad's writer: its extents would expand the MINSERT here, in the parent
    # the same bytes for the same case: ezdxf stamps the time and random GUIDs
    text = re.sub(r"(\$(?:TDU?CREATE|TDU?UPDATE|TDINDWG|VERSIONGUID|FINGERPRINTGUID)\n\s*\d+\n)[^\n]*",
                  r"\g<1>0", stream.getvalue())
    text = re.sub(r"\d{4}-\d\d-\d\dT[\d:.]+\+00:00", "2000-01-01T00:00:00+00:00", text)   # ezdxf's own stamp
    return text.encode("utf-8"), f"depth {depth} cells {cells}"


def minsert_case(rng: random.Random, number: int, laws: list[Path]) -> Case:  # noqa: ARG001
    """``check``/``fix``/``profile`` on a drawing of block references (issue 34 F2, F6)."""
    data, how = minsert_drawing(rng)
    if rng.random() < 0.3:
        data, bytes_how = _bytes_mutation(data, rng)
        how += f" bytes:{bytes_how}"
    verb = rng.choice(["check", "fix", "profile"])
    argv = [verb, "law.dxf"] + _options(rng, LAW_OPTIONS, (0, 1))
    if verb == "fix":
        argv += ["-o", "out/fixed.dxf", "--no-plots"]
    elif verb == "profile":
        argv += ["--lift", "10", "--rb", "50", "--rr", "10", "-o", "out", "--no-plots"]
    if rng.random() < 0.85:
        argv.append("--json")
    return Case(number, "minsert", argv, {"law.dxf": data}, f"minsert {how}")


FUNCTIONS = ("sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "exp", "log", "ln", "log10",
             "log2", "sqrt", "abs")
ODD_TEXT = ("²", "١", "２", "π", "ｘ", "x²", "√x", "1e", "1e999", ".", "..", "1..2", "e", "pi", "__import__", "os",
            "x.real", "'x'", "[x]", "x,x", "()", "(", ")", "**", "^", "--x", "+-x", "x//2", "x%2", "1_000", "0x1F",
            "nan", "inf", "1e-320", "\x00", " ", "")


def _expression(rng: random.Random, depth: int = 0) -> str:
    roll = rng.random()
    if depth > rng.choice([2, 3, 4, 6]) or roll < 0.25:
        return rng.choice(["x", "x", "pi", "e", "1", "2.5", "0", "1e-3", "100", "1e300"])
    if roll < 0.5:
        return f"{rng.choice(FUNCTIONS)}({_expression(rng, depth + 1)})"
    if roll < 0.6:
        return f"-{_expression(rng, depth + 1)}"
    if roll < 0.7:
        return f"({_expression(rng, depth + 1)})"
    op = rng.choice(["+", "-", "*", "/", "^", "**"])
    return f"{_expression(rng, depth + 1)}{op}{_expression(rng, depth + 1)}"


def fgen_case(rng: random.Random, number: int, laws: list[Path]) -> Case:  # noqa: ARG001
    """``linkage fgen --function EXPR`` on a generated expression (issue 34 F12)."""
    roll = rng.random()
    if roll < 0.6:
        text = _expression(rng)
        how = "grammar"
    elif roll < 0.8:
        text = _expression(rng)
        at = rng.randrange(len(text) + 1)
        text = text[:at] + rng.choice(ODD_TEXT) + text[at:]
        how = "odd"
    elif roll < 0.9:
        n = rng.choice([39, 41, 200, 5000])
        text = "(" * n + "x" + ")" * n
        how = "deep"
    else:
        text = rng.choice(["x" + "+x" * rng.choice([100, 199, 1000]), "log(x)", "x^x^x^x^x", "1/(x-x)",
                           "sqrt(-x)", "exp(exp(exp(x)))", "log10(x)", "x*0"])
        how = "edge"
    low = rng.choice([0.5, 1, 1, 2, 0, -1, 10, 1e-300, 1e300])
    high = low + rng.choice([1, 1, 0.5, 2, 0, -1, 1e-12, 1e300])
    argv = ["linkage", "fgen", "--function", text, "--x", f"{low:g}:{high:g}",
            "--input-range", _value(rng, [60, 90, 120, 45]), "--output-range", _value(rng, [60, 90, 45])]
    argv += _options(rng, {"--method": ["q", "precision", "lsq", "minimax"], "--nodes": [3, 5, 7],
                           "--spacing": ["chebyshev", "uniform"], "--mu-min": [30, 40],
                           "--frame": [100, 1]}, (0, 2))
    argv += ["-o", "out", "--no-plots"] + (["--json"] if rng.random() < 0.85 else [])
    return Case(number, "fgen", argv, {}, f"fgen {how}")


SWEEP_KEYS = ("follower.base_radius", "follower.roller_radius", "follower.offset", "law.standard", "law.lift",
              "law.phases.rise", "law.phases.return", "machine.rpm", "contact.width", "law.file", "law.phases",
              "follower.auto_base_radius", "nope", "follower", "mechanisms.x.follower.base_radius", "", "=",
              "follower.base_radius.x")
SWEEP_SPECS = ("30:80:10", "30:40:5", "40,50", "cycloidal,harmonic", "cycloidal,nope", "60,90", "1:1e8:1",
               "30:80:0", "80:30:1", "nan:1:1", "1:2:1e-300", "0:1e308:1e300", "1e-300:2e-300:1e-310",
               "normal(50,1)", "normal(50,0)", "uniform(40,60)", "uniform(1,1)", "normal(nan,1)",
               "uniform(0,1e308)", "1,1", ",,", "x" * 500, "", "true,false", "30:80:1e-5", "-5:5:1", "0:0:1",
               "1e300,1e301", "300,400")


SENSIBLE_SWEEPS = {"follower.base_radius": ["30:60:10", "40,50", "normal(50,2)"], "follower.roller_radius": ["5:15:5"],
                   "law.standard": ["cycloidal,harmonic,poly345"], "law.lift": ["10:30:10"],
                   "law.phases.rise": ["60,90,120", "90:130:20"], "machine.rpm": ["200,300"]}


def sweep_case(rng: random.Random, number: int, laws: list[Path]) -> Case:  # noqa: ARG001
    """``camcad sweep`` on the default scene with generated ``--vary`` specs (issue 34 F3); at most 1 chunk of 2
    designs is computed after design 0 (``--stop-after-chunks``), so a valid sweep stays a short case."""
    argv = ["sweep"]
    for _ in range(rng.choice([1, 1, 2, 3])):
        key, spec = rng.choice(sorted(SENSIBLE_SWEEPS.items()))
        spec = rng.choice(spec)
        if rng.random() < 0.4:
            key = rng.choice(SWEEP_KEYS)
        if rng.random() < 0.4:
            spec = rng.choice(SWEEP_SPECS)
        argv += ["--vary", f"{key}={spec}" if rng.random() < 0.95 else key]
    argv += _options(rng, {"--samples": [2, 3, 0, -1, 10 ** 7], "--seed": [0, 1, -1, 2 ** 70],
                           "--objective": ["min:follower.base_radius", "max:min_margin_ratio", "min:nope", "junk",
                                           "max:pressure angle, rise.margin"],
                           "--plot": ["follower.base_radius,law.phases.rise", "x", "a,b,c"]}, (0, 2))
    argv += ["--workers", "1", "--chunk", "2", "--stop-after-chunks", "1", "--no-plots", "--no-best", "-o", "out"]
    if rng.random() < 0.85:
        argv.append("--json")
    return Case(number, "sweep", argv, {}, "sweep specs")


NEW_SURFACE_CASES = {"edit-script": edit_script_case, "minsert": minsert_case, "fgen": fgen_case,
                     "sweep": sweep_case}


# ---------------------------------------------------------------------------------------------
# Running a case in a forked child
# ---------------------------------------------------------------------------------------------

@dataclass
class Outcome:
    case: int
    command: str
    mutation: str
    argv: list[str]
    status: str         # "ok", "error", "memory" or "FINDING"
    detail: str
    seconds: float      # wall time
    cpu: float = 0.0    # CPU seconds of the child


@dataclass
class Running:
    case: Case
    pid: int
    folder: Path
    started: float
    digests: dict[str, str] = field(default_factory=dict)


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def prepare(case: Case, root: Path, canary: Path) -> Running:
    """The case's folder with its input files (hashed), the canary placeholder made a real path."""
    folder = root / f"case{case.number}"
    folder.mkdir()
    (folder / "out").mkdir()
    case.argv = [a.replace(CANARY, str(canary)) for a in case.argv]
    digests = {}
    for name, data in case.files.items():
        data = data.replace(CANARY.encode(), str(canary).encode())
        (folder / name).write_bytes(data)
        digests[name] = _digest(data)
    return Running(case, 0, folder, 0.0, digests)


def _child(case: Case, folder: Path, limit: int, target=None) -> None:
    """In the forked child: confine, limit, run the command (``target(argv)``, default camcad's main), exit
    with its code (never returns)."""
    code = 70
    try:
        os.chdir(folder)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)
        out = os.open(folder / ".stdout", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        err = os.open(folder / ".stderr", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        violations = os.open(folder / ".violations", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(out, 1)
        os.dup2(err, 2)
        # the streams Python writes to may not be fds 1 and 2 (pytest replaces them): bind them anew
        sys.stdout = open(1, "w", encoding="utf-8", errors="replace", closefd=False)  # noqa: SIM115
        sys.stderr = open(2, "w", encoding="utf-8", errors="replace", closefd=False)  # noqa: SIM115
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))  # no core dump when a limit ends the child
        # the kernel ends the child (SIGXCPU after 10 s of CPU, SIGALRM after the wall limit), even in C code
        spent = resource.getrusage(resource.RUSAGE_SELF)
        cpu = int(spent.ru_utime + spent.ru_stime) + TIME_LIMIT_S
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 1))
        signal.signal(signal.SIGXCPU, signal.SIG_DFL)
        signal.signal(signal.SIGALRM, signal.SIG_DFL)
        signal.alarm(WALL_LIMIT_S)
        _watch_writes(str(folder.resolve()), violations)
        if target is None:
            from camcad.cli import main as target
        try:
            target(case.argv)
            code = 0
        except SystemExit as stop:
            code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
        except MemoryError:
            code = 71
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
    except BaseException:  # noqa: BLE001 - whatever happens, the child must not return into the parent's loop
        code = 72
    os._exit(code)


WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND


def _watch_writes(folder: str, sink: int) -> None:
    """Audit hook: record every write-like file operation outside ``folder`` into the file ``sink``."""
    allowed = (folder + os.sep, os.devnull, os.environ.get("MPLCONFIGDIR", "\0"))

    def inside(path) -> bool:
        if isinstance(path, int):
            return True
        try:
            text = os.fsdecode(path)
        except Exception:  # noqa: BLE001
            return False
        full = os.path.realpath(os.path.join(folder, text))
        return full == folder or full.startswith(allowed)

    def hook(event: str, args) -> None:
        try:
            if event == "open":
                path, mode, flags = args
                writing = (isinstance(mode, str) and any(c in mode for c in "wax+")) or \
                    (mode is None and isinstance(flags, int) and flags & WRITE_FLAGS)
                if writing and not inside(path):
                    os.write(sink, f"open {os.fsdecode(path)!r} {mode!r}\n".encode("utf-8", "replace"))
            elif event in ("os.rename", "os.replace", "os.link", "os.symlink"):
                for path in args[:2]:
                    if not inside(path):
                        os.write(sink, f"{event} {os.fsdecode(path)!r}\n".encode("utf-8", "replace"))
            elif event in ("os.remove", "os.rmdir", "os.mkdir", "os.truncate", "os.chmod", "shutil.rmtree") \
                    and args and not inside(args[0]):
                os.write(sink, f"{event} {os.fsdecode(args[0])!r}\n".encode("utf-8", "replace"))
        except Exception:  # noqa: BLE001 - a hook must never raise into the code it watches
            return

    sys.addaudithook(hook)


def classify(case: Case, code: int | None, signalled: int | None, stdout: str, stderr: str,
             changed: list[str], violations: str) -> tuple[str, str]:
    """(status, detail) of a finished case; see the module docstring."""
    if changed:
        return "FINDING", f"input changed: {', '.join(changed)}"
    if violations.strip():
        return "FINDING", f"wrote outside the case folder: {violations.strip().splitlines()[0][:200]}"
    if signalled == signal.SIGXCPU:
        return "FINDING", f"ran past {TIME_LIMIT_S} s of CPU time"
    if signalled == signal.SIGALRM:
        return "FINDING", f"still running after {WALL_LIMIT_S} s of wall time"
    if signalled == signal.SIGKILL:
        return "FINDING", "killed at the CPU or wall-time limit"
    if signalled is not None or code is None:
        return "FINDING", f"killed by signal {signalled}"
    lines = stderr.strip().splitlines()
    if code == 130 and "--stop-after-chunks" in case.argv and len(lines) == 1 and \
            lines[0].startswith("camcad: error: stopped after"):
        return "ok", "exit 130 (stopped after a chunk, as asked)"
    if code in (0, 1):
        if "--json" in case.argv:
            try:
                payload = json.loads(stdout)
            except ValueError:
                return "FINDING", f"exit {code} without one JSON object on stdout"
            if not isinstance(payload, dict):
                return "FINDING", f"exit {code}: stdout JSON is not an object"
        if stderr.strip():
            return "FINDING", f"exit {code} with noise on stderr: {stderr.strip()[:200]}"
        return "ok", f"exit {code}"
    if code == 2 and len(lines) == 1 and lines[0].startswith("camcad: error: ") and "Traceback" not in stderr:
        if "out of memory" in lines[0]:
            return "memory", lines[0][:200]
        if "internal error" in lines[0]:
            return "FINDING", lines[0][:300]
        if len(lines[0]) > 300:
            return "FINDING", f"error line of {len(lines[0])} characters: {lines[0][:200]}"
        return "error", lines[0][:200]
    if code == 71:
        return "memory", "MemoryError outside the command's own handling"
    return "FINDING", f"exit {code}: {stderr.strip()[:300]}"


def finish(running: Running, status_code: int, canary: Path, expected: set[str], cpu: float = 0.0) -> Outcome:
    case, folder = running.case, running.folder
    seconds = time.perf_counter() - running.started
    code = os.waitstatus_to_exitcode(status_code)
    signalled = -code if code < 0 else None
    code = None if signalled is not None else code

    def read(name: str) -> str:
        path = folder / name
        return path.read_bytes().decode("utf-8", "replace") if path.exists() else ""

    changed = [name for name, digest in running.digests.items()
               if not (folder / name).is_file() or _digest((folder / name).read_bytes()) != digest]
    violations = read(".violations")
    cases_root, run_root = folder.parent, folder.parent.parent
    stray = [p for p in canary.iterdir()] + [p for p in cases_root.iterdir() if not p.name.startswith("case")] \
        + [p for p in run_root.iterdir() if p.name not in expected]
    if stray:
        violations += f"found outside: {', '.join(sorted(str(p) for p in stray)[:3])}\n"
        for target in stray:
            if target.is_dir() and not target.is_symlink():
                shutil.rmtree(target, ignore_errors=True)
            else:
                target.unlink(missing_ok=True)
    status, detail = classify(case, code, signalled, read(".stdout"), read(".stderr"), changed, violations)
    return Outcome(case.number, case.command, case.mutation, case.argv, status, detail, seconds, cpu)


def _preload():
    """Import everything the commands use, once, in the parent (the children inherit it); returns the
    function that undoes the one change it makes (the cached click command)."""
    import matplotlib

    matplotlib.use("Agg")
    import ezdxf  # noqa: F401
    import matplotlib.pyplot
    import numpy  # noqa: F401
    import scipy.integrate
    import scipy.optimize
    import scipy.sparse.linalg  # noqa: F401
    import typer.main

    from camcad.cli import app
    from camcad.cli import register_all as _register_commands

    _register_commands()
    # typer rebuilds the click command from the annotations on every call (~0.1 s): build it once here,
    # as a long-running CLI would; the command that runs is the same
    built = typer.main.get_command(app)
    original = typer.main.get_command
    typer.main.get_command = lambda typer_app: built if typer_app is app else original(typer_app)

    def undo() -> None:
        typer.main.get_command = original

    return undo


def run(cases: int, seed: int, workers: int = 2, start: int = 0, progress: bool = False,
        keep: Path | None = None, commands: tuple[str, ...] = COMMANDS, log: Path | None = None, *,
        factory=None, target=None) -> list[Outcome]:
    """Run cases ``start`` … ``start + cases − 1`` of campaign ``seed``, ``workers`` children at a time.

    ``factory(number) -> Case`` and ``target(argv)`` replace the case generator and camcad's main (tests
    of the harness itself use them).
    """
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    for path in (str(ROOT), str(Path(__file__).resolve().parent)):
        if path not in sys.path:
            sys.path.insert(0, path)
    if factory is None:
        laws, scenes = law_corpus(), scene_corpus()

        def factory(number: int) -> Case:
            return make_case(seed, number, laws, scenes, commands)

    outcomes: list[Outcome] = []
    previous_mpl = os.environ.get("MPLCONFIGDIR")
    with tempfile.TemporaryDirectory(prefix="camcad-fuzz-") as tmp:
        root = Path(tmp) / "cases"
        root.mkdir()
        canary = Path(tmp) / "canary"
        canary.mkdir()
        expected = {"cases", "canary", "mpl"}
        os.environ["MPLCONFIGDIR"] = str(Path(tmp) / "mpl")
        undo = _preload()
        limit = _address_space() + MEMORY_HEADROOM
        gc.collect()
        gc.freeze()  # the children inherit the heap; a frozen heap is not copied page by page by their GC
        try:
            _loop(factory, cases, start, workers, root, canary, expected, limit, target, outcomes, keep, log,
                  progress)
        finally:
            gc.unfreeze()
            undo()
            if previous_mpl is None:
                os.environ.pop("MPLCONFIGDIR", None)
            else:
                os.environ["MPLCONFIGDIR"] = previous_mpl
    return outcomes


def _loop(factory, cases, start, workers, root, canary, expected, limit, target, outcomes, keep, log,
          progress) -> None:
    running: dict[int, Running] = {}
    next_case = start
    began = time.perf_counter()
    while next_case < start + cases or running:
        while len(running) < workers and next_case < start + cases:
            case = factory(next_case)
            next_case += 1
            job = prepare(case, root, canary)
            job.started = time.perf_counter()
            pid = os.fork()
            if pid == 0:
                _child(case, job.folder, limit, target)
            job.pid = pid
            running[pid] = job
        pid, status, cpu = _wait(running)
        job = running.pop(pid)
        outcome = finish(job, status, canary, expected, cpu)
        outcomes.append(outcome)
        if outcome.status == "FINDING" and keep is not None:
            _keep(job, outcome, keep)
        if outcome.status == "FINDING" and log is not None:
            with open(log, "a", encoding="utf-8") as stream:
                stream.write(json.dumps(outcome.__dict__) + "\n")
        shutil.rmtree(job.folder, ignore_errors=True)
        if progress and len(outcomes) % 500 == 0:
            rate = len(outcomes) / (time.perf_counter() - began)
            findings = sum(o.status == "FINDING" for o in outcomes)
            print(f"  {len(outcomes)} cases (up to case {next_case - 1}), {rate:.2f}/s, {findings} findings",
                  file=sys.stderr, flush=True)


def _wait(running: dict[int, Running]) -> tuple[int, int, float]:
    """The next finished child (pid, wait status, CPU seconds); a child past every limit is killed."""
    while True:
        pid, status, usage = os.wait4(-1, os.WNOHANG)
        if pid:
            return pid, status, usage.ru_utime + usage.ru_stime
        now = time.perf_counter()
        for job in running.values():
            if now - job.started > WALL_LIMIT_S + 10:
                os.kill(job.pid, signal.SIGKILL)
        time.sleep(0.002)


def _address_space() -> int:
    with open("/proc/self/statm") as stream:
        pages = int(stream.read().split()[0])
    return pages * os.sysconf("SC_PAGE_SIZE")


def _keep(job: Running, outcome: Outcome, keep: Path) -> None:
    target = keep / f"case{outcome.case}"
    shutil.copytree(job.folder, target, dirs_exist_ok=True)
    (target / "OUTCOME.json").write_text(json.dumps(outcome.__dict__, indent=1, default=str))


def summary(outcomes: list[Outcome], seed: int, seconds: float) -> str:
    counts = Counter(o.status for o in outcomes)
    per_command = Counter(o.command for o in outcomes)
    slowest = max(outcomes, key=lambda o: o.cpu) if outcomes else None
    text = (f"{len(outcomes)} cases (seed {seed}) in {seconds:.0f} s ({len(outcomes) / max(seconds, 1e-9):.1f}/s): "
            f"{counts['ok']} results, {counts['error']} clear errors, {counts['memory']} over the memory limit, "
            f"{counts['FINDING']} findings")
    if slowest is not None:
        text += f"; slowest case {slowest.cpu:.2f} s of CPU ({slowest.command}, {slowest.mutation})"
    text += "\nper command: " + ", ".join(f"{k} {v}" for k, v in sorted(per_command.items()))
    findings = Counter(_signature(o) for o in outcomes if o.status == "FINDING")
    if findings:
        text += "\nfindings by kind:\n" + "\n".join(f"  {n:6d}  {k}" for k, n in findings.most_common())
    if outcomes:
        times = sorted(o.cpu for o in outcomes)

        def at(q: float) -> float:
            return times[int(q * (len(times) - 1))]

        text += f"\ncase CPU seconds: median {at(0.5):.3f}, 90 % {at(0.9):.3f}, 99 % {at(0.99):.3f}"
        by_command = {}
        for o in outcomes:
            by_command.setdefault(o.command, []).append(o.cpu)
        text += "\nmean CPU seconds per command: " + ", ".join(
            f"{k} {sum(v) / len(v):.2f}" for k, v in sorted(by_command.items()))
    return text


def _signature(outcome: Outcome) -> str:
    """A finding without its numbers and file-specific words: one line per kind of finding."""
    detail = re.sub(r"\b\d[\d.e+-]*", "#", outcome.detail)
    detail = re.sub(r"got .*", "got ...", detail)
    return f"{outcome.command}: {detail[:110]}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--start", type=int, default=0, help="first case number (to resume or split a run)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--replay", type=int, default=None, help="run this one case and show it")
    parser.add_argument("--keep", type=Path, default=None, help="copy the folders of findings here")
    parser.add_argument("--commands", default=",".join(ALL_COMMANDS), help="comma-separated subset of the commands")
    parser.add_argument("--errors", action="store_true", help="also list the most frequent error lines")
    parser.add_argument("--log", type=Path, default=None, help="append each finding to this file (JSON lines)")
    parser.add_argument("--pin", type=int, default=None,
                        help="write this case's inputs and argv to tests/fixtures/fuzz/seedS-caseN/ (a regression)")
    parser.add_argument("--finding", default="", help="with --pin: what the case found, for its record")
    args = parser.parse_args()
    commands = tuple(c for c in args.commands.split(",") if c in ALL_COMMANDS) or ALL_COMMANDS
    if args.pin is not None:   # the case the command line ran (it draws from the same commands)
        case = make_case(args.seed, args.pin, law_corpus(), scene_corpus(), commands)
        print(pin(case, PINNED / f"seed{args.seed}-case{args.pin}", args.finding, args.seed))
        return 0
    if args.replay is not None:
        args.cases, args.start, args.workers = 1, args.replay, 1
    began = time.perf_counter()
    outcomes = run(args.cases, args.seed, args.workers, args.start, progress=args.replay is None, keep=args.keep,
                   commands=commands, log=args.log)
    print(summary(outcomes, args.seed, time.perf_counter() - began))
    if args.errors:
        common = Counter(re.sub(r"\b\d[\d.e+-]*", "#", o.detail.split(": ", 1)[-1])[:90]
                         for o in outcomes if o.status == "error")
        for text, count in common.most_common(25):
            print(f"  {count:6d}  {text}")
    for o in outcomes:
        if o.status == "FINDING" or args.replay is not None:
            printable = " ".join(repr(a) if (not a or any(c.isspace() or ord(c) < 32 for c in a)) else a
                                 for a in o.argv)
            print(f"{o.status} case {o.case} [{o.mutation}]: camcad {printable}\n    {o.detail}")
    return 1 if any(o.status == "FINDING" for o in outcomes) else 0


if __name__ == "__main__":
    sys.exit(main())
