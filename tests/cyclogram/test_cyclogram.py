"""Cyclogram network, LP optimisation, conflicts, phase-angle limits and phase feedback.

Independent references: a longest-path dynamic programme over a topological order written here
(for precedence-only networks, the optimum must equal it), the source's linear programme solved by
scipy's HiGHS (``lp_reference``, written here: optimise() finds the same schedule by longest paths),
hand-worked networks (comments give
the arithmetic), and the source's linear rebound relation a = −0.003 t + 0.208 (Podgorny et al.
2018), whose limit a ≤ 0.1 mm gives t ≥ (0.208 − 0.1)/0.003 = 36 deg in closed form.
"""

from __future__ import annotations

import json
import math
import tomllib
from itertools import pairwise
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camcad.cyclogram.conflicts import find_conflict
from camcad.cyclogram.constraints import constraints_of
from camcad.cyclogram.limits import LinearRelation, PhaseLimit, least_phase_angle, vibration_limits
from camcad.cyclogram.lp import optimise
from camcad.cyclogram.network import Operation, make_network
from camcad.cyclogram.retime import format_phases, operation_timing, retime_phases, stretch_phase
from camcad.errors import CamcadError
from camcad.scene.sections.cyclogram import parse_cyclogram

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "scenes" / "loom_group1.toml"


# ---------------------------------------------------------------- hand-made network

def hand_network(cycle_deg: float = 360.0):
    # S -> X (>= 10), X -> E (>= 10), S -> Y (>= 40), Y -> E (>= 0), X -> Y in [0, 5].
    # Y >= 40 and Y <= X + 5 force X >= 35, so E >= X + 10 = 45: makespan 45 along
    # S -> Y (lower bound) , Y -> X (upper bound of X->Y, stepping back), X -> E (lower bound).
    # The path S -> X -> E alone would give 20, S -> Y -> E 40.
    ops = [Operation("S", "X", 10), Operation("X", "E", 10), Operation("S", "Y", 40),
           Operation("Y", "E", 0), Operation("X", "Y", 0, 5)]
    return make_network(ops, cycle_deg=cycle_deg)


@pytest.mark.reference("closed form", "the hand-made network's earliest schedule worked by hand: makespan 45 deg, "
                                      "path S-Y-X-E")
def test_active_bounds_on_a_hand_made_case():
    result = optimise(hand_network())
    assert result.feasible
    assert result.makespan_deg == pytest.approx(45.0, abs=1e-9)
    expected_times = {"S": 0.0, "X": 35.0, "Y": 40.0, "E": 45.0}     # earliest schedule
    for event, time in expected_times.items():
        assert result.event_times_deg[event] == pytest.approx(time, abs=1e-9)
    assert result.phase_angles_deg["S->X"] == pytest.approx(35.0, abs=1e-9)   # slack on S->X
    assert list(result.critical_path) == ["S", "Y", "X", "E"]
    assert {(c.label, c.kind) for c in result.active} == {("S->Y", "min"), ("X->Y", "max"), ("X->E", "min")}
    assert sorted(result.active_bounds) == ["S->Y", "X->E", "X->Y"]
    report = result.report()
    for key in ("makespan_deg", "event_times_deg", "phase_angles_deg", "critical_path", "active_bounds",
                "feasible"):
        assert key in report
    json.dumps(report)


@pytest.mark.reference("closed form", "a 42 deg limit on S->Y lifts the makespan to 42 - 5 + 10 = 47 deg")
def test_phase_limit_raises_a_lower_bound_and_becomes_the_active_one():
    # a vibration limit of 42 deg on S->Y lifts the makespan to 42 − 5 + 10 = 47
    limit = PhaseLimit(42.0, 0.1, 0.1, True, "vibration")
    result = optimise(hand_network(), {"S->Y": [limit]})
    assert result.makespan_deg == pytest.approx(47.0, abs=1e-9)
    assert any(c.label == "S->Y" and c.source == "vibration" for c in result.active)
    # a limit below the designer's bound changes nothing
    low = PhaseLimit(30.0, 0.1, 0.1, True, "vibration")
    assert optimise(hand_network(), {"S->Y": [low]}).makespan_deg == pytest.approx(45.0, abs=1e-9)


# ---------------------------------------------------------------- infeasible and cyclic networks

@pytest.mark.reference("closed form", "with the cycle capped at 40 deg the conflict is S->Y >= 40, X->Y <= 5, X->E >= "
                                      "10, excess 5 deg")
def test_infeasible_network_names_its_conflicting_constraints():
    # with the cycle capped at 40 deg the 45-deg path cannot fit: the conflict is exactly
    # S->Y >= 40, X->Y <= 5, X->E >= 10 and makespan <= 40 (excess 40 − 5 + 10 − 40 = 5 deg)
    network = hand_network(cycle_deg=40.0)
    result = optimise(network, strict=False)
    assert not result.feasible
    assert {(c.label, c.kind) for c in result.conflict} == {
        ("S->Y", "min"), ("X->Y", "max"), ("X->E", "min"), ("makespan", "cycle")}
    assert sum(c.weight for c in result.conflict) == pytest.approx(5.0)
    with pytest.raises(CamcadError) as err:
        optimise(network)
    message = err.value.message()
    for text in ("t(S->Y) >= 40", "t(X->Y) <= 5", "t(X->E) >= 10", "makespan", "by at least 5 deg"):
        assert text in message
    assert "\n" not in message


@pytest.mark.reference("closed form", "the two conflicts of the hand-made network, the smaller one (two constraints) "
                                      "reported")
def test_smallest_conflict_is_found():
    # two conflicts: a phase limit of 8 deg on X->Y against its upper bound 5 (two constraints),
    # and the long one through the cycle cap of 40 deg (four). The smallest is reported.
    limit = PhaseLimit(8.0, 0.5, 0.4, True, "contact")
    result = optimise(hand_network(cycle_deg=40.0), {"X->Y": [limit]}, strict=False)
    assert {(c.label, c.kind, c.source) for c in result.conflict} == {
        ("X->Y", "min", "contact"), ("X->Y", "max", "bounds_deg")}
    # the Bellman–Ford fallback (for large networks) finds some positive simple cycle
    constraints = constraints_of(hand_network(cycle_deg=40.0), {"X->Y": [limit]})
    cycle = find_conflict(["S", "X", "Y", "E"], constraints, dense_limit=0)
    assert cycle and sum(c.weight for c in cycle) > 0
    assert all(a.head == b.tail for a, b in zip(cycle, cycle[1:] + cycle[:1]))   # closed


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_cyclic_network_is_rejected_with_the_cycle_named():
    ops = [Operation("1", "2", 10), Operation("2", "3", 10), Operation("3", "4", 5), Operation("4", "2", 5),
           Operation("3", "5", 1)]
    with pytest.raises(CamcadError, match=r"the operations form a cycle: 2 -> 3 -> 4 -> 2"):
        make_network(ops)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("ops, pattern", [
    ([Operation("1", "2"), Operation("1", "2", 5)], "two operations join 1 to 2"),
    ([Operation("1", "1")], "same event"),
    ([Operation("1", "2", 30, 20)], "min > max"),
    ([Operation("1", "3"), Operation("2", "3")], "2 first events"),
    ([Operation("1", "2"), Operation("1", "3")], "2 last events"),
])
def test_malformed_networks(ops, pattern):
    with pytest.raises(CamcadError, match=pattern):
        make_network(ops)


# ---------------------------------------------------------------- LP = longest path (property)

@st.composite
def precedence_networks(draw):
    """A random DAG on events 0..n−1 (arcs i < j), every event on a path from 0 to n−1."""
    n = draw(st.integers(2, 11))
    arcs = {}
    for j in range(1, n):   # at least one predecessor each
        i = draw(st.integers(0, j - 1))
        arcs[(i, j)] = None
    for i in range(n - 1):  # at least one successor each
        j = draw(st.integers(i + 1, n - 1))
        arcs[(i, j)] = None
    extra = draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=2 * n))
    for i, j in extra:
        if i < j:
            arcs[(i, j)] = None
    return n, {arc: draw(st.floats(0.0, 100.0, allow_nan=False)) for arc in arcs}


def dp_longest_path(n, weights):
    # events are numbered in topological order (arcs i < j): one forward sweep
    earliest = [0.0] + [-math.inf] * (n - 1)
    for j in range(1, n):
        earliest[j] = max(earliest[i] + w for (i, jj), w in weights.items() if jj == j)
    return earliest


@pytest.mark.reference("second method", "a longest-path dynamic programme over a topological order written here")
@settings(max_examples=60, deadline=None)
@given(precedence_networks())
def test_lp_equals_longest_path_on_precedence_networks(case):
    n, weights = case
    ops = [Operation(str(i), str(j), w) for (i, j), w in weights.items()]
    network = make_network(ops, cycle_deg=1e6)
    result = optimise(network)
    earliest = dp_longest_path(n, weights)
    assert result.makespan_deg == pytest.approx(earliest[-1], rel=1e-9, abs=1e-9)
    for k in range(n):
        assert result.event_times_deg[str(k)] == pytest.approx(earliest[k], rel=1e-9, abs=1e-9)
    # the critical path is a chain of operations whose lower bounds add up to the makespan, each
    # tight to optimise()'s tight_tol_deg = 1e-6 deg
    path = result.critical_path
    assert path[0] == "0" and path[-1] == str(n - 1)
    total = sum(weights[(int(a), int(b))] for a, b in pairwise(path))
    assert total == pytest.approx(earliest[-1], rel=1e-9, abs=1e-6 * len(path))


def lp_reference(network):
    """The source's LP (minimise p(end) − p(start) s.t. p(head) − p(tail) ≥ weight), then the earliest
    schedule with that makespan (minimise Σ p), by scipy's HiGHS: event times, or None when infeasible."""
    import numpy as np
    from scipy.optimize import linprog

    constraints = constraints_of(network)
    index = {event: k for k, event in enumerate(network.events)}
    n = len(index)
    a_ub = np.zeros((len(constraints), n))
    for row, c in enumerate(constraints):    # p(tail) − p(head) ≤ −weight
        a_ub[row, index[c.tail]] += 1.0
        a_ub[row, index[c.head]] -= 1.0
    b_ub = np.array([-c.weight for c in constraints])
    bounds = [(None, None)] * n
    bounds[index[network.start]] = (network.start_deg, network.start_deg)
    options = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
    goal = np.zeros(n)
    goal[index[network.end]] = 1.0
    first = linprog(goal, A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs", options=options)
    if first.status == 2:
        return None
    assert first.status == 0, first.message
    bounds[index[network.end]] = (None, first.x[index[network.end]] + 1e-9)
    second = linprog(np.ones(n), A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs", options=options)
    assert second.status == 0, second.message
    return {event: float(second.x[index[event]]) for event in network.events}


@pytest.mark.reference("second method", "scipy's linprog on the same constraints: the earliest schedule, infeasible "
                                        "exactly when it is")
@settings(max_examples=60, deadline=None)
@given(precedence_networks(), st.data())
def test_longest_paths_agree_with_the_lp_with_upper_bounds(case, data):
    # with upper bounds the constraint graph has backward arcs; optimise() (longest paths) must give the
    # LP's earliest schedule, and be infeasible exactly when the LP is
    _n, weights = case
    ops = []
    for (i, j), w in weights.items():
        upper = data.draw(st.one_of(st.just(math.inf), st.floats(w, w + 80.0)))
        ops.append(Operation(str(i), str(j), w, upper))
    network = make_network(ops, cycle_deg=1e6)
    reference = lp_reference(network)
    result = optimise(network, strict=False)
    assert result.feasible == (reference is not None)
    if reference is None:
        # the conflict (fewest constraints) and the Bellman–Ford fallback's: closed positive cycles
        for conflict in (result.conflict, find_conflict(network.events, constraints_of(network), dense_limit=0)):
            assert sum(c.weight for c in conflict) > 0
            assert all(a.head == b.tail for a, b in zip(conflict, conflict[1:] + conflict[:1]))
        assert len(result.conflict) <= len(find_conflict(network.events, constraints_of(network), dense_limit=0))
        return
    for event, time in reference.items():
        assert result.event_times_deg[event] == pytest.approx(time, rel=1e-9, abs=1e-7)


# ---------------------------------------------------------------- phase-angle limits

@pytest.mark.reference("published", "Podgorny et al. 2018: a(3,7) = -0.003 t + 0.208 mm <= 0.1 mm gives t >= 36 deg "
                                    "(closed form)")
def test_vibration_limit_from_the_source_relation():
    # a(3,7) = −0.003 t + 0.208 mm ≤ 0.1 mm  ⇔  t ≥ 36 deg (closed form)
    relation = LinearRelation(-0.003, 0.208)
    limit = least_phase_angle(relation, 0.1, 10.0, 60.0, source="vibration")
    assert limit.angle_deg == pytest.approx(36.0, abs=1e-9)
    assert relation.solve(0.1) == pytest.approx(36.0, abs=1e-12)
    assert limit.binding and limit.evaluations < 10
    with pytest.raises(CamcadError, match="even the longest phase angle 30 deg"):
        least_phase_angle(relation, 0.1, 10.0, 30.0, source="vibration")
    ops = [Operation("1", "2", 20, 80, amplitude=relation, amplitude_limit_mm=0.1)]
    limits = vibration_limits(make_network(ops))
    assert limits["1->2"][0].angle_deg == pytest.approx(36.0, abs=1e-9)


# ---------------------------------------------------------------- TOML section

def section(text: str) -> dict:
    return tomllib.loads(text)["cyclogram"]


GOOD = """
[cyclogram]
cycle_deg = 360.0
[[cyclogram.operations]]
from = 1
to = 2
bounds_deg = [20.0, 60.0]
mechanism = "lift"
phase = "rise"
[[cyclogram.operations]]
from = 2
to = 3
bounds_deg = [10.0, inf]
amplitude_limit_mm = 0.1
amplitude_slope_mm_per_deg = -0.003
amplitude_intercept_mm = 0.208
"""


@pytest.mark.reference("closed form", "the section's network: makespan 20 + 36 = 56 deg")
def test_parse_cyclogram_reads_a_section():
    network = parse_cyclogram(section(GOOD), "g.toml [cyclogram]", mechanisms=["lift"])
    assert network.start == "1" and network.end == "3"
    assert network.operation("1->2").phase == "rise"
    result = optimise(network, vibration_limits(network))
    assert result.makespan_deg == pytest.approx(56.0, abs=1e-9)     # 20 + 36


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("edit, pattern", [
    (lambda t: t.replace("bounds_deg = [20.0, 60.0]", "bound_deg = [20.0, 60.0]"), "did you mean 'bounds_deg'"),
    (lambda t: t.replace("bounds_deg = [20.0, 60.0]", "bounds_deg = [60.0, 20.0]"), "min > max"),
    (lambda t: t.replace("bounds_deg = [20.0, 60.0]", "bounds_deg = [20.0]"), r"\[min, max\]"),
    (lambda t: t.replace("bounds_deg = [20.0, 60.0]", ""), "missing value 'bounds_deg'"),
    (lambda t: t.replace('mechanism = "lift"', 'mechanism = "lfit"'), "did you mean 'lift'"),
    (lambda t: t.replace("amplitude_intercept_mm = 0.208", ""), "needs amplitude_limit_mm"),
    (lambda t: t.replace("cycle_deg = 360.0", "cycle_deg = \"360\""), "must be a number"),
    (lambda t: t.replace("to = 3", "to = 1"), "cycle: 1 -> 2 -> 1"),
    (lambda t: t.replace("cycle_deg = 360.0", "events = [1, 2, 4]"), "names event '3', which is not in events"),
    (lambda t: t.replace("cycle_deg = 360.0", "start = 2"), "event '1' does not follow the first event '2'"),
])
def test_parse_cyclogram_errors(edit, pattern):
    with pytest.raises(CamcadError, match=pattern) as err:
        parse_cyclogram(section(edit(GOOD)), "g.toml [cyclogram]", mechanisms=["lift"])
    assert "g.toml [cyclogram]" in err.value.message()


# ---------------------------------------------------------------- feeding angles back

@pytest.mark.reference("closed form", "phases retimed by hand: a rise stretched to 120 deg takes 30 deg from the next "
                                      "dwell")
def test_retime_and_stretch_phases():
    phases = [(0, 90, "dwell"), (90, 180, "rise"), (180, 270, "dwell"), (270, 360, "return")]
    # the cyclogram starts the rise at 40 deg for 50 deg and the return at 200 deg for 60 deg
    new = retime_phases(phases, {("rise", 1): (40.0, 50.0), ("return", 1): (200.0, 60.0)})
    assert new == [(0.0, 40.0, "dwell"), (40.0, 90.0, "rise"), (90.0, 200.0, "dwell"),
                   (200.0, 260.0, "return"), (260.0, 360.0, "dwell")]
    assert format_phases(new) == "0:40:dwell,40:90:rise,90:200:dwell,200:260:return,260:360:dwell"
    with pytest.raises(CamcadError, match="overlap"):
        retime_phases(phases, {("rise", 1): (250.0, 50.0)})
    with pytest.raises(CamcadError, match="no return number 2"):
        retime_phases(phases, {("return", 2): (10.0, 5.0)})
    with pytest.raises(CamcadError, match="across the cycle"):
        retime_phases(phases, {("return", 1): (330.0, 60.0)})
    # stretching the rise to 120 deg takes 30 deg from the following dwell
    assert stretch_phase(phases, 1, 120.0) == [(0, 90, "dwell"), (90, 210, "rise"), (210, 270, "dwell"),
                                               (270, 360, "return")]
    with pytest.raises(CamcadError, match="no neighbouring dwell"):
        stretch_phase(phases, 1, 300.0)


@pytest.mark.reference("closed form", "the operation's start and angle (0, 20 deg) from the schedule")
def test_operation_timing_feeds_the_mechanisms():
    network = parse_cyclogram(section(GOOD), "g", mechanisms=["lift"])
    result = optimise(network, vibration_limits(network))
    assert operation_timing(result) == {"lift": {("rise", 1): (pytest.approx(0.0), pytest.approx(20.0))}}


# ---------------------------------------------------------------- the sample group scene

@pytest.mark.reference("published", "Podgorny et al. 2018: the shuttle lift's operation 3->7 limited to t >= 36 deg "
                                    "by its vibration relation")
def test_sample_scene_has_a_limiting_operation():
    scene = tomllib.loads(SAMPLE.read_text())
    network = parse_cyclogram(scene["cyclogram"], "loom_group1.toml [cyclogram]",
                              mechanisms=list(scene["mechanisms"]))
    limits = vibration_limits(network)
    # the shuttle lift's operation 3->7 carries the source's rebound relation: t ≥ 36 deg
    assert limits["3->7"][0].angle_deg == pytest.approx(36.0, abs=1e-9)
    result = optimise(network, limits)
    assert any(c.label == "3->7" and c.source == "vibration" for c in result.active)
    assert result.phase_angles_deg["3->7"] == pytest.approx(36.0, abs=1e-7)


@pytest.mark.reference("property", "each phase angle is the difference of its event times; the contact-stress limit "
                                   "reaches [sigma_H] = 1100 MPa")
def test_cli_cyclogram_on_the_sample(tmp_path, cli):
    done = cli("cyclogram", SAMPLE, "--json", "-o", tmp_path)
    assert done.code == 0, done.err
    payload = done.json()["cyclogram"]
    for key in ("makespan_deg", "event_times_deg", "phase_angles_deg", "critical_path", "active_bounds",
                "feasible"):
        assert key in payload
    assert payload["feasible"] and "3->7" in payload["active_bounds"]
    for name in ("cyclogram.json", "cyclogram.png", "network.png"):
        assert (tmp_path / name).stat().st_size > 0
    saved = json.loads((tmp_path / "cyclogram.json").read_text())
    assert saved["cyclogram"]["makespan_deg"] == payload["makespan_deg"]
    # every operation's phase angle is the difference of its event times (both rounded to 10 digits in JSON)
    times = payload["event_times_deg"]
    for label, angle in payload["phase_angles_deg"].items():
        tail, head = label.split("->")
        assert angle == pytest.approx(times[head] - times[tail], abs=1e-7)
    # the contact-stress limit of the returner spring opener's rise (7->5) is on the critical path:
    # its angle is where σ_max reaches [σ_H] = 1100 MPa
    assert {"operation": "7->5", "kind": "min", "source": "contact",
            "bound_deg": pytest.approx(payload["phase_angles_deg"]["7->5"], abs=1e-7)} in payload["active"]
    limit = next(entry for entry in payload["phase_limits"]["7->5"] if entry["source"] == "contact")
    assert limit["value"] == pytest.approx(1100.0, rel=1e-6)
    # the phases fed back to each mechanism's law are the cyclogram's: the shuttle lift rises from
    # event 3 to event 7, the weft returner returns from event 6 to event 8
    phases = {name: [tuple(item.split(":")) for item in text.split(",")]
              for name, text in payload["phases"].items()}
    rise = next((float(a), float(b)) for a, b, kind in phases["shuttle_lift"] if kind == "rise")
    assert rise == (pytest.approx(times["3"], abs=1e-7), pytest.approx(times["7"], abs=1e-7))
    back = next((float(a), float(b)) for a, b, kind in phases["weft_returner"] if kind == "return")
    assert back == (pytest.approx(times["6"], abs=1e-7), pytest.approx(times["8"], abs=1e-7))


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_cli_cyclogram_bad_scene(tmp_path, cli):
    plain = GOOD.replace('mechanism = "lift"\nphase = "rise"\n', "")
    for text, pattern in ((plain.replace("to = 3", "to = 1"), "cycle: 1 -> 2 -> 1"),
                          (GOOD, "unknown mechanism 'lift'; add [mechanisms.lift]"),
                          (plain.replace("[[cyclogram.operations]]", "[[cyclogram.operation]]", 1),
                           "did you mean 'operations'"),
                          (plain + "\n[oops", "not valid TOML")):
        scene = tmp_path / "bad.toml"
        scene.write_text(text)
        done = cli("cyclogram", scene, "--json")
        assert done.code == 2 and done.out == "", done.err
        assert done.err.startswith("camcad: error:") and pattern in done.err
        assert len(done.err.strip().splitlines()) == 1


@pytest.mark.reference("closed form", "the cycle is short by 20 + 36 - 50 = 6 deg: exit 1 naming it")
def test_cli_cyclogram_infeasible_exits_1(tmp_path, cli):
    scene = tmp_path / "tight.toml"
    scene.write_text(GOOD.replace('mechanism = "lift"\nphase = "rise"\n', "").replace("cycle_deg = 360.0",
                                                                                         "cycle_deg = 50.0"))
    done = cli("cyclogram", scene, "--json", "-o", tmp_path / "out")
    assert done.code == 1
    payload = done.json()["cyclogram"]
    assert payload["feasible"] is False and "by 6 deg" in payload["explanation"]   # 20 + 36 − 50
