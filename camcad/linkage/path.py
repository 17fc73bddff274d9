"""Guiding four-bars (Sunkuev 1984, ch. 2 and ch. 5): a coupler point that reproduces a curve, a curve with its
timing, or a distance to a fixed point.

Sunkuev 1984's three task groups of guiding mechanisms (ch. 2, "Для направляющих механизмов рассмотрены три группы
задач синтеза"):

1. **points** — a curve y = F(x) (the coupler point passes the given points, no timing);
2. **timed** — x = F_x(φ), y = F_y(φ) (the coupler point is at the given point when the input has turned by φ);
3. **distance** — L = L(φ), the distance from the coupler point to a given fixed point X.

The mechanism (``GuidingFourBar``): input pivot O, crank OA = a turning by θ, coupler AB = b, rocker CB = c pivoted
at C, assembly branch σ (``camcad.linkage.analysis.Loop``: σ = +1 puts B left of C→A), coupler point
M = A + (u + iv)(B − A)/b (u mm along AB, v mm to its left). Lengths mm, angles rad inside, deg at the interface.

**The Q method** (Sunkuev 1984's special objective for guiding mechanisms: "геометрический параметр множества положений
одного и того же неподвижного шарнира механизма. Каждое из этих положений определяется в результате синтеза
механизма по условию интерполяционного приближения заданной зависимости с двумя или тремя узлами"): the free
parameters fix one dyad and the coupler; each node subset gives a position of the other fixed pivot; Q is the
diagonal of the axis-parallel rectangle around those positions (mm), minimised under the limits; the pivot is then
taken at the rectangle's centre. camcad's constructions (Sunkuev 1984 names the idea, not the formulas):

- *points*: the free dyad is the rocker's — pivot C, rocker c, |BM| = e and the crank pin A in the coupler's frame
  (w: A − B along B→M and to its left); B_k is where the circles (C, c) and (M_k, e) meet, A_k follows; the crank
  pivot O of a subset {1, i, j} is the centre of the circle through A_1, A_i, A_j (three nodes; subsets {1,2,3},
  {1,4,5}, …, node 1 in each, every other node once, as for the function generator), or with the crank a free too,
  where the circles (A_1, a) and (A_i, a) meet (two nodes, subsets {1, i}). Which of the two meeting points is
  B_k: the triangle C–B–M can only turn over where |CM| is extreme (B on the line CM), so camcad tries both
  constant sides and the patterns that change side at the gaps next to the largest and the smallest |CM_k|, and
  keeps the least Q.
- *timed*: stage 1, the crank's dyad — free O and |AM| = e; nodes {1, i} give the crank pin A_1 where the circles
  (M_1, e) and (M_i, e) turned back by Δφ_i about O meet; stage 2, the rocker's dyad — free the point B of the
  coupler (w), the pivot C = the centre of the circle through B_1, B_i, B_j.
- *distance*: free the crank (O, a, θ₀), |AM| = e and w; M_k is where the circles (A_k, e) and (X, L_k) meet (one
  side for all k, both tried), B_k follows, C from three nodes.

**The deviation method**: all parameters (9 for a path; + θ₀ with timing) by least squares of the deviations
(the untimed task adds each point's crank angle as an unknown), the limits (transmission angle over the input's
range, link ratio) as constraints (SLSQP on the sum of squares when least squares ends outside them). Its starts:
for points, a crank's dyad fitted to equal crank steps (the step found by least squares, both senses) and the
rocker's dyad fitted to its coupler poses; when none reaches the tolerance, differential evolution on the coupler
curve's implicit equation (branch-free: the crank pin's direction solves two linear equations; the curve is where
cos² + sin² = 1) with the points' assembly branch and the link ratio as penalties, then least squares.

Every position computation (one configuration at one input angle, or one node of a Q evaluation) is counted.

Sources: B. S. Sunkuev 1984 (ch. 2: the three task groups and the special objective; ch. 5: the two-node pivot sets
{A_1i}, {D_1i}); F. Freudenstein and G. N. Sandor, Trans. ASME B 81 (1959) (dyad synthesis of path generators);
C. W. Wampler, A. P. Morgan, A. J. Sommese, J. Mech. Des. 114 (1992) 153–159 (the nine-point problem: at most 1442
solutions, so a local method needs good starts).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.analysis import Loop
from camcad.linkage.family import fit_circle
from camcad.linkage.fgen import Limits

TASKS = ("points", "timed", "distance")
HEADERS = {"points": ("x_mm", "y_mm"), "timed": ("phi_deg", "x_mm", "y_mm"), "distance": ("phi_deg", "L_mm")}
OPTIONS = {"points": "--points", "timed": "--timed", "distance": "--distance"}
#: the accuracy asked for when --max-deviation is not given: this fraction of the target's size
DEFAULT_TOLERANCE = 1e-3
#: samples of the coupler curve over the input's range in the check (the nearest is refined)
CURVE_SAMPLES = 2001
#: how far inside its limits an optimiser keeps a mechanism (cos μ, log link ratio)
INSIDE = 1e-9
#: the same for the exact penalties of the Q searches, which end a hair outside the boundary they are pushed to
PENALTY_INSIDE = 1e-6


# --------------------------------------------------------------------------------------------
# The target
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PathTarget:
    """What the coupler point must do: ``task`` (points, timed, distance), ``points`` (complex mm; for a distance
    task empty), ``phi`` (rad, relative input angles; empty for points), ``distance`` (mm) and ``fixed`` (the
    fixed point X, complex mm) of a distance task, ``source`` (a file name or "values")."""

    task: str
    points: np.ndarray
    phi: np.ndarray
    distance: np.ndarray
    fixed: complex | None
    source: str = "values"

    @property
    def count(self) -> int:
        return len(self.phi) if self.task == "distance" else len(self.points)

    @property
    def size(self) -> float:
        """The target's size (mm): the diagonal of the points' bounding box; for a distance task the range of L
        plus the mean distance (a circle of that radius about X is the scale of the motion)."""
        if self.task == "distance":
            return float(np.ptp(self.distance) + np.mean(self.distance))
        return float(math.hypot(np.ptp(self.points.real), np.ptp(self.points.imag)))


def make_target(task: str, rows, fixed=None, source: str = "values") -> PathTarget:
    """A ``PathTarget`` from rows: (x, y) mm for ``points``, (φ deg, x, y) for ``timed``, (φ deg, L mm) for
    ``distance`` (then ``fixed`` = (X, Y) mm). Checks: finite, at least 5 rows (points: 5 … 9 is the four-bar's
    range of exact synthesis, more are fitted), no repeated point, φ strictly monotone.

    Examples
    --------
    >>> t = make_target("points", [(0, 0), (10, 2), (20, 6), (30, 12), (40, 20)])
    >>> t.count, round(t.size, 6)
    (5, 44.72136)
    """
    if task not in TASKS:
        raise CamcadError(f"unknown path task {task!r}", "linkage path", "give --points, --timed or --distance")
    where = source if source != "values" else OPTIONS[task]
    data = np.asarray(rows, dtype=float)
    width = len(HEADERS[task])
    if data.ndim != 2 or data.shape[1] != width:
        raise CamcadError(f"expected rows of {width} numbers ({', '.join(HEADERS[task])})", where,
                          f"write one row per point: {','.join(HEADERS[task])}")
    if not np.all(np.isfinite(data)):
        raise CamcadError("a value is not a finite number", where, "fix the table")
    if len(data) < 5:
        raise CamcadError(f"{len(data)} rows: a four-bar path needs at least 5", where, "give 5 or more rows")
    if len(data) > 400:
        raise CamcadError(f"{len(data)} rows: at most 400", where, "thin the table")
    phi = np.radians(data[:, 0]) if task != "points" else np.array([])
    if task != "points":
        steps = np.diff(phi)
        if not (np.all(steps > 0) or np.all(steps < 0)):
            raise CamcadError("phi_deg is not strictly monotone", where, "sort the rows by the input angle")
        if abs(phi[-1] - phi[0]) >= 2 * math.pi:
            raise CamcadError("phi_deg spans a full turn or more", where, "give less than 360 deg of input")
        phi = phi - phi[0]
    if task == "distance":
        if fixed is None:
            raise CamcadError("a distance task needs the fixed point", "--fixed-point", "give --fixed-point X,Y (mm)")
        if np.any(data[:, 1] <= 0):
            raise CamcadError("a distance L_mm is not positive", where, "give distances > 0")
        return PathTarget(task, np.array([], dtype=complex), phi, data[:, 1].copy(), complex(*fixed), source)
    points = data[:, -2] + 1j * data[:, -1]
    gaps = np.abs(np.diff(points))
    if np.any(gaps <= 1e-9 * max(1.0, float(np.max(np.abs(points))))):
        k = int(np.argmax(gaps <= 1e-9 * max(1.0, float(np.max(np.abs(points)))))) + 2
        raise CamcadError(f"row {k} repeats the point before it", where, "give each point once")
    target = PathTarget(task, points, phi, np.array([]), None, source)
    if target.size <= 0:
        raise CamcadError("all points coincide", where, "give points spread along the curve")
    return target


def read_target(path: Path, task: str, fixed=None) -> PathTarget:
    """Read a path table: a header naming its columns (``x_mm,y_mm``, ``phi_deg,x_mm,y_mm`` or ``phi_deg,L_mm``),
    then rows; comma, semicolon, tab or spaces; ``#`` comments. A header of another task is refused.

    Examples
    --------
    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "p.csv"
    >>> _ = p.write_text("x_mm,y_mm\\n0,0\\n10,2\\n20,6\\n30,12\\n40,20\\n")
    >>> read_target(p, "points").count
    5
    """
    path = Path(path)
    if not path.is_file():
        raise CamcadError("file not found" if not path.exists() else "not a file", str(path),
                          f"give a table with the header {','.join(HEADERS[task])}")
    text = path.read_bytes().decode("utf-8", errors="replace")
    rows, header = [], None
    for number, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip().lstrip("\ufeff")
        if not content:
            continue
        cells = [c for c in content.replace(";", ",").replace("\t", ",").replace(" ", ",").split(",") if c]
        if header is None:
            header = tuple(c.strip().strip('"').lower() for c in cells)
            wanted = tuple(h.lower() for h in HEADERS[task])
            if header != wanted:
                kinds = {tuple(h.lower() for h in v): k for k, v in HEADERS.items()}
                other = kinds.get(header)
                hint = f" (that is a {other} table: use {OPTIONS[other]})" if other else ""
                raise CamcadError(f"the header is {','.join(header)!r}, not {','.join(HEADERS[task])!r}{hint}",
                                  str(path), f"start the table with the line {','.join(HEADERS[task])}")
            continue
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            raise CamcadError(f"line {number} is not numbers", str(path), "fix or delete that line") from None
        if len(rows[-1]) != len(HEADERS[task]):
            raise CamcadError(f"line {number} has {len(rows[-1])} values, not {len(HEADERS[task])}", str(path),
                              "give one value per column")
    if header is None:
        raise CamcadError("the table is empty", str(path), f"write the header {','.join(HEADERS[task])} and rows")
    return make_target(task, rows, fixed, str(path))


# --------------------------------------------------------------------------------------------
# The mechanism
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class GuidingFourBar:
    """A four-bar with a coupler point (module docstring); ``theta0`` is the crank's angle at the first target row
    (timed and distance tasks: θ = θ₀ + φ).

    Examples
    --------
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.0)
    >>> a_pt, b_pt, p_pt = m.positions(np.array([math.pi / 2]))
    >>> round(float(abs(a_pt[0] - b_pt[0])), 9), round(float(abs(b_pt[0] - 100)), 9)
    (120.0, 90.0)
    """

    o: complex
    pivot: complex          # C, the rocker's pivot
    a: float
    b: float
    c: float
    branch: int
    point: complex          # u + iv in the coupler's frame at A (u along AB)
    theta0: float = 0.0

    @property
    def loop(self) -> Loop:
        return Loop((self.o.real, self.o.imag), (self.pivot.real, self.pivot.imag), self.a, self.b, self.c,
                    self.branch)

    def links(self) -> tuple[float, float, float, float]:
        """OA, AB, CB, OC (mm)."""
        return self.a, self.b, self.c, abs(self.pivot - self.o)

    def positions(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A, B and the coupler point M (complex mm) at absolute crank angles θ (rad); NaN where it opens."""
        a_pt, b_pt = self.loop.joints(np.asarray(theta, dtype=float))
        a_pt, b_pt = np.asarray(a_pt, dtype=complex), np.asarray(b_pt, dtype=complex)
        return a_pt, b_pt, a_pt + self.point * (b_pt - a_pt) / self.b

    def worst_transmission(self, lo: float, hi: float) -> float:
        """Smallest min(μ, π − μ) (rad) over the crank angles [lo, hi], closed form; NaN if it opens there."""
        return self.loop.worst_transmission(lo, hi)


def from_dyads(o: complex, a_1: complex, b_1: complex, pivot: complex, m_1: complex, theta0: float = 0.0
               ) -> GuidingFourBar:
    """The guiding four-bar whose input pivot is ``o``, rocker pivot ``pivot`` and which has its crank pin, its
    rocker pin and its coupler point at ``a_1``, ``b_1``, ``m_1`` (complex mm) in one position.

    Examples
    --------
    >>> m = from_dyads(0j, 40j, 100 + 90j, 100 + 0j, 30 + 60j)
    >>> [round(v, 9) for v in m.links()], m.branch
    ([40.0, 111.803398875, 90.0, 100.0], -1)
    """
    b = abs(b_1 - a_1)
    if not (b > 0 and abs(a_1 - o) > 0 and abs(b_1 - pivot) > 0):
        raise ValueError("a link of zero length: no four-bar")
    frame = (b_1 - a_1) / b
    point = (m_1 - a_1) / frame
    base = GuidingFourBar(o, pivot, abs(a_1 - o), b, abs(b_1 - pivot), 1, point, theta0)
    loop = base.loop.with_branch_through(cmath.phase(a_1 - o), b_1)
    return replace(base, branch=loop.branch)


# --------------------------------------------------------------------------------------------
# Small geometric helpers (vectorised)
# --------------------------------------------------------------------------------------------

def circle_meet(z1, r1, z2, r2, side):
    """The point where the circles (z1, r1) and (z2, r2) meet on ``side`` (±1: left / right of z1→z2), and the
    gap where they do not (0 where they meet); arrays broadcast. Where they do not meet, the nearest point of
    the first circle on the line of centres is returned.

    Examples
    --------
    >>> p, gap = circle_meet(np.array([0j]), 5.0, np.array([6 + 0j]), 5.0, 1)
    >>> complex(p[0]), float(gap[0])
    ((3+4j), 0.0)
    """
    dz = z2 - z1
    dist = np.abs(dz)
    with np.errstate(all="ignore"):
        along = (r1 * r1 - r2 * r2 + dist * dist) / (2 * dist)
        h2 = r1 * r1 - along * along
        unit = dz / dist
    gap = np.maximum(-h2, 0.0)
    return z1 + (along + side * 1j * np.sqrt(np.maximum(h2, 0.0))) * unit, gap


def circumcentre(z1, z2, z3):
    """Centre of the circle through three points (complex, broadcast); inf where they are collinear.

    Examples
    --------
    >>> abs(complex(circumcentre(1 + 0j, 1j, -1 + 0j))) < 1e-12
    True
    """
    w = (z3 - z1) / (z2 - z1)
    with np.errstate(all="ignore"):
        return (z2 - z1) * (w - np.abs(w) ** 2) / (2j * w.imag) + z1


def _box(points: np.ndarray) -> tuple[float, complex]:
    """Q (the diagonal of the axis-parallel rectangle around ``points``) and the rectangle's centre."""
    xs, ys = points.real, points.imag
    return (float(math.hypot(xs.max() - xs.min(), ys.max() - ys.min())),
            complex((xs.max() + xs.min()) / 2, (ys.max() + ys.min()) / 2))


def _nearest(pair: tuple[complex, complex], ref: complex) -> complex:
    """The one of ``pair`` nearest ``ref`` (the first on a tie)."""
    return min(pair, key=lambda z: abs(z - ref))


def subsets(count: int, nodes: int) -> list[tuple[int, ...]]:
    """Sunkuev 1984's node subsets (0-based): node 1 in each, every other node once — {1, i} for two-node
    interpolation, {1,2,3}, {1,4,5}, … for three-node (an even count repeats the last node).

    Examples
    --------
    >>> subsets(9, 3), subsets(4, 2)
    ([(0, 1, 2), (0, 3, 4), (0, 5, 6), (0, 7, 8)], [(0, 1), (0, 2), (0, 3)])
    """
    if nodes == 2:
        return [(0, i) for i in range(1, count)]
    out: list[tuple[int, ...]] = [(0, i, i + 1) for i in range(1, count - 1, 2)]
    if (count - 1) % 2:
        out.append((0, count - 2, count - 1))
    return out


# --------------------------------------------------------------------------------------------
# Work and the check
# --------------------------------------------------------------------------------------------

@dataclass
class PathWork:
    """Position computations and objective evaluations of a synthesis."""

    positions: int = 0
    evaluations: int = 0


@dataclass(frozen=True)
class PathCheck:
    """A mechanism judged against the target: deviations per row (mm), the input angle of each row (rad), the
    input's range (rad), the worst transmission angle over it (deg), branch and order."""

    deviations: np.ndarray
    theta: np.ndarray
    reproduced: np.ndarray     # the coupler point (complex mm) at each row; for a distance task M itself
    lo: float
    hi: float
    mu_min_deg: float
    branch_ok: bool
    in_order: bool
    positions: int

    @property
    def max_deviation(self) -> float:
        return float(np.max(self.deviations))

    @property
    def rms_deviation(self) -> float:
        return float(np.sqrt(np.mean(self.deviations ** 2)))


def _nearest_on_curve(mech: GuidingFourBar, target: PathTarget) -> tuple[np.ndarray, np.ndarray, int]:
    """Each target point's nearest point on the coupler curve over a full crank turn (where the loop closes and
    on the mechanism's branch): the crank angle and the distance, refined by a bounded search."""
    from scipy.optimize import minimize_scalar

    theta = np.linspace(0.0, 2 * math.pi, CURVE_SAMPLES)
    _, _, curve = mech.positions(theta)
    count = CURVE_SAMPLES
    thetas, dists = [], []
    for p in target.points:
        d = np.abs(curve - p)
        d = np.where(np.isfinite(d), d, np.inf)
        k = int(np.argmin(d))
        if not math.isfinite(float(d[k])):
            thetas.append(math.nan)
            dists.append(math.inf)
            continue
        h = theta[1] - theta[0]

        def dist(t, p=p):
            value = abs(complex(mech.positions(np.array([t]))[2][0]) - p)
            return value if math.isfinite(value) else 1e300

        res = minimize_scalar(dist, bounds=(theta[k] - h, theta[k] + h), method="bounded", options={"xatol": 1e-13})
        count += int(res.nfev)
        best = (res.x, res.fun) if res.fun <= d[k] else (theta[k], float(d[k]))
        thetas.append(float(best[0]))
        dists.append(float(best[1]))
    return np.array(thetas), np.array(dists), count


def _traced_range(theta: np.ndarray) -> tuple[float, float, bool]:
    """The crank's range that meets the rows in their order: from the first row's angle, turning in the sense
    that reaches them in order within one turn; (lo, hi, in order). Rows met in another order: the smallest arc
    covering them all, ``in order`` False."""
    for sense in (1.0, -1.0):
        steps = np.remainder(sense * np.diff(theta), 2 * math.pi)
        if steps.sum() < 2 * math.pi - 1e-9:
            end = theta[0] + sense * steps.sum()
            return min(theta[0], end), max(theta[0], end), True
    t = np.sort(np.remainder(theta, 2 * math.pi))
    gaps = np.diff(np.r_[t, t[0] + 2 * math.pi])
    k = int(np.argmax(gaps))
    lo = t[(k + 1) % len(t)]
    return float(lo), float(lo + 2 * math.pi - gaps[k]), False


def check(mech: GuidingFourBar, target: PathTarget) -> PathCheck:
    """Judge ``mech`` against ``target``: the deviation of every row (points: the distance to the coupler curve,
    its nearest point refined; timed: |M(θ₀ + φ) − P|; distance: | |M(θ₀ + φ) − X| − L |), the input's range
    (points: from the first row through the others in order), the worst transmission angle over it (closed
    form), and whether the loop closes over it without a dead point.

    Examples
    --------
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.3)
    >>> _, _, pts = m.positions(0.3 + np.radians([0, 20, 40, 60, 80]))
    >>> t = make_target("timed", [(p, z.real, z.imag) for p, z in zip([0, 20, 40, 60, 80], pts)])
    >>> c = check(m, t)
    >>> c.max_deviation < 1e-9, c.branch_ok
    (True, True)
    """
    if target.task == "points":
        theta, dev, count = _nearest_on_curve(mech, target)
        if not np.all(np.isfinite(theta)):
            return PathCheck(dev, theta, np.full(len(dev), np.nan + 0j), 0.0, 0.0, math.nan, False, False, count)
        lo, hi, in_order = _traced_range(theta)
        reproduced = mech.positions(theta)[2]
    else:
        theta = mech.theta0 + target.phi
        reproduced = mech.positions(theta)[2]
        count = len(theta)
        if target.task == "timed":
            dev = np.abs(reproduced - target.points)
        else:
            dev = np.abs(np.abs(reproduced - target.fixed) - target.distance)
        dev = np.where(np.isfinite(dev), dev, np.inf)
        lo, hi, in_order = float(min(theta[0], theta[-1])), float(max(theta[0], theta[-1])), True
    worst = mech.worst_transmission(lo, hi)
    count += 4
    branch_ok = bool(math.isfinite(worst) and worst > 1e-6)
    return PathCheck(dev, theta, reproduced, lo, hi, math.degrees(worst) if math.isfinite(worst) else math.nan,
                     branch_ok, in_order, count)


def limit_margins(mech: GuidingFourBar, lo: float, hi: float, limits: Limits, inside: float = INSIDE) -> np.ndarray:
    """The limits as smooth constraints (>= 0 when met): cos μ_min ∓ cos μ at the ends of the crank's range and
    where the crank lies on the frame line inside it (one angle per base: a fixed length); log R_max −
    log(l_i/l_j) for every pair of links.

    Examples
    --------
    Crank 30 of a 30/120/90/100 crank-rocker: the diagonal runs 70…130 mm, μ 35.4…75.0 deg over a turn:

    >>> m = GuidingFourBar(0j, 100 + 0j, 30.0, 120.0, 90.0, 1, 60 + 20j)
    >>> bool(limit_margins(m, 0.0, 2 * math.pi, Limits(30.0, 10.0)).min() > 0)
    True
    """
    eps = cmath.phase(mech.pivot - mech.o)
    a, b, c = mech.a, mech.b, mech.c
    d = abs(mech.pivot - mech.o)
    angles = [lo - eps, hi - eps]
    for base in (0.0, math.pi):      # one angle per base (cos is periodic), so the length never changes
        inside_angle = base + 2 * math.pi * math.ceil((lo - eps - base) / (2 * math.pi))
        angles.append(inside_angle if inside_angle <= hi - eps else lo - eps)
    th = np.array(angles)
    cos_mu = (b * b + c * c - (a * a + d * d - 2 * a * d * np.cos(th))) / (2 * b * c)
    bound = math.cos(math.radians(limits.mu_min_deg))
    logs = np.log(np.array([a, b, c, max(d, 1e-300)]))
    ratio = [math.log(limits.ratio_max) - (logs[i] - logs[j]) for i in range(4) for j in range(4) if i != j]
    return np.concatenate([bound - cos_mu, bound + cos_mu, ratio]) - inside


# --------------------------------------------------------------------------------------------
# The deviation method
# --------------------------------------------------------------------------------------------

def _pack(mech: GuidingFourBar) -> np.ndarray:
    return np.array([mech.o.real, mech.o.imag, mech.pivot.real, mech.pivot.imag, math.log(mech.a), math.log(mech.b),
                     math.log(mech.c), mech.point.real, mech.point.imag, mech.theta0])


def _unpack(x, branch: int) -> GuidingFourBar:
    a, b, c = (math.exp(min(float(v), 700.0)) for v in x[4:7])
    return GuidingFourBar(complex(x[0], x[1]), complex(x[2], x[3]), a, b, c, branch, complex(x[7], x[8]), float(x[9]))


def _residuals(target: PathTarget, mech: GuidingFourBar, theta: np.ndarray, work: PathWork) -> np.ndarray:
    work.positions += len(theta)
    work.evaluations += 1
    m = mech.positions(theta)[2]
    if target.task == "distance":
        r = np.abs(m - target.fixed) - target.distance
        r = np.where(np.isfinite(r), r, 10.0 * target.size)
        return r / target.size
    r = m - target.points
    r = np.where(np.isfinite(r), r, 10.0 * target.size)
    return np.concatenate([r.real, r.imag]) / target.size


def _angles(target: PathTarget, x: np.ndarray) -> np.ndarray:
    """The crank angles of the rows: θ₀ + φ (timed, distance) or the extra unknowns (points)."""
    if target.task == "points":
        return np.asarray(x[10:], dtype=float)
    return x[9] + target.phi


def polish(target: PathTarget, mech: GuidingFourBar, limits: Limits, work: PathWork,
           theta: np.ndarray | None = None) -> GuidingFourBar:
    """Least squares of the deviations over every parameter from ``mech`` (points: the rows' crank angles too,
    from ``theta``), then, when the result leaves the limits, SLSQP on the sum of squares with the limits as
    constraints. Returns the better admissible mechanism (``mech`` itself when neither improves on it)."""
    from scipy.optimize import least_squares, minimize

    branch = mech.branch
    x0 = _pack(mech)
    if target.task == "points":
        x0 = np.concatenate([x0, theta if theta is not None else check(mech, target).theta])

    def residuals(x):
        return _residuals(target, _unpack(x, branch), _angles(target, x), work)

    def margins(x):
        th = _angles(target, x)
        return limit_margins(_unpack(x, branch), float(np.min(th)), float(np.max(th)), limits)

    big = math.log(target.size)
    lower = np.full(len(x0), -np.inf)
    upper = np.full(len(x0), np.inf)
    lower[4:7], upper[4:7] = big - 8.0, big + 8.0          # link lengths within e^±8 of the target's size
    x0 = np.clip(x0, lower + 1e-9, upper - 1e-9)
    fit = least_squares(residuals, x0, method="trf", x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                        max_nfev=100 * len(x0), bounds=(lower, upper))
    x = fit.x
    if not np.all(np.isfinite(x)) or margins(x).min() < 0:
        res = minimize(lambda z: float(np.sum(residuals(z) ** 2)), x, method="SLSQP",
                       bounds=[(float(lo) if math.isfinite(lo) else None, float(hi) if math.isfinite(hi) else None)
                               for lo, hi in zip(lower, upper)],
                       constraints=[{"type": "ineq", "fun": margins}], options={"maxiter": 300, "ftol": 1e-20})
        x = res.x if np.all(np.isfinite(res.x)) and margins(res.x).min() >= -INSIDE else x0
    out = _unpack(x, branch)
    return out


def _distinct(fits: list, size: float, key, keep: int = 6) -> list:
    """The fits of least cost (within 10× the best, or exact), one per distinct solution (``key``: a point)."""
    fits = sorted(fits, key=lambda f: f.cost)
    if not fits:
        return []
    bound = max(1e-20, 10.0 * fits[0].cost)
    out: list = []
    for f in fits:
        if f.cost > bound or not np.all(np.isfinite(f.x)):
            break
        if all(abs(key(f) - key(g)) > 1e-6 * size for g in out):
            out.append(f)
        if len(out) == keep:
            break
    return out


def _crank_dyad(target: PathTarget, phi: np.ndarray | None, rng, starts: int, work: PathWork, every: bool = False
                ) -> list:
    """O, a, θ₀, e = |AM| with |M_k − A(θ₀ + φ_k)| = e by least squares (``phi`` None: equal steps, the step a
    further unknown and φ_k = k·step): the distinct solutions of least cost as (O, a, crank angles, cost). With
    more rows than unknowns the first exact fit ends the search; with as many (five rows) every start runs, as the
    exact solutions are several."""
    from scipy.optimize import least_squares

    pts, size = target.points, target.size
    centre = complex(np.mean(pts))
    free_step = phi is None
    k = np.arange(len(pts))
    square = every or len(pts) <= 5 + int(free_step)
    fits = []
    for _ in range(starts):
        x0 = [centre.real + rng.uniform(-1.5, 1.5) * size, centre.imag + rng.uniform(-1.5, 1.5) * size,
              math.log(size) + rng.uniform(-2.5, 0.3), rng.uniform(-math.pi, math.pi),
              math.log(size) + rng.uniform(-1.5, 0.7)]
        if free_step:
            x0.append(rng.choice([2 * math.pi / len(pts), 2 * math.pi / (len(pts) - 1)]) * rng.choice([1, -1])
                      * rng.uniform(0.6, 1.0))

        def res(x):
            work.positions += len(pts)
            angles = k * x[5] if free_step else phi
            a_pts = x[0] + 1j * x[1] + math.exp(min(x[2], 700.0)) * np.exp(1j * (x[3] + angles))
            return (np.abs(pts - a_pts) - math.exp(min(x[4], 700.0))) / size

        fits.append(least_squares(res, x0, method="lm", xtol=1e-15, ftol=1e-15, max_nfev=300))
        if not square and fits[-1].cost < 1e-24:
            break
    out = []
    for fit in _distinct(fits, size, lambda f: complex(f.x[0], f.x[1])):
        x = fit.x
        angles = k * x[5] if free_step else phi
        out.append((complex(x[0], x[1]), math.exp(x[2]), x[3] + angles, fit.cost))
    return out


def _rocker_dyad(target_points: np.ndarray, a_pts: np.ndarray, size: float, rng, starts: int, work: PathWork,
                 every: bool = False) -> list:
    """The coupler points B (w from A along A→M and to its left) whose positions lie on one circle (C, c): the
    distinct solutions of least cost as (B_k, C)."""
    from scipy.optimize import least_squares

    g = (target_points - a_pts) / np.abs(target_points - a_pts)
    square = every or len(a_pts) <= 5
    fits = []
    for _ in range(starts):
        w0 = complex(rng.uniform(-3, 3), rng.uniform(-3, 3)) * size
        b_pts = a_pts + w0 * g
        c0 = complex(np.mean(b_pts))
        x0 = [w0.real, w0.imag, c0.real, c0.imag, math.log(float(np.mean(np.abs(b_pts - c0))) + 1e-9 * size)]

        def res(x):
            work.positions += len(a_pts)
            b = a_pts + complex(x[0], x[1]) * g
            return (np.abs(b - complex(x[2], x[3])) - math.exp(min(x[4], 700.0))) / size

        fit = least_squares(res, x0, method="lm", xtol=1e-15, ftol=1e-15, max_nfev=300)
        if abs(complex(fit.x[0], fit.x[1])) < 1e-3 * size:
            continue                                 # B on A: no coupler
        fits.append(fit)
        if not square and fit.cost < 1e-24:
            break
    return [(a_pts + complex(f.x[0], f.x[1]) * g, complex(f.x[2], f.x[3]))
            for f in _distinct(fits, size, lambda f: complex(f.x[2], f.x[3]))]


def _from_poses(o: complex, a_pts: np.ndarray, b_pts: np.ndarray, pivot: complex, m_pts: np.ndarray,
                theta_1: float) -> GuidingFourBar:
    return from_dyads(o, complex(a_pts[0]), complex(b_pts[0]), pivot, complex(m_pts[0]), theta_1)


def _implicit(x: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The coupler curve's implicit equation at points ``m`` for parameter rows ``x`` (S, 9): o, C, log a, log c,
    log e1 = |AM|, log e2 = |BM|, γ = the angle AMB. With A = M + e1 e^{iα}, B = M + e2 e^{i(α+γ)}, the crank and
    rocker conditions are linear in (cos α, sin α); the curve is where their solution has cos² + sin² = 1."""
    o = (x[:, 0] + 1j * x[:, 1])[:, None]
    c_pt = (x[:, 2] + 1j * x[:, 3])[:, None]
    a, c, e1, e2 = (np.exp(x[:, i])[:, None] for i in range(4, 8))
    z, w = m[None, :] - o, (m[None, :] - c_pt) * np.exp(-1j * x[:, 8])[:, None]
    p1, q1, r1 = 2 * e1 * z.real, 2 * e1 * z.imag, a * a - np.abs(z) ** 2 - e1 * e1
    p2, q2, r2 = 2 * e2 * w.real, 2 * e2 * w.imag, c * c - np.abs(m[None, :] - c_pt) ** 2 - e2 * e2
    det = p1 * q2 - p2 * q1
    return (r1 * q2 - r2 * q1) ** 2 + (p1 * r2 - p2 * r1) ** 2 - det ** 2, (r1 * q2 - r2 * q1) / det, \
        (p1 * r2 - p2 * r1) / det


def _evolution_starts(target: PathTarget, limits: Limits, seed: int, work: PathWork, trials: int = 3
                      ) -> list[tuple[GuidingFourBar, np.ndarray]]:
    """Starts for the untimed task from differential evolution on the implicit equation (normalised by its
    gradient: a distance), with penalties for rows on different assembly branches and for the link ratio."""
    from scipy.optimize import differential_evolution

    pts, size = target.points, target.size
    centre = complex(np.mean(pts))
    big = math.log(size)
    bounds = [(centre.real - 3 * size, centre.real + 3 * size), (centre.imag - 3 * size, centre.imag + 3 * size)] * 2
    bounds += [(big - 2.7, big + 1.0)] * 4 + [(-math.pi, math.pi)]
    h = 1e-6 * size

    def objective(pop):
        x = pop.T
        work.evaluations += len(x)
        work.positions += 5 * len(x) * len(pts)
        f, cos_a, sin_a = _implicit(x, pts)
        fx = (_implicit(x, pts + h)[0] - _implicit(x, pts - h)[0]) / (2 * h)
        fy = (_implicit(x, pts + 1j * h)[0] - _implicit(x, pts - 1j * h)[0]) / (2 * h)
        dist = f / np.sqrt(fx * fx + fy * fy + 1e-300) / size
        alpha = np.arctan2(sin_a, cos_a)
        c_pt = (x[:, 2] + 1j * x[:, 3])[:, None]
        a_pts = pts[None, :] + np.exp(x[:, 6])[:, None] * np.exp(1j * alpha)
        b_pts = pts[None, :] + np.exp(x[:, 7])[:, None] * np.exp(1j * (alpha + x[:, 8][:, None]))
        cross = ((a_pts - c_pt).conj() * (b_pts - c_pt)).imag / size ** 2
        side = np.sign(np.sum(np.sign(cross), 1, keepdims=True) + 1e-9)
        b_len = np.abs(np.exp(x[:, 6]) - np.exp(x[:, 7]) * np.exp(1j * x[:, 8]))
        links = np.stack([np.exp(x[:, 4]), b_len, np.exp(x[:, 5]), np.abs(c_pt[:, 0] - x[:, 0] - 1j * x[:, 1])])
        ratio = np.maximum(0.0, np.log(links.max(0) / links.min(0)) - math.log(limits.ratio_max))
        value = np.sqrt(np.mean(dist * dist, 1)) + np.sum(np.maximum(0.0, -side * cross), 1) + ratio
        return np.where(np.isfinite(value), value, 1e6)

    out = []
    for trial in range(trials):
        res = differential_evolution(objective, bounds, vectorized=True, popsize=40, maxiter=400, tol=1e-12,
                                     seed=seed * 101 + trial, polish=False, updating="deferred", mutation=(0.5, 1.0),
                                     recombination=0.9)
        values = objective(res.population.T)
        for k in np.argsort(values)[:3]:
            x = res.population[k]
            _, cos_a, sin_a = _implicit(x[None, :], pts)
            alpha = np.arctan2(sin_a[0], cos_a[0])
            a_pts = pts + math.exp(x[6]) * np.exp(1j * alpha)
            b_pts = pts + math.exp(x[7]) * np.exp(1j * (alpha + x[8]))
            o = complex(x[0], x[1])
            theta = np.angle(a_pts - o)
            if np.all(np.isfinite(a_pts)) and np.all(np.isfinite(b_pts)):
                out.append((_from_poses(o, a_pts, b_pts, complex(x[2], x[3]), pts, float(theta[0])), theta))
        if res.fun < 1e-6:
            break
    return out


def _dyad_starts(target: PathTarget, seed: int, work: PathWork, every: bool = False
                 ) -> list[tuple[GuidingFourBar, np.ndarray]]:
    """Starts from the dyads: the crank's fitted to a timing of the rows (timed: the given φ; points: equal crank
    steps with the step a further unknown, and steps in proportion to the chords between the points over one turn,
    both senses), the rocker's to the coupler poses that gives."""
    rng = np.random.default_rng(seed)
    out: list[tuple[GuidingFourBar, np.ndarray]] = []
    if target.task == "distance":
        return out
    size = target.size
    timings: list[np.ndarray | None] = [target.phi] if target.task == "timed" else [None, None]
    if target.task == "points":
        chords = np.abs(np.diff(np.r_[target.points, target.points[0]]))
        steps = np.r_[0.0, np.cumsum(chords[:-1])] * 2 * math.pi / float(np.sum(chords))
        timings += [steps, -steps]
    for phi in timings:
        for o, a, theta, _ in _crank_dyad(target, phi, rng, 30, work, every):
            a_pts = o + a * np.exp(1j * theta)
            for b_pts, pivot in _rocker_dyad(target.points, a_pts, size, rng, 30, work, every):
                try:
                    out.append((_from_poses(o, a_pts, b_pts, pivot, target.points, float(theta[0])), theta))
                except ValueError:
                    continue
    return out


def _random_distance_starts(target: PathTarget, seed: int, count: int
                            ) -> list[tuple[GuidingFourBar, np.ndarray | None]]:
    """Random mechanisms around the fixed point (the distance task has no points to fit dyads to); no start
    angles (None)."""
    rng = np.random.default_rng(seed)
    size = target.size
    x = target.fixed
    assert x is not None            # make_target gives every distance task its fixed point
    out: list[tuple[GuidingFourBar, np.ndarray | None]] = []
    for _ in range(count):
        o = x + complex(*rng.uniform(-1.5, 1.5, 2)) * size
        pivot = o + complex(*rng.uniform(-1.5, 1.5, 2)) * size
        a, b, c = (size * math.exp(v) for v in rng.uniform(-2.0, 0.5, 3))
        mech = GuidingFourBar(o, pivot, a, b, c, int(rng.choice([1, -1])), complex(*rng.uniform(-1, 1, 2)) * size,
                              float(rng.uniform(-math.pi, math.pi)))
        out.append((mech, None))
    return out


# --------------------------------------------------------------------------------------------
# The Q method
# --------------------------------------------------------------------------------------------

@dataclass
class QPath:
    """One value of the path Q: the pivots found from the node subsets, Q (mm), the centre mechanism."""

    q: float
    pivots: np.ndarray
    mechanism: GuidingFourBar | None
    theta: np.ndarray | None
    split: int = 0          # the timed task: the first ``split`` pivots are stage 1's (crank pins), the rest stage 2's


def _side_patterns(dist: np.ndarray) -> list[np.ndarray]:
    """The sides of B (±1 per row) to try: both constant, and those that change at the gaps next to the largest
    and the smallest |CM_k| (where the triangle C–B–M can turn over)."""
    n = len(dist)
    out = [np.ones(n), -np.ones(n)]
    kmax, kmin = int(np.argmax(dist)), int(np.argmin(dist))
    for gmax in (kmax, kmax + 1):
        for gmin in (kmin, kmin + 1):
            s = -np.ones(n)
            idx = gmax % n
            while idx != gmin % n:
                s[idx] = 1.0
                idx = (idx + 1) % n
            out += [s, -s]
    return out


class PathQ:
    """The Q objective of one task (module docstring); ``nodes`` 2 or 3; counts positions in ``work``."""

    def __init__(self, target: PathTarget, nodes: int, limits: Limits, work: PathWork):
        self.target, self.nodes, self.limits, self.work = target, nodes, limits, work
        self.subsets = subsets(target.count, nodes)
        self.size = target.size

    # free parameters, per task -------------------------------------------------------------
    def start_of(self, mech: GuidingFourBar) -> np.ndarray:
        """The free parameters of a mechanism (to start the Q search from it)."""
        t = self.target
        if t.task == "points":
            chk = check(mech, t)
            a_pts, b_pts, m_pts = mech.positions(chk.theta)
            e = abs(m_pts[0] - b_pts[0])
            w = (a_pts[0] - b_pts[0]) / ((m_pts[0] - b_pts[0]) / e)
            x = [mech.pivot.real, mech.pivot.imag, math.log(mech.c), math.log(e), w.real, w.imag]
            return np.array(x + ([math.log(mech.a)] if self.nodes == 2 else []))
        a_pts, b_pts, m_pts = mech.positions(mech.theta0 + t.phi)
        g = (m_pts[0] - a_pts[0]) / abs(m_pts[0] - a_pts[0])
        w = (b_pts[0] - a_pts[0]) / g
        if t.task == "timed":
            return np.array([mech.o.real, mech.o.imag, math.log(abs(m_pts[0] - a_pts[0])), w.real, w.imag])
        return np.array([mech.o.real, mech.o.imag, math.log(mech.a), mech.theta0, math.log(abs(m_pts[0] - a_pts[0])),
                         w.real, w.imag] + ([math.log(mech.c)] if self.nodes == 2 else []))

    def state(self, x: np.ndarray) -> QPath:
        t = self.target
        self.work.evaluations += 1
        self.work.positions += t.count
        solve = {"points": self._points, "timed": self._timed, "distance": self._distance}[t.task]
        try:
            return solve(x)
        except (ValueError, ZeroDivisionError, OverflowError):      # a degenerate set of free parameters
            return QPath(math.inf, np.array([complex(math.nan)]), None, None)

    def _found(self, pts: np.ndarray, radius: float | None) -> np.ndarray:
        """The pivot of each node subset: the circumcentre (3 nodes) or, with ``radius``, the meeting point of
        the circles about node 1 and node i nearest the others (2 nodes)."""
        if self.nodes == 3:
            return np.array([circumcentre(pts[i], pts[j], pts[k]) for i, j, k in self.subsets])
        cands = []
        for i, j in self.subsets:
            p1, _ = circle_meet(pts[i], radius, pts[j], radius, 1.0)
            p2, _ = circle_meet(pts[i], radius, pts[j], radius, -1.0)
            cands.append((complex(p1), complex(p2)))
        best, best_q = None, math.inf
        for ref in cands[0]:
            chosen = np.array([_nearest(pair, ref) for pair in cands])
            q, _ = _box(chosen)
            if q < best_q:
                best, best_q = chosen, q
        if best is None:   # no finite meeting point: the caller's finiteness check rejects it
            return np.full(len(cands), complex(math.nan))
        return np.asarray(best)

    def _points(self, x) -> QPath:
        pts = self.target.points
        pivot, c, e, w = complex(x[0], x[1]), math.exp(x[2]), math.exp(x[3]), complex(x[4], x[5])
        dist = np.abs(pts - pivot)
        best = None
        for side in _side_patterns(dist):
            b_pts, gap = circle_meet(pivot, c, pts, e, -side)
            a_pts = b_pts + w * (pts - b_pts) / e
            radius = math.exp(x[6]) if self.nodes == 2 else None
            found = self._found(a_pts, radius)
            q, centre = _box(found) if np.all(np.isfinite(found)) else (math.inf, 0j)
            q += float(np.sum(gap)) / self.size
            if best is None or q < best[0]:
                best = (q, found, centre, a_pts, b_pts)
        assert best is not None         # _side_patterns gives two or more patterns
        q, found, centre, a_pts, b_pts = best
        if not math.isfinite(q):
            return QPath(q, found, None, None)
        theta = np.angle(a_pts - centre)
        mech = from_dyads(centre, complex(a_pts[0]), complex(b_pts[0]), pivot, complex(pts[0]), float(theta[0]))
        mech = replace(mech, a=float(np.mean(np.abs(a_pts - centre))))
        return QPath(q, found, mech, theta)

    def _timed(self, x) -> QPath:
        t = self.target
        pts, phi = t.points, t.phi
        o, e = complex(x[0], x[1]), math.exp(x[2])
        # stage 1: the crank pin at node 1 from nodes {1, i}: circles (M_1, e) and (M_i, e) turned back about O
        back = o + (pts - o) * np.exp(-1j * phi)
        cands = [circle_meet(pts[0], e, back[i], e, s)[0] for i in range(1, len(pts)) for s in (1.0, -1.0)]
        pairs = [(complex(cands[2 * k]), complex(cands[2 * k + 1])) for k in range(len(pts) - 1)]
        best, best_q = None, math.inf
        for ref in pairs[0]:
            chosen = np.array([_nearest(p, ref) for p in pairs])
            q, _ = _box(chosen)
            if q < best_q:
                best, best_q = chosen, q
        if best is None:   # no finite crank pin (e.g. a crank so long its square overflows): a degenerate start
            return QPath(math.inf, np.array([complex(math.nan)]), None, None)
        q1, a_1 = _box(np.asarray(best))
        a_pts = o + (a_1 - o) * np.exp(1j * phi)
        g = (pts - a_pts) / np.abs(pts - a_pts)
        w = complex(x[3], x[4])
        b_pts = a_pts + w * g
        found = np.array([circumcentre(b_pts[i], b_pts[j], b_pts[k]) for i, j, k in subsets(len(pts), 3)])
        q2, pivot = _box(found) if np.all(np.isfinite(found)) else (math.inf, 0j)
        if not math.isfinite(q2):
            return QPath(math.inf, found, None, None)
        theta_1 = cmath.phase(a_1 - o)
        mech = from_dyads(o, a_1, complex(b_pts[0]), pivot, complex(pts[0]), theta_1)
        return QPath(q1 + q2, np.concatenate([best, found]), mech, theta_1 + phi, len(best))

    def _distance(self, x) -> QPath:
        t = self.target
        o, a, theta0, e, w = complex(x[0], x[1]), math.exp(x[2]), x[3], math.exp(x[4]), complex(x[5], x[6])
        theta = theta0 + t.phi
        a_pts = o + a * np.exp(1j * theta)
        best = None
        for side in (1.0, -1.0):
            m_pts, gap = circle_meet(a_pts, e, t.fixed, t.distance, side)
            g = (m_pts - a_pts) / e
            b_pts = a_pts + w * g
            if self.nodes == 3:
                found = np.array([circumcentre(b_pts[i], b_pts[j], b_pts[k]) for i, j, k in self.subsets])
            else:
                found = self._found(b_pts, math.exp(x[7]))
            q, pivot = _box(found) if np.all(np.isfinite(found)) else (math.inf, 0j)
            q += float(np.sum(gap)) / self.size
            if best is None or q < best[0]:
                best = (q, found, pivot, m_pts, b_pts)
        assert best is not None         # two sides tried
        q, found, pivot, m_pts, b_pts = best
        if not math.isfinite(q):
            return QPath(q, found, None, None)
        mech = from_dyads(o, complex(a_pts[0]), complex(b_pts[0]), pivot, complex(m_pts[0]), float(theta0))
        return QPath(q, found, mech, theta)

    def residual(self, x: np.ndarray) -> np.ndarray:
        """The pivots' spread as a vector (its zero is Q = 0) and the limits as exact penalties (10 × violation)."""
        st = self.state(x)
        k = len(st.pivots)
        if st.mechanism is None or not np.all(np.isfinite(st.pivots)):
            return np.full(2 * k + 1, 10.0)
        groups = [st.pivots[:st.split], st.pivots[st.split:]] if st.split else [st.pivots]
        spread = np.concatenate([g - np.mean(g) for g in groups]) / self.size
        lo, hi = self._range(st)
        margins = limit_margins(st.mechanism, lo, hi, self.limits, inside=PENALTY_INSIDE)
        penalty = 10.0 * float(np.sum(np.maximum(0.0, -margins)))
        return np.concatenate([spread.real, spread.imag, [penalty]])

    def _range(self, st: QPath) -> tuple[float, float]:
        if self.target.task == "points":
            lo, hi, _ = _traced_range(np.asarray(st.theta))
            return lo, hi
        th = np.asarray(st.theta)
        return float(min(th[0], th[-1])), float(max(th[0], th[-1]))


@dataclass
class PathResult:
    """A guiding four-bar found by one method: the mechanism, its check, the work, the method's details."""

    method: str
    mechanism: GuidingFourBar
    check: PathCheck
    work: PathWork
    q: float | None = None
    q_pivots: np.ndarray | None = None
    starts: int = 0
    notes: list[str] = field(default_factory=list)
    candidates: list[GuidingFourBar] = field(default_factory=list)   # every polished mechanism (deviation)


def _best(target: PathTarget, mechs: list[GuidingFourBar], limits: Limits) -> tuple[GuidingFourBar, PathCheck]:
    """The admissible mechanism of least maximum deviation (else the least deviation)."""
    judged = [(m, check(m, target)) for m in mechs]

    def key(item):
        m, c = item
        ok = admissible(m, c, limits)
        return (0 if ok else 1, c.max_deviation if math.isfinite(c.max_deviation) else math.inf)

    return min(judged, key=key)


def admissible(mech: GuidingFourBar, chk: PathCheck, limits: Limits) -> bool:
    """The limits are met: the loop closes over the input's range without a dead point, μ >= μ_min, ratio."""
    links = mech.links()
    return bool(chk.branch_ok and chk.mu_min_deg >= limits.mu_min_deg
                and max(links) / min(links) <= limits.ratio_max)


def _start_cost(target: PathTarget, item, work: PathWork) -> float:
    """The sum of squared deviations of a start (its own crank angles for points)."""
    mech, theta = item
    angles = theta if target.task == "points" and theta is not None else mech.theta0 + target.phi
    if target.task == "points" and theta is None:
        return math.inf
    r = _residuals(target, mech, np.asarray(angles, dtype=float), work)
    return float(np.sum(r * r))


def deviation_synthesis(target: PathTarget, limits: Limits, seed: int = 0, tolerance: float | None = None,
                        every: bool = False, evolution: bool = True) -> PathResult:
    """The deviation method (module docstring): starts from the dyads (and, for points that they do not reach,
    from differential evolution on the implicit equation), each polished by least squares under the limits.

    Examples
    --------
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.3)
    >>> phi = np.radians(np.arange(0, 160, 20))
    >>> t = make_target("timed", [(p, z.real, z.imag) for p, z in zip(np.degrees(phi), m.positions(0.3 + phi)[2])])
    >>> r = deviation_synthesis(t, Limits(30.0, 10.0))
    >>> r.check.max_deviation < 1e-6 * t.size
    True
    """
    work = PathWork()
    tol = tolerance if tolerance is not None else DEFAULT_TOLERANCE * target.size
    starts = _dyad_starts(target, seed, work, every) if target.task != "distance" else \
        _random_distance_starts(target, seed, 40)
    notes: list[str] = []

    def polished(pool) -> list[GuidingFourBar]:
        """Polish the starts best first; stop at the first admissible one within a tenth of the tolerance (all
        of the best eight with ``every``, as a family's starts)."""
        ranked = sorted(pool, key=lambda item: _start_cost(target, item, work))
        out = []
        for mech, theta in ranked[:8]:
            out.append(polish(target, mech, limits, work, theta))
            chk = check(out[-1], target)
            if not every and admissible(out[-1], chk, limits) and chk.max_deviation <= 0.1 * tol:
                break
        return out

    mechs = polished(starts)
    if target.task == "points" and evolution:
        best = _best(target, mechs, limits) if mechs else None
        if best is None or not admissible(*best, limits) or best[1].max_deviation > tol:
            evo = _evolution_starts(target, limits, seed, work)
            mechs += polished(evo)
            notes.append(f"starts: {len(starts)} from the dyads (equal crank steps, chord steps), {len(evo)} from "
                         "differential evolution on the implicit equation")
            starts = starts + evo
    if not mechs:
        raise CamcadError("no four-bar was found for this path", target.source,
                          "check the table (points along one curve, in order)")
    mech, chk = _best(target, mechs, limits)
    return PathResult("deviation", mech, chk, work, starts=len(starts), notes=notes, candidates=mechs)


def q_synthesis(target: PathTarget, limits: Limits, nodes: int = 3, seed: int = 0,
                starts: list[GuidingFourBar] | None = None, random_starts: int = 30) -> PathResult:
    """Sunkuev 1984's Q method for the task (module docstring): Q minimised (least squares on the pivots' spread with
    the limits as exact penalties) from the given starts and ``random_starts`` random ones; the pivot at the
    rectangle's centre.

    Examples
    --------
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.3)
    >>> phi = np.radians(np.arange(0, 160, 20))
    >>> t = make_target("timed", [(p, z.real, z.imag) for p, z in zip(np.degrees(phi), m.positions(0.3 + phi)[2])])
    >>> r = q_synthesis(t, Limits(30.0, 10.0), starts=[m])
    >>> r.q < 1e-9, r.check.max_deviation < 1e-6
    (True, True)
    """
    from scipy.optimize import least_squares

    if nodes not in (2, 3):
        raise CamcadError(f"--nodes {nodes}: the Q method interpolates on 2 or 3 nodes", "--nodes", "give 2 or 3")
    if target.task == "timed" and nodes == 2:
        nodes = 3                 # the timed task's stage 1 is a two-node construction, stage 2 three-node
    work = PathWork()
    problem = PathQ(target, nodes, limits, work)
    rng = np.random.default_rng(seed)
    xs = [problem.start_of(m) for m in (starts or [])]
    size, centre = target.size, complex(np.mean(target.points)) if target.task != "distance" else target.fixed
    assert centre is not None       # make_target gives every distance task its fixed point
    for _ in range(random_starts):
        if target.task == "points":
            x = [centre.real + rng.uniform(-2, 2) * size, centre.imag + rng.uniform(-2, 2) * size,
                 math.log(size) + rng.uniform(-1.5, 0.7), math.log(size) + rng.uniform(-1.5, 0.7),
                 rng.uniform(-2, 2) * size, rng.uniform(-2, 2) * size]
            x += [math.log(size) + rng.uniform(-2.5, 0.3)] if nodes == 2 else []
        elif target.task == "timed":
            x = [centre.real + rng.uniform(-2, 2) * size, centre.imag + rng.uniform(-2, 2) * size,
                 math.log(size) + rng.uniform(-1.5, 0.7), rng.uniform(-2, 2) * size, rng.uniform(-2, 2) * size]
        else:
            x = [centre.real + rng.uniform(-1.5, 1.5) * size, centre.imag + rng.uniform(-1.5, 1.5) * size,
                 math.log(size) + rng.uniform(-2.5, 0.3), rng.uniform(-math.pi, math.pi),
                 math.log(size) + rng.uniform(-1.5, 0.5), rng.uniform(-2, 2) * size, rng.uniform(-2, 2) * size]
            x += [math.log(size) + rng.uniform(-1.5, 0.5)] if nodes == 2 else []
        xs.append(np.array(x))
    best = None
    given = len(xs) - random_starts
    for index, x0 in enumerate(xs):
        if index == given and best is not None and not best[0][0] and best[0][1] <= 1e-9 * size:
            break                 # a given start reached Q = 0 within the limits: no random start can do better
        try:
            fit = least_squares(problem.residual, x0, method="trf", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
        except ValueError:
            continue
        st = problem.state(fit.x)
        if st.mechanism is None:
            continue
        penalty = float(problem.residual(fit.x)[-1])
        key = (penalty > 0, st.q)
        if best is None or key < best[0]:
            best = (key, st)
    if best is None:
        raise CamcadError("the Q method found no pivots for this path (the circles never meet)", target.source,
                          "check the table, or try --method deviation")
    st = best[1]
    mech = st.mechanism
    assert mech is not None         # only states with a mechanism are kept
    chk = check(mech, target)
    return PathResult("q", mech, chk, work, st.q, st.pivots, len(xs),
                      [] if best[0][0] is False else ["the least Q found violates a limit"])


# --------------------------------------------------------------------------------------------
# Adjustable guiding mechanisms: a family of curves, of timed curves, of distances (Sunkuev 1984, ch. 5)
# --------------------------------------------------------------------------------------------

@dataclass
class PathFamilyResult:
    """One adjustable guiding four-bar for a family of targets: every member's mechanism (they differ only by the
    position of the moved pivot, which lies on the arc of ``centre``, ``radius`` at the angles ``settings``) and
    its check; ``q`` = Σ Q⁽ʲ⁾ (mm) of stage 1; ``moved`` names the moved pivot (O or C)."""

    members: list[PathTarget]
    mechanisms: list[GuidingFourBar]
    checks: list[PathCheck]
    centre: complex
    radius: float
    settings: np.ndarray
    circle_residual: float
    q: float
    q_members: list[float]
    moved: str
    work: PathWork
    starts: int


def _family_states(problems: list[PathQ], x: np.ndarray) -> list[QPath]:
    task = problems[0].target.task
    if task == "distance":          # shared: O, log a, log e, w (, log c); per member: θ₀
        shared, phases = x[:len(x) - len(problems)], x[len(x) - len(problems):]
        return [p.state(np.concatenate([shared[:3], [ph], shared[3:]])) for p, ph in zip(problems, phases)]
    return [p.state(x) for p in problems]


def _family_residual(problems: list[PathQ], limits: Limits, x: np.ndarray) -> np.ndarray:
    states = _family_states(problems, x)
    size = max(p.size for p in problems)
    out = []
    for p, st in zip(problems, states):
        k = max(2 * len(st.pivots) + 1, 3)
        if st.mechanism is None or not np.all(np.isfinite(st.pivots)):
            out.append(np.full(k, 10.0))
            continue
        groups = [st.pivots[:st.split], st.pivots[st.split:]] if st.split else [st.pivots]
        spread = np.concatenate([g - np.mean(g) for g in groups]) / size
        lo, hi = p._range(st)
        penalty = 10.0 * float(np.sum(np.maximum(0.0, -limit_margins(st.mechanism, lo, hi, limits,
                                                                     inside=PENALTY_INSIDE))))
        out.append(np.concatenate([spread.real, spread.imag, [penalty]]))
    if problems[0].target.task == "timed":    # one crank: the crank pins of the members at one radius from O
        o = complex(x[0], x[1])
        radii = [abs(st.mechanism.a) if st.mechanism is not None else 0.0 for st in states]
        out.append(np.array([(r - np.mean(radii)) / size for r in radii]))
        del o
    return np.concatenate(out)


def path_family(targets: list[PathTarget], limits: Limits, seed: int = 0, random_starts: int = 20
                ) -> PathFamilyResult:
    """One adjustable guiding four-bar for a family of targets of one task (Sunkuev 1984's ch. 5, Figs. 10–12).

    Stage 1: the Q construction of each member (``PathQ``, two-node subsets for curves so the crank is shared)
    with the free parameters shared by all members — points: the rocker's dyad, the coupler and the crank (the
    crank's pivot O is each member's found pivot); timed: the crank's pivot O, |AM| and the coupler (each
    member's crank pins and rocker pivot C are found; the crank pins' radius is held equal); distance: every
    free parameter but the crank's phase θ₀⁽ʲ⁾ (each member's rocker pivot C is found) — minimising Σ Q⁽ʲ⁾ with
    the limits as exact penalties (least squares on the pivots' spreads), from a member's own synthesis and
    ``random_starts`` random starts (the first member's synthesis: every distinct dyad solution with timing, the
    dyad starts without differential evolution for curves). Stage 2: the centres of the members' rectangles lie on
    the arc of the adjustable link: the circle through them (three members; least squares beyond) gives its
    centre and radius, and the settings are the angles of the pivot about it.

    Examples
    --------
    Three timed members made by one four-bar whose rocker pivot sits at three points of an arc:

    >>> base = GuidingFourBar(0j, 100 + 0j, 35.0, 110.0, 95.0, 1, 55 + 35j, 0.3)
    >>> arc = [100 + 20 * cmath.exp(1j * t) - 20 for t in (0.0, 0.25, 0.5)]
    >>> phi = np.radians(np.arange(0.0, 240.0, 40.0))
    >>> members = [make_target("timed", [(math.degrees(p), z.real, z.imag) for p, z in
    ...                                 zip(phi, replace(base, pivot=c).positions(0.3 + phi)[2])]) for c in arc]
    >>> r = path_family(members, Limits(20.0, 10.0), random_starts=0)
    >>> round(abs(r.centre - 80), 6), round(r.radius, 6)
    (0.0, 20.0)
    """
    from scipy.optimize import least_squares

    task = targets[0].task
    if len(targets) < 3 or any(t.task != task for t in targets):
        raise CamcadError(f"a family needs three or more tables of one task, got {len(targets)}", "linkage path",
                          "repeat --points (or --timed, or --distance) for each member")
    if task == "distance" and len({t.fixed for t in targets}) != 1:
        raise CamcadError("the members of a distance family share the fixed point", "--fixed-point",
                          "give one --fixed-point")
    work = PathWork()
    nodes = 2 if task == "points" else 3
    problems = [PathQ(t, nodes, limits, work) for t in targets]
    first = deviation_synthesis(targets[0], limits, seed, every=task != "points", evolution=False)
    xs = []
    for mech in first.candidates:
        try:
            x = problems[0].start_of(mech)
        except (ValueError, ZeroDivisionError):
            continue
        if task == "distance":
            x = np.concatenate([x[:3], x[4:], [x[3]] * len(targets)])
        xs.append(x)
    rng = np.random.default_rng(seed)
    xs += [xs[k % len(xs)] * (1 + 0.05 * rng.standard_normal(len(xs[0]))) for k in range(random_starts) if xs]
    best = None
    for x0 in xs:
        try:
            fit = least_squares(lambda x: _family_residual(problems, limits, x), x0, method="trf", xtol=1e-15,
                                ftol=1e-15, gtol=1e-15, max_nfev=400)
        except ValueError:
            continue
        if best is None or fit.cost < best.cost:
            best = fit
    if best is None:
        raise CamcadError("no adjustable four-bar was found for this family", "linkage path",
                          "check the members (curves of one kind, points in order)")
    states = _family_states(problems, best.x)
    mechs = [st.mechanism for st in states if st.mechanism is not None]
    if len(mechs) != len(states):
        raise CamcadError("the family's Q construction has no pivot for a member", "linkage path",
                          "check the members, or give more rows")
    if task == "points":
        moved = [m.o for m in mechs]
    else:
        moved = [m.pivot for m in mechs]
    centre, rad, residual = fit_circle(moved)
    settings = np.array([cmath.phase(p - centre) for p in moved])
    checks = [check(m, t) for m, t in zip(mechs, targets)]
    q_members = [st.q for st in states]
    return PathFamilyResult(targets, mechs, checks, centre, rad, settings, residual, float(sum(q_members)), q_members,
                            "O" if task == "points" else "C", work, len(xs))
