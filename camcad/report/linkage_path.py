"""What ``camcad linkage path`` writes: the deviation per row, an animation-ready position table, the linkage
with its coupler curve and the target as DXF, and a plot (``camcad.linkage.path``; Sunkuev 1984 ch. 2, 5)."""

from __future__ import annotations

import math

import numpy as np

from camcad.io.dxf_write import Drawing, DxfCircle, DxfLine, DxfPath, DxfText
from camcad.linkage.path import GuidingFourBar
from camcad.linkage.runners import PathReport
from camcad.linkage.variator import VariatorResult

#: frames of the position table (the crank's range through the rows, ends included)
FRAMES = 121
LAYERS = ("FRAME", "LINKS", "JOINTS", "COUPLER_CURVE", "TARGET", "Q_PIVOTS", "TEXT")


def _rows_csv(report: PathReport) -> str:
    target, best = report.target, report.best
    assert target is not None and best is not None  # a path report carries both
    chk = best.check
    head = {"points": "x_mm,y_mm", "timed": "phi_deg,x_mm,y_mm", "distance": "phi_deg,L_mm"}[target.task]
    lines = [f"# {best.method}: each row of the target, the coupler point the mechanism gives, the deviation (mm) and "
             "the crank's angle there (deg)", f"row,{head},reproduced_x_mm,reproduced_y_mm,deviation_mm,theta_deg"]
    for k in range(target.count):
        if target.task == "points":
            given = f"{target.points[k].real:.12g},{target.points[k].imag:.12g}"
        elif target.task == "timed":
            given = f"{math.degrees(target.phi[k]):.12g},{target.points[k].real:.12g},{target.points[k].imag:.12g}"
        else:
            given = f"{math.degrees(target.phi[k]):.12g},{target.distance[k]:.12g}"
        m = chk.reproduced[k]
        lines.append(f"{k + 1},{given},{m.real:.12g},{m.imag:.12g},{chk.deviations[k]:.12g},"
                     f"{math.degrees(chk.theta[k]):.12g}")
    return "\n".join(lines) + "\n"


def _positions_csv(mech: GuidingFourBar, lo: float, hi: float) -> str:
    theta = np.linspace(lo, hi, FRAMES)
    a_pt, b_pt, m_pt = mech.positions(theta)
    lines = ["# the linkage at each frame over the crank's range (mm, deg): O and C are fixed",
             "frame,theta_deg,O_x,O_y,A_x,A_y,B_x,B_y,C_x,C_y,M_x,M_y"]
    for k, t in enumerate(theta):
        cells = [mech.o, a_pt[k], b_pt[k], mech.pivot, m_pt[k]]
        lines.append(f"{k},{math.degrees(t):.12g}," + ",".join(f"{z.real:.12g},{z.imag:.12g}" for z in cells))
    return "\n".join(lines) + "\n"


def path_drawing(report: PathReport) -> Drawing:
    """The guiding four-bar as DXF (mm): FRAME (pivots, ground marks), LINKS (at the first row), JOINTS,
    COUPLER_CURVE (a full crank turn where the loop closes; the range through the rows thicker in the plot),
    TARGET (the points, or for a distance task the fixed point and the circles of L), Q_PIVOTS (the Q method's
    pivot set), TEXT.

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.runners import PathRequest, run_linkage_path
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.3)
    >>> phi = np.arange(0, 160, 20)
    >>> pts = m.positions(0.3 + np.radians(phi))[2]
    >>> r = run_linkage_path(PathRequest(rows=[(p, z.real, z.imag) for p, z in zip(phi, pts)], task="timed",
    ...                                  method="deviation"))
    >>> sorted({c.layer for c in path_drawing(r).circles})
    ['JOINTS', 'TARGET']
    """
    target, best = report.target, report.best
    assert target is not None and best is not None  # a path report carries both
    mech, chk = best.mechanism, best.check
    scale = max(target.size, max(mech.links()))
    r = 0.012 * scale
    h = 0.02 * scale
    lines: list[DxfLine] = []
    circles: list[DxfCircle] = []
    paths: list[DxfPath] = []
    texts: list[DxfText] = []
    for p in (mech.o, mech.pivot):
        lines.append(DxfLine("FRAME", (p.real - 2 * r, p.imag - 1.6 * r), (p.real + 2 * r, p.imag - 1.6 * r)))
        for k in range(5):
            xa = p.real - 2 * r + k * r
            lines.append(DxfLine("FRAME", (xa, p.imag - 1.6 * r), (xa - 0.7 * r, p.imag - 2.3 * r)))
    theta0 = float(chk.theta[0])
    a_pt, b_pt, m_pt = (complex(v[0]) for v in mech.positions(np.array([theta0])))
    for p, q in ((mech.o, a_pt), (a_pt, b_pt), (b_pt, mech.pivot), (a_pt, m_pt), (b_pt, m_pt)):
        lines.append(DxfLine("LINKS", (p.real, p.imag), (q.real, q.imag)))
    for name, p in (("O", mech.o), ("A", a_pt), ("B", b_pt), ("C", mech.pivot), ("M", m_pt)):
        circles.append(DxfCircle("JOINTS", (p.real, p.imag), r))
        texts.append(DxfText("TEXT", name, (p.real + 1.5 * r, p.imag + 1.5 * r), h))
    turn = np.linspace(0.0, 2 * math.pi, 721)
    curve = mech.positions(turn)[2]
    ok = np.isfinite(curve)
    start = 0
    for k in range(1, len(curve) + 1):
        if k == len(curve) or not ok[k]:
            if k - start >= 2 and ok[start]:
                seg = curve[start:k]
                paths.append(DxfPath("COUPLER_CURVE", np.column_stack([seg.real, seg.imag]), False))
            start = k + 1
    if target.task == "distance":
        x = target.fixed
        assert x is not None  # make_target gives every distance task its fixed point
        circles.append(DxfCircle("TARGET", (x.real, x.imag), r))
        texts.append(DxfText("TARGET", "X", (x.real + 1.5 * r, x.imag - 2.5 * r), h))
        for length in target.distance:
            circles.append(DxfCircle("TARGET", (x.real, x.imag), float(length)))
    else:
        for p in target.points:
            circles.append(DxfCircle("TARGET", (p.real, p.imag), 0.6 * r))
            lines.append(DxfLine("TARGET", (p.real - r, p.imag), (p.real + r, p.imag)))
            lines.append(DxfLine("TARGET", (p.real, p.imag - r), (p.real, p.imag + r)))
    if best.q_pivots is not None:
        for p in np.asarray(best.q_pivots):
            if np.isfinite(p):
                lines.append(DxfLine("Q_PIVOTS", (p.real - r, p.imag - r), (p.real + r, p.imag + r)))
                lines.append(DxfLine("Q_PIVOTS", (p.real - r, p.imag + r), (p.real + r, p.imag - r)))
    low = float(np.nanmin(np.r_[curve.imag[ok], mech.o.imag, mech.pivot.imag])) - 6 * r
    left = float(np.nanmin(np.r_[curve.real[ok], mech.o.real, mech.pivot.real]))
    links = mech.links()
    info = [f"guiding four-bar ({target.task}), method {best.method}",
            f"OA {links[0]:.3f}  AB {links[1]:.3f}  CB {links[2]:.3f}  OC {links[3]:.3f} mm; coupler point u "
            f"{mech.point.real:.3f} v {mech.point.imag:.3f} mm",
            f"max deviation {chk.max_deviation:.4g} mm, min transmission angle {chk.mu_min_deg:.2f} deg"]
    for k, line in enumerate(info):
        texts.append(DxfText("TEXT", line, (left, low - k * 1.8 * h), h))
    return Drawing(paths=tuple(paths), circles=tuple(circles), lines=tuple(lines), texts=tuple(texts), layers=LAYERS)


def path_figure(report: PathReport):
    """The coupler curve against the target with the linkage at the first row (left) and each row's deviation
    with the tolerance (right)."""
    from matplotlib.figure import Figure

    target, best = report.target, report.best
    assert target is not None and best is not None  # a path report carries both
    mech, chk = best.mechanism, best.check
    fig = Figure(figsize=(11.0, 5.4), layout="constrained")
    ax, ax2 = fig.subplots(1, 2, width_ratios=(1.5, 1.0))
    turn = np.linspace(0.0, 2 * math.pi, 721)
    curve = mech.positions(turn)[2]
    ax.plot(curve.real, curve.imag, color="#9aa9c4", lw=1.0, ls="--", label="coupler curve (full crank turn)")
    used = mech.positions(np.linspace(chk.lo, chk.hi, 361))[2]
    ax.plot(used.real, used.imag, color="#1f4e9c", lw=1.8, label="over the crank's range through the rows")
    if target.task == "distance":
        x = target.fixed
        assert x is not None  # make_target gives every distance task its fixed point
        ax.plot([x.real], [x.imag], "k*", ms=10, label="fixed point X")
        for k, length in enumerate(target.distance):
            arc = x + length * np.exp(1j * np.linspace(0, 2 * math.pi, 181))
            ax.plot(arc.real, arc.imag, color="#e0b0a8", lw=0.6, label="circles of L" if k == 0 else None)
        ax.plot(chk.reproduced.real, chk.reproduced.imag, "o", color="#c0392b", ms=4, label="coupler point at each row")
    else:
        ax.plot(target.points.real, target.points.imag, "o", mfc="none", mec="#c0392b", ms=8, mew=1.5, label="target")
        for k, p in enumerate(target.points):
            ax.annotate(str(k + 1), (p.real, p.imag), textcoords="offset points", xytext=(5, 5), fontsize=7)
    a_pt, b_pt, m_pt = (complex(v[0]) for v in mech.positions(np.array([float(chk.theta[0])])))
    chain = [mech.o, a_pt, b_pt, mech.pivot]
    ax.plot([z.real for z in chain], [z.imag for z in chain], "-o", color="black", lw=2.0, ms=5,
            label="linkage at row 1")
    tri = [a_pt, m_pt, b_pt]
    ax.fill([z.real for z in tri], [z.imag for z in tri], color="#f0d98c", alpha=0.6, lw=0.8, ec="black")
    ax.plot([mech.o.real, mech.pivot.real], [mech.o.imag, mech.pivot.imag], "^", color="black", ms=10)
    if best.q_pivots is not None:
        piv = np.asarray(best.q_pivots)
        piv = piv[np.isfinite(piv)]
        ax.plot(piv.real, piv.imag, "x", color="#7b3294", ms=6, label=f"Q pivots (Q = {best.q:.3g} mm)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"{best.method}: OA {mech.a:.2f}, AB {mech.b:.2f}, CB {mech.c:.2f}, OC {mech.links()[3]:.2f} mm",
                 fontsize=9)
    rows = np.arange(1, target.count + 1)
    tol = report.payload["tolerance_mm"]
    ax2.bar(rows, chk.deviations, color="#1f4e9c")
    ax2.axhline(tol, color="#c0392b", ls="--", lw=1.0, label=f"tolerance {tol:.3g} mm")
    ax2.set_yscale("log")
    floor = max(float(np.nanmin(chk.deviations[chk.deviations > 0])) if np.any(chk.deviations > 0) else tol, 1e-12)
    ax2.set_ylim(floor / 3, max(tol, float(np.nanmax(chk.deviations))) * 3)
    ax2.set_xlabel("row")
    ax2.set_ylabel("deviation (mm)")
    ax2.set_xticks(rows)
    ax2.grid(True, lw=0.4, alpha=0.5, which="both")
    ax2.legend(fontsize=8)
    ax2.set_title(f"max {chk.max_deviation:.3g} mm; min transmission angle {chk.mu_min_deg:.2f} deg", fontsize=9)
    return fig


COLOURS = ("#1f4e9c", "#c0392b", "#2d7f3b", "#7b3294", "#e66101", "#666666")


def _family_csv(report: PathReport) -> str:
    fam = report.family
    assert fam is not None  # a family report
    lines = ["# every member: each row of its target, the coupler point its setting gives, the deviation (mm)",
             "member,row,target_x_mm,target_y_mm,phi_deg,L_mm,reproduced_x_mm,reproduced_y_mm,deviation_mm,theta_deg"]
    for j, (t, chk) in enumerate(zip(fam.members, fam.checks), start=1):
        for k in range(t.count):
            p = t.points[k] if t.task != "distance" else complex(math.nan, math.nan)
            phi = math.degrees(t.phi[k]) if t.task != "points" else math.nan
            length = t.distance[k] if t.task == "distance" else math.nan
            m = chk.reproduced[k]
            lines.append(f"{j},{k + 1},{p.real:.12g},{p.imag:.12g},{phi:.12g},{length:.12g},{m.real:.12g},"
                         f"{m.imag:.12g},{chk.deviations[k]:.12g},{math.degrees(chk.theta[k]):.12g}".replace("nan", ""))
    return "\n".join(lines) + "\n"


def family_drawing(report: PathReport) -> Drawing:
    """The adjustable guiding four-bar as DXF (mm): FRAME, LINKS and JOINTS at member 1's first row, SETTINGS (the
    linkage of every other member), COUPLER_CURVE (every member's curve over its range), TARGET, ADJUSTMENT (the
    arc of the moved pivot, its centre and the lock radii), TEXT."""
    fam = report.family
    assert fam is not None  # a family report
    size = max(t.size for t in fam.members)
    r = 0.012 * max(size, max(fam.mechanisms[0].links()))
    h = 0.02 * max(size, max(fam.mechanisms[0].links()))
    lines: list[DxfLine] = []
    circles: list[DxfCircle] = []
    paths: list[DxfPath] = []
    texts: list[DxfText] = []
    for j, (mech, chk, t) in enumerate(zip(fam.mechanisms, fam.checks, fam.members)):
        layer = "LINKS" if j == 0 else "SETTINGS"
        a_pt, b_pt, m_pt = (complex(v[0]) for v in mech.positions(np.array([float(chk.theta[0])])))
        for p, q in ((mech.o, a_pt), (a_pt, b_pt), (b_pt, mech.pivot), (a_pt, m_pt), (b_pt, m_pt)):
            lines.append(DxfLine(layer, (p.real, p.imag), (q.real, q.imag)))
        for p in (mech.o, a_pt, b_pt, mech.pivot, m_pt):
            circles.append(DxfCircle("JOINTS", (p.real, p.imag), r))
        curve = mech.positions(np.linspace(chk.lo, chk.hi, 361))[2]
        ok = np.isfinite(curve)
        if ok.sum() >= 2:
            paths.append(DxfPath("COUPLER_CURVE", np.column_stack([curve.real[ok], curve.imag[ok]]), False))
        if t.task != "distance":
            for p in t.points:
                lines.append(DxfLine("TARGET", (p.real - r, p.imag), (p.real + r, p.imag)))
                lines.append(DxfLine("TARGET", (p.real, p.imag - r), (p.real, p.imag + r)))
        moved = mech.o if fam.moved == "O" else mech.pivot
        lines.append(DxfLine("ADJUSTMENT", (fam.centre.real, fam.centre.imag), (moved.real, moved.imag)))
        texts.append(DxfText("TEXT", f"x{j + 1}", (moved.real + 1.5 * r, moved.imag + 1.5 * r), h))
    for p in (fam.mechanisms[0].o if fam.moved == "C" else fam.mechanisms[0].pivot, fam.centre):
        lines.append(DxfLine("FRAME", (p.real - 2 * r, p.imag - 1.6 * r), (p.real + 2 * r, p.imag - 1.6 * r)))
    lo = min(fam.settings) - 0.2
    hi = max(fam.settings) + 0.2
    arc = fam.centre + fam.radius * np.exp(1j * np.linspace(lo, hi, 91))
    paths.append(DxfPath("ADJUSTMENT", np.column_stack([arc.real, arc.imag]), False))
    circles.append(DxfCircle("ADJUSTMENT", (fam.centre.real, fam.centre.imag), r))
    mech = fam.mechanisms[0]
    links = mech.links()
    low = min(float(np.nanmin([c.reproduced.imag.min() for c in fam.checks])), fam.centre.imag) - 6 * r
    left = min(float(np.nanmin([c.reproduced.real.min() for c in fam.checks])), fam.centre.real)
    info = [f"adjustable guiding four-bar ({fam.members[0].task}, {len(fam.members)} members), the "
            f"{'crank pivot O' if fam.moved == 'O' else 'rocker pivot C'} on an arc",
            f"OA {links[0]:.3f}  AB {links[1]:.3f}  CB {links[2]:.3f} mm; coupler point u {mech.point.real:.3f} v "
            f"{mech.point.imag:.3f} mm",
            f"arc centre ({fam.centre.real:.3f}, {fam.centre.imag:.3f}) radius {fam.radius:.3f} mm; settings "
            + ", ".join(f"{math.degrees(x):.3f}" for x in fam.settings) + " deg"]
    for k, line in enumerate(info):
        texts.append(DxfText("TEXT", line, (left, low - k * 1.8 * h), h))
    return Drawing(paths=tuple(paths), circles=tuple(circles), lines=tuple(lines), texts=tuple(texts),
                   layers=("FRAME", "LINKS", "SETTINGS", "JOINTS", "COUPLER_CURVE", "TARGET", "ADJUSTMENT", "TEXT"))


def family_figure(report: PathReport):
    """Every member's coupler curve against its target, the linkage at every setting and the arc (left); each
    member's deviation per row (right)."""
    from matplotlib.figure import Figure

    fam = report.family
    assert fam is not None  # a family report
    fig = Figure(figsize=(11.0, 5.4), layout="constrained")
    ax, ax2 = fig.subplots(1, 2, width_ratios=(1.5, 1.0))
    for j, (mech, chk, t) in enumerate(zip(fam.mechanisms, fam.checks, fam.members)):
        colour = COLOURS[j % len(COLOURS)]
        curve = mech.positions(np.linspace(chk.lo, chk.hi, 361))[2]
        ax.plot(curve.real, curve.imag, color=colour, lw=1.6, label=f"member {j + 1}: x = "
                f"{math.degrees(fam.settings[j]):.2f} deg")
        if t.task != "distance":
            ax.plot(t.points.real, t.points.imag, "o", mfc="none", mec=colour, ms=7)
        a_pt, b_pt, m_pt = (complex(v[0]) for v in mech.positions(np.array([float(chk.theta[0])])))
        chain = [mech.o, a_pt, b_pt, mech.pivot]
        ax.plot([z.real for z in chain], [z.imag for z in chain], "-", color=colour, lw=0.9, alpha=0.8)
        ax.plot([a_pt.real, m_pt.real, b_pt.real], [a_pt.imag, m_pt.imag, b_pt.imag], ":", color=colour, lw=0.8)
        rows = np.arange(1, t.count + 1)
        ax2.plot(rows, chk.deviations, "o-", color=colour, ms=4, label=f"member {j + 1}")
    arc = fam.centre + fam.radius * np.exp(1j * np.linspace(min(fam.settings) - 0.2, max(fam.settings) + 0.2, 91))
    ax.plot(arc.real, arc.imag, color="black", lw=1.0, ls="--", label="arc of the moved pivot")
    ax.plot([fam.centre.real], [fam.centre.imag], "k+", ms=10)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize=7, loc="best")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"one adjustable four-bar for {len(fam.members)} {fam.members[0].task} targets (sum of Q "
                 f"{fam.q:.3g} mm)", fontsize=9)
    ax2.set_yscale("log")
    ax2.set_xlabel("row")
    ax2.set_ylabel("deviation (mm)")
    ax2.grid(True, lw=0.4, alpha=0.5, which="both")
    ax2.legend(fontsize=8)
    return fig


def path_files(report: PathReport, plots: bool):
    """(texts, figures, drawing) of a path report for ``write_linkage_outputs``."""
    if report.family is not None:
        figures = {"path.png": lambda: family_figure(report)} if plots else {}
        return {"deviation.csv": _family_csv(report)}, figures, family_drawing(report)
    best = report.best
    assert best is not None  # a path report carries its best result
    texts = {"deviation.csv": _rows_csv(report),
             "positions.csv": _positions_csv(best.mechanism, best.check.lo, best.check.hi)}
    figures = {"path.png": lambda: path_figure(report)} if plots else {}
    return texts, figures, path_drawing(report)


def variator_figure(result: VariatorResult):
    """U over the working interval at every setting (left) and the six-bar at each setting (right)."""
    from matplotlib.figure import Figure

    v = result.variator
    fig = Figure(figsize=(11.0, 5.0), layout="constrained")
    ax, ax2 = fig.subplots(1, 2)
    for j, x in enumerate(result.settings):
        colour = COLOURS[j % len(COLOURS)]
        theta, _, _, u = v.ratios(float(x))
        row = result.rows[j]
        ax.plot(np.degrees(theta - theta[0]), u, color=colour, lw=1.5,
                label=f"x = {row['setting_deg']:.2f} deg: U_cp {row['u_mean']:.4g}, δ {row['delta']:.3f}")
        ax.axhline(row["u_mean"], color=colour, lw=0.6, ls=":")
        first, second = v.loops(float(x))
        t0 = float(theta[len(theta) // 2])
        a_pt, b_pt = (complex(np.asarray(p)) for p in first.joints(t0))
        beta = float(first.output(t0))
        _, d_pt = (complex(np.asarray(p)) for p in second.joints(beta))
        c_pt, e_pt = complex(*first.q), complex(*second.q)
        chain = [0j, a_pt, b_pt, c_pt]
        ax2.plot([z.real for z in chain], [z.imag for z in chain], "-o", color=colour, lw=1.2, ms=3)
        ax2.plot([b_pt.real, d_pt.real, e_pt.real], [b_pt.imag, d_pt.imag, e_pt.imag], "-o", color=colour, lw=1.2,
                 ms=3)
    arc = v.radius * np.exp(1j * np.linspace(min(result.settings) - 0.3, max(result.settings) + 0.3, 91))
    ax2.plot(arc.real, arc.imag, "k--", lw=0.8, label="arc of C about O")
    ax2.plot([0.0, v.pivot_e.real], [0.0, v.pivot_e.imag], "k^", ms=9)
    ax.set_xlabel("crank angle over the working interval (deg)")
    ax.set_ylabel("U = dψ/dφ")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize=7)
    ax.set_title(f"impulse variator: max δ {result.delta_max:.3f} (first loop alone δ_w {result.delta_w:.3f})",
                 fontsize=9)
    ax2.set_aspect("equal", adjustable="datalim")
    ax2.grid(True, lw=0.4, alpha=0.5)
    ax2.legend(fontsize=7)
    ax2.set_title("the six-bar at every setting (mid working interval), mm", fontsize=9)
    return fig


def variator_drawing(result: VariatorResult) -> Drawing:
    """The variator's six-bar at every setting (layer SETTINGS; the first also LINKS), the pivots (FRAME), the
    arc of C about O (ADJUSTMENT), JOINTS and TEXT (mm)."""
    v = result.variator
    r = 0.02 * max(v.b, v.c, v.radius)
    h = 1.5 * r
    lines, circles, paths, texts = [], [], [], []
    for j, x in enumerate(result.settings):
        layer = "LINKS" if j == 0 else "SETTINGS"
        first, second = v.loops(float(x))
        t0 = float(x) + v.start + v.interval / 2
        a_pt, b_pt = (complex(np.asarray(p)) for p in first.joints(t0))
        _, d_pt = (complex(np.asarray(p)) for p in second.joints(float(first.output(t0))))
        c_pt = complex(*first.q)
        for p, q in ((0j, a_pt), (a_pt, b_pt), (c_pt, b_pt), (b_pt, d_pt), (v.pivot_e, d_pt)):
            lines.append(DxfLine(layer, (p.real, p.imag), (q.real, q.imag)))
        for p in (a_pt, b_pt, c_pt, d_pt):
            circles.append(DxfCircle("JOINTS", (p.real, p.imag), r))
        texts.append(DxfText("TEXT", f"C{j + 1}", (c_pt.real + r, c_pt.imag + r), h))
    for p in (0j, v.pivot_e):
        circles.append(DxfCircle("FRAME", (p.real, p.imag), r))
        lines.append(DxfLine("FRAME", (p.real - 2 * r, p.imag - 1.6 * r), (p.real + 2 * r, p.imag - 1.6 * r)))
    arc = v.radius * np.exp(1j * np.linspace(min(result.settings) - 0.3, max(result.settings) + 0.3, 91))
    paths.append(DxfPath("ADJUSTMENT", np.column_stack([arc.real, arc.imag]), False))
    texts.append(DxfText("TEXT", f"impulse variator: max delta {result.delta_max:.4f}; OA {v.a:.3f} AB {v.b:.3f} CB "
                                 f"{v.c:.3f} OC {v.radius:.3f} BD {v.e:.3f} ED {v.f:.3f} mm",
                         (min(0.0, v.pivot_e.real), min(0.0, v.pivot_e.imag) - 6 * r), h))
    return Drawing(paths=tuple(paths), circles=tuple(circles), lines=tuple(lines), texts=tuple(texts),
                   layers=("FRAME", "LINKS", "SETTINGS", "JOINTS", "ADJUSTMENT", "TEXT"))
