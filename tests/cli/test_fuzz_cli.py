"""The fuzz campaign (tests/fuzz_cli.py): a short fixed-seed slice, and the harness's own checks.

The long run is `python tests/fuzz_cli.py --cases 100000 --seed 11`; the README quotes its last result. Its
findings are pinned as files (tests/fixtures/fuzz/, `python tests/fuzz_cli.py --seed S --pin N`), not as case
numbers, which name other cases once the corpus or the generator changes.
"""

from __future__ import annotations

import math
import os
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
    outcomes = run(1, 0, workers=1, factory=lambda number: case, target=target)
    assert outcomes[0].cpu < 5                     # the spin ended by its 1 s CPU limit (CPU time: load-proof)
    assert outcomes[0].status == "FINDING" and expected in outcomes[0].detail, outcomes[0].detail


PINNED = fuzz_cli.pinned_cases()


def test_the_pinned_findings_are_there():
    # the campaign's findings, each pinned as files (tests/fixtures/fuzz/): never zero cases by accident
    assert len(PINNED) >= 8, PINNED


@pytest.mark.parametrize("folder", PINNED, ids=[p.name for p in PINNED])
def test_the_campaign_s_findings_stay_fixed(folder):
    # each folder holds a finding's inputs and argv as the campaign made them (case.json says what it found, and
    # in which commit it was fixed: run against that commit's parent, the case is a FINDING again); the inputs
    # are files, so the case stays the same when the corpus or the generator changes
    case, record = fuzz_cli.load_pinned(folder)
    outcomes = run(1, 0, workers=1, factory=lambda number: case)
    assert not _findings(outcomes), (record["finding"], _findings(outcomes))
    assert outcomes[0].status == record["expect"]["status"], outcomes[0].detail
    assert record["expect"]["detail"] in outcomes[0].detail, outcomes[0].detail


def test_a_case_pins_and_loads_back_unchanged(tmp_path):
    laws, scenes = fuzz_cli.law_corpus(), fuzz_cli.scene_corpus()
    case = fuzz_cli.make_case(11, 4711, laws, scenes)
    folder = fuzz_cli.pin(case, tmp_path / "pinned", "nothing", 11)
    again, record = fuzz_cli.load_pinned(folder)
    assert (again.number, again.command, again.argv, again.files, again.mutation) == \
        (case.number, case.command, case.argv, case.files, case.mutation)
    assert record["campaign"] == {"seed": 11, "case": 4711} and record["finding"] == "nothing"


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
