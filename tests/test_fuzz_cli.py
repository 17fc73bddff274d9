"""The fuzz campaign (tests/fuzz_cli.py): a short fixed-seed slice, and the harness's own checks.

The long run is `python tests/fuzz_cli.py --cases 100000 --seed 11`; the README quotes its last result.
"""

from __future__ import annotations

import math
import os
import time
import tomllib

import fuzz_cli
import pytest
from fuzz_cli import Case, classify, run, toml_text


def _findings(outcomes):
    return [(o.case, o.argv, o.detail) for o in outcomes if o.status == "FINDING"]


def test_short_slice_of_the_drawn_law_commands_has_no_findings():
    commands = ("check", "fix", "profile-law", "spectrum", "dynamics", "impact")
    outcomes = run(cases=10, seed=101, workers=2, commands=commands)
    assert not _findings(outcomes), _findings(outcomes)
    assert {"ok", "error"} <= {o.status for o in outcomes}
    assert max(o.cpu for o in outcomes) < fuzz_cli.TIME_LIMIT_S


def test_short_slice_of_the_scene_commands_has_no_findings():
    commands = ("profile-scene", "contact", "cyclogram")
    outcomes = run(cases=4, seed=202, workers=2, commands=commands)
    assert not _findings(outcomes), _findings(outcomes)
    assert any(o.status in ("ok", "error") for o in outcomes)


def test_cases_are_reproducible_one_by_one():
    laws, scenes = fuzz_cli.law_corpus(), fuzz_cli.scene_corpus()
    first = fuzz_cli.make_case(11, 4711, laws, scenes)
    again = fuzz_cli.make_case(11, 4711, laws, scenes)
    assert first.argv == again.argv and first.files == again.files and first.mutation == again.mutation


def test_scene_writer_round_trips_hostile_values():
    data = {"name": "a\x00b\nc\"d\\e", "value": math.inf, "neg": -math.inf, "zero": -0.0, "big": 2 ** 63 - 1,
            "tiny": 5e-324, "list": [1, "x", 2.5], "law": {"file": "../../x.dxf", "lift": math.nan},
            "cyclogram": {"operations": [{"from": 1, "to": 2, "bounds_deg": [0.0, math.inf]}]}}
    back = tomllib.loads(toml_text(data))
    assert back["name"] == data["name"] and back["law"]["file"] == "../../x.dxf"
    assert back["value"] == math.inf and back["neg"] == -math.inf and math.isnan(back["law"]["lift"])
    assert math.copysign(1.0, back["zero"]) == -1.0 and back["big"] == 2 ** 63 - 1 and back["tiny"] == 5e-324
    assert back["cyclogram"]["operations"][0]["bounds_deg"] == [0.0, math.inf]


def test_classify_catches_what_it_must():
    case = Case(0, "check", ["check", "law.dxf", "--json"], {}, "intact")
    assert classify(case, 0, None, "{}", "", [], "")[0] == "ok"
    assert classify(case, 0, None, "not json", "", [], "")[0] == "FINDING"
    assert classify(case, 1, None, "{}", "UserWarning: overflow", [], "")[0] == "FINDING"       # noise
    assert classify(case, 2, None, "", "camcad: error: law.dxf: no curve; draw one", [], "")[0] == "error"
    assert classify(case, 2, None, "", "camcad: error: internal error (ValueError: x); report", [], "")[0] == \
        "FINDING"
    assert classify(case, 2, None, "", "camcad: error: " + "x" * 300, [], "")[0] == "FINDING"
    assert classify(case, 2, None, "", "camcad: error: a\ncamcad: error: b", [], "")[0] == "FINDING"
    assert classify(case, 3, None, "", "camcad: error: internal error", [], "")[0] == "FINDING"
    assert "CPU" in classify(case, None, 24, "", "", [], "")[1]                                    # SIGXCPU
    assert "wall" in classify(case, None, 14, "", "", [], "")[1]                                   # SIGALRM
    assert classify(case, None, 11, "", "", [], "")[0] == "FINDING"                              # SIGSEGV
    assert classify(case, 0, None, "{}", "", ["law.dxf"], "")[0] == "FINDING"                     # input changed
    assert classify(case, 0, None, "{}", "", [], "open '/etc/x' 'w'")[0] == "FINDING"             # wrote outside


def _spin(argv):
    while True:
        pass


def _write_outside(argv):
    with open(os.path.join("..", "..", "escaped.txt"), "w") as stream:
        stream.write("x")


def _change_input(argv):
    with open("law.dxf", "ab") as stream:
        stream.write(b"x")


@pytest.mark.parametrize("target,expected", [(_spin, "CPU time"), (_write_outside, "outside"),
                                             (_change_input, "input changed")],
                         ids=["hang", "write outside", "input changed"])
def test_the_harness_sees_hangs_escapes_and_changed_inputs(monkeypatch, target, expected):
    monkeypatch.setattr(fuzz_cli, "TIME_LIMIT_S", 1)
    case = Case(0, "check", ["check", "law.dxf"], {"law.dxf": b"0\nEOF\n"}, "test")
    began = time.perf_counter()
    outcomes = run(1, 0, workers=1, factory=lambda number: case, target=target)
    assert time.perf_counter() - began < 30
    assert outcomes[0].status == "FINDING" and expected in outcomes[0].detail, outcomes[0].detail


@pytest.mark.parametrize("number", [4039, 4093, 4388, 7730, 31087, 44694, 53324])
def test_the_campaign_s_findings_stay_fixed(number):
    # seed 11: 4039 `spectrum --fn 1e9` built 9e7 harmonics before counting them (out of memory); 4093 a scene
    # listing 10,000 linkage settings (0.17 s of CPU each); 4388 `dynamics --rpm 1e-300` (ω² underflowed to 0);
    # 7730 `check --trapezoid --step 1e-300` (an array past numpy's largest size); 31087 a law_of = "output" law
    # drawn unbalanced, drifting to -3.8 deg below its start, where the four-bar's inverse is NaN (profile
    # --arcs: internal error in the arc fit); 44694 `fix --mode phase-keypoints --max-stretch nan` (NaN stretch
    # factors, the law's phases lost: IndexError); 53324 `profile --rb 1e9` (2.5 million chords at 0.001 mm, 7
    # samples each: out of memory; now at most 1,000,000 points, refused before sampling)
    outcomes = run(cases=1, seed=11, workers=1, start=number)
    assert not _findings(outcomes), _findings(outcomes)
    assert outcomes[0].status == "error"       # each is bad input now: exit 2 with one line


def test_a_filter_at_a_slow_speed_stays_within_the_campaign_s_limit():
    # seed 11, case 21419: `spectrum --filter` on the batten scene mutated to 3 rpm puts the 113 Hz band at
    # harmonics 2150-2380; the filter evaluated those 229 terms by Horner over all 2,374 coefficients at
    # 524,296 points (92 s of CPU, past the campaign's 10 s). Now the non-zero terms only, and the FFT on the
    # uniform grid: a normal run, every check reported
    outcomes = run(cases=1, seed=11, workers=1, start=21419)
    assert not _findings(outcomes), _findings(outcomes)
    assert outcomes[0].status == "ok"


def test_a_scene_mutation_may_name_a_table_the_scene_lacks():
    # a group scene has no top-level [law]; a mutation of its phases used to crash the campaign (KeyError)
    data = {"mechanisms": {"a": {"law": {"phases": "0:360:dwell"}}}}
    fuzz_cli._set(data, ("law", "phases"), "0:360:rise")
    assert data["law"] == {"phases": "0:360:rise"}


def test_short_slice_of_the_new_surfaces_has_no_findings():
    # issue 34: edit scripts, MINSERT drawings, linkage --function expressions and sweep specs
    outcomes = run(cases=12, seed=303, workers=2, commands=fuzz_cli.NEW_SURFACES)
    assert not _findings(outcomes), _findings(outcomes)
    assert {o.command for o in outcomes} <= set(fuzz_cli.NEW_SURFACES)
    assert max(o.cpu for o in outcomes) < fuzz_cli.TIME_LIMIT_S


def test_new_surface_cases_are_reproducible_and_the_old_numbers_unchanged():
    laws, scenes = fuzz_cli.law_corpus(), fuzz_cli.scene_corpus()
    for number in range(40):
        first = fuzz_cli.make_case(34, number, laws, scenes, fuzz_cli.NEW_SURFACES)
        again = fuzz_cli.make_case(34, number, laws, scenes, fuzz_cli.NEW_SURFACES)
        assert first.argv == again.argv and first.files == again.files, number
    # the earlier campaigns' case numbers still name the same cases (the pinned findings above)
    assert fuzz_cli.make_case(11, 4039, laws, scenes).command == "spectrum"
