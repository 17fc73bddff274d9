"""Where the slack of a least-makespan cyclogram goes (camcad.cyclogram.slack), and checks at their limit.

Independent references: the max–min rule written here as a sequence of linear programmes solved by scipy's
HiGHS (``leximin_reference``: critical operations by maximising each phase angle alone, then round by round
"maximise z with every free operation at least [φ](1 + z)", an operation held when an LP cannot lengthen it
past [φ](1 + z)); hand-worked networks (the arithmetic in comments); the property that the makespan does
not change.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camcad.cyclogram.constraints import constraints_of
from camcad.cyclogram.lp import optimise
from camcad.cyclogram.network import Operation, make_network
from camcad.verdict import AT_LIMIT, Check

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "scenes" / "loom_group1.toml"


def _lp(network, extra_rows, goal, n_extra=0, bounds_extra=()):
    """min goal·x over x = (p events…, extra variables) with the network's constraints (makespan ≤ the
    cycle constraint as given) and ``extra_rows`` (a_row, b) meaning a_row·x ≤ b."""
    from scipy.optimize import linprog

    index = {event: k for k, event in enumerate(network.events)}
    n = len(index) + n_extra
    rows, rhs = [], []
    for c in constraints_of(network):     # p(tail) − p(head) ≤ −weight
        row = np.zeros(n)
        row[index[c.tail]] += 1.0
        row[index[c.head]] -= 1.0
        rows.append(row)
        rhs.append(-c.weight)
    for row, b in extra_rows:
        rows.append(row)
        rhs.append(b)
    bounds = [(None, None)] * n
    bounds[index[network.start]] = (network.start_deg, network.start_deg)
    for k, bound in bounds_extra:
        bounds[k] = bound
    options = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
    found = linprog(goal, A_ub=np.array(rows), b_ub=np.array(rhs), bounds=bounds, method="highs", options=options)
    assert found.status == 0, found.message
    return found


def leximin_reference(network):
    """{label: relative margin} by the max–min rule, every step an LP (scipy HiGHS); and the least makespan."""
    index = {event: k for k, event in enumerate(network.events)}
    n = len(index)
    goal = np.zeros(n)
    goal[index[network.end]] = 1.0
    makespan = _lp(network, [], goal).fun - network.start_deg
    cap = np.zeros(n)
    cap[index[network.end]], cap[index[network.start]] = 1.0, -1.0
    hold = [(cap, makespan + 1e-7)]   # the LP's own makespan, its round-off allowed
    ops = {op.label: op for op in network.operations if op.min_deg > 0}

    def row(op, n_all, z_column=None, z_factor=0.0):
        # p(tail) − p(head) + [φ] z ≤ −[φ]  ⇔  t ≥ [φ](1 + z)
        r = np.zeros(n_all)
        r[index[op.tail]], r[index[op.head]] = 1.0, -1.0
        if z_column is not None:
            r[z_column] = z_factor
        return r

    def longest(op, rows):
        goal = np.zeros(n)
        goal[index[op.head]], goal[index[op.tail]] = -1.0, 1.0
        return -_lp(network, rows, goal).fun

    free = [label for label, op in ops.items() if longest(op, hold) > op.min_deg * (1 + 1e-9) + 1e-8]
    margins = {label: 0.0 for label in ops}
    held: dict[str, float] = {}
    while free:
        rows = [(np.append(r, 0.0), b) for r, b in hold]
        # a margin held at the z an earlier LP found carries that LP's round-off: held 1e-7 deg looser, so the next
        # LP is not made infeasible by it (the margins are compared to 1e-6)
        rows += [(row(ops[label], n + 1), -ops[label].min_deg * (1 + z) + 1e-7) for label, z in held.items()]
        rows += [(row(ops[label], n + 1, n, ops[label].min_deg), -ops[label].min_deg) for label in free]
        goal = np.zeros(n + 1)
        goal[n] = -1.0
        z = -_lp(network, rows, goal, n_extra=1, bounds_extra=((n, (0.0, None)),)).fun
        fixed_rows = [(r[:n], b) for r, b in rows if r[n] == 0.0]
        pinned = []
        for label in free:
            others = fixed_rows + [(row(ops[k], n), -ops[k].min_deg * (1 + z) + 1e-7) for k in free if k != label]
            if longest(ops[label], others) <= ops[label].min_deg * (1 + z) + 1e-6:
                pinned.append(label)
        assert pinned
        for label in pinned:
            held[label] = margins[label] = z
        free = [label for label in free if label not in held]
    return margins, makespan


@st.composite
def networks(draw):
    """A random DAG on events 0..n−1 (arcs i < j), each event on a path from 0 to n−1, with lower bounds and
    some upper bounds."""
    n = draw(st.integers(3, 9))
    arcs = set()
    for j in range(1, n):
        arcs.add((draw(st.integers(0, j - 1)), j))
    for i in range(n - 1):
        arcs.add((i, draw(st.integers(i + 1, n - 1))))
    for i, j in draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=2 * n)):
        if i < j:
            arcs.add((i, j))
    ops = []
    for i, j in sorted(arcs):
        low = draw(st.sampled_from([0.0, 5.0, 10.0, 20.0, 35.0, 50.0]))
        high = draw(st.sampled_from([math.inf, math.inf, low + 15.0, low + 40.0]))
        ops.append(Operation(str(i), str(j), low, high))
    return make_network(ops, cycle_deg=1e5)


@pytest.mark.reference("second method", "the max-min rule as a sequence of LPs solved by scipy HiGHS")
@settings(max_examples=40, deadline=None)
@given(networks())
def test_leximin_margins_equal_the_lp_reference(network):
    earliest = optimise(network, strict=False)
    if not earliest.feasible:
        return
    result = optimise(network, schedule="leximin")
    margins, makespan = leximin_reference(network)
    # the makespan does not change, and it is the LP's
    assert result.makespan_deg == pytest.approx(earliest.makespan_deg, abs=1e-9)
    assert result.makespan_deg == pytest.approx(makespan, abs=1e-7)
    assert set(result.margins) == set(margins)
    for label, margin in margins.items():
        assert result.margins[label] == pytest.approx(margin, abs=1e-6), label
        op = network.operation(label)
        assert result.phase_angles_deg[label] >= op.min_deg * (1 + margin) - 1e-6   # the margins hold to 1e-6
    # every constraint holds in the spread schedule; every non-critical operation has a positive margin
    for op in network.operations:
        assert op.min_deg - 1e-9 <= result.phase_angles_deg[op.label] <= op.max_deg + 1e-9
    for label in result.margins:
        if label not in result.critical_operations:
            assert result.margins[label] > 0.0
            assert result.phase_angles_deg[label] > network.operation(label).min_deg


@pytest.mark.reference("closed form", "hand-worked network: 75 (1 + z) = 100 gives z = 1/3")
def test_leximin_on_a_hand_worked_network():
    # a→b ≥ 30, b→c in [45, 60], a→c ≥ 100: the makespan is 100 (a→c alone, critical). a→b and b→c share the
    # 100 deg: 30 (1 + z) + 45 (1 + z) = 100, z = 1/3, t(a→b) = 40, t(b→c) = 60 (its upper bound)
    network = make_network([Operation("a", "b", 30.0), Operation("b", "c", 45.0, 60.0), Operation("a", "c", 100.0)])
    result = optimise(network, schedule="leximin")
    assert result.critical_operations == ("a->c",)
    assert result.margins["a->b"] == pytest.approx(1 / 3, abs=1e-12)
    assert result.margins["b->c"] == pytest.approx(1 / 3, abs=1e-12)
    assert result.phase_angles_deg["a->b"] == pytest.approx(40.0, abs=1e-12)
    # a second round: x→y ≥ 10 beside a→b can take everything up to b once a→b is held
    wide = make_network([Operation("a", "b", 30.0), Operation("b", "c", 45.0, 60.0), Operation("a", "c", 100.0),
                         Operation("a", "x", 10.0), Operation("x", "b", 0.0)])
    found = optimise(wide, schedule="leximin")
    # round 1: z = 1/3 holds a→b and b→c (the bottleneck cycle); round 2: a→x up to b at 40: z = 3
    assert found.margins["a->b"] == pytest.approx(1 / 3, abs=1e-12)
    assert found.margins["a->x"] == pytest.approx(3.0, abs=1e-12)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_unknown_schedule_is_refused():
    from camcad.errors import CamcadError

    network = make_network([Operation("a", "b", 30.0)])
    with pytest.raises(CamcadError, match="unknown schedule 'latest'"):
        optimise(network, schedule="latest")


# ---------------------------------------------------------------- checks at their limit

@pytest.mark.reference("property", "a check's margin against AT_LIMIT x its limit")
def test_a_check_at_its_limit_is_a_warning_not_a_clean_pass():
    at = Check("stress", 1100.0 - 1e-7, 1100.0, "MPa")
    assert at.passed and at.at_limit and at.status == "at limit" and "at its limit" in at.why
    clear = Check("stress", 1100.0 * (1 - 10 * AT_LIMIT), 1100.0, "MPa")
    assert clear.status == "ok" and not clear.at_limit
    assert Check("angle", 30.0, 30.0, "deg", sense="min").status == "at limit"
    assert Check("stress", 1200.0, 1100.0, "MPa").status == "fail"
    assert Check("gap", 0.0, 0.0, "mm").status == "at limit"
    assert Check("figure", 3.0, None).status == "ok"
    assert Check("stress", 1100.0, 1100.0, "MPa").to_dict()["status"] == "at limit"


@pytest.mark.reference("property", "issue 28 must-show: no 'ok' within 1e-6 of a limit, margins off the critical path")
def test_loom_group_has_no_ok_at_a_limit_and_margins_off_the_critical_path(tmp_path):
    done = subprocess.run([sys.executable, "-m", "camcad", "profile", str(SAMPLE), "-o", str(tmp_path), "--no-plots"],
                          capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    import json
    import re

    report = json.loads((tmp_path / "report.json").read_text())
    # every printed "ok" line with a limit has a margin above 1e-6 of that limit
    for line in done.stdout.splitlines():
        found = re.search(r"^\s+ok\s+.* limit (\S+) \S*, margin (\S+)", line)
        if found:
            limit, margin = float(found.group(1)), float(found.group(2))
            assert margin > 1e-6 * abs(limit), line
    # and in the JSON: every check of every mechanism and of the cyclogram
    def checks(tree):
        if isinstance(tree, dict):
            if "status" in tree and "margin" in tree and "passed" in tree:
                yield tree
            for value in tree.values():
                yield from checks(value)
    seen = list(checks(report))
    assert seen
    for check in seen:
        if check["status"] == "ok" and check["limit"] not in (None, 0):
            assert check["margin"] > 1e-6 * abs(check["limit"]), check["why"]
    cyclogram = report["cyclogram"]
    critical = set(cyclogram["critical_operations"])
    margins = cyclogram["phase_margins"]
    assert critical and {"3->7", "6->8"} <= critical
    for label, margin in margins.items():
        if label not in critical:
            assert margin["relative"] > 0.0 and margin["deg"] > 0.0, label
    # each mechanism's checks on its non-critical phases keep a margin: the shuttle spring opener works off the
    # critical path entirely
    opener = report["mechanisms"]["shuttle_spring_opener"]["checks"]
    assert all(c["status"] == "ok" for c in opener.values())
