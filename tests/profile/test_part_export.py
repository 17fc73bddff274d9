"""From design to part (issue 29): profile_points.csv, cutter_path.csv, profile.nc, cam.step, cam.stl, --units.

The references are built here, not by camcad: the cam's profile and the cutter's path from the closed-form laws
(Norton's cycloidal, 3-4-5, 4-5-6-7 and simple-harmonic rises) and the follower's geometry (the roller centre on
the axis x = e, turned into the cam's frame; the normal perpendicular to the tangent of that curve); the
program is run by a small G-code interpreter of this file (G0/G1/G2/G3 with I/J, G20/G21); the mesh and the
solid are measured by the divergence theorem and by the kernel reading the STEP file back, and by FreeCAD.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import re
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest
import shapely

HAVE_KERNEL = True
try:
    import OCP as _ocp  # noqa: F401
except ImportError:  # the optional extra camcad[solid] is not installed
    HAVE_KERNEL = False
needs_kernel = pytest.mark.skipif(not HAVE_KERNEL, reason="the optional CAD kernel is not installed "
                                                         "(pip install 'camcad[solid]'); CI installs it")

INCH = 25.4


# --------------------------------------------------------------------------------------------------
# closed-form references
# --------------------------------------------------------------------------------------------------

def rise(shape: str, u: np.ndarray, h: float, beta: float) -> tuple[np.ndarray, np.ndarray]:
    """s (mm) and ds/dθ (mm/rad) of a rise of h over β rad, u = (θ − θ0)/β (Norton 2009, ch. 3)."""
    if shape == "cycloidal":
        return h * (u - np.sin(2 * np.pi * u) / (2 * np.pi)), h / beta * (1 - np.cos(2 * np.pi * u))
    if shape == "poly345":
        return h * (10 * u**3 - 15 * u**4 + 6 * u**5), h / beta * (30 * u**2 - 60 * u**3 + 30 * u**4)
    if shape == "poly4567":
        return (h * (35 * u**4 - 84 * u**5 + 70 * u**6 - 20 * u**7),
                h / beta * (140 * u**3 - 420 * u**4 + 420 * u**5 - 140 * u**6))
    if shape == "harmonic":
        return h / 2 * (1 - np.cos(np.pi * u)), h * np.pi / (2 * beta) * np.sin(np.pi * u)
    raise ValueError(shape)


class Cam:
    """A dwell-rise-dwell-return cam with a translating roller follower, from the closed forms."""

    def __init__(self, rise_deg, far_deg, return_deg, lift, rise_shape, return_shape, rb, rr, offset=0.0, cw=False):
        self.b1, self.b2, self.b3 = np.radians([rise_deg, rise_deg + far_deg, rise_deg + far_deg + return_deg])
        self.lift, self.rises, self.returns = lift, rise_shape, return_shape
        self.rb, self.rr, self.e, self.sigma = rb, rr, offset, -1.0 if cw else 1.0

    def law(self, theta):
        s, v = np.zeros_like(theta), np.zeros_like(theta)
        up = theta < self.b1
        s[up], v[up] = rise(self.rises, theta[up] / self.b1, self.lift, self.b1)
        far = (theta >= self.b1) & (theta < self.b2)
        s[far] = self.lift
        back = (theta >= self.b2) & (theta < self.b3)
        beta = self.b3 - self.b2
        rs, rv = rise(self.returns, (theta[back] - self.b2) / beta, self.lift, beta)
        s[back], v[back] = self.lift - rs, -rv
        return s, v

    def pitch(self, theta):
        """Roller centre P in the cam's frame, its tangent dP/dθ and the outward unit normal."""
        s, v = self.law(theta)
        d = math.sqrt((self.rb + self.rr) ** 2 - self.e**2)
        q = np.stack((np.full_like(theta, self.e), d + s), axis=-1)
        dq = np.stack((np.zeros_like(theta), v), axis=-1)
        angle = -self.sigma * theta            # the cam has turned by σθ: its frame sees the follower turned back
        c, sn = np.cos(angle), np.sin(angle)

        def turn(p):
            return np.stack((c * p[:, 0] - sn * p[:, 1], sn * p[:, 0] + c * p[:, 1]), axis=-1)

        jq = np.stack((-q[:, 1], q[:, 0]), axis=-1)
        point, tangent = turn(q), turn(dq - self.sigma * jq)
        normal = np.stack((tangent[:, 1], -tangent[:, 0]), axis=-1)
        normal /= np.hypot(normal[:, 0], normal[:, 1])[:, None]
        normal *= np.sign(np.sum(normal * point, axis=1))[:, None]       # away from the cam centre
        return point, tangent, normal

    def profile(self, theta):
        p, _, n = self.pitch(theta)
        return p - self.rr * n

    def cutter(self, theta, radius):
        p, _, n = self.pitch(theta)
        return p + (radius - self.rr) * n


DEFAULT = Cam(120, 60, 120, 25.0, "cycloidal", "poly345", 50.0, 10.0)
#: a cam of this file's own: 4-5-6-7 rise, harmonic return, offset follower, turning clockwise
OWN = Cam(100, 50, 140, 18.0, "poly4567", "harmonic", 40.0, 8.0, offset=6.0, cw=True)
OWN_OPTIONS = ["--rise-law", "poly4567", "--return-law", "harmonic", "--phases",
               "0:100:rise,100:150:dwell,150:290:return,290:360:dwell", "--lift", "18", "--rb", "40", "--rr", "8",
               "--offset", "6", "--cw"]
FINE = np.linspace(0.0, 2 * np.pi, 100_001)[:-1]


# --------------------------------------------------------------------------------------------------
# a small G-code interpreter
# --------------------------------------------------------------------------------------------------

def interpret(text: str, step_mm: float = 0.01) -> list[tuple[str, str, np.ndarray]]:
    """Run a program: (G-code, the last comment, points along the move in mm) for every move in XY.

    G0/G1 lines, G2 (clockwise)/G3 arcs about start + (I, J) with the radius going linearly from the start's to
    the end's, G20 (inch) / G21 (mm), absolute coordinates (G90). Points every ``step_mm`` along each move."""
    scale, mode, label = 1.0, None, ""
    x = y = 0.0
    moves = []
    for raw in text.splitlines():
        comment = re.findall(r"\(([^)]*)\)", raw)
        if comment:
            label = comment[-1]
        line = re.sub(r"\([^)]*\)", "", raw).strip()
        if not line or line == "%":
            continue
        words = dict((w[0], float(w[1:])) for w in re.findall(r"[A-Z][-+.0-9]+", line) if w[0] != "G")
        for g in re.findall(r"G(\d+)", line):
            g = int(g)
            if g == 20:
                scale = INCH
            elif g == 21:
                scale = 1.0
            elif g in (0, 1, 2, 3):
                mode = g
        if "X" not in words and "Y" not in words:
            continue
        nx, ny = words.get("X", x / scale) * scale, words.get("Y", y / scale) * scale
        if mode in (0, 1):
            n = max(2, int(math.hypot(nx - x, ny - y) / step_mm) + 2)
            pts = np.column_stack((np.linspace(x, nx, n), np.linspace(y, ny, n)))
        else:
            cx, cy = x + words["I"] * scale, y + words["J"] * scale
            r0, r1 = math.hypot(x - cx, y - cy), math.hypot(nx - cx, ny - cy)
            a0, a1 = math.atan2(y - cy, x - cx), math.atan2(ny - cy, nx - cx)
            sweep = a1 - a0
            if mode == 3 and sweep <= 0:
                sweep += 2 * math.pi
            if mode == 2 and sweep >= 0:
                sweep -= 2 * math.pi
            n = max(2, int(abs(sweep) * max(r0, r1) / step_mm) + 2)
            t = np.linspace(0.0, 1.0, n)
            r, a = r0 + (r1 - r0) * t, a0 + sweep * t
            pts = np.column_stack((cx + r * np.cos(a), cy + r * np.sin(a)))
        moves.append((f"G{mode}", label, pts))
        x, y = nx, ny
    return moves


def to_polyline(points: np.ndarray, polyline: np.ndarray, closed: bool = True) -> np.ndarray:
    """Distance (mm) from each point to the polyline through ``polyline``'s vertices: to the segments on either
    side of each of the 4 nearest vertices (exact for a polyline whose vertices are dense against its
    curvature, as every one here)."""
    from scipy.spatial import cKDTree

    count = len(polyline)
    _, near = cKDTree(polyline).query(points, k=4)
    best = np.full(len(points), np.inf)
    for j in range(near.shape[1]):
        for shift in (-1, 0):
            a_index = near[:, j] + shift
            b_index = a_index + 1
            if closed:
                a_index, b_index = a_index % count, b_index % count
            else:
                a_index, b_index = np.clip(a_index, 0, count - 1), np.clip(b_index, 0, count - 1)
            a, b = polyline[a_index], polyline[b_index]
            seg = b - a
            length2 = np.einsum("ij,ij->i", seg, seg)
            t = np.clip(np.einsum("ij,ij->i", points - a, seg) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
            foot = a + t[:, None] * seg
            best = np.minimum(best, np.hypot(*(points - foot).T))
    return best


def hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    """Hausdorff distance between two closed polylines (points, mm): each one's vertices to the other's
    segments."""
    return max(float(to_polyline(a, b).max()), float(to_polyline(b, a).max()))


# --------------------------------------------------------------------------------------------------
# running camcad
# --------------------------------------------------------------------------------------------------

def run(cli, folder: Path, *args) -> Path:
    result = cli("profile", "--no-plots", "--json", "-o", folder, *map(str, args))
    assert result.code in (0, 1), result.err
    return folder


def table(path: Path) -> dict[str, np.ndarray]:
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    names = lines[0].split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {name: data[:, k] for k, name in enumerate(names)}


# --------------------------------------------------------------------------------------------------
# the contour program
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "cutter centre = roller centre + (R - Rr) * outward normal of the pitch curve, "
                                      "from Norton's closed-form laws; the program run by this file's interpreter")
@pytest.mark.parametrize("cam_name", ["default", "own"])
@pytest.mark.parametrize("radius", [5.0, 10.0])
def test_program_follows_the_exact_offset(cli, tmp_path, cam_name, radius):
    cam, options = (DEFAULT, []) if cam_name == "default" else (OWN, OWN_OPTIONS)
    folder = run(cli, tmp_path / "a", *options, "--export", "gcode,cutter", "--cutter-radius", radius,
                 "--feed", 300, "--depth", 10)
    text = (folder / "profile.nc").read_text()
    moves = interpret(text)
    contour = np.concatenate([pts for code, label, pts in moves if label.endswith("the contour") or
                              (code in ("G2", "G3") and label.endswith("the contour"))])
    reference = cam.cutter(FINE, radius)
    assert hausdorff(contour, reference) <= 0.01
    # the cutter never enters the cam: every point of the program at depth is at least R from the profile,
    # outside it (the rapid move above the stock excluded)
    outline = cam.profile(FINE)
    cut = np.concatenate([pts for code, label, pts in moves if code != "G0"])
    assert to_polyline(cut, outline).min() >= radius - 0.01
    assert not shapely.contains(shapely.Polygon(outline), shapely.points(cut[::50])).any()
    # cutter_path.csv: the exact offset, at its cam angles
    rows = table(folder / "cutter_path.csv")
    exact = cam.cutter(np.radians(rows["theta_deg"]), radius)
    table_points = np.column_stack((rows["x_mm"], rows["y_mm"]))
    assert np.abs(table_points - exact).max() <= 1e-9
    assert to_polyline(table_points, contour).max() <= 0.01      # the program passes through the table's points
    # the program: the common subset, mm, absolute, XY plane, one feed
    assert "G17 G21 G90 G94 G40" in text and text.rstrip().endswith("M30\n%") and "F300" in text


@pytest.mark.reference("property", "the same design gives the same bytes")
def test_every_part_file_is_byte_identical_across_runs(cli, tmp_path):
    kinds = "points,cutter,gcode" + (",step,stl" if HAVE_KERNEL else "")
    args = [*OWN_OPTIONS, "--export", kinds, "--cutter-radius", 5, "--feed", 250, "--thickness", 10, "--bore", 16]
    first, second = run(cli, tmp_path / "a", *args), run(cli, tmp_path / "b", *args)
    names = sorted(p.name for p in first.iterdir() if p.name != "report.json")
    assert {"profile_points.csv", "cutter_path.csv", "profile.nc"} <= set(names)
    for name in names:
        assert (first / name).read_bytes() == (second / name).read_bytes(), name


@pytest.mark.reference("closed form", "the lead arcs are tangent: the direction of travel turns by less than 1e-6 "
                                      "rad from one move to the next")
def test_the_program_is_tangent_continuous_through_its_leads(cli, tmp_path):
    folder = run(cli, tmp_path / "a", "--export", "gcode", "--cutter-radius", 5, "--feed", 300, "--depth", 10)
    moves = [pts for code, _, pts in interpret((folder / "profile.nc").read_text(), step_mm=1e-4) if code != "G0"]
    for before, after in itertools.pairwise(moves):
        if np.allclose(before[-1], before[0]) or np.allclose(after[-1], after[0]):
            continue
        t0 = before[-1] - before[-2]
        t1 = after[1] - after[0]
        turn = math.atan2(t0[0] * t1[1] - t0[1] * t1[0], t0 @ t1)
        assert abs(turn) < 2e-3     # the interpreter's own sampling step bounds this
    text = (folder / "profile.nc").read_text()
    assert text.count("(lead-in)") == 1 and text.count("(lead-out)") == 1


@pytest.mark.reference("closed form", "G41 on the nominal profile: the programmed contour is the profile itself")
def test_machine_compensation_programs_the_profile_with_g41(cli, tmp_path):
    folder = run(cli, tmp_path / "a", *OWN_OPTIONS, "--export", "gcode", "--cutter-radius", 4, "--feed", 200,
                 "--depth", 6, "--comp", "machine")
    text = (folder / "profile.nc").read_text()
    moves = interpret(text)
    contour = np.concatenate([pts for _, label, pts in moves if label.endswith("the contour")])
    assert hausdorff(contour, OWN.profile(FINE)) <= 0.01
    lines = text.splitlines()
    g41 = next(i for i, line in enumerate(lines) if "G41" in line)
    g40 = max(i for i, line in enumerate(lines) if line.startswith("G1") and "G40" in line)
    first_contour = next(i for i, line in enumerate(lines) if line.endswith("the contour)"))
    assert g41 < first_contour < g40


@pytest.mark.reference("second method", "the profile's concave radius of curvature from the circle through three "
                                        "neighbouring exact profile points")
def test_a_cutter_larger_than_a_concave_radius_is_refused_with_the_cam_angle(cli, tmp_path):
    options = ["--rise-law", "cycloidal", "--return-law", "cycloidal", "--phases",
               "0:60:rise,60:120:dwell,120:180:return,180:360:dwell", "--lift", "30", "--rb", "20", "--rr", "5",
               "--pa-rise", "0", "--pa-return", "0"]
    cam = Cam(60, 60, 60, 30.0, "cycloidal", "cycloidal", 20.0, 5.0)
    theta = np.linspace(0, 2 * np.pi, 72_001)
    x = cam.profile(theta)
    a, b, c = x[:-2], x[1:-1], x[2:]
    cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
    radius = (np.hypot(*(b - a).T) * np.hypot(*(c - b).T) * np.hypot(*(c - a).T)) / (2 * np.abs(cross))
    concave = np.where(cross > 0, radius, np.inf)     # the profile runs clockwise: a left turn is concave
    smallest = float(concave.min())
    refused = cli("profile", "--no-plots", "-o", tmp_path / "a", *options, "--export", "cutter",
                  "--cutter-radius", f"{1.1 * smallest:.4f}")
    assert refused.code == 2 and len(refused.err.strip().splitlines()) == 1
    found = float(re.search(r"at cam angle ([0-9.]+) deg", refused.err).group(1))
    at = np.degrees(theta[1:-1])[concave < 1.1 * smallest]   # where the flank is tighter than the cutter
    assert at.min() - 0.1 <= found <= at.max() + 0.1
    assert float(re.search(r"concave radius is ([0-9.]+) mm", refused.err).group(1)) == pytest.approx(smallest,
                                                                                                       rel=1e-3)
    assert not (tmp_path / "a").exists()        # nothing written
    accepted = cli("profile", "--no-plots", "-o", tmp_path / "b", *options, "--export", "cutter",
                   "--cutter-radius", f"{0.9 * smallest:.4f}")
    assert accepted.code in (0, 1), accepted.err
    assert (tmp_path / "b" / "cutter_path.csv").exists()


# --------------------------------------------------------------------------------------------------
# tables
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "profile = roller centre - Rr * outward normal (Norton's laws)")
def test_points_table_is_the_exact_profile_with_its_normals(cli, tmp_path):
    folder = run(cli, tmp_path / "a", *OWN_OPTIONS, "--export", "points", "--step-deg", "0.5")
    text = (folder / "profile_points.csv").read_text()
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert any("units: lengths in mm" in line for line in header)
    assert any("clockwise" in line for line in header) and any("e 6 mm" in line for line in header)
    rows = table(folder / "profile_points.csv")
    assert list(rows)[:3] == ["theta_deg", "x_mm", "y_mm"]
    assert len(rows["theta_deg"]) == 720
    theta = np.radians(rows["theta_deg"])
    _, _, normal = OWN.pitch(theta)
    xy = np.column_stack((rows["x_mm"], rows["y_mm"]))
    assert np.abs(xy - OWN.profile(theta)).max() <= 1e-9
    assert np.abs(np.column_stack((rows["nx"], rows["ny"])) - normal).max() <= 1e-9
    assert np.abs(rows["r_mm"] - np.hypot(*xy.T)).max() <= 1e-9
    assert np.abs(np.radians(rows["polar_deg"]) - np.arctan2(xy[:, 1], xy[:, 0]) % (2 * np.pi)).max() <= 1e-9
    pitch, _, _ = OWN.pitch(theta)
    assert np.abs(np.column_stack((rows["pitch_x_mm"], rows["pitch_y_mm"])) - pitch).max() <= 1e-9


@pytest.mark.reference("property", "chord nodes: the polygon through the rows stays within --tol-mm of the exact "
                                   "profile")
def test_points_at_the_chord_nodes(cli, tmp_path):
    folder = run(cli, tmp_path / "a", "--export", "points", "--step-deg", "chord", "--tol-mm", "0.01")
    rows = table(folder / "profile_points.csv")
    polygon = np.column_stack((rows["x_mm"], rows["y_mm"]))
    exact = DEFAULT.profile(FINE)
    assert float(to_polyline(exact, polygon).max()) <= 0.01


@pytest.mark.reference("closed form", "a groove's flanks are the pitch curve -/+ Rr along its normal; the cutter "
                                      "centre is R inside each flank")
def test_groove_cam_has_both_flanks_and_a_finishing_pass_on_each(cli, tmp_path):
    folder = run(cli, tmp_path / "a", "--groove", "--export", "points,cutter,gcode", "--cutter-radius", 6,
                 "--feed", 200, "--depth", 8)
    rows = table(folder / "cutter_path.csv")
    theta = np.radians(rows["theta_deg"])
    pitch, _, normal = DEFAULT.pitch(theta)
    assert np.abs(np.column_stack((rows["x_mm"], rows["y_mm"])) - (pitch - 4.0 * normal)).max() <= 1e-9
    assert np.abs(np.column_stack((rows["outer_x_mm"], rows["outer_y_mm"])) - (pitch + 4.0 * normal)).max() <= 1e-9
    text = (folder / "profile.nc").read_text()
    moves = interpret(text)
    slot = np.concatenate([p for _, label, p in moves if label == "groove: along the pitch curve"])
    assert hausdorff(slot, DEFAULT.pitch(FINE)[0]) <= 0.01
    for name, side in (("profile", -4.0), ("outer flank", 4.0)):
        pts = np.concatenate([p for _, label, p in moves if label == f"{name}, finishing: the contour"])
        assert hausdorff(pts, DEFAULT.pitch(FINE)[0] + side * DEFAULT.pitch(FINE)[2]) <= 0.01
    # every point of the program at depth keeps the cutter inside the groove
    cut = np.concatenate([p for code, _, p in moves if code != "G0"])
    assert to_polyline(cut, DEFAULT.profile(FINE)).min() >= 6.0 - 0.01
    assert to_polyline(cut, DEFAULT.pitch(FINE)[0] + 10.0 * DEFAULT.pitch(FINE)[2]).min() >= 6.0 - 0.01
    refused = cli("profile", "--no-plots", "-o", tmp_path / "b", "--groove", "--export", "cutter",
                  "--cutter-radius", 12)
    assert refused.code == 2 and "wider than the groove" in refused.err


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_what_the_part_needs_is_asked_for(cli, tmp_path):
    for args, needle in ((["--export", "gcode", "--feed", "100"], "--cutter-radius"),
                         (["--export", "gcode", "--cutter-radius", "5", "--depth", "3"], "--feed"),
                         (["--export", "gcode", "--cutter-radius", "5", "--feed", "100"], "--depth"),
                         (["--export", "stl"], "--thickness"),
                         (["--export", "points,dxf"], "unknown export 'dxf'"),
                         (["--units", "cm"], "use mm or in"),
                         (["--export", "points", "--step-deg", "7"], "does not divide"),
                         (["--export", "step", "--thickness", "5", "--keyway", "6,2"], "a keyway needs a bore"),
                         (["--export", "cutter", "--cutter-radius", "-1"], "--cutter-radius")):
        result = cli("profile", "--no-plots", "-o", tmp_path / "x", *args)
        assert result.code == 2, (args, result.err)
        assert needle in result.err and len(result.err.strip().splitlines()) == 1, (args, result.err)
        assert not (tmp_path / "x").exists()


@pytest.mark.reference("property", "without Open CASCADE the solids are refused in one line naming camcad[solid]")
def test_the_solids_say_what_to_install_without_the_kernel(cli, tmp_path, monkeypatch):
    import builtins

    real = builtins.__import__

    def no_kernel(name, *args, **kwargs):
        if name == "OCP" or name.startswith("OCP."):
            raise ImportError("no OCP")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_kernel)
    result = cli("profile", "--no-plots", "-o", tmp_path / "x", "--export", "step", "--thickness", "10")
    assert result.code == 2 and "pip install 'camcad[solid]'" in result.err
    assert len(result.err.strip().splitlines()) == 1 and not (tmp_path / "x").exists()


@pytest.mark.reference("property", "a scene's [export] and the command line give G20 (in) and G21 (mm) programs, the "
                                   "option over the scene")
def test_scene_export_section(tmp_path, cli):
    scene = tmp_path / "cam.toml"
    scene.write_text('name = "plate"\n[law]\nstandard = "cycloidal"\n'
                     'phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"\nlift = 20.0\n'
                     '[follower]\ntype = "roller"\nbase_radius = 40.0\nroller_radius = 10.0\n'
                     '[export]\nkinds = "points,gcode"\ncutter_radius = 5.0\nfeed = 250.0\ndepth = 6.0\n'
                     'units = "in"\n')
    result = cli("profile", scene, "--no-plots", "--json", "-o", tmp_path / "out")
    assert result.code == 0, result.err
    report = result.json()
    assert report["export"]["units"] == "in" and set(report["export"]["files"]) == {"profile_points.csv",
                                                                                     "profile.nc"}
    assert "G20" in (tmp_path / "out" / "profile.nc").read_text()
    # a command-line option is put over the scene's
    cli("profile", scene, "--no-plots", "-o", tmp_path / "mm", "--units", "mm")
    assert "G21" in (tmp_path / "mm" / "profile.nc").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(scene.read_text().replace("cutter_radius", "cuter_radius"))
    refused = cli("profile", bad, "--no-plots", "-o", tmp_path / "bad")
    assert refused.code == 2 and "cutter_radius" in refused.err


# --------------------------------------------------------------------------------------------------
# units
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "1 in = 25.4 mm exactly")
def test_inches_divide_every_length_by_25_4(cli, tmp_path):
    import ezdxf

    args = ["--export", "points,cutter,gcode", "--cutter-radius", 5, "--feed", 254, "--depth", 12.7]
    mm, inch = run(cli, tmp_path / "mm", *args), run(cli, tmp_path / "in", *args, "--units", "in")
    for name in ("profile_points.csv", "cutter_path.csv"):
        a, b = table(mm / name), table(inch / name)
        assert [k.replace("_mm", "_in") for k in a] == list(b)
        for key in a:
            expected = a[key] / INCH if key.endswith("_mm") else a[key]
            assert np.abs(b[key.replace("_mm", "_in")] - expected).max() <= 1e-12 * max(1.0, np.abs(expected).max())
    law_mm, law_in = table(mm / "law.csv"), table(inch / "law.csv")
    assert np.abs(law_in["s_in"] - law_mm["s_mm"] / INCH).max() <= 1e-12 * 25.0
    a_doc, b_doc = ezdxf.readfile(mm / "profile.dxf"), ezdxf.readfile(inch / "profile.dxf")
    assert a_doc.header["$INSUNITS"] == 4 and b_doc.header["$INSUNITS"] == 1
    a_ents, b_ents = list(a_doc.modelspace()), list(b_doc.modelspace())
    assert [e.dxftype() for e in a_ents] == [e.dxftype() for e in b_ents]
    for ea, eb in zip(a_ents, b_ents):
        if ea.dxftype() == "LWPOLYLINE":
            pa, pb = np.array(ea.get_points("xyb")), np.array(eb.get_points("xyb"))
            assert np.abs(pb[:, :2] - pa[:, :2] / INCH).max() <= 1e-12 * 10
            assert np.array_equal(pa[:, 2], pb[:, 2])                 # bulges have no unit
        elif ea.dxftype() == "CIRCLE":
            assert eb.dxf.radius == pytest.approx(ea.dxf.radius / INCH, rel=1e-12)
        elif ea.dxftype() == "LINE":
            assert np.abs(np.array(eb.dxf.end) - np.array(ea.dxf.end) / INCH).max() <= 1e-12 * 10
    a_nc, b_nc = (mm / "profile.nc").read_text(), (inch / "profile.nc").read_text()
    assert "G21" in a_nc and "G20" in b_nc and "F254" in a_nc and "F10" in b_nc
    for (ca, la, pa), (cb, lb, pb) in zip(interpret(a_nc), interpret(b_nc)):
        assert ca == cb and la == lb
        assert np.abs(pa[-1] - pb[-1]).max() <= 0.5e-5 * INCH + 0.5e-4     # each rounded to its last digit


@pytest.mark.reference("closed form", "a triangular lobe of height A over pi/2 rad and its negative: rise A pi^2/8")
def test_a_law_drawn_in_inches_is_read_and_reported_in_inches(cli, tmp_path):
    import ezdxf

    height = 8.0 / math.pi**2                       # a rise of exactly 1 (in)
    law = [(0, 0), (45, height), (90, 0), (135, -height), (180, 0), (225, -height), (270, 0), (315, height),
           (360, 0)]
    doc = ezdxf.new("R2000", units=1)
    doc.modelspace().add_lwpolyline(law)
    doc.modelspace().add_line((0, 0), (360, 0))
    path = tmp_path / "law_in.dxf"
    doc.saveas(path)
    checked = cli("check", path, "--json")
    assert checked.code == 0, checked.err
    report = checked.json()
    assert report["length_unit"] == "in" and report["rise"] == pytest.approx(1.0, rel=1e-9)
    assert any("reported in in" in note for note in report["notes"])
    assert "rise 1 in" in cli("check", path).out
    made = cli("profile", path, "--rb", 50, "--rr", 10, "--no-plots", "--json", "-o", tmp_path / "out",
               "--export", "points")
    assert made.code in (0, 1), made.err
    notes = made.json()["law"]["notes"]
    assert any("drawn in in: rise 1 in = 25.4 mm" in note for note in notes), notes
    rows = table(tmp_path / "out" / "profile_points.csv")
    assert rows["pitch_r_mm"].max() == pytest.approx(60.0 + 25.4, rel=1e-9)


# --------------------------------------------------------------------------------------------------
# solids
# --------------------------------------------------------------------------------------------------

def read_stl(path: Path) -> tuple[np.ndarray, np.ndarray, str]:
    """Binary STL → unique vertices, triangles (indices) and the header text."""
    data = path.read_bytes()
    count = struct.unpack("<I", data[80:84])[0]
    records = np.frombuffer(data[84:84 + 50 * count], dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)),
                                                             ("attr", "<u2")])
    corners = records["v"].reshape(-1, 3).astype(float)
    vertices, index = np.unique(corners, axis=0, return_inverse=True)
    return vertices, index.reshape(-1, 3), data[:80].decode("ascii").strip()


@needs_kernel
@pytest.mark.reference("closed form", "volume = (profile area - bore area) x thickness; the profile area from the "
                                      "closed-form profile (100,000 points); the mesh's volume by the divergence "
                                      "theorem")
def test_stl_is_watertight_and_holds_the_plate_volume(cli, tmp_path):
    folder = run(cli, tmp_path / "a", "--export", "stl,step,points", "--thickness", 12, "--bore", 20)
    vertices, faces, header = read_stl(folder / "cam.stl")
    assert "units mm" in header
    edges = np.sort(np.concatenate((faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]])), axis=1)
    directed = np.concatenate((faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]))
    _, uses = np.unique(edges, axis=0, return_counts=True)
    assert set(uses.tolist()) == {2}                       # every edge between exactly two triangles
    assert len(np.unique(directed, axis=0)) == len(directed)   # and run once each way: oriented consistently
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    mesh_volume = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
    expected = (shapely.Polygon(DEFAULT.profile(FINE)).area - math.pi * 10.0**2) * 12.0
    assert mesh_volume == pytest.approx(expected, rel=5e-3)
    assert vertices[:, 2].min() == 0.0 and vertices[:, 2].max() == pytest.approx(12.0, abs=1e-5)


def _read_step(path: Path):
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader

    reader = STEPControl_Reader()
    assert reader.ReadFile(str(path)) == IFSelect_RetDone
    reader.TransferRoots()
    return reader.OneShape()


def _outline_edges(shape, z: float, per_edge: int = 2000) -> list[np.ndarray]:
    """Each edge of ``shape`` in the plane z (not circles: the bore) as points along it, in order."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomAbs import GeomAbs_Circle
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    explorer = TopExp_Explorer(shape, TopAbs_EDGE)
    while explorer.More():
        curve = BRepAdaptor_Curve(TopoDS.Edge(explorer.Current()))
        explorer.Next()
        if curve.GetType() == GeomAbs_Circle:
            continue
        u = np.linspace(curve.FirstParameter(), curve.LastParameter(), per_edge)
        pts = np.array([[p.X(), p.Y(), p.Z()] for p in (curve.Value(float(t)) for t in u)])
        if np.all(np.abs(pts[:, 2] - z) < 1e-9):
            out.append(pts[:, :2])
    return out


@needs_kernel
@pytest.mark.reference("closed form", "the plate's volume from the closed-form profile area; the outline against "
                                      "profile_points.csv")
@pytest.mark.parametrize("units", ["mm", "in"])
def test_step_read_back_has_the_volume_and_the_profile(cli, tmp_path, units):
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    folder = run(cli, tmp_path / "a", "--export", "step,points", "--thickness", 12, "--bore", 20,
                 "--units", units)
    text = (folder / "cam.step").read_text()
    assert ("'INCH'" in text.upper()) == (units == "in")
    shape = _read_step(folder / "cam.step")       # the kernel reads it back in mm whatever the file's unit
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    expected = (shapely.Polygon(DEFAULT.profile(FINE)).area - math.pi * 10.0**2) * 12.0
    assert props.Mass() == pytest.approx(expected, rel=1e-4)
    rows = table(folder / "profile_points.csv")
    k = INCH if units == "in" else 1.0
    points = np.column_stack((rows[f"x_{units}"], rows[f"y_{units}"])) * k
    edges = _outline_edges(shape, 0.0)
    distance = np.min([to_polyline(points, edge, closed=False) for edge in edges], axis=0)
    assert distance.max() <= 0.005


@needs_kernel
@pytest.mark.reference("closed form", "the keyway removes W x (D/2 + H) less the part of that slot inside the bore")
def test_keyway_volume(cli, tmp_path):
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    plain = run(cli, tmp_path / "a", "--export", "step", "--thickness", 10, "--bore", 20)
    keyed = run(cli, tmp_path / "b", "--export", "step", "--thickness", 10, "--bore", 20, "--keyway", "6,2.8")
    volumes = []
    for folder in (plain, keyed):
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(_read_step(folder / "cam.step"), props)
        volumes.append(props.Mass())
    # the slot x in [-3, 3], y in [0, 12.8] less its part inside the circle r = 10
    inside = 2 * (1.5 * math.sqrt(100 - 9) + 50 * math.asin(0.3))
    # to the kernel's volume integration, 1e-6 of the plate (measured 3e-7)
    assert volumes[0] - volumes[1] == pytest.approx((6 * 12.8 - inside) * 10, abs=1e-6 * volumes[0])
    refused = cli("profile", "--no-plots", "-o", tmp_path / "c", "--export", "step", "--thickness", 10,
                  "--bore", 101)
    assert refused.code == 2 and "--bore" in refused.err


@pytest.mark.reference("second method", "FreeCAD (an independent kernel) reads the STEP file: one valid solid of the "
                                        "plate's volume")
@needs_kernel
def test_freecad_opens_the_step_file(cli, tmp_path):
    freecad = shutil.which("freecadcmd")
    if freecad is None:
        if os.environ.get("CAMCAD_REQUIRE_FREECAD"):
            pytest.fail("freecadcmd is required (CAMCAD_REQUIRE_FREECAD) and missing")
        pytest.skip("freecadcmd is not installed")
    folder = run(cli, tmp_path / "a", "--export", "step", "--thickness", 12, "--bore", 20, "--units", "in")
    script = tmp_path / "read.py"
    script.write_text("import json, Part\n"
                      f"shape = Part.read({str(folder / 'cam.step')!r})\n"
                      "print('camcad-step ' + json.dumps({'valid': shape.isValid(), 'solids': len(shape.Solids),"
                      " 'volume': shape.Volume, 'zmax': shape.BoundBox.ZMax}))\n")
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300)
    line = next(line for line in done.stdout.splitlines() if line.startswith("camcad-step "))
    found = json.loads(line.removeprefix("camcad-step "))
    expected = (shapely.Polygon(DEFAULT.profile(FINE)).area - math.pi * 10.0**2) * 12.0
    assert found["valid"] and found["solids"] == 1
    assert found["volume"] == pytest.approx(expected, rel=1e-4)     # FreeCAD reads the inch file back in mm
    assert found["zmax"] == pytest.approx(12.0, abs=1e-6)


@needs_kernel
@pytest.mark.reference("closed form", "a groove cam: the disc less the groove ring (between the flanks) to its depth")
def test_groove_and_conjugate_solids(cli, tmp_path):
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    folder = run(cli, tmp_path / "a", "--groove", "--export", "step", "--thickness", 15, "--depth", 8,
                 "--plate", 220)
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(_read_step(folder / "cam.step"), props)
    pitch, _, normal = DEFAULT.pitch(FINE)
    ring = shapely.Polygon(pitch + 10 * normal).area - shapely.Polygon(pitch - 10 * normal).area
    assert props.Mass() == pytest.approx(math.pi * 110.0**2 * 15 - ring * 8, rel=1e-4)
    pair = run(cli, tmp_path / "b", "--pair-distance", 150, "--export", "step,gcode", "--thickness", 10,
               "--cutter-radius", 5, "--feed", 200)
    assert {"cam.step", "counter_cam.step", "profile.nc", "counter_profile.nc"} <= {p.name for p in pair.iterdir()}


# --------------------------------------------------------------------------------------------------
# LibreOffice and --arcs / --spline: the limitation the output states, measured
# --------------------------------------------------------------------------------------------------

@pytest.mark.reference("second method", "LibreOffice Draw's own drawing of profile.dxf (its SVG export), mapped back "
                                        "onto the drawing by a least-squares similarity")
def test_libreoffice_draws_the_arcs_as_chords_as_the_note_says(cli, tmp_path):
    if shutil.which("soffice") is None:
        if os.environ.get("CAMCAD_REQUIRE_READERS") == "1":
            pytest.fail("soffice is required (CAMCAD_REQUIRE_READERS=1) and missing")
        pytest.skip("LibreOffice (soffice) is not installed")
    import ezdxf
    from ezdxf import appsettings

    made = cli("profile", "--no-plots", "--json", "-o", tmp_path / "a", "--arcs", "--spline")
    notes = made.json()["notes"]
    arcs_note = next(n for n in notes if "draws the tangent arcs as their chords" in n)
    assert any("does not draw SPLINE entities" in n for n in notes)
    stated = float(re.search(r"up to ([0-9.]+) mm", arcs_note).group(1))
    # only the profile, so that its path is the one LibreOffice draws
    source = ezdxf.readfile(tmp_path / "a" / "profile.dxf")
    (profile,) = [e for e in source.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "PROFILE"]
    vertices = np.array([p[:2] for p in profile.get_points("xy")])
    doc = ezdxf.new("R2000", units=4)
    doc.modelspace().add_lwpolyline(profile.get_points("xyb"), format="xyb", close=True)
    appsettings.update_extents(doc)          # LibreOffice collapses a drawing without its extents
    alone = tmp_path / "alone.dxf"
    doc.saveas(alone)
    subprocess.run(["soffice", f"-env:UserInstallation=file://{tmp_path / 'lo'}", "--headless", "--convert-to", "svg",
                    "--outdir", str(tmp_path), str(alone)], timeout=300, capture_output=True, check=True)
    svg = (tmp_path / "alone.svg").read_text()
    paths = [re.findall(r"-?\d+(?:\.\d+)?", d) for d in re.findall(r'd="(M [^"]*)"', svg) if "C" not in d]
    drawn = max(paths, key=len)
    drawn = np.array(drawn, dtype=float).reshape(-1, 2)
    assert len(drawn) == len(vertices)            # one straight line per arc: the bulges are not drawn
    # the drawn polygon back on the drawing: x' = s R x + t, fitted to the vertices (SVG's y points down)
    drawn[:, 1] *= -1.0
    a, b = drawn - drawn.mean(axis=0), vertices - vertices.mean(axis=0)
    scale = math.sqrt((b**2).sum() / (a**2).sum())
    mapped = a * scale + vertices.mean(axis=0)
    assert np.abs(mapped - vertices).max() < 0.2      # the page's rounding (1/100 mm) times the scale
    measured = float(to_polyline(DEFAULT.profile(FINE), vertices).max())   # the exact profile to the chords
    assert measured == pytest.approx(stated, rel=0.01)


@pytest.mark.reference("property", "an output named as an input is refused; the input is unchanged")
def test_a_part_file_is_never_written_over_an_input(cli, tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    law = folder / "profile_points.csv"          # the law is read from the very file --export points would write
    rows = [(0, 0), (45, 1), (90, 0), (135, -1), (180, 0), (225, -1), (270, 0), (315, 1), (360, 0)]
    law.write_text("".join(f"{t},{a}\n" for t, a in rows))
    before = law.read_bytes()
    result = cli("profile", law, "--rb", 50, "--rr", 10, "--lift", 20, "--no-plots", "-o", folder,
                 "--export", "points")
    assert result.code == 2 and len(result.err.strip().splitlines()) == 1, result.err
    assert law.read_bytes() == before
    assert not (folder / "profile.dxf").exists()
