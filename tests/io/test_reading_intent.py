"""Drawings read as the designer meant them, or refused with one line that says why (issue 25, items 2, 3, 6).

Every law here is defined by its own points in this module, and its true phase boundaries are known by
construction: a rise and a return that meet with no dwell meet where the designer's lobes meet (the drawn
vertex), whether or not the drawing is balanced. The references are computed here, independently of camcad:
areas of a polyline law exactly by trapezoids, the velocity's sign change by integrating the polyline in
closed form and bisecting, plateau areas as height × width.

The drawings come from several producers: ezdxf (LWPOLYLINE, LINE chains, paper-space layouts, fit-point
splines), byte-level files written the way OpenSCAD 2019.05 (one LINE per outline edge, no header) and
2021.01 (a closed LWPOLYLINE under an AC1006 header, 6 significant digits) write them (openscad/src/io/
export_dxf.cc), and — when installed — Inkscape 1.2 (stroke to path; separate subpaths; the R12 exporter)
and FreeCAD 0.20 (Draft wires; Part.Wire.makeOffset2D outlines). Copies made by the programs are committed
in tests/fixtures/reading/ and are read always (``python tests/io/test_reading_intent.py`` regenerates them).
"""

from __future__ import annotations

import itertools
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from camcad.law.phases import parse_phases, read_phases

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "reading"
REQUIRED = os.environ.get("CAMCAD_REQUIRE_READERS") == "1"
REQUIRE_FREECAD = os.environ.get("CAMCAD_REQUIRE_FREECAD") == "1"
TIMEOUT_S = 120

# --------------------------------------------------------------------------------------------------
# The laws, in their own coordinates: u along the cycle (0..WIDTH drawing units = 0..360 deg), a up
# from the zero axis. A lobe is a sine half-wave drawn as a polyline of N_LOBE segments.
# --------------------------------------------------------------------------------------------------

WIDTH = 180.0
PEAK = 10.0
N_LOBE = 12
DEG = 360.0 / WIDTH

#: rise and return with no dwell; the rise's decelerating lobe 15 % weak: boundary at u = 90 (180 deg)
NO_DWELL = ((0, 45, PEAK), (45, 90, -0.85 * PEAK), (90, 135, -PEAK), (135, 180, PEAK))
NO_DWELL_TWIN = ((0, 45, PEAK), (45, 90, -PEAK), (90, 135, -PEAK), (135, 180, PEAK))
#: dwell, rise, return, dwell; the rise's decelerating lobe 20 % weak: boundaries 30, 210, 330 deg
DWELL_RISE_RETURN = ((0, 15, 0), (15, 60, PEAK), (60, 105, -0.8 * PEAK), (105, 135, -1.2 * PEAK),
                     (135, 165, 1.2 * PEAK), (165, 180, 0))
DWELL_RISE_RETURN_TWIN = ((0, 15, 0), (15, 60, PEAK), (60, 105, -PEAK), (105, 135, -1.2 * PEAK),
                          (135, 165, 1.2 * PEAK), (165, 180, 0))
#: a return then a rise with no dwell, the return's decelerating lobe 10 % strong: boundary 180 deg
RETURN_RISE = ((0, 45, -PEAK), (45, 90, 1.1 * PEAK), (90, 135, PEAK), (135, 180, -PEAK))
#: constant acceleration plateaus (drawn without risers): dwell, rise, dwell, return, dwell
PLATEAUS = ((0, 15, 0), (15, 45, PEAK), (45, 75, -PEAK), (75, 105, 0), (105, 135, -PEAK), (135, 165, PEAK),
            (165, 180, 0))
EXPECTED = {
    NO_DWELL: [("rise", 0, 180), ("return", 180, 360)],
    NO_DWELL_TWIN: [("rise", 0, 180), ("return", 180, 360)],
    DWELL_RISE_RETURN: [("dwell", 0, 30), ("rise", 30, 210), ("return", 210, 330), ("dwell", 330, 360)],
    DWELL_RISE_RETURN_TWIN: [("dwell", 0, 30), ("rise", 30, 210), ("return", 210, 330), ("dwell", 330, 360)],
    RETURN_RISE: [("return", 0, 180), ("rise", 180, 360)],
    PLATEAUS: [("dwell", 0, 30), ("rise", 30, 150), ("dwell", 150, 210), ("return", 210, 330), ("dwell", 330, 360)],
}


def polyline(spec, n: int = N_LOBE) -> np.ndarray:
    """The law's vertices (u, a): dwells as one segment, lobes as sine half-waves of n segments."""
    out = []
    for u0, u1, h in spec:
        u = np.array([u0, u1], float) if h == 0 else np.linspace(u0, u1, n + 1)
        a = np.zeros(2) if h == 0 else h * np.sin(np.pi * (u - u0) / (u1 - u0))
        part = np.column_stack((u, a))
        out.append(part if not out else part[1:])
    return np.vstack(out)


def plateau_lines(spec) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """The plateaus as horizontal segments (no risers)."""
    return [((float(u0), float(h)), (float(u1), float(h))) for u0, u1, h in spec]


def lobe_areas(points: np.ndarray, spec) -> list[float]:
    """∫ a dθ over each lobe of ``spec`` (θ in rad, θ = u·2π/WIDTH), exact for the polyline (trapezoids)."""
    k = 2 * math.pi / WIDTH
    areas = []
    for u0, u1, h in spec:
        if h == 0:
            continue
        inside = (points[:, 0] >= u0) & (points[:, 0] <= u1)
        part = points[inside]
        areas.append(k * float(np.sum(np.diff(part[:, 0]) * (part[1:, 1] + part[:-1, 1]) / 2)))
    return areas


def velocity_zero(points: np.ndarray, start_u: float, lo_u: float, hi_u: float) -> float:
    """Where the velocity (integrated from rest at ``start_u``) changes sign in (lo_u, hi_u), deg: the
    polyline integrated in closed form (v is quadratic on each segment), the root by bisection."""
    k = 2 * math.pi / WIDTH

    def v(u: float) -> float:
        total = 0.0
        for (u0, a0), (u1, a1) in itertools.pairwise(points):
            if u1 <= start_u or u0 >= u:
                continue
            a_lo = a0 + (a1 - a0) * (max(u0, start_u) - u0) / (u1 - u0) if u1 > u0 else a0
            b = min(u1, u)
            a_hi = a0 + (a1 - a0) * (b - u0) / (u1 - u0) if u1 > u0 else a1
            total += k * (b - max(u0, start_u)) * (a_lo + a_hi) / 2
        return total

    lo, hi = lo_u, hi_u
    assert v(lo) * v(hi) < 0
    for _ in range(80):
        mid = (lo + hi) / 2
        if v(lo) * v(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return (lo + hi) / 2 * DEG


def phases_deg(payload: dict) -> list[tuple[str, float, float]]:
    return [(p["kind"], p["start_deg"], p["end_deg"]) for p in payload["phases"]]


def assert_phases(found, expected, tol: float = 1e-6) -> None:
    assert [k for k, _, _ in found] == [k for k, _, _ in expected], found
    for (_, s, e), (_, s0, e0) in zip(found, expected):
        assert s == pytest.approx(s0, abs=tol) and e == pytest.approx(e0, abs=tol), found


def as_law(points: np.ndarray):
    """(θ rad, a) of a polyline law."""
    return np.radians(points[:, 0] * DEG), points[:, 1].copy()


# --------------------------------------------------------------------------------------------------
# Writers: ezdxf, and byte-level OpenSCAD
# --------------------------------------------------------------------------------------------------

X0, Y0 = 40.0, 120.0   # where the law sits on the sheet; its zero axis is drawn as a line


def ezdxf_law(path: Path, points: np.ndarray, *, axis: bool = True, layout: str | None = None,
              pieces: list[np.ndarray] | None = None, lines: list | None = None) -> Path:
    """An R2018 drawing (mm) with the law as one LWPOLYLINE (or ``pieces`` as LWPOLYLINEs, or ``lines`` as
    LINEs) at (X0, Y0), and its zero axis, in the model space or in a paper-space ``layout``."""
    import ezdxf

    doc = ezdxf.new("R2018")
    doc.units = 4
    space = doc.layouts.get(layout) if layout else doc.modelspace()
    shift = np.array([X0, Y0])
    if lines is not None:
        for p, q in lines:
            space.add_line(tuple(np.add(p, shift)), tuple(np.add(q, shift)))
    else:
        for part in pieces if pieces is not None else [points]:
            space.add_lwpolyline(np.asarray(part) + shift)
    if axis:
        space.add_line((X0 - 5, Y0), (X0 + WIDTH + 5, Y0))
    if layout:
        doc.modelspace().add_text("the law is on the sheet", dxfattribs={"height": 2.5})
    doc.saveas(path)
    return path


def stroke_outline(points: np.ndarray, half_width: float, round_ends: bool) -> np.ndarray:
    """The closed outline of the law stroked with half-width w: round caps and joins (OpenSCAD's hull of
    circles), or butt caps and mitre joins (Illustrator's Outline Stroke); shapely's buffer."""
    import shapely

    line = shapely.LineString(points)
    shape = line.buffer(half_width, cap_style="round" if round_ends else "flat",
                        join_style="round" if round_ends else "mitre", quad_segs=8)
    return np.array(shape.exterior.coords)[:-1]


def _g(value: float) -> str:
    """A number as C++'s ostream writes it by default (6 significant digits)."""
    return f"{value:.6g}"


def openscad_2019(rings: list[np.ndarray]) -> bytes:
    """OpenSCAD 2019.05's DXF of outlines: no header, an empty BLOCKS section, one LINE per edge."""
    out = ["  0", "SECTION", "  2", "BLOCKS", "  0", "ENDSEC", "  0", "SECTION", "  2", "ENTITIES"]
    for ring in rings:
        for p, q in zip(ring, np.roll(ring, -1, axis=0)):
            out += ["  0", "LINE", "  8", "0", " 10", _g(p[0]), " 20", _g(p[1]), " 11", _g(q[0]), " 21", _g(q[1])]
    out += ["  0", "ENDSEC", "  0", "SECTION", "  2", "OBJECTS", "  0", "DICTIONARY", "  0", "ENDSEC", "  0", "EOF"]
    return ("\n".join(out) + "\n").encode("ascii")


def openscad_2021(rings: list[np.ndarray]) -> bytes:
    """OpenSCAD 2021.01's DXF of outlines: an AC1006 header with the extents, LTYPE/LAYER/STYLE tables,
    an empty BLOCKS section and each outline as one closed LWPOLYLINE."""
    every = np.vstack(rings)
    lo, hi = every.min(axis=0), every.max(axis=0)
    out = ["999", "DXF from OpenSCAD", "  0", "SECTION", "  2", "HEADER", "  9", "$ACADVER", "  1", "AC1006",
           "  9", "$INSBASE", " 10", "0.0", " 20", "0.0", " 30", "0.0",
           "  9", "$EXTMIN", " 10", _g(lo[0]), " 20", _g(lo[1]), "  9", "$EXTMAX", " 10", _g(hi[0]), " 20", _g(hi[1]),
           "  9", "$LINMIN", " 10", _g(lo[0]), " 20", _g(lo[1]), "  9", "$LINMAX", " 10", _g(hi[0]), " 20", _g(hi[1]),
           "  0", "ENDSEC", "  0", "SECTION", "  2", "TABLES",
           "  0", "TABLE", "  2", "LTYPE", " 70", "1", "  0", "LTYPE", "  2", "CONTINUOUS", " 70", "64", "  3",
           "Solid line", " 72", "65", " 73", "0", " 40", "0.000000", "  0", "ENDTAB",
           "  0", "TABLE", "  2", "LAYER", " 70", "6", "  0", "LAYER", "  2", "0", " 70", "64", " 62", "7", "  6",
           "CONTINUOUS", "  0", "ENDTAB", "  0", "TABLE", "  2", "STYLE", " 70", "0", "  0", "ENDTAB",
           "  0", "ENDSEC", "  0", "SECTION", "  2", "BLOCKS", "  0", "ENDSEC", "  0", "SECTION", "  2", "ENTITIES"]
    for ring in rings:
        out += ["  0", "LWPOLYLINE", "100", "AcDbEntity", "  8", "0", "100", "AcDbPolyline", " 90", str(len(ring)),
                " 70", "1"]
        for x, y in ring:
            out += [" 10", _g(x), " 20", _g(y)]
    out += ["  0", "ENDSEC", "  0", "EOF"]
    return ("\n".join(out) + "\n").encode("ascii")


SCAD_HALF_WIDTH = 0.25


def openscad_rings() -> list[np.ndarray]:
    """The no-dwell unbalanced law stroked as OpenSCAD draws a line (the hull of circles: round joins and
    caps), and its zero axis as a thin rectangle (square(), the only way to draw it there), at (X0, Y0)."""
    law = stroke_outline(polyline(NO_DWELL), SCAD_HALF_WIDTH, round_ends=True) + np.array([X0, Y0])
    w = SCAD_HALF_WIDTH
    axis = np.array([[X0 - 5, Y0 - w], [X0 + WIDTH + 5, Y0 - w], [X0 + WIDTH + 5, Y0 + w], [X0 - 5, Y0 + w]])
    return [law, axis]


# --------------------------------------------------------------------------------------------------
# Programs: Inkscape (stroke to path, separate subpaths, the R12 exporter) and FreeCAD (Draft wires,
# makeOffset2D)
# --------------------------------------------------------------------------------------------------

PAGE_H = 297.0
SVG_X0, SVG_AXIS = 15.0, 150.0   # the law's start and zero axis on the SVG page (mm, y down)
INK_HALF_WIDTH = 0.25


def _svg_d(points: np.ndarray) -> str:
    return "M " + " L ".join(f"{SVG_X0 + u:.6f},{SVG_AXIS - a:.6f}" for u, a in points)


def svg_document(paths: list[tuple[str, str, float]]) -> str:
    """An A4 SVG (mm): (id, d, stroke width) paths, and the zero axis as a path of its own."""
    axis = f"M {SVG_X0 - 5:.6f},{SVG_AXIS:.6f} L {SVG_X0 + WIDTH + 5:.6f},{SVG_AXIS:.6f}"
    body = "".join(f'  <path id="{pid}" d="{d}" stroke="black" stroke-width="{w:g}" fill="none"/>\n'
                   for pid, d, w in paths)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="210mm" height="{PAGE_H:g}mm" '
            f'viewBox="0 0 210 {PAGE_H:g}">\n{body}'
            f'  <path id="axis" d="{axis}" stroke="black" stroke-width="0.1" fill="none"/>\n</svg>\n')


def _run(args: list[str], **kwargs) -> subprocess.CompletedProcess:
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    return subprocess.run(args, check=False, capture_output=True, text=True, timeout=TIMEOUT_S, env=env, **kwargs)


def make_inkscape(folder: Path) -> dict[str, Path]:
    """Inkscape 1.2's R12 exporter on: the dwell-rise-return-dwell law stroked 0.5 mm and turned into its
    outline by Stroke to Path (object-stroke-to-path); the plateaus as subpaths of one path with no risers;
    the law in two paths whose ends miss each other by 1e-4 of its width; the no-dwell law as one path."""
    sources = {
        "inkscape_outline": [("law", _svg_d(polyline(DWELL_RISE_RETURN)), 2 * INK_HALF_WIDTH)],
        "inkscape_plateaus": [("law", " ".join(f"M {SVG_X0 + p[0]:.6f},{SVG_AXIS - p[1]:.6f} "
                                                f"L {SVG_X0 + q[0]:.6f},{SVG_AXIS - q[1]:.6f}"
                                                for p, q in plateau_lines(PLATEAUS)), 0.3)],
        "inkscape_gap": [("rise", _svg_d(polyline(DWELL_RISE_RETURN_TWIN)[:2 * N_LOBE + 2]), 0.3),
                         ("return", _svg_d(polyline(DWELL_RISE_RETURN_TWIN)[2 * N_LOBE + 1:] + [GAP, 0.0]), 0.3)],
        "inkscape_no_dwell": [("law", _svg_d(polyline(NO_DWELL)), 0.3)],
    }
    out = {}
    for name, paths in sources.items():
        svg = folder / f"{name}.svg"
        svg.write_text(svg_document(paths))
        out[name] = folder / f"{name}.dxf"
        stroke = "select-by-id:law;object-stroke-to-path;" if name == "inkscape_outline" else ""
        _run(["inkscape", f"--actions={stroke}export-type:dxf;export-filename:{out[name]};export-do", str(svg)])
        assert out[name].exists() and out[name].stat().st_size > 0, name
    return out


FC_X0, FC_Y0 = 20.0, 80.0
FC_HALF_WIDTH = 0.3
GAP = 1e-4 * WIDTH   # a missed snap: 1e-4 of the law's width


def freecad_script(folder: Path) -> str:
    """A freecadcmd script writing with importDXF.export: the unbalanced dwell-rise-return-dwell law as a
    Draft wire with its axis; the plateaus as separate wires; the no-dwell law's outline made by
    Part.Wire.makeOffset2D (an open wire offset both ways: round ends) with the axis; the law as two
    wires whose ends miss each other by GAP."""
    shift = np.array([FC_X0, FC_Y0])

    def listed(points) -> list[tuple[float, float]]:
        return [(float(x), float(y)) for x, y in np.asarray(points, dtype=float)]

    law = listed(polyline(DWELL_RISE_RETURN) + shift)
    no_dwell = listed(polyline(NO_DWELL) + shift)
    plateaus = [listed([np.add(p, shift), np.add(q, shift)]) for p, q in plateau_lines(PLATEAUS)]
    twin = polyline(DWELL_RISE_RETURN_TWIN)
    first = listed(twin[:2 * N_LOBE + 2] + shift)
    second = listed(twin[2 * N_LOBE + 1:] + shift + np.array([GAP, 0.0]))
    axis = [(FC_X0 - 5, FC_Y0), (FC_X0 + WIDTH + 5, FC_Y0)]
    return f"""
import FreeCAD, Draft, Part, importDXF
V = FreeCAD.Vector
def wire(points):
    return Draft.make_wire([V(x, y, 0) for x, y in points])
doc = FreeCAD.newDocument("laws")
law, axis = wire({law!r}), wire({axis!r})
doc.recompute()
importDXF.export([law, axis], {str(folder / "freecad_rise_return.dxf")!r})
parts = [wire(p) for p in {plateaus!r}]
doc.recompute()
importDXF.export(parts, {str(folder / "freecad_plateaus.dxf")!r})
shape = Part.Wire(Part.makePolygon([V(x, y, 0) for x, y in {no_dwell!r}]))
outline = doc.addObject("Part::Feature", "Outline")
outline.Shape = shape.makeOffset2D({FC_HALF_WIDTH!r}, 0, False, False, False)
axis2 = wire({axis!r})
doc.recompute()
importDXF.export([outline, axis2], {str(folder / "freecad_outline.dxf")!r})
a, b, axis3 = wire({first!r}), wire({second!r}), wire({axis!r})
doc.recompute()
importDXF.export([a, b, axis3], {str(folder / "freecad_gap.dxf")!r})
print("camcad-fixtures-written")
"""


def make_freecad(folder: Path) -> dict[str, Path]:
    script = folder / "make.py"
    script.write_text(freecad_script(folder))
    done = _run(["freecadcmd", "-c", f"exec(open({str(script)!r}).read())"], stdin=subprocess.DEVNULL)
    assert "camcad-fixtures-written" in done.stdout, done.stdout[-2000:] + done.stderr[-2000:]
    return {name: folder / f"{name}.dxf" for name in
            ("freecad_rise_return", "freecad_plateaus", "freecad_outline", "freecad_gap")}


GDAL_X0, GDAL_Y0 = 1000.0, 500.0


def make_gdal(folder: Path) -> dict[str, Path]:
    """GDAL's ogr2ogr -f DXF (LWPOLYLINEs from its template, $INSUNITS 1) on GeoJSON: the no-dwell law with its
    axis, and the balanced twin in two line strings whose ends miss each other by GAP in x."""
    shift = np.array([GDAL_X0, GDAL_Y0])
    axis = [[GDAL_X0 - 5, GDAL_Y0], [GDAL_X0 + WIDTH + 5, GDAL_Y0]]
    twin = polyline(DWELL_RISE_RETURN_TWIN)
    sources = {"gdal_no_dwell": [axis, (polyline(NO_DWELL) + shift).tolist()],
               "gdal_gap": [axis, (twin[:2 * N_LOBE + 2] + shift).tolist(),
                            (twin[2 * N_LOBE + 1:] + shift + [GAP, 0.0]).tolist()]}
    out = {}
    for name, lines in sources.items():
        source = folder / f"{name}.geojson"
        source.write_text(json.dumps({"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": c}}
            for c in lines]}))
        out[name] = folder / f"{name}.dxf"
        done = _run(["ogr2ogr", "-f", "DXF", str(out[name]), str(source)])
        assert done.returncode == 0 and out[name].exists(), done.stderr
    return out


def make_byte_level(folder: Path) -> dict[str, Path]:
    out = {}
    for name, data in (("openscad_2019", openscad_2019(openscad_rings())),
                       ("openscad_2021", openscad_2021(openscad_rings()))):
        out[name] = folder / f"{name}.dxf"
        out[name].write_bytes(data)
    return out


def make_ezdxf(folder: Path) -> dict[str, Path]:
    """ezdxf-made drawings: the laws as LWPOLYLINEs, a paper-space layout, an outline with butt caps and
    mitre joins (Illustrator's Outline Stroke), plateaus as LINEs, a missed snap, an interpolating spline."""
    out = {"ezdxf_no_dwell": ezdxf_law(folder / "ezdxf_no_dwell.dxf", polyline(NO_DWELL)),
           "ezdxf_no_dwell_twin": ezdxf_law(folder / "ezdxf_no_dwell_twin.dxf", polyline(NO_DWELL_TWIN)),
           "ezdxf_rise_return": ezdxf_law(folder / "ezdxf_rise_return.dxf", polyline(DWELL_RISE_RETURN)),
           "ezdxf_rise_return_twin": ezdxf_law(folder / "ezdxf_rise_return_twin.dxf",
                                               polyline(DWELL_RISE_RETURN_TWIN)),
           "ezdxf_return_rise": ezdxf_law(folder / "ezdxf_return_rise.dxf", polyline(RETURN_RISE)),
           "ezdxf_paperspace": ezdxf_law(folder / "ezdxf_paperspace.dxf", polyline(DWELL_RISE_RETURN),
                                         layout="Layout1"),
           "ezdxf_plateaus": ezdxf_law(folder / "ezdxf_plateaus.dxf", None, lines=plateau_lines(PLATEAUS)),
           "ezdxf_outline": ezdxf_law(folder / "ezdxf_outline.dxf", None,
                                      pieces=[np.vstack((ring := stroke_outline(polyline(DWELL_RISE_RETURN), 0.25,
                                                                                round_ends=False), ring[:1]))]),
           }
    twin = polyline(DWELL_RISE_RETURN_TWIN)
    second = twin[2 * N_LOBE + 1:].copy()
    second[0, 1] += GAP     # the return's first vertex snapped GAP above the rise's last one
    out["ezdxf_gap"] = ezdxf_law(folder / "ezdxf_gap.dxf", None, pieces=[twin[:2 * N_LOBE + 2], second])
    return out


# what each drawing holds: (the law's spec, a note it must carry, phase tolerance deg, area tolerance
# as a fraction of the largest lobe's area)
CASES = {
    "ezdxf_no_dwell": (NO_DWELL, "the drawn vertex where the acceleration touches zero", 1e-6, 1e-9),
    "ezdxf_no_dwell_twin": (NO_DWELL_TWIN, None, 1e-6, 1e-9),
    "ezdxf_rise_return": (DWELL_RISE_RETURN, "the drawn vertex where the acceleration touches zero", 1e-6, 1e-9),
    "ezdxf_rise_return_twin": (DWELL_RISE_RETURN_TWIN, None, 1e-6, 1e-9),
    "ezdxf_return_rise": (RETURN_RISE, "the drawn vertex where the acceleration touches zero", 1e-6, 1e-9),
    "ezdxf_paperspace": (DWELL_RISE_RETURN, "read from the paper-space layout 'Layout1'", 1e-6, 1e-9),
    "ezdxf_plateaus": (PLATEAUS, "plateaus drawn without risers joined by 6 vertical jumps", 1e-6, 1e-9),
    "ezdxf_outline": (DWELL_RISE_RETURN, "is the outline of a stroke of half-width 0.25", 0.5, 1e-3),
    "ezdxf_gap": (DWELL_RISE_RETURN_TWIN, "joined as a missed snap", 1e-6, 1e-6),
    "openscad_2019": (NO_DWELL, "is the outline of a stroke of half-width 0.25", 0.5, 1e-3),
    "openscad_2021": (NO_DWELL, "is the outline of a stroke of half-width 0.25", 0.5, 1e-3),
    "inkscape_outline": (DWELL_RISE_RETURN, "is the outline of a stroke of half-width 0.25", 0.5, 1e-3),
    "inkscape_plateaus": (PLATEAUS, "plateaus drawn without risers joined by 6 vertical jumps", 1e-4, 1e-4),
    "inkscape_gap": (DWELL_RISE_RETURN_TWIN, "joined as a missed snap", 0.05, 2e-4),
    "inkscape_no_dwell": (NO_DWELL, "the drawn vertex where the acceleration touches zero", 1e-4, 1e-4),
    "freecad_rise_return": (DWELL_RISE_RETURN, "the drawn vertex where the acceleration touches zero", 1e-3, 1e-5),
    "freecad_plateaus": (PLATEAUS, "plateaus drawn without risers joined by 6 vertical jumps", 1e-3, 1e-5),
    "freecad_outline": (NO_DWELL, "is the outline of a stroke of half-width 0.3", 0.6, 1e-3),
    "freecad_gap": (DWELL_RISE_RETURN_TWIN, "joined as a missed snap", 0.05, 2e-4),
    "gdal_no_dwell": (NO_DWELL, "the drawn vertex where the acceleration touches zero", 1e-6, 1e-9),
    "gdal_gap": (DWELL_RISE_RETURN_TWIN, "joined as a missed snap", 0.05, 2e-4),
}
MAKERS = {"inkscape": make_inkscape, "freecad": make_freecad, "gdal": make_gdal}


def _program(case: str) -> str | None:
    return case.split("_")[0] if case.split("_")[0] in MAKERS else None


def _available(program: str) -> bool:
    return shutil.which({"inkscape": "inkscape", "freecad": "freecadcmd", "gdal": "ogr2ogr"}[program]) is not None


def _need(program: str) -> None:
    if _available(program):
        return
    if REQUIRED and (program != "freecad" or REQUIRE_FREECAD):
        pytest.fail(f"{program} is not installed but CAMCAD_REQUIRE_READERS=1")
    pytest.skip(f"{program} is not installed")


def _check(cli, path: Path, *options: str) -> dict:
    result = cli("check", path, "--json", *options)
    assert result.code in (0, 1), result.err
    return result.json()


def assert_read_as_meant(case: str, payload: dict) -> None:
    """The phases of the law's construction, its lobes' areas (trapezoids of its own vertices, or height ×
    width for plateaus), and the note that says what was decided."""
    spec, note, phase_tol, area_tol = CASES[case]
    assert_phases(phases_deg(payload), EXPECTED[spec], phase_tol)
    if spec is PLATEAUS:
        k = 2 * math.pi / WIDTH
        reference = [k * (u1 - u0) * h for u0, u1, h in spec if h]
    else:
        reference = lobe_areas(polyline(spec), spec)
    names = ["rise_accel", "rise_decel", "return_accel", "return_decel"]
    got = [payload["areas"][n] for n in names]
    if spec is RETURN_RISE:   # the return comes first: its lobes are the first two
        reference = reference[2:] + reference[:2]
    scale = max(abs(r) for r in reference)
    for name, value, expected in zip(names, got, reference):
        assert value == pytest.approx(expected, abs=area_tol * scale), (name, payload["areas"])
    if note:
        assert any(note in n for n in payload["notes"]), payload["notes"]
    else:
        assert not any("drawn vertex" in n or "velocity changes sign" in n for n in payload["notes"])


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """Drawings made now: ezdxf and byte-level always, the programs' when installed ({case: path})."""
    cache: dict[str, Path] = {}
    cache.update(make_ezdxf(tmp_path_factory.mktemp("ezdxf")))
    cache.update(make_byte_level(tmp_path_factory.mktemp("bytes")))
    done: set[str] = set()

    def get(case: str) -> Path:
        program = _program(case)
        if program and program not in done:
            _need(program)
            cache.update(MAKERS[program](tmp_path_factory.mktemp(program)))
            done.add(program)
        return cache[case]

    return get


# --------------------------------------------------------------------------------------------------
# Every producer: read as meant
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "the laws' construction: boundaries where their lobes meet; lobe areas by "
                                      "trapezoids of their own vertices, plateaus height x width")
@pytest.mark.parametrize("case", list(CASES))
def test_made_now_reads_as_meant(case, made, cli):
    assert_read_as_meant(case, _check(cli, made(case)))


@pytest.mark.reference("closed form", "the laws' construction (as test_made_now_reads_as_meant)")
@pytest.mark.parametrize("case", [c for c in CASES if _program(c) or c.startswith("openscad")])
def test_committed_drawing_reads_as_meant(case, cli):
    path = FIXTURES / f"{case}.dxf"
    assert path.exists(), f"{path} is missing: run python tests/io/test_reading_intent.py"
    assert_read_as_meant(case, _check(cli, path))


@pytest.mark.reference("property", "the committed byte-level files are what this module writes")
def test_byte_level_files_are_what_the_fixtures_hold():
    for name, data in (("openscad_2019", openscad_2019(openscad_rings())),
                       ("openscad_2021", openscad_2021(openscad_rings()))):
        assert (FIXTURES / f"{name}.dxf").read_bytes() == data, name


@pytest.mark.reference("property", "the reading notes are printed and in the JSON")
def test_notes_are_printed_and_in_the_json(made, cli):
    path = made("ezdxf_no_dwell")
    payload = _check(cli, path)
    text = cli("check", path)
    note = next(n for n in payload["notes"] if "drawn vertex" in n)
    assert note in text.out


# --------------------------------------------------------------------------------------------------
# Phase boundaries between motions with no dwell
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "boundaries by construction; the velocity's zero by integrating the "
                                      "polyline in closed form and bisecting")
@pytest.mark.parametrize("spec, start_u, window", [(NO_DWELL, 0.0, (60.0, 150.0)),
                                                   (DWELL_RISE_RETURN, 15.0, (80.0, 130.0)),
                                                   (RETURN_RISE, 0.0, (60.0, 150.0))])
def test_unbalanced_laws_split_at_the_drawn_vertex_not_the_velocity_zero(spec, start_u, window):
    points = polyline(spec)
    x, a = as_law(points)
    reading = read_phases(x, a, 2 * math.pi)
    assert_phases([(p.kind, math.degrees(p.start), math.degrees(p.end)) for p in reading.phases], EXPECTED[spec])
    # the velocity changes sign far from the drawn vertex (the law is unbalanced): the note names both
    v_zero = velocity_zero(points, start_u, *window)
    boundary = next(e for k, _, e in EXPECTED[spec] if k in ("rise", "return") and e not in (330, 360))
    assert abs(v_zero - boundary) > 5.0
    note = next(n for n in reading.notes if "drawn vertex" in n)
    assert f"taken at {boundary:g} deg" in note
    quoted = float(note.split("velocity changes sign (")[1].split(" deg")[0])
    assert quoted == pytest.approx(v_zero, abs=1e-6)


@pytest.mark.reference("closed form", "boundaries by construction (the balanced twins)")
@pytest.mark.parametrize("spec", [NO_DWELL_TWIN, DWELL_RISE_RETURN_TWIN])
def test_balanced_twins_read_the_same_with_nothing_to_say(spec):
    x, a = as_law(polyline(spec))
    reading = read_phases(x, a, 2 * math.pi)
    assert_phases([(p.kind, math.degrees(p.start), math.degrees(p.end)) for p in reading.phases], EXPECTED[spec])
    assert reading.notes == ()


@pytest.mark.reference("closed form", "boundary by construction: the vertex drawn 2 % of the peak past the zero")
def test_a_vertex_drawn_a_hair_past_the_zero_is_the_boundary():
    points = polyline(NO_DWELL)
    x, a = as_law(points)
    middle = int(np.flatnonzero(points[:, 0] == 90.0)[0])
    a[middle] = 0.03 * PEAK          # the two negative lobes meet 3 % of the peak above the axis
    reading = read_phases(x, a, 2 * math.pi)
    assert [(p.kind, round(math.degrees(p.start), 9), round(math.degrees(p.end), 9)) for p in reading.phases] == \
        [("rise", 0.0, 180.0), ("return", 180.0, 360.0)]
    assert any("crosses zero" in n for n in reading.notes), reading.notes


@pytest.mark.reference("closed form", "boundary by construction: sin² lobes meet at 180 deg with zero slope")
def test_lobes_meeting_the_zero_tangentially_meet_there():
    # sin² lobes (zero acceleration and zero jerk at their ends, like a 4-5-6-7 polynomial) sampled every
    # 0.5 deg; the rise's decelerating lobe 15 % weak: the velocity changes sign far from 180 deg
    theta = np.arange(0.0, 360.25, 0.5)
    lobe = np.sin(np.radians(theta) * 2) ** 2
    a = np.where(theta < 90, 1.0, np.where(theta < 180, -0.85, np.where(theta < 270, -1.0, 1.0))) * lobe
    reading = read_phases(np.radians(theta), a, 2 * math.pi)
    assert [(p.kind, math.degrees(p.start), math.degrees(p.end)) for p in reading.phases] == \
        [("rise", 0.0, pytest.approx(180.0, abs=1e-9)), ("return", pytest.approx(180.0, abs=1e-9), 360.0)]
    assert any("drawn vertex" in n for n in reading.notes)


@pytest.mark.reference("property", "a far dwell drawn wavering about the zero (a filtered law) shows no vertex: "
                                   "the velocity's zero is the boundary and the law stays balanced")
def test_an_acceleration_wavering_about_the_zero_is_no_drawn_vertex():
    # a balanced rise (sin 4θ over 0..90 deg) and return (−sin 4θ over 270..360 deg), and between them a far
    # dwell drawn wavering about the zero by 1 % of the peak
    theta = np.arange(0.0, 360.25, 0.25)
    t = np.radians(theta)
    a = np.where(theta <= 90, np.sin(4 * t), np.where(theta >= 270, -np.sin(4 * t), 0.01 * np.sin(60 * t)))
    reading = read_phases(t, a, 2 * math.pi)
    rise_end = next(p.end for p in reading.phases if p.kind == "rise")
    from camcad.law.law import PiecewiseLinearLaw

    law = PiecewiseLinearLaw(t, a, 2 * math.pi, reading.phases)
    assert abs(law.kinematics(np.array([rise_end])).v[0]) < 1e-9
    assert not any("drawn vertex" in n for n in reading.notes)
    assert any("wavers about the zero (no single vertex) between their lobes" in n for n in reading.notes)


@pytest.mark.reference("property", "a law whose acceleration never reaches zero between rise and return: the "
                                   "velocity's zero is the only boundary it shows, and --phases restates it")
def test_no_zero_between_the_lobes_uses_the_velocity_and_says_how_to_state_it():
    # a harmonic rise and return with no dwell, unbalanced: a = cos θ, the return's half 10 % stronger
    theta = np.radians(np.arange(0.0, 360.5, 1.0))
    a = np.cos(theta) * np.where(theta > math.pi, 1.1, 1.0)
    reading = read_phases(theta, a, 2 * math.pi)
    note = next(n for n in reading.notes if "does not reach zero between their lobes" in n)
    stated = note.split('--phases "')[1].rstrip('"')
    again = parse_phases(stated, 360.0)
    assert [(p.kind, round(math.degrees(p.start), 5), round(math.degrees(p.end), 5)) for p in again] == \
        [(p.kind, round(math.degrees(p.start), 5), round(math.degrees(p.end), 5)) for p in reading.phases]
    # the boundary is where v = 0: v(θ) = sin θ on the rise (closed form), so 180 deg
    assert math.degrees(reading.phases[0].end) == pytest.approx(180.0, abs=1e-6)


@pytest.mark.reference("closed form", "lobe areas 50 - 30 - 20: the velocity changes sign at 200 deg, nearer 220")
def test_several_zeros_between_the_lobes_are_named():
    # the decelerating and accelerating lobes between rise and return drawn as three lobes touching zero twice
    spec = ((0, 50, PEAK), (50, 80, -PEAK), (80, 110, -PEAK), (110, 140, -PEAK), (140, 180, PEAK))
    x, a = as_law(polyline(spec))
    reading = read_phases(x, a, 2 * math.pi)
    note = next(n for n in reading.notes if "reaches zero at 2 places" in n)
    assert "(160, 220 deg)" in note and "--phases" in note
    # the velocity changes sign at u = 100 (200 deg: lobe areas 50 - 30 - 20 in units of P·2/π): 220 is nearer
    assert math.degrees(reading.phases[0].end) == pytest.approx(220.0, abs=1e-9)


@pytest.mark.reference("property", "the return's lobes were balanced as drawn, the rise's decelerating lobe 15 % "
                                   "weak: the correction's area goes to the rise")
def test_fix_corrects_the_lobes_that_are_wrong(made, cli, tmp_path):
    source = tmp_path / "law.dxf"
    shutil.copy(made("ezdxf_no_dwell"), source)
    before = _check(cli, source)
    assert before["velocity_closure"]["rise"] > 0.1    # the rise is the unbalanced motion
    assert before["areas"]["return_accel"] == pytest.approx(-before["areas"]["return_decel"], rel=1e-9)
    out = tmp_path / "law.fixed.dxf"
    result = cli("fix", source, "-o", out, "--json", "--no-plots")
    assert result.code == 0, result.err
    after = result.json()["after"]
    assert after["balanced"]
    assert_phases(phases_deg(after), EXPECTED[NO_DWELL])
    change = {k: after["areas"][k] - before["areas"][k] for k in before["areas"]}
    # the rise's decelerating lobe takes the largest change; the return's net area stays zero
    assert abs(change["rise_decel"]) == max(abs(c) for c in change.values())
    assert abs(change["return_accel"] + change["return_decel"]) <= 1e-6 * abs(change["rise_decel"])


# --------------------------------------------------------------------------------------------------
# Missed snaps, plateaus, outlines, paper space: the refusals
# --------------------------------------------------------------------------------------------------

def _one_line(result) -> str:
    assert result.code == 2, result.out
    lines = result.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error: "), result.err
    return lines[0]


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_gap_larger_than_a_missed_snap_is_refused_naming_it(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)   # the one line names the file: a short name keeps it whole
    twin = polyline(DWELL_RISE_RETURN_TWIN)
    path = ezdxf_law(Path("gap.dxf"), None, pieces=[twin[:2 * N_LOBE + 2], twin[2 * N_LOBE + 1:] + [0.5, 0.0]])
    line = _one_line(cli("check", path))
    assert "close that gap" in line and "0.5 drawing units short of LWPOLYLINE" in line


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_plateaus_that_no_jump_can_join_are_refused_naming_the_place(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    lines = plateau_lines(PLATEAUS) + [((45.0, 5.0), (60.0, 5.0))]    # a third loose end where two plateaus meet
    line = _one_line(cli("check", ezdxf_law(Path("plateaus.dxf"), None, lines=lines)))
    assert "plateaus drawn without risers cannot be joined: 3 loose ends meet at x = 85" in line


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_horizontal_lines_that_do_not_meet_get_advice_that_helps(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    lines = [((0.0, 0.0), (30.0, 0.0)), ((35.0, 10.0), (90.0, 10.0)), ((95.0, -10.0), (150.0, -10.0))]
    line = _one_line(cli("check", ezdxf_law(Path("flat.dxf"), None, lines=lines, axis=False)))
    assert "only straight lines, horizontal ones at 3 heights" in line and "--handle" not in line
    assert "draw the jumps between them" in line


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_closed_curve_that_is_not_a_band_is_still_refused(cli, tmp_path):
    circle = np.column_stack((50 * np.cos(np.linspace(0, 2 * np.pi, 181)), 50 * np.sin(np.linspace(0, 2 * np.pi, 181))))
    line = _one_line(cli("check", ezdxf_law(tmp_path / "cam.dxf", None, pieces=[circle], axis=False)))
    assert "it is closed" in line


@pytest.mark.reference("property", "a drawing with entities is never called empty; its contents are listed")
def test_no_entities_is_never_said_of_a_drawing_that_holds_some(cli, tmp_path):
    import ezdxf

    doc = ezdxf.new()
    doc.layouts.get("Layout1").add_text("law to come")
    doc.modelspace().add_point((0, 0))
    doc.saveas(tmp_path / "text.dxf")
    line = _one_line(cli("check", tmp_path / "text.dxf"))
    assert "1 POINT in the model space; 1 TEXT in the layout 'Layout1'" in line and "no entities" not in line
    ezdxf.new().saveas(tmp_path / "empty.dxf")
    assert "no entities in the model space or any layout" in _one_line(cli("check", tmp_path / "empty.dxf"))


@pytest.mark.reference("property", "a model space of block references without curves: the law read from the sheet, "
                                   "said so")
def test_a_model_space_of_block_references_without_curves_sends_the_reader_to_the_sheet(cli, tmp_path):
    import ezdxf

    doc = ezdxf.new("R2018")
    doc.blocks.new("TITLE").add_text("title block")
    doc.modelspace().add_blockref("TITLE", (0, 0))
    sheet = doc.layouts.get("Layout1")
    sheet.add_lwpolyline(polyline(DWELL_RISE_RETURN) + [X0, Y0])
    sheet.add_line((X0 - 5, Y0), (X0 + WIDTH + 5, Y0))
    doc.saveas(tmp_path / "sheet.dxf")
    payload = _check(cli, tmp_path / "sheet.dxf")
    assert_phases(phases_deg(payload), EXPECTED[DWELL_RISE_RETURN])
    assert payload["notes"][0] == ("the model space holds no curves (1 INSERT, 1 TEXT): the law is read from the "
                                   "paper-space layout 'Layout1'")


@pytest.mark.reference("property", "a paper-space law is corrected in its layout, the model space untouched")
def test_a_paper_space_law_is_corrected_in_its_layout(made, cli, tmp_path):
    import ezdxf

    source = tmp_path / "sheet.dxf"
    shutil.copy(made("ezdxf_paperspace"), source)
    out = tmp_path / "sheet.fixed.dxf"
    result = cli("fix", source, "-o", out, "--json", "--no-plots")
    assert result.code == 0, result.err
    doc = ezdxf.readfile(out)
    assert [e.dxftype() for e in doc.modelspace()] == ["TEXT"]
    assert sorted(e.dxftype() for e in doc.layouts.get("Layout1")) == ["LINE", "LWPOLYLINE"]
    again = _check(cli, out)
    assert again["balanced"] and any("paper-space layout 'Layout1'" in n for n in again["notes"])


# --------------------------------------------------------------------------------------------------
# Splines drawn through dwell points
# --------------------------------------------------------------------------------------------------

#: fit points of interpolating splines: dwell points on the zero, one point at each lobe's peak
SPLINE_FITS = {
    # dwell, unbalanced rise, return with no dwell, dwell: a small overshoot in the dwells
    "small": ([(0, 0), (5, 0), (10, 0), (15, 0), (37.5, PEAK), (60, 0), (82.5, -0.8 * PEAK), (105, 0),
               (120, -1.2 * PEAK), (135, 0), (150, 1.2 * PEAK), (165, 0), (170, 0), (175, 0), (180, 0)],
              [("dwell", 0, 30), ("rise", 30, 210), ("return", 210, 330), ("dwell", 330, 360)]),
    # a long dwell given by three points after steep lobes: the spline dips by the whole peak there
    "large": ([(0, 0), (5, 0), (10, 0), (15, 0), (20, PEAK), (25, 0), (30, -PEAK), (35, 0), (36, 0), (37, 0),
               (42, -PEAK), (47, 0), (52, PEAK), (57, 0), (120, 0), (180, 0)],
              [("dwell", 0, 30), ("rise", 30, 70), ("dwell", 70, 74), ("return", 74, 114), ("dwell", 114, 360)]),
}


def fit_spline_drawing(path: Path, fits) -> Path:
    import ezdxf

    doc = ezdxf.new("R2018")
    doc.units = 4
    doc.modelspace().add_spline([(X0 + u, Y0 + a) for u, a in fits])
    doc.modelspace().add_line((X0 - 5, Y0), (X0 + WIDTH + 5, Y0))
    doc.saveas(path)
    return path


@pytest.mark.reference("closed form", "the dwells and lobe ends where the designer put the fit points")
@pytest.mark.parametrize("name", list(SPLINE_FITS))
def test_interpolating_spline_phases_come_from_its_drawn_points(cli, tmp_path, name):
    fits, expected = SPLINE_FITS[name]
    payload = _check(cli, fit_spline_drawing(tmp_path / f"{name}.dxf", fits))
    assert_phases(phases_deg(payload), expected, 1e-6)
    warning = next(n for n in payload["notes"] if "overshoots through the dwell points" in n)
    assert warning.startswith("warning: SPLINE ") and "the phases take the drawn dwell points" in warning
    if name == "large":   # more than half the peak: warned all the same
        assert float(warning.split("% of the peak")[0].split("(")[-1]) > 50.0


@pytest.mark.reference("closed form", "FreeCAD's interpolated B-spline through the fit points of "
                                      "tests/io/test_real_drawings.py: dwells at u 0..30, 90..105, 165..180")
def test_freecad_interpolated_bspline_keeps_its_phases(cli):
    payload = _check(cli, Path(__file__).resolve().parents[1] / "fixtures" / "real" / "freecad_interpolated.dxf")
    assert_phases(phases_deg(payload), [("dwell", 0, 60), ("rise", 60, 180), ("dwell", 180, 210),
                                        ("return", 210, 330), ("dwell", 330, 360)], 1e-6)


@pytest.mark.reference("property", "Bezier lobes are not taken for an interpolating spline; fitted splines are")
def test_a_designers_bezier_lobes_are_not_taken_for_an_interpolating_spline():
    import ezdxf

    from camcad.io.dxf_read import is_interpolating_cubic

    real = Path(__file__).resolve().parents[1] / "fixtures" / "real"
    splines = [e for e in ezdxf.readfile(real / "freecad_bspline.dxf").modelspace() if e.dxftype() == "SPLINE"]
    assert splines and not any(is_interpolating_cubic(e) for e in splines)
    fitted = [e for e in ezdxf.readfile(real / "freecad_interpolated.dxf").modelspace() if e.dxftype() == "SPLINE"]
    assert fitted and all(is_interpolating_cubic(e) for e in fitted)


# --------------------------------------------------------------------------------------------------
# The editor's (and fix's) tables: cam degrees, read back to the same law
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("property", "a table written from a drawn law reads back to the same law (areas, phases)")
@pytest.mark.parametrize("options", [(), ("--cycle", "180"), ("--lift", "12")])
def test_the_editors_table_reads_back_to_the_same_law(cli, tmp_path, options):
    # a drawing whose x runs 0..180 (the default maps it to 360 deg; --cycle 180 makes x the degrees)
    source = ezdxf_law(tmp_path / "law.dxf", polyline(DWELL_RISE_RETURN_TWIN) - [X0, 0.0] + [-0.0, 0.0])
    drawn = _check(cli, source, *options)
    script = tmp_path / "save.json"
    script.write_text(json.dumps([{"op": "save", "path": "law.table.csv"}]))
    result = cli("edit", source, "--script", script, "--json", *options)
    assert result.code in (0, 1), result.err
    table = tmp_path / "law.table.csv"
    lines = table.read_text().splitlines()
    header = next(line for line in lines if not line.startswith("# camcad-law:"))   # after camcad's record
    assert header == "# theta_deg,accel"
    rows = np.loadtxt(table, delimiter=",", comments="#")
    cycle = 180.0 if "--cycle" in options else 360.0
    assert rows[0, 0] == 0.0 and rows[-1, 0] == pytest.approx(cycle, abs=1e-9)
    again = _check(cli, table, *options)
    assert_phases(phases_deg(again), phases_deg(drawn), 1e-9)
    for name, value in drawn["areas"].items():
        assert again["areas"][name] == pytest.approx(value, rel=1e-9), name


@pytest.mark.reference("property", "the fixed table is in cam degrees, the note says how to read it back; it checks "
                                   "balanced")
def test_fix_writes_a_table_in_cam_degrees_and_says_how_to_read_it(cli, tmp_path):
    source = ezdxf_law(tmp_path / "law.dxf", polyline(DWELL_RISE_RETURN))
    out = tmp_path / "law.fixed.csv"
    result = cli("fix", source, "-o", out, "--json", "--cycle", "180", "--no-plots")
    assert result.code == 0, result.err
    note = next(n for n in result.json()["notes"] if n.startswith("theta_deg is the cam angle"))
    assert "0..180 deg" in note and f"zero axis y = {Y0:g}" in note and "read it back with --cycle 180" in note
    again = _check(cli, out, "--cycle", "180")
    assert again["balanced"]
    assert_phases(phases_deg(again), phases_deg(result.json()["after"]), 1e-9)


# --------------------------------------------------------------------------------------------------
# Regenerating the committed drawings
# --------------------------------------------------------------------------------------------------

def regenerate() -> None:
    """Write tests/fixtures/reading/: byte-level files always, program exports where the program is installed."""
    import tempfile

    FIXTURES.mkdir(parents=True, exist_ok=True)
    for path in make_byte_level(FIXTURES).values():
        print("wrote", path)
    with tempfile.TemporaryDirectory() as tmp:
        for program, maker in MAKERS.items():
            if not _available(program):
                print("skipped", program, "(not installed)")
                continue
            folder = Path(tmp) / program
            folder.mkdir()
            for name, path in maker(folder).items():
                shutil.copyfile(path, FIXTURES / f"{name}.dxf")
                print("wrote", FIXTURES / f"{name}.dxf")


if __name__ == "__main__":
    sys.exit(regenerate())
