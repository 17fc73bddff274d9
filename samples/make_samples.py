"""Regenerate the sample laws in samples/dxf/ (run: python samples/make_samples.py).

Laws drawn the way designers draw them: x along the cam angle in drawing units (not always
degrees), y the acceleration analog at some drawing scale (scale with --lift), vertical segments
for jumps, sometimes a grid, axes and text around the law. Several are deliberately unbalanced.
Deterministic: the same files every run.
"""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import ezdxf
import numpy as np
from ezdxf import appsettings

from camcad.law.standard import compose

HERE = Path(__file__).resolve().parent / "dxf"


def sampled(phases, lift, shape, step_deg, return_shape=None):
    """The law's acceleration every step_deg; where it jumps at a phase boundary, a vertical segment."""
    law = compose(phases, lift, shape, return_shape)
    theta = np.radians(np.arange(0.0, 360.0 + step_deg / 2, step_deg))
    a = law.kinematics(theta).a
    for boundary in sorted({p.start for p in law.phases[1:]}, reverse=True):
        left = law.kinematics(np.array([boundary - 1e-12])).a[0]
        right = law.kinematics(np.array([boundary])).a[0]
        if abs(left - right) > 1e-9 * np.abs(a).max():
            keep = ~np.isclose(theta, boundary, rtol=0, atol=1e-12)
            cut = np.searchsorted(theta[keep], boundary)
            theta = np.insert(theta[keep], cut, [boundary, boundary])
            a = np.insert(a[keep], cut, [left, right])
    return np.degrees(theta), a


def scale_lobe(theta_deg, a, start, end, factor):
    a = a.copy()
    inside = (theta_deg > start) & (theta_deg < end)
    a[inside] *= factor
    return a


def new_doc(version="R2000"):
    doc = ezdxf.new(version)
    if version != "R12":
        doc.units = 4
    return doc, doc.modelspace()


def save(doc, name):
    appsettings.update_extents(doc)
    doc.saveas(HERE / name)


def balanced_drdr():
    """Dwell–rise–dwell–return, cycloidal, 2° vertices, x in degrees: balanced."""
    t, a = sampled([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 25.0, "cycloidal", 2.0)
    doc, msp = new_doc()
    doc.layers.add("ACCEL", color=1)
    msp.add_lwpolyline(list(zip(t, a)), dxfattribs={"layer": "ACCEL"})
    save(doc, "balanced_drdr_cycloidal.dxf")


def fig2_unbalanced():
    """The source's Fig. 2 case: the rise's accelerating area is larger, so the profile breaks."""
    t, a = sampled([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 30.0, "harmonic", 1.0)
    a = scale_lobe(t, a, 60, 120, 1.12)
    doc, msp = new_doc()
    doc.layers.add("ACCEL", color=1)
    msp.add_lwpolyline(list(zip(t * 0.5, a * 0.2)), dxfattribs={"layer": "ACCEL"})  # x 0..180 drawing units
    save(doc, "fig2_rise_area_too_large.dxf")


def drrd_unbalanced():
    """Dwell–rise–return–dwell (no far dwell), 3-4-5 shape, return lobe drawn 6 % short."""
    t, a = sampled([("dwell", 80), ("rise", 100), ("return", 100), ("dwell", 80)], 20.0, "poly345", 1.0)
    a = scale_lobe(t, a, 230, 280, 0.94)
    doc, msp = new_doc()
    msp.add_lwpolyline(list(zip(t, a)), dxfattribs={"layer": "LAW"})
    save(doc, "drrd_return_short.dxf")


def constant_acceleration_jumps():
    """Piecewise-constant acceleration (parabolic law) drawn with vertical segments; rise accel 8 % high."""
    h, beta = 20.0, np.radians(100)
    level = 4 * h / beta**2
    pts = [(0, 0), (60, 0), (60, level * 1.08), (110, level * 1.08), (110, -level), (160, -level), (160, 0),
           (200, 0), (200, -level), (250, -level), (250, level), (300, level), (300, 0), (360, 0)]
    doc, msp = new_doc()
    doc.layers.add("ACCEL", color=3)
    msp.add_lwpolyline(pts, dxfattribs={"layer": "ACCEL"})
    save(doc, "constant_accel_jumps.dxf")


def r12_polyline():
    """R12 POLYLINE (2D), simple harmonic dwell–rise–dwell–return, return decelerating lobe 5 % high."""
    t, a = sampled([("dwell", 45), ("rise", 135), ("dwell", 45), ("return", 135)], 40.0, "harmonic", 1.5)
    a = scale_lobe(t, a, 292.5, 360, 1.05)
    doc, msp = new_doc("R12")
    msp.add_polyline2d(list(zip(t, a)), dxfattribs={"layer": "ACCEL"})
    save(doc, "r12_polyline_harmonic.dxf")


def spline_law():
    """A SPLINE through control points (degree 3), unbalanced; read by flattening to a tolerance."""
    t, a = sampled([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 25.0, "cycloidal", 10.0)
    a = scale_lobe(t, a, 60, 120, 1.04)
    doc, msp = new_doc()
    msp.add_open_spline(list(zip(t, a, np.zeros_like(t))), degree=3, dxfattribs={"layer": "SPLINE_LAW"})
    save(doc, "spline_law.dxf")


def line_chain():
    """A trapezoidal law drawn as separate LINEs joined end to end (some reversed); decel lobe 7 % low."""
    pts = [(0, 0), (40, 0), (55, 10), (85, 10), (100, 0), (115, -9.3), (145, -9.3), (160, 0), (200, 0),
           (215, -10), (245, -10), (260, 0), (275, 10), (305, 10), (320, 0), (360, 0)]
    doc, msp = new_doc()
    for i, (p, q) in enumerate(pairwise(pts)):
        if i % 3 == 1:
            p, q = q, p  # designers do not draw every line in the same direction
        msp.add_line(p, q, dxfattribs={"layer": "ACCEL"})
    save(doc, "line_chain_trapezoid.dxf")


def drawing_with_axes():
    """A law inside a real-looking sheet: frame, axes, grid, tick text, title, a dimension. Cycloidal, 3 % off."""
    t, a = sampled([("dwell", 90), ("rise", 100), ("dwell", 70), ("return", 100)], 15.0, "cycloidal", 1.0)
    a = scale_lobe(t, a, 190, 260, 1.0)
    a = scale_lobe(t, a, 115, 140, 1.03)
    doc, msp = new_doc()
    for name, color in (("ACCEL", 1), ("AXES", 7), ("GRID", 8), ("TEXT", 2), ("FRAME", 7)):
        doc.layers.add(name, color=color)
    y_scale = 2.0
    msp.add_lwpolyline(list(zip(t, a * y_scale)), dxfattribs={"layer": "ACCEL"})
    msp.add_line((0, 0), (380, 0), dxfattribs={"layer": "AXES"})
    msp.add_line((0, -120), (0, 120), dxfattribs={"layer": "AXES"})
    for x in range(0, 361, 30):
        msp.add_line((x, -110), (x, 110), dxfattribs={"layer": "GRID"})
        msp.add_text(f"{x}", dxfattribs={"layer": "TEXT", "height": 4}).set_placement((x, -118))
    for y in range(-100, 101, 25):
        msp.add_line((0, y), (360, y), dxfattribs={"layer": "GRID"})
    msp.add_lwpolyline([(-20, -140), (400, -140), (400, 140), (-20, 140)], close=True, dxfattribs={"layer": "FRAME"})
    msp.add_text("ACCELERATION ANALOG a(phi)", dxfattribs={"layer": "TEXT", "height": 6}).set_placement((100, 125))
    dim = msp.add_linear_dim(base=(0, -130), p1=(90, 0), p2=(190, 0), dxfattribs={"layer": "TEXT"})
    dim.render()
    save(doc, "drawing_with_axes_grid_text.dxf")


def press_feed_sheet():
    """The README's worked example: a press-feed law drawn as a designer draws it on a sheet. The graph's
    origin is at (50, 140) on the sheet, 1 drawing unit = 2 deg, axes and a title around it; the dwells are
    LINEs and each motion is its own polyline (the law is the chain of its pieces); modified-sine rise and
    return of 90 deg, the return's decelerating lobe drawn 6 % low, so the follower does not come back."""
    t, a = sampled([("dwell", 60), ("rise", 90), ("dwell", 60), ("return", 90), ("dwell", 60)], 20.0,
                   "modified_sine", 1.0)
    a = scale_lobe(t, a, 255, 300, 0.94)
    x0, y0, x_scale, y_scale = 50.0, 140.0, 0.5, 4.0
    x, y = x0 + x_scale * t, y0 + y_scale * a
    doc, msp = new_doc()
    for name, color in (("LAW", 1), ("AXES", 7), ("NOTES", 3), ("FRAME", 7)):
        doc.layers.add(name, color=color)
    pieces = [(0, 60), (60, 150), (150, 210), (210, 300), (300, 360)]
    for start, end in pieces:
        inside = (t >= start - 1e-9) & (t <= end + 1e-9)
        points = list(zip(x[inside], y[inside]))
        if (start, end) in ((60, 150), (210, 300)):
            msp.add_lwpolyline(points, dxfattribs={"layer": "LAW"})
        else:
            msp.add_line(points[0], points[-1], dxfattribs={"layer": "LAW"})
    msp.add_line((x0 - 10, y0), (x0 + 190, y0), dxfattribs={"layer": "AXES"})
    msp.add_line((x0, y0 - 60), (x0, y0 + 60), dxfattribs={"layer": "AXES"})
    for deg in range(0, 361, 60):
        msp.add_text(f"{deg}", dxfattribs={"layer": "NOTES", "height": 3}).set_placement(
            (x0 + x_scale * deg - 3, y0 - 66))
    msp.add_text("PRESS FEED  a(phi), 1 unit = 2 deg", dxfattribs={"layer": "NOTES", "height": 5}).set_placement(
        (x0, y0 + 70))
    msp.add_lwpolyline([(10, 40), (287, 40), (287, 240), (10, 240)], close=True, dxfattribs={"layer": "FRAME"})
    save(doc, "press_feed_sheet.dxf")


def right_to_left_duplicates():
    """Drawn right to left, with duplicated vertices and a doubled jump vertex: the reader copes."""
    t, a = sampled([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 10.0, "poly345", 3.0)
    pts = list(zip(t, a))
    pts = pts[:40] + [pts[40]] * 3 + pts[40:]
    doc, msp = new_doc()
    msp.add_lwpolyline(pts[::-1], dxfattribs={"layer": "ACCEL"})
    save(doc, "right_to_left_duplicates.dxf")


def tables():
    t, a = sampled([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 25.0, "cycloidal", 1.0)
    a = scale_lobe(t, a, 135, 180, 0.97)
    lines = ["# cycloidal dwell-rise-dwell-return, decelerating part of the rise 3 % short", "theta_deg,accel"]
    lines += [f"{x:.1f},{y:.9f}" for x, y in zip(t, a)]
    (HERE.parent / "law_table.csv").write_text("\n".join(lines) + "\n")
    lines = ["# european spreadsheet export: semicolon separator, decimal comma, no 360 row", "phi;a"]
    lines += [f"{x:.1f};{y:.9f}".replace(".", ",") for x, y in zip(t[:-1], a[:-1])]
    (HERE.parent / "law_table_semicolon.txt").write_text("\n".join(lines) + "\n")


def main():
    HERE.mkdir(parents=True, exist_ok=True)
    for make in (balanced_drdr, fig2_unbalanced, drrd_unbalanced, constant_acceleration_jumps, r12_polyline,
                 spline_law, line_chain, drawing_with_axes, press_feed_sheet, right_to_left_duplicates, tables):
        make()
    print(f"samples written to {HERE.parent}")


if __name__ == "__main__":
    main()
