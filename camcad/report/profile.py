"""Plots of a synthesised cam: kinematics, pressure angle, curvature, profile, hodograph, and the one-page
summary that a scene writes by default.

Each ``plot_*`` function returns a matplotlib Figure (``camcad.report.figure``); each ``draw_*`` function
draws into axes the caller gives, so the summary page reuses them. Each figure says its units, shades
what is not allowed, and labels the extrema and the margins, so that a reader sees at a glance whether
the design passes and where it is tight.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from camcad.profile.summary import profile_report
from camcad.report.figure import COLOURS, TITLE_Y, fix_label_positions, new_figure, save_figure
from camcad.report.verdict_text import verdict_lines

PHASE_COLOURS = {"rise": "#d9f0d3", "return": "#fde0c5", "dwell": None}
#: line spacing of the verdict's monospace lines (a multiple of the font size): 1.3 × 8 pt, the step between
#: its text objects
VERDICT_LINESPACING = 1.3
FORBIDDEN = "#f4c7c3"


def _shade_phases(ax, result) -> None:
    law = result.law
    cycle = math.degrees(law.cycle)
    for lobe in range(result.geometry.lobes):
        for phase in law.phases:
            colour = PHASE_COLOURS.get(phase.kind)
            if colour:
                ax.axvspan(lobe * cycle + math.degrees(phase.start), lobe * cycle + math.degrees(phase.end),
                           color=colour, alpha=0.6, lw=0, zorder=0)


def _label_point(ax, x: float, y: float, text: str, below: bool = False, fontsize: int = 8) -> None:
    """Mark (x, y) (x in deg on a 0–360 axis) with a dot and ``text`` beside it, on its left near the
    right-hand edge so that it is not cut off."""
    ax.plot(x, y, "o", ms=4, color="black", zorder=5)
    right_edge = x > 0.6 * 360.0
    ax.annotate(text, (x, y), textcoords="offset points", xytext=(-6 if right_edge else 6, -4 if below else 4),
                ha="right" if right_edge else "left", va="top" if below else "bottom", fontsize=fontsize)


def _annotate_extrema(ax, x: np.ndarray, y: np.ndarray, unit: str) -> None:
    """Label the largest and the smallest value, unless it is zero to round-off (a dwell at s = 0)."""
    finite = np.isfinite(y)
    if not finite.any():
        return
    scale = float(np.max(np.abs(y[finite])))
    for index, below in ((int(np.nanargmax(np.where(finite, y, -np.inf))), False),
                         (int(np.nanargmin(np.where(finite, y, np.inf))), True)):
        if abs(y[index]) <= 1e-9 * scale:
            continue
        _label_point(ax, float(x[index]), float(y[index]), f"{y[index]:.4g} {unit}\n@ {x[index]:.1f}°", below)


def _theta_axis(ax, step: int = 30) -> None:
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, step))
    ax.grid(True, lw=0.4, alpha=0.6)


def plot_kinematics(result):
    """The law's s, v, a and j against the cam angle, phases shaded, extrema labelled.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``camcad.synthesize``).

    Returns
    -------
    matplotlib.figure.Figure
        Four axes sharing the cam angle θ (deg): s (mm), v (mm/rad), a (mm/rad²), j (mm/rad³); for an oscillating
        follower rad of swing instead of mm.
        Saving it (``fig.savefig``) is the caller's choice.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> figure = camcad.plot_kinematics(result)
    >>> [axes.get_ylabel() for axes in figure.axes]
    ['s (mm)', 'v = ds/dθ (mm/rad)', 'a = d²s/dθ² (mm/rad²)', 'j = d³s/dθ³ (mm/rad³)']
    >>> figure.axes[-1].get_xlabel()
    'cam angle θ (deg)'
    """
    fig, axes = new_figure(10, 10, rows=4, sharex=True)
    draw_kinematics(list(axes), result)
    fig.suptitle(f"{result.name}: motion law — green rise, orange return, white dwell", fontsize=11)
    return fig


def draw_kinematics(axes, result, rows: tuple[str, ...] = ("s", "v", "a", "j"), titles: bool = True) -> None:
    """The law's kinematic functions named in ``rows`` into ``axes`` (one each)."""
    t = result.table
    deg = np.degrees(t.theta)
    unit = "rad" if result.follower.kind == "oscillating" else "mm"
    table = {"s": (t.s, unit, "s", "displacement"), "v": (t.v, f"{unit}/rad", "v = ds/dθ", "velocity analog"),
             "a": (t.a, f"{unit}/rad²", "a = d²s/dθ²", "acceleration analog"),
             "j": (t.j, f"{unit}/rad³", "j = d³s/dθ³", "jerk analog")}
    for ax, (y, units, symbol, title) in zip(axes, (table[r] for r in rows)):
        _shade_phases(ax, result)
        ax.plot(deg, y, lw=1.4, color="#1f4e79")
        ax.axhline(0.0, color="black", lw=0.6)
        ax.set_ylabel(f"{symbol} ({units})")
        if titles:
            ax.set_title(title, fontsize=9, loc="right", y=TITLE_Y)
        _annotate_extrema(ax, deg, y, units)
        low, high = np.nanmin(y), np.nanmax(y)
        pad = 0.25 * (high - low) if high > low else 1.0
        ax.set_ylim(low - pad, high + pad)
        _theta_axis(ax)
    axes[-1].set_xlabel("cam angle θ (deg)")


def plot_pressure_angle(result):
    """The pressure angle against the cam angle, with its limits shaded and the extremes labelled.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``camcad.synthesize``).

    Returns
    -------
    matplotlib.figure.Figure
        One axes: the pressure angle (deg) against the cam angle θ (deg).
        Saving it (``fig.savefig``) is the caller's choice.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> axes = camcad.plot_pressure_angle(result).axes[0]
    >>> axes.get_xlabel(), axes.get_ylabel()
    ('cam angle θ (deg)', 'pressure angle (deg)')
    """
    fig, ax = new_figure(10, 5)
    draw_pressure_angle(ax, result)
    return fig


def draw_pressure_angle(ax, result) -> None:
    """The pressure angle, its limits (the region over them shaded) and its extrema, into ``ax``."""
    t = result.table
    deg = np.degrees(t.theta)
    phi = np.degrees(t.pressure_angle)
    _shade_phases(ax, result)
    if result.follower.kind == "flat":
        ax.plot(deg, phi, lw=1.6, color="#1f4e79")
        ax.text(0.5, 0.6, "flat face perpendicular to its axis: pressure angle is 0",
                transform=ax.transAxes, ha="center")
        ax.set_ylim(-10, 10)
    else:
        limit = np.degrees(t.limit)
        top = max(np.nanmax(np.abs(phi)), np.nanmax(limit) if np.isfinite(limit).any() else 0.0) * 1.15 + 1.0
        if np.isfinite(limit).any():
            ax.fill_between(deg, limit, top, where=np.isfinite(limit), color=FORBIDDEN, lw=0, label="over the limit")
            ax.fill_between(deg, -top, -limit, where=np.isfinite(limit), color=FORBIDDEN, lw=0)
            ax.plot(deg, limit, color="#b03a2e", lw=1.0, ls="--", label="limit ±")
            ax.plot(deg, -limit, color="#b03a2e", lw=1.0, ls="--")
        ax.plot(deg, phi, lw=1.6, color="#1f4e79", label="pressure angle φ")
        pa = result.pressure_angle
        for ext, below in ((pa.maximum, False), (pa.minimum, True)):
            x, y = math.degrees(ext.at), math.degrees(ext.value)
            _label_point(ax, x % 360.0, y, f"{y:.2f}° @ {x:.1f}°", below, fontsize=9)
        ax.set_ylim(-top, top)
        verdict = "within the limits" if pa.passed else "OVER THE LIMIT"
        ax.set_title(f"pressure angle — {verdict}" + (" (reversible)" if result.follower.reversible else ""),
                     fontsize=10, y=TITLE_Y)
        ax.legend(loc="upper right", fontsize=8)
    ax.axhline(0.0, color="black", lw=0.6)
    ax.set_ylabel("pressure angle (deg)")
    ax.set_xlabel("cam angle θ (deg)")
    _theta_axis(ax)


def plot_curvature(result):
    """The radius of curvature of the profile and of the pitch curve, with the undercut zone shaded.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``camcad.synthesize``).

    Returns
    -------
    matplotlib.figure.Figure
        One axes: the radius of curvature (mm, + convex) against the cam angle θ (deg).
        Saving it (``fig.savefig``) is the caller's choice.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> camcad.plot_curvature(result).axes[0].get_ylabel()
    'radius of curvature ρ (mm), + convex, − concave'
    """
    fig, ax = new_figure(10, 5)
    draw_curvature(ax, result)
    return fig


def draw_curvature(ax, result) -> None:
    """Radii of curvature against the cam angle, the undercut zone and the ρ_min limit, into ``ax``."""
    t = result.table
    f = result.follower
    deg = np.degrees(t.theta)
    cap = 3.0 * (f.prime_radius + float(np.ptp(t.s)) * (f.arm if f.kind == "oscillating" else 1.0))
    shown = np.concatenate((t.rho_profile, t.rho_pitch if f.kind != "flat" else t.rho_profile))
    shown = shown[np.isfinite(shown) & (np.abs(shown) <= cap)]
    top = max(1.35 * float(shown.max(initial=0.0)), 2.0 * f.roller_radius, 10.0)   # headroom for the legend
    bottom = min(1.15 * float(shown.min(initial=0.0)), -0.15 * top)

    def shown_part(rho: np.ndarray) -> np.ndarray:
        # through an inflection ρ passes ±∞: break the line there instead of drawing a wall
        return np.where(np.abs(rho) <= cap, rho, np.nan)

    _shade_phases(ax, result)
    if f.kind != "flat" and f.roller_radius > 0.0:
        ax.axhspan(0.0, f.roller_radius, color=FORBIDDEN, lw=0,
                   label=f"undercut: pitch ρ ≤ Rr {f.roller_radius:g} mm")
        ax.plot(deg, shown_part(t.rho_pitch), lw=1.2, color="#7f7f7f", ls="--", label="pitch ρ")
    if f.rho_min is not None:
        ax.axhline(f.rho_min, color="#b03a2e", lw=1.0, ls=":", label=f"limit ρ_min = {f.rho_min:g} mm")
    ax.plot(deg, shown_part(t.rho_profile), lw=1.6, color="#1f4e79", label="profile ρ")
    best = result.profile.rho_convex_min
    if best is not None:
        _label_point(ax, math.degrees(best.at) % 360.0, best.value,
                     f"smallest convex ρ {best.value:.4g} mm @ {math.degrees(best.at):.1f}°", below=True, fontsize=9)
    ax.axhline(0.0, color="black", lw=0.6)
    ax.set_ylim(bottom, top)
    ax.set_ylabel("radius of curvature ρ (mm), + convex, − concave")
    ax.set_xlabel("cam angle θ (deg)")
    ax.set_title("radius of curvature" + (" — UNDERCUT" if result.undercut else ""), fontsize=10, y=TITLE_Y)
    ax.legend(loc="upper center", fontsize=8, ncol=3)   # one row, in the headroom left above the curves
    _theta_axis(ax)


def plot_profile(result):
    """The cam as drawn: profile, pitch curve, base circle and the follower at θ = 0.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``camcad.synthesize``).

    Returns
    -------
    matplotlib.figure.Figure
        One axes in the cam's frame, x and y in mm, equal scales.
        Saving it (``fig.savefig``) is the caller's choice.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> axes = camcad.plot_profile(result).axes[0]
    >>> axes.get_xlabel(), axes.get_ylabel(), axes.get_aspect()
    ('x (mm)', 'y (mm)', 1.0)
    """
    fig, ax = new_figure(8, 8)
    draw_profile(ax, result)
    return fig


def draw_profile(ax, result, legend: bool | float = True, title: str | None = None) -> None:
    """The cam profile, pitch curve, base circle and the follower at θ = 0, into ``ax``."""
    f = result.follower
    geometry = result.geometry

    def closed(points: np.ndarray) -> np.ndarray:
        return np.vstack((points, points[:1]))

    prof = closed(result.profile.polyline.points)
    ax.fill(prof[:, 0], prof[:, 1], color="#dbe6f1", zorder=0)
    ax.plot(prof[:, 0], prof[:, 1], color="#1f4e79", lw=1.8, label="profile")
    pitch = closed(result.pitch.polyline.points)
    if f.kind != "flat":
        ax.plot(pitch[:, 0], pitch[:, 1], color="#7f7f7f", lw=1.0, ls="--", label="pitch curve")
    for curve, colour, label in ((result.outer, "#1f4e79", "groove outer flank"),
                                 (result.counter, "#2e7d32", "counter-cam")):
        if curve is not None:
            pts = closed(curve.polyline.points)
            ax.plot(pts[:, 0], pts[:, 1], color=colour, lw=1.4, ls="-.", label=label)
    circle = np.linspace(0.0, 2.0 * math.pi, 361)
    ax.plot(f.base_radius * np.cos(circle), f.base_radius * np.sin(circle), color="#4a7ebb", lw=0.8,
            ls=":", label=f"base circle Rb = {f.base_radius:g} mm")
    cross = 0.15 * f.base_radius
    ax.plot([-cross, cross], [0, 0], color="#b03a2e", lw=0.8)
    ax.plot([0, 0], [-cross, cross], color="#b03a2e", lw=0.8)
    zero = np.array([0.0])
    centre = geometry.pitch(zero).centre[0]
    if f.kind == "flat":
        height = f.base_radius + float(geometry.kinematics(zero).s[0])
        left, right = result.face_extent
        ax.plot([f.offset + left - 3, f.offset + right + 3], [height, height], color="#c27c0e", lw=2.5,
                label="flat face at θ = 0")
    else:
        if f.roller_radius > 0.0:
            ax.plot(centre[0] + f.roller_radius * np.cos(circle), centre[1] + f.roller_radius * np.sin(circle),
                    color="#c27c0e", lw=1.6, label=f"roller at θ = 0, Rr = {f.roller_radius:g} mm")
        ax.plot(*centre, "o", color="#c27c0e", ms=3)
        if f.kind == "oscillating":
            ax.plot([f.pivot, centre[0]], [0.0, centre[1]], color="#c27c0e", lw=1.2)
            ax.plot(f.pivot, 0.0, "s", color="#c27c0e", ms=5, label=f"pivot C = {f.pivot:g} mm, arm L = {f.arm:g} mm")
        worst = result.pressure_angle.maximum
        if abs(worst.value) > 0.0 and f.roller_radius > 0.0:
            at = geometry.pitch(np.array([worst.at]))
            p = at.points[0]
            ax.plot(p[0] + f.roller_radius * np.cos(circle), p[1] + f.roller_radius * np.sin(circle),
                    color="#b03a2e", lw=0.8, ls="--",
                    label=f"roller at the largest pressure angle ({math.degrees(worst.value):.1f}° "
                          f"@ {math.degrees(worst.at):.0f}°)")
    turn = "clockwise" if f.cw else "counter-clockwise"
    ax.set_title(title or f"{result.name}: cam profile (cam turns {turn}; drawn at θ = 0)", fontsize=10, y=TITLE_Y)
    ax.set_aspect("equal")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    if legend:
        ax.legend(loc="lower left", fontsize=7 if legend is True else legend, framealpha=0.9)


def plot_hodograph(result):
    """The velocity hodograph: s against v = ds/dθ, the follower's phase portrait.

    For a translating follower it doubles as the classical construction of the base radius:
    the pressure angle at each point is the angle from the vertical of the line from the cam
    centre O = (σe, −d) to the point (v, s), so O must lie below both lines drawn at the rise
    and return limits tangent to the curve (the shaded wedge).

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``camcad.synthesize``).

    Returns
    -------
    matplotlib.figure.Figure
        One axes: s (mm) against v = ds/dθ (mm/rad).
        Saving it (``fig.savefig``) is the caller's choice.

    References
    ----------
    O. M. Dupliak, R. I. Kotsiyba (2018), Dupliak & Kotsiyba 2018: the velocity hodograph among the outputs.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> axes = camcad.plot_hodograph(result).axes[0]
    >>> axes.get_xlabel(), axes.get_ylabel()
    ('v = ds/dθ (mm/rad)', 's (mm)')
    """
    fig, ax = new_figure(8, 7)
    t = result.table
    f = result.follower
    if f.kind == "oscillating":
        ax.plot(t.v, np.degrees(t.s), color="#1f4e79", lw=1.6)
        ax.set_xlabel("ψ' = dψ/dθ (rad/rad)")
        ax.set_ylabel("swing ψ (deg)")
        ax.set_title("velocity hodograph (swing against its velocity analog)", fontsize=10)
    else:
        ax.plot(t.v, t.s, color="#1f4e79", lw=1.6, label="(v, s) over the cycle")
        if f.kind != "flat":
            ox, oy = f.sigma * f.offset, -result.geometry.height
            ax.plot(ox, oy, "o", color="#b03a2e", ms=6, label=f"cam centre O (d = {result.geometry.height:.4g} mm)")
            rise, back = f.pressure_angle_limit_rise_deg, f.pressure_angle_limit_return_deg
            if f.reversible:
                strict = min(x for x in (rise, back) if x is not None) if (rise or back) else None
                rise = back = strict
            x = np.linspace(min(ox, t.v.min()) - 0.3 * np.ptp(t.v) - 5, max(ox, t.v.max()) + 0.3 * np.ptp(t.v) + 5, 200)
            bound = np.full_like(x, np.inf)
            moving_up, moving_down = t.v > 0, t.v < 0
            if rise is not None and moving_up.any():
                k = 1.0 / math.tan(math.radians(rise))
                line = x * k + np.min(t.s[moving_up] - t.v[moving_up] * k)
                ax.plot(x, line, color="#b03a2e", lw=1.0, ls="--", label=f"rise limit {rise:g}°")
                bound = np.minimum(bound, line)
            if back is not None and moving_down.any():
                k = 1.0 / math.tan(math.radians(back))
                line = -x * k + np.min(t.s[moving_down] + t.v[moving_down] * k)
                ax.plot(x, line, color="#e67e22", lw=1.0, ls="--", label=f"return limit {back:g}°")
                bound = np.minimum(bound, line)
            if np.isfinite(bound).all():
                low = min(oy, bound.min()) - 0.2 * abs(oy) - 5
                ax.fill_between(x, low, bound, color="#d9f0d3", alpha=0.7, lw=0,
                                label="cam centre allowed here")
                ax.set_ylim(low, t.s.max() + 0.2 * abs(oy) + 5)
            for index in (int(np.argmax(t.v)), int(np.argmin(t.v))):
                ax.plot([ox, t.v[index]], [oy, t.s[index]], color="#7f7f7f", lw=0.6)
        ax.set_xlabel("v = ds/dθ (mm/rad)")
        ax.set_ylabel("s (mm)")
        ax.set_title("velocity hodograph: s against v; the angle of O→(v, s) from vertical is the pressure angle",
                     fontsize=9)
        ax.set_aspect("equal", adjustable="datalim")
    ax.axvline(0.0, color="black", lw=0.6)
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(loc="upper left", fontsize=8)
    return fig


def plot_summary(result, report: dict | None = None):
    """One page per cam: the profile, the law, the pressure angle, the curvature and the verdict.

    The pressure angle and the curvature are drawn with their limits; the verdict lists every check with
    its margin, tightest first, and the warnings.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam.
    report : dict, optional
        Its report (``camcad.report``, or the scene's mechanism report, which adds the models'
        checks; angles in deg, lengths in mm); computed from ``result`` when not given.

    Returns
    -------
    matplotlib.figure.Figure
        The page: the profile (mm), s and a against θ (mm, mm/rad², deg), the pressure angle (deg) and the
        radius of curvature (mm) with their limits, and the verdict's lines.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> figure = camcad.plot_summary(result)
    >>> figure.axes[0].get_xlabel(), figure.axes[1].get_ylabel()
    ('x (mm)', 's (mm)')
    """
    return SummaryPage().draw(result, report if report is not None else profile_report(result))


class SummaryPage:
    """The summary page (``plot_summary``) as one figure drawn again for each cam: its axes, their ticks and
    tick labels are made once, and each ``draw`` replaces only what it shows (the lines, fills, labels,
    legends and the verdict), so a group of mechanisms pays for one page's set-up.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0)
    >>> settings = camcad.ProfileSettings(plots=False, design=False)
    >>> page = SummaryPage()
    >>> first = page.draw(camcad.synthesize(law, follower, settings, name="a"), {"passed": True})
    >>> second = page.draw(camcad.synthesize(law, follower.with_base_radius(60.0), settings, name="b"), {})
    >>> first is second, bool(second.axes[0].get_xlim()[1] > 70.0), second.texts[0].get_text()
    (True, True, 'b: FAILED')
    """

    def __init__(self) -> None:
        fig = new_figure(15, 9, rows=0, layout=None)[0]
        # fixed margins: a layout engine would measure every label of the page before drawing it (~40 % of the
        # time of this figure)
        grid = fig.add_gridspec(2, 3, width_ratios=[1.0, 1.25, 1.25], left=0.05, right=0.985, top=0.92,
                                bottom=0.1, wspace=0.42, hspace=0.32)
        self.figure = fig
        self.profile_ax = fig.add_subplot(grid[:, 0])
        self.law_ax = fig.add_subplot(grid[0, 1])
        self.accel_ax = self.law_ax.twinx()
        self.pressure_ax = fig.add_subplot(grid[0, 2])
        self.curvature_ax = fig.add_subplot(grid[1, 1])
        self.text_ax = fig.add_subplot(grid[1, 2])
        self.text_ax.axis("off")
        self._title = None

    def _clear(self) -> None:
        """Remove what the last ``draw`` showed; the axes and their ticks stay."""
        for ax in self.figure.axes:
            for artist in [*ax.lines, *ax.patches, *ax.collections, *ax.texts, *ax.images]:
                artist.remove()
            if ax.get_legend() is not None:
                ax.get_legend().remove()
            for loc in ("left", "center", "right"):
                ax.set_title("", loc=loc, y=TITLE_Y)
            ax.ignore_existing_data_limits = True     # the next cam's data set the limits afresh
            ax.set_autoscale_on(True)
        if self._title is not None:
            self._title.remove()

    def draw(self, result, report: dict):
        """Draw the page of ``result`` and its ``report`` (``plot_summary``); returns the figure."""
        import textwrap

        self._clear()
        fig = self.figure
        turn = "clockwise" if result.follower.cw else "counter-clockwise"
        draw_profile(self.profile_ax, result, legend=False, title=f"cam profile at θ = 0 (turns {turn})")
        self.profile_ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), fontsize=7, ncol=1, frameon=False)
        law_ax, accel = self.law_ax, self.accel_ax
        draw_kinematics([law_ax], result, rows=("s",), titles=False)
        t = result.table
        unit = "rad" if result.follower.kind == "oscillating" else "mm"
        accel.plot(np.degrees(t.theta), t.a, color="#c27c0e", lw=1.0, ls="--")
        accel.set_ylabel(f"a (dashed, {unit}/rad²)", color="#c27c0e")
        law_ax.set_title("displacement s (solid) and acceleration analog a (dashed)", fontsize=9, loc="left",
                         y=TITLE_Y)
        law_ax.set_xlabel("cam angle θ (deg)")
        draw_pressure_angle(self.pressure_ax, result)
        draw_curvature(self.curvature_ax, result)
        for ax in (law_ax, self.pressure_ax, self.curvature_ax):
            _theta_axis(ax, 60)
        for ax in (self.profile_ax, accel):
            ax.relim()
            ax.autoscale_view()
        text_ax = self.text_ax
        wrapped = []
        for line, colour in _verdict_lines(report):
            for k, piece in enumerate(textwrap.wrap(line, 56) or [""]):
                wrapped.append(("    " + piece if k else piece, colour))
        height_in = text_ax.get_position().height * fig.get_figheight()
        step = 1.3 * 8.0 / 72.0 / height_in            # one line of 8 pt text, in axes fractions
        # one text object per run of lines of one colour (a page pays for each text object it draws)
        shown = wrapped[: int(1.0 / step)]
        k = 0
        while k < len(shown):
            end = k + 1
            while k > 0 and end < len(shown) and shown[end][1] == shown[k][1]:
                end += 1
            text_ax.text(0.0, 1.0 - k * step, "\n".join(line for line, _ in shown[k:end]),
                         transform=text_ax.transAxes, fontsize=8, va="top", family="monospace", color=shown[k][1],
                         weight="bold" if k == 0 else "normal", linespacing=VERDICT_LINESPACING)
            k = end
        verdict = "all checks passed" if report.get("passed") else "FAILED"
        phases = report.get("phase_angles", "")
        self._title = fig.suptitle(f"{result.name}: {verdict}" + (f" — {phases}" if phases else ""), fontsize=12,
                                   color=COLOURS["ok"] if report.get("passed") else COLOURS["fail"])
        fix_label_positions(fig)
        return fig


def _verdict_lines(report: dict) -> list[tuple[str, str]]:
    """(text, colour) lines of the summary's verdict panel (``camcad.report.verdict_text``)."""
    colour = {"ok": COLOURS["ok"], "fail": COLOURS["fail"], "warn": "#b35900"}
    prefix = {"ok": "ok   ", "fail": "FAIL ", "warn": "!    "}
    lines = [("checks, tightest margin first; warnings", "black")]
    lines += [(prefix[status] + text, colour[status]) for status, text in verdict_lines(report)]
    return lines


#: the plots of a profile by name; "summary" is what a run writes unless asked for more
PLOTS = {"summary": plot_summary, "kinematics": plot_kinematics, "pressure_angle": plot_pressure_angle,
         "curvature": plot_curvature, "profile": plot_profile, "hodograph": plot_hodograph}


def save_profile_plots(result, folder: str | Path, which=("summary",), report: dict | None = None,
                       page: SummaryPage | None = None) -> list[Path]:
    """Draw the plots named in ``which`` (keys of ``PLOTS``; "all" for every one) and save each as
    ``<name>.png`` in ``folder``; the summary into ``page`` when given (a ``SummaryPage`` drawn again for
    each mechanism of a group). Returns the written paths."""
    names = list(PLOTS) if "all" in which else [name for name in PLOTS if name in which]
    written = []
    for name in names:
        if name == "summary":
            fig = (page or SummaryPage()).draw(result, report if report is not None else profile_report(result))
        else:
            fig = PLOTS[name](result)
        written.append(save_figure(fig, Path(folder) / f"{name}.png"))
    return written
