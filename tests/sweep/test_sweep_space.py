"""The design space of `camcad sweep`: keys, SPECs, design ids, draws, a design's scene, and the analysis
helpers (Pareto front, best design, boundary) against brute force. No pipeline runs here (fast)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from camcad.errors import CamcadError
from camcad.scene.default import default_tables
from camcad.sweep.analysis import (
    Objective,
    best_index,
    feasible_boundary,
    pareto_front,
    parse_objective,
)
from camcad.sweep.space import (
    DesignSpace,
    apply_values,
    build_space,
    parse_spec,
    resolve_key,
    stretched_phases,
)

SCENES = Path(__file__).resolve().parents[2] / "samples" / "scenes"


def loom() -> dict:
    return tomllib.loads((SCENES / "loom_group1.toml").read_text())


# --------------------------------------------------------------------------------------------
# keys
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("property", "keys resolve to their tables, kinds and units")
def test_keys_of_a_single_mechanism_and_of_a_group():
    t = default_tables()
    key = resolve_key("follower.base_radius", t)
    assert (key.tables, key.name, key.kind, key.unit) == (("follower",), "base_radius", "float", "mm")
    assert resolve_key("law.standard", t).kind == "str"
    assert resolve_key("machine.rpm", t).unit == "rpm"          # the default scene has no [machine]: rpm adds it
    rise = resolve_key("law.phases.rise", t)
    assert rise.phase and rise.unit == "deg"
    group = resolve_key("mechanisms.shuttle_lift.contact.width", loom())
    assert group.tables == ("mechanisms", "shuttle_lift", "contact") and group.name == "width"
    assert resolve_key("mechanisms.weft_returner.law.phases.return", loom()).phase
    assert resolve_key("cyclogram.start_deg", loom()).unit == "deg"


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("path, words", [
    ("follower.base_radus", "did you mean 'follower.base_radius'?"),
    ("contact.width", "the scene has no [contact] section"),
    ("law.phases", "law.phases.rise"),
    ("law.phases.rise_3", "did you mean"),
    ("law.file", "does not vary the law's file"),
    ("mechanisms.shuttle_lift.follower.base_radius", "unknown key"),   # not a group scene
])
def test_a_key_the_scene_does_not_have_is_one_line(path, words):
    with pytest.raises(CamcadError) as err:
        resolve_key(path, default_tables())
    message = err.value.message()
    assert words in message and "\n" not in message and len(message) < 300


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_drawn_law_s_phase_angles_are_not_varied():
    t = {"law": {"file": "x.dxf", "phases": "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"},
         "follower": {"base_radius": 50.0, "roller_radius": 10.0}}
    with pytest.raises(CamcadError, match="drawn law"):
        resolve_key("law.phases.rise", t)


# --------------------------------------------------------------------------------------------
# specs
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "A:B:S gives A + i S rounded, B included only on the grid")
def test_a_range_is_a_plus_i_step_without_accumulated_round_off():
    key = resolve_key("follower.base_radius", default_tables())
    values = parse_spec(key, "30:80:0.5").values
    assert len(values) == 101 and values[0] == 30.0 and values[-1] == 80.0
    assert all(v == round(30 + 0.5 * i, 9) for i, v in enumerate(values))
    tenths = parse_spec(key, "0.1:1:0.1").values   # 0.1 + 2*0.1 is 0.30000000000000004 in binary
    assert tenths == tuple(round(0.1 * (i + 1), 12) for i in range(10))
    assert parse_spec(key, "30:31:0.3").values == (30.0, 30.3, 30.6, 30.9)   # B off the grid: not included


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("key, spec, words", [
    ("follower.base_radius", "30:20:1", "runs backwards"),
    ("follower.base_radius", "30:40:0", "step must be positive"),
    ("follower.base_radius", "30:40", "not A:B:STEP"),
    ("follower.base_radius", "a,b", "'a' is not a number"),
    ("follower.base_radius", "0:10:5", "must be positive"),            # the scene parser's own rule
    ("follower.base_radius", "normal(50)", "two numbers"),
    ("follower.base_radius", "normal(50,0)", "sigma > 0"),
    ("follower.base_radius", "uniform(5,1)", "a < b"),
    ("follower.base_radius", "40,40", "listed twice"),
    ("law.standard", "cycloidal,sinus", "sinus"),
    ("law.standard", "1:3:1", "takes a list"),
    ("follower.type", "roller,wheel", "not one of"),
    ("follower.pressure_angle_limit_rise", "80:100:10", "at most 90"),
    ("law.phases.rise", "0,60", "phase angle must be positive"),
    ("follower.reversible", "yes", "not true or false"),
])
def test_a_bad_spec_is_one_line(key, spec, words):
    with pytest.raises(CamcadError) as err:
        parse_spec(resolve_key(key, default_tables()), spec)
    message = err.value.message()
    assert words in message and "\n" not in message and len(message) < 300


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_samples_go_with_distributions():
    t = default_tables()
    with pytest.raises(CamcadError, match="--samples"):
        build_space(t, ["follower.roller_radius=normal(10,0.1)"])
    with pytest.raises(CamcadError, match="without a distribution"):
        build_space(t, ["follower.base_radius=30:40:1"], samples=10)
    with pytest.raises(CamcadError, match="varied twice"):
        build_space(t, ["follower.base_radius=30:40:1", "follower.base_radius=50"])
    with pytest.raises(CamcadError, match="KEY=SPEC"):
        build_space(t, ["follower.base_radius"])


# --------------------------------------------------------------------------------------------
# design ids and draws
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("property", "design ids enumerate the grid (last key fastest) then the draws; common random "
                                   "numbers")
def test_design_ids_enumerate_the_grid_last_key_fastest_then_the_draws():
    t = default_tables()
    space = build_space(t, ["follower.base_radius=30:34:2", "law.standard=cycloidal,harmonic",
                            "follower.roller_radius=uniform(9,11)"], samples=4, seed=7)
    assert space.size == 3 * 2 * 4 and space.shape == (3, 2)
    seen = set()
    for design in range(space.size):
        v = space.values(design)
        grid, sample = divmod(design, 4)
        assert v["follower.base_radius"] == 30 + 2 * (grid // 2)
        assert v["law.standard"] == ("cycloidal", "harmonic")[grid % 2]
        assert 9 <= v["follower.roller_radius"] < 11
        seen.add((v["follower.base_radius"], v["law.standard"], sample))
    assert len(seen) == space.size
    # every grid point sees the same draws (common random numbers), whatever order they are asked in
    draws = [space.values(d)["follower.roller_radius"] for d in range(4)]
    assert [space.values(4 * 5 + j)["follower.roller_radius"] for j in range(4)] == draws
    again = build_space(t, ["follower.base_radius=30:34:2", "law.standard=cycloidal,harmonic",
                            "follower.roller_radius=uniform(9,11)"], samples=4, seed=7)
    assert [again.values(d) for d in reversed(range(again.size))] == [space.values(d) for d in
                                                                       reversed(range(space.size))]
    assert build_space(t, ["follower.roller_radius=uniform(9,11)"], samples=4, seed=8).values(0) != space.values(0)


@pytest.mark.reference("property", "the sample mean and s.d. within 4 standard errors of the asked 50 and 0.2")
def test_normal_draws_have_the_asked_mean_and_spread():
    # reference: the distribution's own parameters; tolerance 4 standard errors of the mean and of the s.d.
    space = build_space(default_tables(), ["follower.base_radius=normal(50,0.2)"], samples=4000, seed=1)
    draws = np.array([space.values(d)["follower.base_radius"] for d in range(space.size)])
    n = len(draws)
    assert abs(draws.mean() - 50.0) < 4 * 0.2 / math.sqrt(n)
    assert abs(draws.std(ddof=1) - 0.2) < 4 * 0.2 / math.sqrt(2 * (n - 1))


# --------------------------------------------------------------------------------------------
# a design's scene
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "phases stretched by hand: the next dwell takes up the change")
def test_a_phase_angle_keeps_its_start_and_the_next_dwell_takes_up_the_change():
    t = default_tables()   # 0:120:rise,120:180:dwell,180:300:return,300:360:dwell
    assert stretched_phases(t["law"]["phases"], "rise", 75.5) == \
        "0:75.5:rise,75.5:180:dwell,180:300:return,300:360:dwell"
    assert stretched_phases(t["law"]["phases"], "return", 150) == \
        "0:120:rise,120:180:dwell,180:330:return,330:360:dwell"
    # the dwell after the rise vanishes at 180 deg; wider takes the previous dwell, none here
    assert stretched_phases(t["law"]["phases"], "rise", 180) == "0:180:rise,180:300:return,300:360:dwell"
    with pytest.raises(CamcadError, match="cannot be made 200 deg wide"):
        stretched_phases(t["law"]["phases"], "rise", 200)


@pytest.mark.reference("property", "values written into a copy; the scene itself untouched")
def test_values_are_written_into_a_copy_of_the_scene():
    t = default_tables()
    space = build_space(t, ["law.phases.rise=90", "follower.base_radius=41", "machine.rpm=300"])
    keys = {s.key.path: s.key for s in space.specs}
    out = apply_values(t, keys, space.values(0))
    assert out["follower"]["base_radius"] == 41 and out["machine"] == {"rpm": 300.0}
    assert out["law"]["phases"] == "0:90:rise,90:180:dwell,180:300:return,300:360:dwell"
    assert t == default_tables()   # the scene itself is untouched
    group = loom()
    space = build_space(group, ["mechanisms.shuttle_lift.law.phases.rise=40",
                                "mechanisms.shuttle_lift.contact.width=12"])
    out = apply_values(group, {s.key.path: s.key for s in space.specs}, space.values(0))
    lift = out["mechanisms"]["shuttle_lift"]
    assert lift["law"]["phases"] == "0:50:dwell,50:90:rise,90:160:dwell,160:220:return,220:360:dwell"
    assert lift["contact"]["width"] == 12 and group == loom()


# --------------------------------------------------------------------------------------------
# analysis helpers against brute force
# --------------------------------------------------------------------------------------------

def _dominated(costs: np.ndarray, i: int) -> bool:
    return bool(np.any(np.all(costs <= costs[i], axis=1) & np.any(costs < costs[i], axis=1)))


@pytest.mark.reference("second method", "the Pareto front by brute-force pairwise domination")
@pytest.mark.parametrize("k", [2, 3])
def test_pareto_front_equals_brute_force(k):
    rng = np.random.default_rng(3)
    values = np.round(rng.random((400, k)) * 20) / 2      # ties on purpose
    values[5] = values[6]                                  # an exact duplicate
    values[17, 0] = np.nan                                 # a missing figure is left out
    senses = ["min", "max", "min"][:k]
    costs = values * np.array([1 if s == "min" else -1 for s in senses])
    finite = np.isfinite(costs).all(axis=1)
    brute = [i for i in range(len(values)) if finite[i] and not _dominated(costs[finite], int(np.sum(finite[:i])))]
    # of identical rows the front keeps one: drop later duplicates from the brute-force set
    unique = []
    for i in brute:
        if not any(np.array_equal(costs[i], costs[j]) for j in unique):
            unique.append(i)
    assert pareto_front(values, senses).tolist() == unique


@pytest.mark.reference("closed form", "hand-made rows: the lexicographic best is row 3 (then 4), none when nothing is "
                                      "feasible")
def test_best_design_is_lexicographic_over_feasible_rows():
    points = {"design": np.arange(6), "feasible": np.array([False, True, True, True, True, True]),
              "r": np.array([10.0, 30.0, 20.0, 20.0, 25.0, 20.0]), "m": np.array([9.0, 0.1, 0.2, 0.5, 0.9, 0.5])}
    assert best_index(points, [Objective("min", "r"), Objective("max", "m")]) == 3   # 20 mm; 0.5; first of 3, 5
    assert best_index(points, [Objective("max", "m")]) == 4
    assert best_index({**points, "feasible": np.zeros(6, bool)}, [Objective("min", "r")]) is None


@pytest.mark.reference("property", "boundaries and objectives parsed as written; bad ones refused with the reason")
def test_boundary_and_objective_parsing():
    x = np.repeat([60.0, 90.0, 120.0], 4)
    y = np.tile([30.0, 31.0, 32.0, 33.0], 3)
    feasible = np.array([0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1], dtype=bool)
    b = feasible_boundary(x, y, feasible)
    assert [(e["least_feasible"], e["greatest_infeasible"], e["monotone"]) for e in b] == \
        [(32.0, 31.0, True), (31.0, 30.0, False), (30.0, None, True)]
    names = ["follower.base_radius", "pressure angle, rise.value", "pressure angle, rise.margin", "min_margin_ratio"]
    assert parse_objective("max:pressure angle, rise", names).column == "pressure angle, rise.margin"
    with pytest.raises(CamcadError, match=r"did you mean 'follower\.base_radius'"):
        parse_objective("min:follower.base_radis", names)
    with pytest.raises(CamcadError, match="min:COLUMN"):
        parse_objective("smallest:follower.base_radius", names)


@pytest.mark.reference("property", "tomllib reads back every sample scene as written")
def test_scene_toml_round_trips_every_sample_scene():
    from camcad.report.scene_toml import scene_toml

    for path in sorted(SCENES.glob("*.toml")):
        tables = tomllib.loads(path.read_text())
        assert tomllib.loads(scene_toml(tables, header="a header\nwith two lines")) == tables, path.name
    odd = {"name": 'quote " and \\ back\nslash', "law": {"x y": [1, 2.5, True, "s"], "inf": -math.inf}}
    assert tomllib.loads(scene_toml(odd)) == odd


@pytest.mark.reference("property", "one design: size 1, its values; no second design")
def test_a_design_space_of_one_design():
    space = DesignSpace((parse_spec(resolve_key("follower.base_radius", default_tables()), "50"),))
    assert space.size == 1 and space.values(0) == {"follower.base_radius": 50.0}
    with pytest.raises(IndexError):
        space.values(1)


@pytest.mark.reference("property", "the module's docstring examples run and print what they say")
@pytest.mark.parametrize("module", ["camcad.sweep.space", "camcad.sweep.analysis", "camcad.sweep.run",
                                    "camcad.sweep.evaluate", "camcad.report.sweep"])
def test_the_docstring_examples_run(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(module))
    assert result.failed == 0 and result.attempted > 0


@pytest.mark.reference("property", "each model's checks become columns named by the model, margins and units kept")
def test_a_model_s_own_checks_become_columns_named_by_the_model():
    # the JSON form of camcad.verdict.Check (value, limit, margin, ...) as a model's report carries it
    from camcad.sweep.evaluate import design_checks

    def check(value, limit, sense="max", unit="mm"):
        margin = limit - value if sense == "max" else value - limit
        return {"value": value, "limit": limit, "margin": margin, "margin_ratio": margin / limit, "unit": unit,
                "sense": sense, "passed": margin >= 0}

    report = {"mechanisms": {"lift": {
        "checks": {"pressure angle, rise": check(31.0, 30.0, unit="deg")},
        "impact": {"passed": False, "checks": {"first rebound": check(0.105, 0.1)}},
        "contact": {"passed": True, "sigma_max_MPa": 900.0, "allowable_MPa": 1100.0, "separation": False}}},
        "cyclogram": {"passed": True, "checks": {"makespan": check(141.0, 360.0, unit="deg")}}}
    found = {f.name: f for f in design_checks(report)}
    assert list(found) == ["lift/pressure angle, rise", "lift/impact first rebound", "lift/contact stress",
                           "lift/contact separation", "cyclogram makespan"]
    assert found["lift/impact first rebound"].margin == pytest.approx(-0.005) and not found[
        "lift/impact first rebound"].passed
    assert found["lift/contact stress"].margin == 200.0 and found["lift/contact stress"].unit == "MPa"
    assert found["cyclogram makespan"].margin_ratio == pytest.approx(219.0 / 360.0)
