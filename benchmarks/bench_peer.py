"""Peer comparison: camcad against the PyPI package ``mechanism`` and against the closed form.

The cam: dwell 90°, cycloidal rise of h = 20 mm over 90°, dwell 90°, cycloidal return over 90°;
centred translating roller follower, Rb = 40 mm (base circle of the profile), Rr = 10 mm; the cam
turns counter-clockwise. Both tools get this cam; each answer is measured against the closed form
written here (``cycloidal_drdr``, ``exact_pitch``, ``exact_profile``, ``exact_pressure_angle``),
which uses nothing of camcad's.

The peer is not a camcad dependency. It is installed once, pinned (``PEER_REQUIREMENT``), into its
own virtual environment ``benchmarks/.peer-venv/`` and run in a subprocess with that environment's
python (``benchmarks/peer_mechanism.py`` prints JSON). camcad runs in this process. Without the
peer (no network, no venv module) ``run`` still measures camcad and adds one row whose ``status``
is ``"peer unavailable: <reason>"``.

Conventions, aligned explicitly (read from mechanism 1.1.10, ``mechanism/cams.py``):
- its grid is ``np.arange(0, 2π, h)`` (rad; 2π itself excluded), and its law starts, like
  camcad's ``compose``, with the first dwell at θ = 0;
- ``Motion.get_profile(base, thetas_r)`` returns (base + s(θ))·e^{iθ_r} with θ_r = −θ for
  ``rotation="ccw"``: the point of cam angle θ lies at polar angle −θ, measured from +x (its
  follower is on the +x axis). camcad's follower is on +y, so its point lies at 90° − θ. The
  peer's points are therefore turned by +90°, (x, y) → (−y, x), into camcad's frame; the bench
  checks the alignment on the pitch curve (index to index, ≤ 1e-6 mm) before measuring anything;
- the package draws a roller cam as that curve with base = Rb (the profile) and base = Rb + Rr
  (the pitch curve, ``Cam.profile(show_pitch=True)``); ``Cam.save_coordinates(base=Rb)`` writes
  the former. That "profile" is the pitch curve moved radially inward by Rr, which is the exact
  profile only for a knife edge: the roller touches the cam along the common normal, so the
  exact profile is the pitch curve moved by Rr along its normal. The difference is about
  Rr (1 − cos φ) to first order (0.81 mm at φ = 23.2°), more where the pitch curve bends
  (0.95 mm measured, near θ = 316° where its radius of curvature is about 57 mm), and it does
  not shrink with the step h;
- its pressure angle exists only inside ``Cam.get_base_circle``: |φ| = |atan(v/(y + Rb + Rr))|
  on its grid at the base radius it solves for (given the largest allowed |φ|), returned when
  asked to plot. It is given the exact peak pressure angle of this cam, so its answer should be
  Rb = 40 mm; camcad's equivalent is ``profile.min_base_radius`` with that limit on rise and return.

Errors, all against the closed form:
- profile points: the largest distance from a written point to the exact profile, taken as a
  parametric curve (point-to-curve distance, ``curve_distance``), not point to point by index;
- polyline: the Hausdorff distance between the closed polyline through the points and the exact
  curve (``polyline_deviation``): what a CAD program importing the points draws;
- pressure angle: the largest |φ_tool − φ_exact| (deg) over what the tool reports;
- sizing: |Rb_tool − 40 mm|.
Times are medians of repeated runs. camcad "same grid" is ``compose`` + ``CamGeometry`` + the
profile (or pressure angle) at the peer's own θ grid, the work ``Cam(...)`` + ``get_profile`` does;
camcad ``synthesize`` also places the points by its chord tolerance and runs every check.

Run: python benchmarks/bench_peer.py [--quick]
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from timing import median_time

HERE = Path(__file__).resolve().parent
VENV_DIR = HERE / ".peer-venv"
HELPER = HERE / "peer_mechanism.py"
PEER_NAME, PEER_VERSION = "mechanism", "1.1.10"
PEER_REQUIREMENT = f"{PEER_NAME}=={PEER_VERSION}"  # pinned: the conventions above are read from this version

LIFT_MM = 20.0
BASE_RADIUS_MM = 40.0
ROLLER_RADIUS_MM = 10.0
PHASES_DEG = (("dwell", 90.0), ("rise", 90.0), ("dwell", 90.0), ("return", 90.0))
BETA = math.pi / 2.0                                    # width of the rise and of the return (rad)
RISE_START, FAR_DWELL_START, RETURN_START = math.pi / 2.0, math.pi, 1.5 * math.pi

K_PROFILE = "peer: roller profile points"
K_PRESSURE = "peer: pressure angle"
K_SIZING = "peer: base radius for a pressure-angle limit"


# --------------------------------------------------------------------------------------------
# the closed form
# --------------------------------------------------------------------------------------------

def cycloidal_drdr(theta: np.ndarray, lift: float = LIFT_MM) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """s (mm), v = ds/dθ (mm/rad), a = d²s/dθ² (mm/rad²) of the D-R-D-R cycloidal cycle at θ (rad).

    Period 2π; β = π/2. Dwell at 0 on [0, π/2); rise s = h (u − sin(2πu)/(2π)), u = (θ − π/2)/β,
    on [π/2, π); dwell at h on [π, 3π/2); return s = h (1 − u + sin(2πu)/(2π)), u = (θ − 3π/2)/β,
    on [3π/2, 2π). v = ±(h/β)(1 − cos 2πu), a = ±(2πh/β²) sin 2πu (+ rise, − return).

    Source: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), eq. 3.8.
    """
    t = np.mod(np.asarray(theta, dtype=float), 2.0 * math.pi)
    s, v, a = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
    for start, sign, base in ((RISE_START, 1.0, 0.0), (RETURN_START, -1.0, lift)):
        on = (t >= start) & (t < start + BETA)
        u = (t[on] - start) / BETA
        w = 2.0 * math.pi * u
        s[on] = base + sign * lift * (u - np.sin(w) / (2.0 * math.pi))
        v[on] = sign * lift / BETA * (1.0 - np.cos(w))
        a[on] = sign * 2.0 * math.pi * lift / BETA**2 * np.sin(w)
    s[(t >= FAR_DWELL_START) & (t < RETURN_START)] = lift
    return s, v, a


def _frame(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """e_r = (sin θ, cos θ), the follower's axis seen from the cam, and e_t = (−cos θ, sin θ) = −de_r/dθ."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack((s, c), axis=-1), np.stack((-c, s), axis=-1)


def exact_pitch(theta: np.ndarray, lift: float = LIFT_MM, rb: float = BASE_RADIUS_MM,
                rr: float = ROLLER_RADIUS_MM) -> np.ndarray:
    """Roller centre in the cam's frame (mm), shape (N, 2): P = (Rb + Rr + s) e_r.

    Fixed frame: the follower's axis is +y through the cam centre, so the roller centre is
    q = (0, r), r = Rb + Rr + s. The cam turns counter-clockwise by θ, so in the cam's own frame
    the point is R(−θ) q = r (sin θ, cos θ) = r e_r (camcad's docs/INTERFACE.md convention; at θ = 0 it is
    on +y, and it moves clockwise round the cam as θ grows).
    """
    theta = np.asarray(theta, dtype=float)
    s, _, _ = cycloidal_drdr(theta, lift)
    e_r, _ = _frame(theta)
    return (rb + rr + s)[:, None] * e_r


def exact_profile(theta: np.ndarray, lift: float = LIFT_MM, rb: float = BASE_RADIUS_MM,
                  rr: float = ROLLER_RADIUS_MM) -> np.ndarray:
    """Cam profile touched by the roller, in the cam's frame (mm), shape (N, 2).

    With P = r e_r and de_r/dθ = −e_t: P' = v e_r − r e_t. The pitch curve runs clockwise as θ
    grows, so its outward normal is P' turned by +90° (J e_r = e_t, J e_t = −e_r):
        n = (r e_r + v e_t) / √(r² + v²),
    and the roller (radius Rr, outside the cam) touches the cam at X = P − Rr n. For v = 0 this is
    (r − Rr) e_r = (Rb + s) e_r, the base circle on the near dwell.

    Source: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 8 (the
    profile as the inner envelope of the roller); derived again here in polar form.
    """
    theta = np.asarray(theta, dtype=float)
    s, v, _ = cycloidal_drdr(theta, lift)
    r = rb + rr + s
    e_r, e_t = _frame(theta)
    length = np.hypot(r, v)
    normal = (r[:, None] * e_r + v[:, None] * e_t) / length[:, None]
    return r[:, None] * e_r - rr * normal


def exact_pressure_angle(theta: np.ndarray, lift: float = LIFT_MM, rb: float = BASE_RADIUS_MM,
                         rr: float = ROLLER_RADIUS_MM) -> np.ndarray:
    """Pressure angle φ (rad), positive on the rise: the angle between the normal n and the
    follower's direction of travel e_r; cos φ = n·e_r = r/√(r² + v²), so φ = atan(v/(Rb + Rr + s))
    (docs/INTERFACE.md with e = 0). Source: Norton (2009), ch. 8."""
    s, v, _ = cycloidal_drdr(theta, lift)
    return np.arctan2(v, rb + rr + s)


def pressure_angle_extremes(lift: float = LIFT_MM, rb: float = BASE_RADIUS_MM, rr: float = ROLLER_RADIUS_MM,
                            xtol: float = 1e-15) -> dict:
    """Largest and smallest φ (rad) and where (rad), from d/dθ (v/r) = 0, i.e. a r − v² = 0.

    On the rise (u ∈ (0, 1/2]) g = a r − v² is > 0 near u = 0 (a ~ u, v² ~ u⁴) and = −v² < 0 at
    u = 1/2; on the return g < 0 at u = 1/2 and > 0 near u = 1; Brent's method finds the root in
    each bracket (knob: ``xtol``, rad).
    """
    def g(t: float) -> float:
        s, v, a = cycloidal_drdr(np.array([t]), lift)
        return float(a[0] * (rb + rr + s[0]) - v[0] ** 2)

    eps = 1e-3 * BETA
    at_max = brentq(g, RISE_START + eps, RISE_START + BETA / 2, xtol=xtol, rtol=4 * np.finfo(float).eps)
    at_min = brentq(g, RETURN_START + BETA / 2, RETURN_START + BETA - eps, xtol=xtol,
                    rtol=4 * np.finfo(float).eps)
    phi = exact_pressure_angle(np.array([at_max, at_min]), lift, rb, rr)
    return {"max": float(phi[0]), "max_at": at_max, "min": float(phi[1]), "min_at": at_min}


def peer_to_camcad_frame(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The peer's points (follower on +x, point of angle θ at polar angle −θ) turned by +90° into
    camcad's frame (follower on +y, point at 90° − θ): (x, y) → (−y, x). Shape (N, 2), mm."""
    return np.stack((-np.asarray(y, dtype=float), np.asarray(x, dtype=float)), axis=-1)


# --------------------------------------------------------------------------------------------
# distances to a closed parametric curve and to a closed polyline
# --------------------------------------------------------------------------------------------

GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def curve_distance(points: np.ndarray, curve, *, samples: int = 1 << 17, iterations: int = 64) -> np.ndarray:
    """Distance (mm) from each point to the closed curve X(t), t ∈ [0, 2π): min over t of |Q − X(t)|.

    ``curve`` maps t (rad, any real; X is 2π-periodic) to (N, 2) points. The start is the nearest
    of ``samples`` equally spaced curve points (k-d tree); a golden-section search on |Q − X(t)|²
    over t ± 2Δ (Δ = 2π/samples) then finds the foot of the perpendicular. The bracket shrinks by
    0.618 per iteration: 64 iterations leave 4Δ·0.618⁶⁴ ≈ 1e-17 rad. Assumes the curve has no
    other branch within ~Δ·|X'| of a point (true for a smooth cam profile without undercut).
    """
    points = np.asarray(points, dtype=float)
    grid = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    step = 2.0 * math.pi / samples
    _, nearest = cKDTree(curve(grid)).query(points)
    lo, hi = grid[nearest] - 2.0 * step, grid[nearest] + 2.0 * step

    def squared(t: np.ndarray) -> np.ndarray:
        d = points - curve(t)
        return np.einsum("ij,ij->i", d, d)

    inner, outer = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)   # lo < inner < outer < hi
    f_inner, f_outer = squared(inner), squared(outer)
    for _ in range(iterations):
        left = f_inner < f_outer                  # the minimum lies in [lo, outer], else in [inner, hi]
        hi = np.where(left, outer, hi)
        lo = np.where(left, lo, inner)
        kept = np.where(left, f_inner, f_outer)  # the surviving interior point becomes outer / inner
        inner, outer = (np.where(left, hi - GOLDEN * (hi - lo), outer),
                        np.where(left, inner, lo + GOLDEN * (hi - lo)))
        fresh = squared(np.where(left, inner, outer))
        f_inner, f_outer = np.where(left, fresh, kept), np.where(left, kept, fresh)
    best = np.minimum(np.minimum(f_inner, f_outer), np.minimum(squared(lo), squared(hi)))
    return np.sqrt(best)


def polyline_distance(points: np.ndarray, vertices: np.ndarray, neighbours: int = 4) -> np.ndarray:
    """Distance (mm) from each point to the closed polyline through ``vertices`` (exact
    point-to-segment distances to both segments at each of the ``neighbours`` nearest vertices)."""
    n = len(vertices)
    k = min(neighbours, n)
    _, near = cKDTree(vertices).query(points, k=k)
    near = near.reshape(len(points), k)
    best = np.full(len(points), np.inf)
    for start in np.concatenate((near, (near - 1) % n), axis=1).T:
        a, b = vertices[start], vertices[(start + 1) % n]
        seg = b - a
        t = np.clip(np.einsum("ij,ij->i", points - a, seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300),
                    0.0, 1.0)
        gap = points - (a + t[:, None] * seg)
        best = np.minimum(best, np.einsum("ij,ij->i", gap, gap))
    return np.sqrt(best)


def polyline_deviation(vertices: np.ndarray, curve, *, samples: int = 1 << 16,
                       fractions: tuple[float, ...] = (0.25, 0.5, 0.75)) -> float:
    """Hausdorff distance (mm) between the closed polyline through ``vertices`` and the closed
    curve X(t): the larger of (a) the largest distance from ``samples`` curve points to the
    polyline and (b) the largest distance from the vertices and the points at ``fractions`` of
    every chord to the curve (``curve_distance``). Part (b) measures each chord's sagitta at its
    midpoint to round-off, however short the chord; part (a) catches what lies far from every
    chord (a missing lobe, a wrong turn), so it needs no finer sampling than the shortest
    feature. Knobs: ``samples``, ``fractions``."""
    vertices = np.asarray(vertices, dtype=float)
    dense = curve(np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False))
    to_polyline = float(polyline_distance(dense, vertices).max())
    following = np.roll(vertices, -1, axis=0)
    chord_points = [vertices] + [vertices + f * (following - vertices) for f in fractions]
    to_curve = float(curve_distance(np.concatenate(chord_points), curve, iterations=48).max())
    return max(to_polyline, to_curve)


# --------------------------------------------------------------------------------------------
# the peer: its own virtual environment and a subprocess
# --------------------------------------------------------------------------------------------

class PeerUnavailable(Exception):
    """The peer could not be installed or run; the message says why."""


def _venv_python(venv: Path) -> Path:
    unix = venv / "bin" / "python"
    return unix if unix.exists() or os.name != "nt" else venv / "Scripts" / "python.exe"


def _last_line(text: str) -> str:
    lines = [line.strip() for line in (text or "").splitlines() if line.strip()]
    errors = [line for line in lines if line.startswith("ERROR")]
    return (errors or lines or ["no message"])[-1][:300]


def _installed_version(python: Path) -> str | None:
    if not python.exists():
        return None
    probe = subprocess.run([str(python), "-c", f"import importlib.metadata as m; print(m.version({PEER_NAME!r}))"],
                           capture_output=True, text=True, timeout=120)
    return probe.stdout.strip() if probe.returncode == 0 else None


def peer_python(venv: Path | None = None, timeout_s: float = 900.0) -> Path:
    """The python of the peer's virtual environment, made once with ``PEER_REQUIREMENT`` installed.

    The environment is built under a temporary name and renamed into place, so an interrupted or
    concurrent build never leaves a half-made ``venv`` (default ``VENV_DIR``). Raises
    PeerUnavailable with the reason.
    """
    venv = Path(venv) if venv is not None else VENV_DIR
    python = _venv_python(venv)
    if _installed_version(python) == PEER_VERSION:
        return python
    staging = venv.with_name(f"{venv.name}.tmp-{os.getpid()}")
    shutil.rmtree(staging, ignore_errors=True)
    try:
        made = subprocess.run([sys.executable, "-m", "venv", str(staging)], capture_output=True, text=True,
                              timeout=timeout_s)
        if made.returncode != 0:
            raise PeerUnavailable(f"python -m venv failed: {_last_line(made.stderr or made.stdout)}")
        pip = subprocess.run([str(_venv_python(staging)), "-m", "pip", "install", "--disable-pip-version-check",
                              "--quiet", "--retries", "1", "--timeout", "30", PEER_REQUIREMENT],
                             capture_output=True, text=True, timeout=timeout_s)
        if pip.returncode != 0:
            raise PeerUnavailable(f"pip install {PEER_REQUIREMENT} failed: {_last_line(pip.stderr)}")
        if venv.exists():
            shutil.rmtree(venv, ignore_errors=True)  # a broken or outdated environment
        try:
            os.rename(staging, venv)
        except OSError:
            pass  # another run put its environment in place first; it is checked below
    except subprocess.TimeoutExpired as err:
        raise PeerUnavailable(f"{err.cmd[0]} did not finish in {timeout_s:g} s") from err
    except OSError as err:
        raise PeerUnavailable(f"cannot build {venv}: {err}") from err
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    python = _venv_python(venv)
    found = _installed_version(python)
    if found != PEER_VERSION:
        raise PeerUnavailable(f"{venv} holds {PEER_NAME} {found}, not {PEER_VERSION}")
    return python


def run_peer(python: Path, steps: list[float], repeats: int, max_pressure_angle_deg: float,
             timeout_s: float = 600.0) -> dict:
    """Run ``peer_mechanism.py`` with the peer's python; its JSON answer (see that script)."""
    settings = {"lift_mm": LIFT_MM, "base_radius_mm": BASE_RADIUS_MM, "roller_radius_mm": ROLLER_RADIUS_MM,
                "steps_rad": steps, "repeats": repeats, "max_pressure_angle_deg": max_pressure_angle_deg}
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("PYTHONPATH", None)  # the peer sees its own environment only
    try:
        done = subprocess.run([str(python), str(HELPER)], input=json.dumps(settings), capture_output=True,
                              text=True, timeout=timeout_s, env=env, cwd=str(HERE))
    except subprocess.TimeoutExpired as err:
        raise PeerUnavailable(f"the peer script did not finish in {timeout_s:g} s") from err
    if done.returncode != 0:
        raise PeerUnavailable(f"the peer script failed: {_last_line(done.stderr)}")
    try:
        return json.loads(done.stdout)
    except json.JSONDecodeError as err:
        raise PeerUnavailable(f"the peer script printed no JSON ({err})") from err


# --------------------------------------------------------------------------------------------
# measurements
# --------------------------------------------------------------------------------------------

def timed(function, repeats: int):
    return median_time(function, repeats, warm_up=False)


def camcad_case(phi_limit_deg: float | None = None):
    """camcad's law and follower for this cam (with both pressure-angle limits set to the given
    value, for sizing)."""
    from camcad.law.standard import compose
    from camcad.profile.followers import Follower

    law = compose(list(PHASES_DEG), LIFT_MM, "cycloidal")
    follower = Follower("roller", base_radius=BASE_RADIUS_MM, roller_radius=ROLLER_RADIUS_MM,
                        pressure_angle_limit_rise_deg=phi_limit_deg, pressure_angle_limit_return_deg=phi_limit_deg)
    return law, follower


def profile_errors(profile_points: np.ndarray, pitch_points: np.ndarray) -> dict:
    return {"error": float(curve_distance(profile_points, exact_profile).max()),
            "polyline_mm": polyline_deviation(profile_points, exact_profile),
            "pitch_mm": float(curve_distance(pitch_points, exact_pitch).max()),
            "pitch_polyline_mm": polyline_deviation(pitch_points, exact_pitch),
            "points": len(profile_points)}


def _row(kernel: str, method: str, setting: str, time_s, error, error_unit: str, **extra) -> dict:
    return {"kernel": kernel, "method": method, "setting": setting, "time_s": time_s, "error": error,
            "error_unit": error_unit, "status": "ok", **extra}


def camcad_rows(repeats: int, tolerances: tuple[float, ...], grids: tuple[int, ...], extremes: dict) -> list[dict]:
    """camcad alone: synthesize at each chord tolerance (profile points, peak pressure angles) and
    min_base_radius at each grid for the exact peak pressure angle."""
    from camcad.profile.design import min_base_radius
    from camcad.profile.summary import profile_report as report
    from camcad.profile.synth import ProfileSettings, synthesize

    law, follower = camcad_case()
    rows = []
    for tol in tolerances:
        settings = ProfileSettings(tol_mm=tol, plots=False, design=False)
        synthesize(law, follower, settings)  # warm-up: the first call imports shapely
        seconds, result = timed(lambda settings=settings: synthesize(law, follower, settings), repeats)
        figures = report(result)
        figures_mm = profile_errors(result.profile.polyline.points, result.pitch.polyline.points)
        rows.append(_row(K_PROFILE, "camcad synthesize (chords)", f"tol {tol:g} mm", seconds, figures_mm.pop("error"),
                         "mm (points to exact profile)", **figures_mm))
        peak = max(abs(figures["pressure_angle_max_deg"] - math.degrees(extremes["max"])),
                   abs(figures["pressure_angle_min_deg"] - math.degrees(extremes["min"])))
        where = max(abs(figures["pressure_angle_max_at_deg"] - math.degrees(extremes["max_at"])),
                    abs(figures["pressure_angle_min_at_deg"] - math.degrees(extremes["min_at"])))
        rows.append(_row(K_PRESSURE, "camcad synthesize: peak φ (grid + Brent)", f"tol {tol:g} mm", seconds, peak,
                         "deg (error of the peak φ)", location_error_deg=where))
    limit_deg = math.degrees(max(extremes["max"], -extremes["min"]))
    law, sized = camcad_case(limit_deg)
    for grid in grids:
        seconds, design = timed(lambda grid=grid: min_base_radius(law, sized, grid=grid), repeats)
        rb = design.rb_pressure_angle
        rows.append(_row(K_SIZING, "camcad min_base_radius", f"grid {grid}", seconds, abs(rb - BASE_RADIUS_MM),
                         "mm (Rb error; exact Rb = 40)", rb_mm=rb, rb_curvature_mm=design.rb_curvature))
    return rows


def same_grid_rows(theta: np.ndarray, step: float, repeats: int) -> list[dict]:
    """camcad's closed-form geometry on the peer's own θ grid: the work the peer does per call."""
    from camcad.law.standard import compose
    from camcad.profile.geometry import CamGeometry

    _, follower = camcad_case()

    def profile_points():
        geometry = CamGeometry(compose(list(PHASES_DEG), LIFT_MM, "cycloidal"), follower)
        return geometry.profile(theta).points

    def pressure_angles():
        geometry = CamGeometry(compose(list(PHASES_DEG), LIFT_MM, "cycloidal"), follower)
        return geometry.pressure_angle(theta)

    seconds, points = timed(profile_points, repeats)
    pitch = CamGeometry(compose(list(PHASES_DEG), LIFT_MM, "cycloidal"), follower).pitch(theta).points
    setting = f"h {step:g} rad"
    figures_mm = profile_errors(points, pitch)
    rows = [_row(K_PROFILE, "camcad CamGeometry.profile, same grid", setting, seconds, figures_mm.pop("error"),
                 "mm (points to exact profile)", **figures_mm)]
    seconds, phi = timed(pressure_angles, repeats)
    error = float(np.degrees(np.max(np.abs(phi - exact_pressure_angle(theta)))))
    rows.append(_row(K_PRESSURE, "camcad CamGeometry.pressure_angle, same grid", setting, seconds, error,
                     "deg (largest φ error on the grid)"))
    return rows


def peer_rows(run: dict, version: str, extremes: dict) -> list[dict]:
    """The peer's answers for one step h, measured against the closed form."""
    theta = np.asarray(run["theta"])
    step = run["step_rad"]
    setting = f"h {step:g} rad"
    pitch = peer_to_camcad_frame(run["pitch_x"], run["pitch_y"])
    profile = peer_to_camcad_frame(run["profile_x"], run["profile_y"])
    misaligned = float(np.max(np.linalg.norm(pitch - exact_pitch(theta), axis=1)))
    if misaligned > 1e-6:
        raise RuntimeError(f"{PEER_NAME} {version}: pitch points are {misaligned:.3g} mm from the exact pitch "
                           "curve at their own θ; its conventions differ from those in this module's docstring")
    name = f"{PEER_NAME} {version}"
    figures_mm = profile_errors(profile, pitch)
    rows = [_row(K_PROFILE, f"{name} save_coordinates(base=Rb)", setting, run["time_profile_s"],
                 figures_mm.pop("error"), "mm (points to exact profile)", alignment_mm=misaligned,
                 saved_vs_memory_mm=run["saved_vs_memory_mm"], **figures_mm)]
    phis = np.radians(np.asarray(run["phis_deg"]))
    rb_peer = run["base_circle"]["rb_mm"]
    asked = np.abs(exact_pressure_angle(theta))
    own = np.abs(exact_pressure_angle(theta, rb=rb_peer))
    peak_own = pressure_angle_extremes(rb=rb_peer)
    rows.append(_row(K_PRESSURE, f"{name} get_base_circle: φ on its grid", setting, run["time_base_circle_s"],
                     float(np.degrees(np.max(np.abs(phis - asked)))), "deg (largest φ error on the grid)",
                     error_at_own_rb_deg=float(np.degrees(np.max(np.abs(phis - own)))), rb_mm=rb_peer))
    rows.append(_row(K_SIZING, f"{name} get_base_circle", setting, run["time_base_circle_s"],
                     abs(rb_peer - BASE_RADIUS_MM), "mm (Rb error; exact Rb = 40)", rb_mm=rb_peer,
                     peak_phi_error_deg=math.degrees(peak_own["max"] - extremes["max"]),
                     min_rho_pitch_mm=run["base_circle"]["min_rho_pitch_mm"]))
    return rows


KERNEL_ORDER = {K_PROFILE: 0, K_PRESSURE: 1, K_SIZING: 2}


def run(quick: bool = False) -> list[dict]:
    """Rows kernel, method, setting, time_s, error, error_unit, status (+ figures); see the docstring."""
    repeats = 3 if quick else 7
    tolerances = (1e-2, 1e-3, 1e-4) if quick else (1e-2, 1e-3, 1e-4, 1e-5)
    steps = [0.0062, 0.001] if quick else [0.0062, 0.001, 0.0002]  # 0.0062 rad is the peer's default
    grids = (256, 2048)
    extremes = pressure_angle_extremes()
    rows = camcad_rows(repeats, tolerances, grids, extremes)
    try:
        python = peer_python()
        peer = run_peer(python, steps, repeats, math.degrees(max(extremes["max"], -extremes["min"])))
    except PeerUnavailable as err:
        status = f"peer unavailable: {err}"
        # the status goes into ``setting`` too, so tables that show only the common keys still say why
        rows.append({"kernel": K_PROFILE, "method": f"{PEER_NAME} {PEER_VERSION}", "setting": status,
                     "time_s": None, "error": None, "error_unit": "mm (points to exact profile)", "status": status})
        return sorted(rows, key=lambda row: KERNEL_ORDER[row["kernel"]])
    for one in peer["runs"]:
        rows += peer_rows(one, peer["version"], extremes)
        rows += same_grid_rows(np.asarray(one["theta"]), one["step_rad"], repeats)
    return sorted(rows, key=lambda row: KERNEL_ORDER[row["kernel"]])


# --------------------------------------------------------------------------------------------
# ratios and the table
# --------------------------------------------------------------------------------------------

def _ratio(a: float, b: float) -> str:
    if not (a and b) or not (math.isfinite(a) and math.isfinite(b)):
        return "n/a"
    return f"{a / b:.3g}"


def summary(rows: list[dict]) -> list[str]:
    """Speed ratios (peer time / camcad time) and accuracy ratios (peer error / camcad error),
    each with the figures it comes from; or why the peer is missing."""
    peer = [r for r in rows if r["method"].startswith(PEER_NAME) and r["status"] == "ok"]
    if not peer:
        return [r["status"] for r in rows if r["status"] != "ok"]
    lines = []
    by = {(r["kernel"], r["method"], r["setting"]): r for r in rows}
    synth = [c for c in rows if c["kernel"] == K_PROFILE and c["method"].startswith("camcad synthesize")]
    for r in (r for r in peer if r["kernel"] == K_PROFILE):
        same = by[(K_PROFILE, "camcad CamGeometry.profile, same grid", r["setting"])]
        lines.append(f"profile, same grid ({r['setting']}, {r['points']} points): time {r['time_s'] * 1e3:.3g} ms "
                     f"vs {same['time_s'] * 1e3:.3g} ms, speed ratio {_ratio(r['time_s'], same['time_s'])}; "
                     f"points {r['error']:.2g} vs {same['error']:.2g} mm, "
                     f"accuracy ratio {_ratio(r['error'], same['error'])}; "
                     f"polyline {r['polyline_mm']:.2g} vs {same['polyline_mm']:.2g} mm, accuracy ratio "
                     f"{_ratio(r['polyline_mm'], same['polyline_mm'])} (the peer's pitch curve: points "
                     f"{r['pitch_mm']:.2g} mm, polyline {r['pitch_polyline_mm']:.2g} mm)")
        matched = [c for c in synth if c["polyline_mm"] <= r["pitch_polyline_mm"]]
        if matched:
            c = min(matched, key=lambda c: c["points"])
            lines.append(f"  against camcad synthesize at {c['setting']} ({c['points']} points; its polyline "
                         f"{c['polyline_mm']:.2g} mm is within the peer's pitch polyline): "
                         f"time {r['time_s'] * 1e3:.3g} vs {c['time_s'] * 1e3:.3g} ms, "
                         f"speed ratio {_ratio(r['time_s'], c['time_s'])}; profile polyline accuracy ratio "
                         f"{_ratio(r['polyline_mm'], c['polyline_mm'])}")
    for r in (r for r in peer if r["kernel"] == K_PRESSURE):
        same = by[(K_PRESSURE, "camcad CamGeometry.pressure_angle, same grid", r["setting"])]
        lines.append(f"pressure angle ({r['setting']}): {r['error']:.2g} vs {same['error']:.2g} deg, accuracy ratio "
                     f"{_ratio(r['error'], same['error'])} (the peer's error at its own Rb "
                     f"{r['rb_mm']:.9g} mm: {r['error_at_own_rb_deg']:.2g} deg)")
    best = min((c for c in rows if c["kernel"] == K_SIZING and c["method"].startswith("camcad")),
               key=lambda c: c["time_s"])
    for r in (r for r in peer if r["kernel"] == K_SIZING):
        lines.append(f"sizing ({r['setting']}) against camcad {best['setting']}: time {r['time_s'] * 1e3:.3g} vs "
                     f"{best['time_s'] * 1e3:.3g} ms, speed ratio {_ratio(r['time_s'], best['time_s'])}; Rb error "
                     f"{r['error']:.2g} vs {best['error']:.2g} mm, accuracy ratio {_ratio(r['error'], best['error'])} "
                     f"(peak φ of the cam it sizes − the limit given: {r['peak_phi_error_deg']:+.2g} deg)")
    return lines


def _fmt(value, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def main() -> None:
    quick = "--quick" in sys.argv
    rows = run(quick)
    print(f"{'kernel':45s} {'method':51s} {'setting':14s} {'time':>10s} {'error':>9s} {'polyline':>9s} "
          f"{'points':>7s}  unit")
    for r in rows:
        seconds = "-" if r["time_s"] is None else f"{r['time_s'] * 1e3:8.2f}ms"
        print(f"{r['kernel']:45s} {r['method']:51s} {r['setting']:14s} {seconds:>10s} {_fmt(r['error'], '9.2e')} "
              f"{_fmt(r.get('polyline_mm'), '9.2e'):>9s} {_fmt(r.get('points'), '7d'):>7s}  {r['error_unit']}"
              + ("" if r["status"] == "ok" else f"  [{r['status']}]"))
    print("speed ratio = peer time / camcad time (> 1: camcad is faster); accuracy ratio = peer error / camcad error")
    for line in summary(rows):
        print(line)


if __name__ == "__main__":
    main()
