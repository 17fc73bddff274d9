"""`camcad linkage path`: guiding four-bars for a curve, a timed curve and a distance (Sunkuev 1984, ch. 2 and 5).

Evidence: targets made here by four-bars of known dimensions with a closed-form position analysis written in
this file (not camcad's); the mechanism camcad returns is judged by the same closed form (its coupler curve
sampled over a full crank turn, each target point's distance to it), and its transmission angle by the law of
cosines on the diagonal.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

#: the crank-rocker of the must-show: crank 35, coupler 110, rocker 95, frame 100 mm, coupler point 55 mm along
#: AB and 35 mm to its left (chosen here; Grashof: 35 + 110 < 95 + 100)
CRANK_ROCKER = {"o": 0j, "c_pivot": 100 + 0j, "a": 35.0, "b": 110.0, "c": 95.0, "u": 55.0, "v": 35.0}


def coupler(mech: dict, theta, branch: int = 1):
    """The coupler point M (complex mm) of the four-bar ``mech`` at crank angles θ (rad), closed form: A on the
    crank circle, B where the circles (C, c) and (A, b) meet on the side ``branch`` (+1: left of C→A)."""
    theta = np.asarray(theta, dtype=float)
    a_pt = mech["o"] + mech["a"] * np.exp(1j * theta)
    f = np.abs(a_pt - mech["c_pivot"])
    cos_g = (mech["c"] ** 2 + f ** 2 - mech["b"] ** 2) / (2 * mech["c"] * f)
    with np.errstate(invalid="ignore"):
        gamma = np.where(np.abs(cos_g) <= 1, np.arccos(np.clip(cos_g, -1, 1)), np.nan)
    b_pt = mech["c_pivot"] + mech["c"] * np.exp(1j * (np.angle(a_pt - mech["c_pivot"]) + branch * gamma))
    return a_pt + (mech["u"] + 1j * mech["v"]) * (b_pt - a_pt) / mech["b"]


def transmission_deg(mech: dict, theta) -> np.ndarray:
    """min(μ, 180 − μ) (deg) at crank angles θ: cos μ = (b² + c² − f²)/(2bc), f = |C − A|."""
    a_pt = mech["o"] + mech["a"] * np.exp(1j * np.asarray(theta, dtype=float))
    f = np.abs(a_pt - mech["c_pivot"])
    mu = np.degrees(np.arccos(np.clip((mech["b"] ** 2 + mech["c"] ** 2 - f ** 2) / (2 * mech["b"] * mech["c"]), -1,
                                      1)))
    return np.minimum(mu, 180.0 - mu)


def from_json(payload: dict) -> dict:
    return {"o": complex(*payload["input_pivot_mm"]), "c_pivot": complex(*payload["output_pivot_mm"]),
            "a": payload["links"]["a"], "b": payload["links"]["b"], "c": payload["links"]["c"],
            "u": payload["coupler_point_mm"]["u"], "v": payload["coupler_point_mm"]["v"]}


def distance_to_curve(mech: dict, branch: int, points: np.ndarray) -> np.ndarray:
    """Each point's distance to the coupler curve over a full crank turn (10^5 samples, then a parabola through the
    nearest three)."""
    theta = np.linspace(0.0, 2 * math.pi, 100_001)
    curve = coupler(mech, theta, branch)
    out = []
    for p in points:
        d = np.abs(curve - p)
        d = np.where(np.isfinite(d), d, np.inf)
        k = int(np.argmin(d))
        fine = np.linspace(theta[max(k - 1, 0)], theta[min(k + 1, len(theta) - 1)], 2001)
        out.append(float(np.nanmin(np.abs(coupler(mech, fine, branch) - p))))
    return np.array(out)


def _write(path, header: str, rows) -> None:
    path.write_text(header + "\n" + "".join(",".join(f"{v:.12f}" for v in row) + "\n" for row in rows))


@pytest.mark.reference("closed form", "coupler curve of a chosen crank-rocker by the law of cosines, written in this "
                                      "test; the returned mechanism judged by the same closed form")
def test_nine_points_of_a_crank_rocker_give_a_mechanism_through_every_point(cli, tmp_path):
    theta = np.radians(15.0 + 40.0 * np.arange(9))
    points = coupler(CRANK_ROCKER, theta)
    assert transmission_deg(CRANK_ROCKER, np.linspace(0, 2 * math.pi, 3601)).min() > 30.0   # a sound crank-rocker
    _write(tmp_path / "p.csv", "x_mm,y_mm", [(z.real, z.imag) for z in points])
    size = math.hypot(np.ptp(points.real), np.ptp(points.imag))
    run = cli("linkage", "path", "--points", tmp_path / "p.csv", "--json", "-o", tmp_path / "out", "--no-plots")
    assert run.code == 0, run.err
    payload = run.json()
    for key in ("max_deviation_mm", "mu_min_deg", "position_evaluations", "passed"):
        assert key in payload
    assert payload["passed"] and payload["position_evaluations"] > 0
    mech = from_json(payload)
    gaps = distance_to_curve(mech, payload["branch"], points)
    assert gaps.max() <= 1e-3 * size
    assert payload["max_deviation_mm"] <= 1e-3 * size
    lo, hi = np.radians(payload["input_range_deg"])
    assert transmission_deg(mech, np.linspace(lo, hi, 3601)).min() >= 30.0 - 1e-6
    assert payload["mu_min_deg"] >= 30.0


@pytest.mark.reference("closed form", "a timed curve and a distance made by a chosen four-bar (this file's closed "
                                      "form); the returned mechanism re-evaluated at the given input angles")
def test_timed_curve_and_distance_are_reproduced_at_their_input_angles(cli, tmp_path):
    phi = np.arange(0.0, 200.0, 40.0)
    theta0 = 0.4
    points = coupler(CRANK_ROCKER, theta0 + np.radians(phi))
    _write(tmp_path / "t.csv", "phi_deg,x_mm,y_mm", [(p, z.real, z.imag) for p, z in zip(phi, points)])
    run = cli("linkage", "path", "--timed", tmp_path / "t.csv", "--json", "-o", tmp_path / "t", "--no-plots")
    assert run.code == 0, run.err
    payload = run.json()
    mech = from_json(payload)
    best = next(m for m in payload["methods"] if m["method"] == payload["best_method"])
    start = math.radians(best["input_angles_deg"][0])
    again = coupler(mech, start + np.radians(phi), payload["branch"])
    assert np.max(np.abs(again - points)) <= 1e-6 * 60
    fixed = 150 + 80j
    _write(tmp_path / "d.csv", "phi_deg,L_mm", [(p, abs(z - fixed)) for p, z in zip(phi, points)])
    run = cli("linkage", "path", "--distance", tmp_path / "d.csv", "--fixed-point", "150,80", "--json", "-o",
              tmp_path / "d", "--no-plots")
    assert run.code == 0, run.err
    payload = run.json()
    best = next(m for m in payload["methods"] if m["method"] == payload["best_method"])
    mech = from_json(payload)
    again = coupler(mech, np.radians(best["input_angles_deg"]), payload["branch"])
    assert np.max(np.abs(np.abs(again - fixed) - np.abs(points - fixed))) <= 1e-6 * 100
    assert payload["fixed_point_mm"] == [150.0, 80.0]


@pytest.mark.reference("property", "Q = 0 exactly when every node subset gives the same pivot: a target made by a "
                                   "four-bar, started from that four-bar, has Q at round-off")
def test_the_q_method_reaches_zero_on_a_four_bar_target():
    from camcad.linkage.fgen import Limits
    from camcad.linkage.path import GuidingFourBar, make_target, q_synthesis

    m = GuidingFourBar(0j, 100 + 0j, 35.0, 110.0, 95.0, 1, 55 + 35j, 0.3)
    for task in ("points", "timed"):
        phi = np.arange(0.0, 360.0, 40.0) if task == "points" else np.arange(0.0, 240.0, 40.0)
        pts = m.positions(0.3 + np.radians(phi))[2]
        rows = [(z.real, z.imag) for z in pts] if task == "points" else [(p, z.real, z.imag) for p, z in zip(phi, pts)]
        target = make_target(task, rows)
        result = q_synthesis(target, Limits(30.0, 10.0), starts=[m], random_starts=0)
        assert result.q <= 1e-9 * target.size, task
        assert result.check.max_deviation <= 1e-6 * target.size, task


@pytest.mark.reference("property", "the files and JSON keys docs/INTERFACE.md promises")
def test_path_files_and_their_contract(cli, tmp_path):
    import ezdxf

    points = coupler(CRANK_ROCKER, np.radians(15.0 + 40.0 * np.arange(9)))
    _write(tmp_path / "p.csv", "x_mm,y_mm", [(z.real, z.imag) for z in points])
    run = cli("linkage", "path", "--points", tmp_path / "p.csv", "--method", "deviation", "-o", tmp_path / "out")
    assert run.code == 0, run.err
    out = tmp_path / "out"
    for name in ("path.json", "deviation.csv", "positions.csv", "path.dxf", "path.png"):
        assert (out / name).stat().st_size > 0, name
    doc = ezdxf.readfile(out / "path.dxf")
    layers = {e.dxf.layer for e in doc.modelspace()}
    assert {"FRAME", "LINKS", "JOINTS", "COUPLER_CURVE", "TARGET", "TEXT"} <= layers
    frames = [line for line in (out / "positions.csv").read_text().splitlines() if not line.startswith("#")]
    assert frames[0].startswith("frame,theta_deg,O_x") and len(frames) == 1 + 121
    data = json.loads((out / "path.json").read_text())
    assert data["outputs"][-1].endswith("path.json") and data["methods"][0]["method"] == "deviation"


@pytest.mark.reference("property", "bad input: one line naming the key, exit 2")
@pytest.mark.parametrize(("args", "where"), [
    (["--points", "t.csv"], "not 'x_mm,y_mm'"),
    (["--timed", "p.csv"], "use --points"),
    (["--distance", "d.csv"], "--fixed-point"),
    (["--points", "short.csv"], "at least 5"),
    (["--points", "p.csv", "--timed", "t.csv"], "exactly one"),
    (["--points", "p.csv", "--method", "best"], "--method"),
    (["--points", "missing.csv"], "missing.csv"),
])
def test_bad_path_input_is_one_line_and_exit_2(cli, tmp_path, monkeypatch, args, where):
    monkeypatch.chdir(tmp_path)
    _write(tmp_path / "p.csv", "x_mm,y_mm", [(k, k * k) for k in range(6)])
    _write(tmp_path / "t.csv", "phi_deg,x_mm,y_mm", [(10 * k, k, k * k) for k in range(6)])
    _write(tmp_path / "d.csv", "phi_deg,L_mm", [(10 * k, 50 + k) for k in range(6)])
    _write(tmp_path / "short.csv", "x_mm,y_mm", [(k, k * k) for k in range(3)])
    run = cli("linkage", "path", *args, "-o", tmp_path / "out")
    assert run.code == 2, run.out
    assert where in run.err and run.err.count("\n") == 1
