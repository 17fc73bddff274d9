"""A machine of groups (camcad.cyclogram.machine, camcad.scene.machine, ``camcad machine``).

Independent references: the machine's linear programmes written here from the joined network's operations and
their least admissible angles, solved by scipy's HiGHS — minimise p(end) − p(start) (least cycle) and maximise
p(head) − p(tail) of the limiting operation within the cycle — on the sample machine and on random machines
(random groups joined by random machine operations and shared events, none of them in the repository); a
hand-worked series machine (arithmetic in the comments); the property that every group's retimed phases start
and end at the machine's event times.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camcad.cyclogram.machine import Group, make_machine, optimise_machine
from camcad.cyclogram.network import Operation, make_network
from camcad.errors import CamcadError
from camcad.scene.machine import analyse_machine
from camcad.scene.pipeline import PipelineOptions

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "scenes" / "loom_machine.toml"


def machine_lp(machine, lower: dict, goal: str):
    """The machine's LP by HiGHS: variables p(event); p(head) − p(tail) ≥ least and ≤ max per operation, each
    group's own cycle when shorter, p(end) − p(start) ≤ cycle, p(start) = start_deg. ``goal`` "least_cycle":
    minimise p(end) − p(start); "limiting": maximise the limiting operation. Returns the optimal value (deg)."""
    from scipy.optimize import linprog

    network = machine.network
    index = {e: k for k, e in enumerate(network.events)}
    n = len(index)
    rows, rhs = [], []

    def row(tail, head, sign):   # sign·(p(head) − p(tail)) ≤ rhs
        r = np.zeros(n)
        r[index[head]] += sign
        r[index[tail]] -= sign
        return r

    for op in network.operations:
        rows.append(row(op.tail, op.head, -1.0))
        rhs.append(-lower[op.label])
        if math.isfinite(op.max_deg):
            rows.append(row(op.tail, op.head, 1.0))
            rhs.append(op.max_deg)
    for group in machine.groups:
        if group.network.cycle_deg < network.cycle_deg:
            rows.append(row(machine.event_of[f"{group.name}:{group.network.start}"],
                            machine.event_of[f"{group.name}:{group.network.end}"], 1.0))
            rhs.append(group.network.cycle_deg)
    rows.append(row(network.start, network.end, 1.0))
    rhs.append(network.cycle_deg)
    bounds = [(None, None)] * n
    bounds[index[network.start]] = (network.start_deg, network.start_deg)
    objective = np.zeros(n)
    if goal == "least_cycle":
        objective[index[network.end]] = 1.0
    else:
        op = network.operation(machine.limiting)
        objective[index[op.head]], objective[index[op.tail]] = -1.0, 1.0
    options = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
    found = linprog(objective, A_ub=np.array(rows), b_ub=np.array(rhs), bounds=bounds, method="highs", options=options)
    if found.status == 2:
        return None
    assert found.status == 0, found.message
    if goal == "least_cycle":
        return float(found.x[index[network.end]] - network.start_deg)
    return float(-found.fun)


def least_angles(machine) -> dict:
    """Each operation's least admissible angle: the largest of its bound and its phase limits (deg)."""
    lower = {}
    for op in machine.network.operations:
        lower[op.label] = max([op.min_deg] + [limit.angle_deg for limit in machine.limits.get(op.label, ())])
    return lower


@pytest.fixture(scope="module")
def sample():
    least = analyse_machine(SAMPLE, PipelineOptions(plots=()), objective="least_cycle")
    return least


@pytest.mark.reference("second method", "the machine's LPs (least cycle, longest limiting operation) by scipy HiGHS")
def test_sample_machine_makespan_and_limiting_operation_equal_the_lp(sample):
    machine = sample.machine
    assert len(machine.groups) == 2
    lower = least_angles(machine)
    least = sample.result
    assert least.objective == "least_cycle" and least.feasible
    assert least.result.makespan_deg == pytest.approx(machine_lp(machine, lower, "least_cycle"), abs=1e-9)
    longest = sample.other
    assert longest.objective == "limiting" and longest.feasible
    reference = machine_lp(machine, lower, "limiting")
    assert longest.limiting_deg == pytest.approx(reference, abs=1e-9)
    assert longest.limiting_longest_deg == pytest.approx(reference, abs=1e-9)
    # the paper's objective lengthens the limiting operation by shortening the groups
    assert longest.limiting_deg > least.limiting_deg + 1.0
    assert least.limiting_deg == pytest.approx(machine.network.operation(machine.limiting).min_deg, abs=1e-9)
    # with the limiting operation at its longest the cycle is full, and the groups are at their least makespans
    assert longest.result.makespan_deg == pytest.approx(machine.network.cycle_deg, abs=1e-9)
    for name in ("group1", "group2"):
        assert longest.groups[name].makespan_deg == pytest.approx(least.groups[name].makespan_deg, abs=1e-9)


@pytest.mark.reference("property", "each group's retimed phases start and end at the machine's event times")
def test_every_group_is_regenerated_at_the_machine_phase_angles(sample):
    times = sample.result.result.event_times_deg
    group2 = sample.report["groups"]["group2"]
    assert group2["passed"]
    phases = {name: [item.split(":") for item in text.split(",")] for name, text in
              group2["cyclogram"]["phases"].items()}
    heald_rise = next(p for p in phases["heald"] if p[2] == "rise")
    # the heald crosses the shed from group2:1 (the machine's 10.2) to group2:2
    assert float(heald_rise[0]) == pytest.approx(times["10.2"], abs=1e-7)
    assert float(heald_rise[1]) == pytest.approx(times["group2:2"], abs=1e-7)
    # and its profile was made with those phases (the mechanism's report says whose phase angles)
    heald = group2["mechanisms"]["heald"]
    assert "the cyclogram's phase angles" in heald["phase_angles"]
    assert heald["retimed_by_cyclogram"] == group2["cyclogram"]["phases"]["heald"]
    lift = sample.report["groups"]["group1"]["cyclogram"]["phases"]["shuttle_lift"]
    rise = next(p.split(":") for p in lift.split(",") if p.endswith("rise"))
    assert float(rise[1]) - float(rise[0]) == pytest.approx(36.0, abs=1e-7)   # held by the source's relation


@pytest.mark.reference("closed form", "series machine: 40 + 90 + 60 = 190 deg, L = 360 - 40 - 60 = 260 deg")
def test_hand_worked_series_machine():
    a = Group("a", make_network([Operation("1", "2", 40.0)]))
    b = Group("b", make_network([Operation("1", "2", 60.0), Operation("1", "3", 20.0), Operation("3", "2", 0.0)]))
    machine = make_machine([a, b], [Operation("0", "a:1"), Operation("b:2", "end"), Operation("a:2", "b:1", 90.0,
                                                                                              name="L")],
                           limiting="L")
    least = optimise_machine(machine, "least_cycle")
    longest = optimise_machine(machine, "limiting")
    assert least.least_cycle_deg == pytest.approx(190.0, abs=1e-12)
    assert longest.limiting_deg == pytest.approx(260.0, abs=1e-12)
    # b's 1->3 is off the critical path: it keeps a margin (1->3 and 3->2 share b's 60 deg: 1->3 = 60)
    assert longest.groups["b"].phase_angles_deg["1->3"] == pytest.approx(60.0, abs=1e-9)
    assert "1->3" not in longest.groups["b"].critical_operations
    # shared events: a's end is b's start, the limiting operation runs beside the groups
    parallel = make_machine([a, b], [Operation("0", "a:1"), Operation("0", "x"), Operation("x", "y", 30.0, name="L"),
                                     Operation("y", "end"), Operation("b:2", "end")], [["a:2", "b:1"]],
                            limiting="L", cycle_deg=150.0)
    found = optimise_machine(parallel, "limiting")
    assert found.least_cycle_deg == pytest.approx(100.0, abs=1e-12)     # a then b: 40 + 60
    assert found.limiting_deg == pytest.approx(150.0, abs=1e-12)        # beside them, the whole cycle


@st.composite
def random_machines(draw):
    """2–3 random groups (DAGs with bounds) and machine operations joining them in series or in parallel, some
    group events shared with machine events."""
    groups = []
    for g in range(draw(st.integers(2, 3))):
        n = draw(st.integers(2, 6))
        arcs = set()
        for j in range(1, n):
            arcs.add((draw(st.integers(0, j - 1)), j))
        for i in range(n - 1):
            arcs.add((i, draw(st.integers(i + 1, n - 1))))
        ops = []
        for i, j in sorted(arcs):
            low = draw(st.sampled_from([0.0, 5.0, 10.0, 25.0]))
            high = draw(st.sampled_from([math.inf, math.inf, low + 20.0]))
            ops.append(Operation(str(i), str(j), low, high))
        groups.append(Group(f"g{g}", make_network(ops)))
    ends = [(f"{g.name}:{g.network.start}", f"{g.name}:{g.network.end}") for g in groups]
    links = [Operation("S", ends[0][0], draw(st.sampled_from([0.0, 5.0])))]
    shared = []
    for k in range(1, len(groups)):
        if draw(st.booleans()):      # in series through a shared event
            shared.append([ends[k - 1][1], ends[k][0]])
        else:                        # from the machine's start, in parallel
            links.append(Operation("S", ends[k][0], draw(st.sampled_from([0.0, 10.0]))))
            links.append(Operation(ends[k - 1][1], "E", 0.0))
    links.append(Operation(ends[-1][1], "E", 0.0))
    links.append(Operation("S", "L0", 0.0))
    links.append(Operation("L0", "L1", draw(st.sampled_from([10.0, 40.0])), name="L"))
    anchor = draw(st.integers(0, len(groups) - 1))
    links.append(Operation("L1", ends[anchor][0], 0.0))
    return make_machine(groups, links, shared, cycle_deg=draw(st.sampled_from([200.0, 360.0])), limiting="L")


@pytest.mark.reference("second method", "random machines: the LPs by scipy HiGHS")
@settings(max_examples=40, deadline=None)
@given(random_machines())
def test_random_machines_equal_the_lp(machine):
    lower = least_angles(machine)
    reference = machine_lp(machine, lower, "least_cycle")
    least = optimise_machine(machine, "least_cycle")
    assert least.feasible == (reference is not None)
    if reference is None:
        assert least.result.conflict
        return
    assert least.result.makespan_deg == pytest.approx(reference, abs=1e-9)
    longest = optimise_machine(machine, "limiting")
    assert longest.limiting_deg == pytest.approx(machine_lp(machine, lower, "limiting"), abs=1e-9)
    assert longest.limiting_deg >= least.limiting_deg - 1e-9
    # every group's schedule read off the machine keeps its own bounds
    for name, found in longest.groups.items():
        for op in machine.group(name).network.operations:
            assert op.min_deg - 1e-9 <= found.phase_angles_deg[op.label] <= op.max_deg + 1e-9


# ---------------------------------------------------------------- bad input

def _machine_text(tmp_path, network: str, extra: str = "", objective: str = "least_cycle") -> Path:
    group = tmp_path / "g.toml"
    group.write_text((ROOT / "samples" / "scenes" / "loom_group1.toml").read_text())
    path = tmp_path / "m.toml"
    path.write_text(f'name = "m"\n[machine]\nrpm = [280.0, 420.0]\nobjective = "{objective}"\n{extra}\n'
                    f'[groups.a]\nscene = "g.toml"\n[network]\n{network}')
    return path


GOOD_NETWORK = ('[[network.operations]]\nfrom = "s"\nto = "a:1"\nbounds_deg = [0.0, inf]\n'
                '[[network.operations]]\nfrom = "a:8"\nto = "e"\nbounds_deg = [10.0, inf]\nname = "L"\n')


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("network, extra, pattern", [
    (GOOD_NETWORK.replace('"a:1"', '"b:1"'), "", "names unknown group 'b'"),
    (GOOD_NETWORK.replace('"a:1"', '"a:11"'), "", "group 'a' has no event '11'"),
    (GOOD_NETWORK, 'limiting = "X"', "the limiting operation 'X' is not one of the machine's operations"),
    ('shared = [["a:1", "a:8"]]\n' + GOOD_NETWORK, "", "the operations form a cycle"),
    ('shared = [["a:1", "s", "e"]]\n' + GOOD_NETWORK, "", "joins two machine events"),
    ("", "", "missing value 'operations'"),
    (GOOD_NETWORK.replace("[0.0, inf]", "[5.0, 1.0]"), "", "must have 0 <= min <= max"),
])
def test_bad_machine_scenes_are_one_line_errors(tmp_path, network, extra, pattern):
    path = _machine_text(tmp_path, network, extra)
    with pytest.raises(CamcadError, match=pattern):
        analyse_machine(path, PipelineOptions(plots=()))


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_machine_without_limiting_operation_refuses_the_limiting_objective(tmp_path):
    path = _machine_text(tmp_path, GOOD_NETWORK, objective="limiting")
    with pytest.raises(CamcadError, match="needs a limiting operation"):
        analyse_machine(path, PipelineOptions(plots=()))


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_group_both_file_and_inline_is_refused(tmp_path):
    path = _machine_text(tmp_path, GOOD_NETWORK)
    path.write_text(path.read_text().replace('scene = "g.toml"', 'scene = "g.toml"\n[groups.a.cyclogram]\nx = 1'))
    with pytest.raises(CamcadError, match="either a scene file or inline"):
        analyse_machine(path, PipelineOptions(plots=()))


@pytest.mark.reference("property", "the limiting objective gives the limiting operation more than least-cycle does; "
                                   "infeasible: exit 1; bad: exit 2")
def test_cli_machine_json_outputs_and_exit_codes(tmp_path, cli):
    done = cli("machine", SAMPLE, "--json", "-o", tmp_path / "out", "--no-plots")
    assert done.code == 0, done.err
    payload = done.json()
    machine = payload["machine"]
    for key in ("makespan_deg", "event_times_deg", "phase_angles_deg", "critical_path", "active_bounds", "feasible",
                "objective", "limiting", "least_cycle_deg", "groups"):
        assert key in machine
    assert machine["objective"] == "limiting"
    assert payload["objectives"]["limiting"]["limiting_deg"] > payload["objectives"]["least_cycle"]["limiting_deg"]
    assert (tmp_path / "out" / "machine.json").stat().st_size > 0
    assert (tmp_path / "out" / "group2" / "heald" / "profile.dxf").stat().st_size > 0
    assert json.loads((tmp_path / "out" / "machine.json").read_text())["machine"]["makespan_deg"] == \
        machine["makespan_deg"]
    # a machine whose insertion cannot fit: exit 1 with the conflict named
    tight = tmp_path / "tight.toml"
    text = SAMPLE.read_text().replace("bounds_deg = [60.0, inf]", "bounds_deg = [200.0, inf]")
    tight.write_text(text.replace('scene = "loom_group1.toml"', f'scene = "{SAMPLE.parent / "loom_group1.toml"}"'))
    done = cli("machine", tight, "--json", "-o", tmp_path / "tight", "--no-plots")
    assert done.code == 1
    assert done.json()["machine"]["feasible"] is False and "overrun" in done.json()["machine"]["explanation"]
    # bad input: exit 2, one line
    done = cli("machine", tmp_path / "missing.toml")
    assert done.code == 2 and len(done.err.strip().splitlines()) == 1 and "no such scene file" in done.err
