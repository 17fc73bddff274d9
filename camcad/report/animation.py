"""The mechanism in motion as a file: a self-contained HTML page (SVG and inline JavaScript, no server, no
external address), and on request a GIF (Pillow, through matplotlib) or an MP4 (ffmpeg, when installed).

The page draws the cam turning, the follower (the roller turning as it rolls), the contact and its common
normal, the linkage after the follower, and beside them the law s(θ) and the pressure angle φ(θ) with a
cursor at the current cam angle and the figures of the frame. It plays on its own; a slider, the arrow keys
and the space bar step and pause it. The frames are computed by the library (``camcad.profile.animation``,
``camcad.scene.animation``); this module only draws them. The animated SVG carries ``data-frames="N"``, the
page sets ``document.body.dataset.frame`` to the frame shown and ``window.camcadAnimation`` to
``{frames, frame, shown, playing}``.
"""

from __future__ import annotations

import html
import json
import math
import shutil
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic
from camcad.report.figure import new_figure
from camcad.scene.animation import LinkageMotion, MechanismFrames

#: animation file kinds: what ``--animate-format`` accepts
FORMATS = ("html", "gif", "mp4")
#: points of a cam curve drawn on the page at most (the library's curves are sampled within 1 µm)
CURVE_POINTS = 1500
#: seconds of one turn of the cam at the page's normal speed
TURN_SECONDS = 6.0
#: frames per second of a GIF or MP4 (one turn lasts frames / FPS seconds)
FPS = 30
#: resolution of a GIF's or MP4's frames (9.6 x 5.4 in: 768 x 432 px)
MOVIE_DPI = 80
COLOURS = {"cam": "#dbe6f1", "cam_edge": "#1f4e79", "pitch": "#7f7f7f", "follower": "#c27c0e",
           "contact": "#c00000", "linkage": "#2e7d32", "fixed": "#555555", "counter": "#2e7d32",
           "rise": "#d9f0d3", "return": "#fde0c5"}


def _decimate(points: np.ndarray | None, most: int = CURVE_POINTS) -> np.ndarray | None:
    if points is None or len(points) == 0:
        return None
    points = np.asarray(points, dtype=float)
    step = max(1, math.ceil(len(points) / most))
    return points[::step]


def _path(points: np.ndarray, closed: bool = True) -> str:
    """SVG path data of a polyline (mm, y up: the page flips the y axis)."""
    text = "M" + " L".join(f"{x:.3f},{y:.3f}" for x, y in points)
    return text + (" Z" if closed else "")


def _rounded(values, digits: int = 4) -> list:
    return [None if not math.isfinite(v) else round(float(v), digits) for v in np.asarray(values, dtype=float)]


def _bounds(frames: MechanismFrames, extra: list[np.ndarray]) -> tuple[float, float, float, float]:
    cam = frames.cam
    radius = float(np.max(np.hypot(*cam.profile.T)))
    for curve in (cam.outer, cam.counter):
        if curve is not None:
            radius = max(radius, float(np.max(np.hypot(*curve.T))))
    points = [np.array([[-radius, -radius], [radius, radius]])] + extra
    everything = np.vstack(points)
    low, high = everything.min(axis=0), everything.max(axis=0)
    pad = 0.06 * float(np.max(high - low))
    return float(low[0] - pad), float(low[1] - pad), float(high[0] + pad), float(high[1] + pad)


def _follower_parts(frames: MechanismFrames) -> tuple[dict, list[np.ndarray], str]:
    """What the page draws of the follower: its static shapes (SVG, at frame 0, mm), the points every frame
    may reach (for the view's bounds) and the SVG of the moving body."""
    cam = frames.cam
    rr, rb = cam.roller_radius, cam.base_radius
    stroke = float(np.ptp(cam.centre[:, 1]))
    reach = [cam.centre + rr * np.array([1.0, 1.0]), cam.centre - rr * np.array([1.0, 1.0])]
    width = max(0.35 * rr, 0.05 * rb, 1.0)
    body = []
    guide = ""
    if cam.kind in ("roller", "knife", "flat"):
        x0, y0 = float(cam.centre[0, 0]), float(cam.centre[0, 1])
        length = max(2.5 * rr, 0.7 * rb) + stroke
        if cam.kind == "flat":
            left, right = cam.face if cam.face is not None else (-0.5 * rb, 0.5 * rb)
            margin = 0.1 * rb
            thick = max(0.04 * rb, 1.0)
            body.append(f'<rect x="{cam.offset + left - margin:.3f}" y="{y0:.3f}" '
                        f'width="{right - left + 2 * margin:.3f}" height="{thick:.3f}" class="part"/>')
            reach += [np.array([[cam.offset + left - margin, y0], [cam.offset + right + margin, y0 + stroke]])]
            y0 += thick
        elif cam.kind == "knife":
            tip = max(0.12 * rb, 2.0 * width)
            body.append(f'<path d="M{x0:.3f},{y0:.3f} L{x0 - width:.3f},{y0 + tip:.3f} L{x0 + width:.3f},'
                        f'{y0 + tip:.3f} Z" class="part"/>')
        body.append(f'<rect x="{x0 - width / 2:.3f}" y="{y0:.3f}" width="{width:.3f}" height="{length:.3f}" '
                    'class="part"/>')
        top = y0 + length
        reach.append(np.array([[x0 - 3 * width, top + stroke], [x0 + 3 * width, top + stroke]]))
        low = float(cam.centre[:, 1].max()) + rr + 0.15 * length
        high = low + 0.35 * length
        for side in (-1.0, 1.0):
            x = x0 + side * (width / 2 + 0.2 * width) - (1.6 * width if side < 0 else 0.0)
            guide += (f'<rect x="{x:.3f}" y="{low:.3f}" width="{1.6 * width:.3f}" height="{high - low:.3f}" '
                      'class="fixed-part"/>')
    if cam.pivot is not None:
        px, py = cam.pivot
        size = max(0.08 * rb, 2.0)
        guide += (f'<path d="M{px:.3f},{py:.3f} L{px - size:.3f},{py - 1.5 * size:.3f} L{px + size:.3f},'
                  f'{py - 1.5 * size:.3f} Z" class="fixed-part"/>')
        reach.append(np.array([[px - size, py - 1.5 * size], [px + size, py + size]]))
    return {"guide": guide, "width": width}, reach, "".join(body)


def _yoke_x(frames: MechanismFrames) -> float:
    """x of the yoke that joins a translating pair's two rollers past the cam and the counter-cam, mm."""
    cam = frames.cam
    reach = max(float(np.max(np.hypot(*curve.T))) for curve in (cam.profile, cam.counter) if curve is not None)
    return cam.offset + reach + cam.roller_radius + 0.12 * cam.base_radius


def _roller(name: str, radius: float) -> str:
    spoke = 0.8 * radius
    return (f'<g id="{name}"><circle r="{radius:.3f}" class="roller"/>'
            f'<line x1="{-spoke:.3f}" y1="0" x2="{spoke:.3f}" y2="0" class="spoke"/>'
            f'<line x1="0" y1="{-spoke:.3f}" x2="0" y2="{spoke:.3f}" class="spoke"/>'
            f'<circle r="{max(0.08 * radius, 0.3):.3f}" class="hub"/></g>')


def _chart(values: np.ndarray, theta: np.ndarray, box: tuple[float, float, float, float], label: str,
           unit: str, name: str, limit: np.ndarray | None = None) -> tuple[str, dict]:
    """An SVG chart of ``values`` against θ in ``box`` (x, y, w, h; px) and its scale for the cursor."""
    x0, y0, w, h = box
    finite = values[np.isfinite(values)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if limit is not None and np.isfinite(limit).any():
        top = float(np.nanmax(limit))
        low, high = min(low, -top), max(high, top)
    if high - low < 1e-12:
        low, high = low - 1.0, high + 1.0
    pad = 0.08 * (high - low)
    low, high = low - pad, high + pad

    def xy(t, v):
        return x0 + w * t / 360.0, y0 + h * (high - v) / (high - low)

    closed_theta = np.append(theta, 360.0)
    closed_values = np.append(values, values[0])
    line = " L".join("{:.2f},{:.2f}".format(*xy(t, v)) for t, v in zip(closed_theta, closed_values) if np.isfinite(v))
    parts = [f'<rect x="{x0}" y="{y0}" width="{w}" height="{h}" class="chart-box"/>']
    for t in range(0, 361, 90):
        x = x0 + w * t / 360.0
        parts.append(f'<line x1="{x:.1f}" y1="{y0}" x2="{x:.1f}" y2="{y0 + h}" class="grid"/>'
                     f'<text x="{x:.1f}" y="{y0 + h + 14}" class="tick" text-anchor="middle">{t}°</text>')
    if low < 0.0 < high:
        zero = xy(0.0, 0.0)[1]
        parts.append(f'<line x1="{x0}" y1="{zero:.2f}" x2="{x0 + w}" y2="{zero:.2f}" class="zero"/>')
    if limit is not None and np.isfinite(limit).any():
        for sign in (1.0, -1.0):
            pts = " L".join("{:.2f},{:.2f}".format(*xy(t, sign * v))
                            for t, v in zip(closed_theta, np.append(limit, limit[0])) if np.isfinite(v))
            parts.append(f'<path d="M{pts}" class="limit"/>')
    for v in (low + pad, high - pad):
        parts.append(f'<text x="{x0 - 4}" y="{xy(0.0, v)[1] + 4:.1f}" class="tick" text-anchor="end">{v:.4g}</text>')
    parts.append(f'<text x="{x0}" y="{y0 - 6}" class="chart-title">{html.escape(label)} ({html.escape(unit)})</text>')
    parts.append(f'<path d="M{line}" class="curve"/>')
    parts.append(f'<line id="{name}-cursor" x1="{x0}" y1="{y0}" x2="{x0}" y2="{y0 + h}" class="cursor"/>'
                 f'<circle id="{name}-dot" r="4" class="dot"/>')
    return "".join(parts), {"x0": x0, "w": w, "y0": y0, "h": h, "low": low, "high": high}


def animation_data(frames: MechanismFrames) -> dict:
    """The frames as the page's JavaScript reads them (lists of numbers, mm and deg, 4 decimals)."""
    cam = frames.cam
    data = {"n": cam.count, "theta": _rounded(cam.theta_deg, 6), "turn": _rounded(cam.cam_turn_deg),
            "cx": _rounded(cam.centre[:, 0]), "cy": _rounded(cam.centre[:, 1]),
            "kx": _rounded(cam.contact[:, 0]), "ky": _rounded(cam.contact[:, 1]),
            "nx": _rounded(cam.normal[:, 0], 6), "ny": _rounded(cam.normal[:, 1], 6),
            "roll": _rounded(cam.roller_turn_deg, 3), "s": _rounded(cam.s, 6),
            "phi": _rounded(cam.pressure_angle_deg), "limit": _rounded(cam.pressure_angle_limit_deg),
            "kind": cam.kind, "pivot": list(cam.pivot) if cam.pivot is not None else None,
            "rr": cam.roller_radius, "law_unit": frames.law_unit}
    if cam.second_centre is not None:
        data["yoke_x"] = round(_yoke_x(frames), 4)
        data.update({"c2x": _rounded(cam.second_centre[:, 0]), "c2y": _rounded(cam.second_centre[:, 1]),
                     "roll2": _rounded(cam.second_roller_turn_deg if cam.second_roller_turn_deg is not None
                                       else np.zeros(cam.count), 3)})
    if frames.working is not None:
        scale = 180.0 / math.pi if frames.working_unit == "rad" else 1.0
        data["working"] = _rounded(np.asarray(frames.working) * scale, 5)
        data["working_unit"] = "deg" if frames.working_unit == "rad" else frames.working_unit
    if frames.linkage is not None:
        data["joints"] = {name: [_rounded(xy[:, 0]), _rounded(xy[:, 1])]
                          for name, xy in frames.linkage.joints.items()}
        data["links"] = [[a, b] for a, b, _ in frames.linkage.links]
        data["mu"] = [_rounded(mu, 3) for mu in frames.linkage.transmission_deg]
    return data


def animation_html(frames: MechanismFrames, title: str = "", subtitle: str = "") -> str:
    """The self-contained HTML page of ``frames`` (module docstring).

    Parameters
    ----------
    frames : MechanismFrames
        The mechanism in motion (``camcad.scene.animation.mechanism_frames``): mm and deg.
    title, subtitle : str
        The page's heading and the line under it (e.g. the follower and the law).

    Returns
    -------
    str
        The page (no unit): one HTML document with its SVG, style and script inline; it loads nothing.

    Examples
    --------
    >>> import camcad
    >>> from camcad.profile.animation import cam_frames
    >>> from camcad.scene.animation import LinkageMotion, MechanismFrames
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> page = animation_html(MechanismFrames("cam", cam_frames(result, 5.0)))
    >>> 'data-frames="72"' in page, "http" in page
    (True, False)
    """
    cam = frames.cam
    parts, reach, body = _follower_parts(frames)
    if frames.linkage is not None:
        reach += list(frames.linkage.joints.values())
    if cam.second_centre is not None:
        reach += [cam.second_centre + cam.roller_radius, cam.second_centre - cam.roller_radius]
        if cam.kind != "oscillating":
            reach.append(np.array([[_yoke_x(frames) + 0.05 * cam.base_radius, float(cam.centre[0, 1])]]))
    x_min, y_min, x_max, y_max = _bounds(frames, reach)
    size = max(x_max - x_min, y_max - y_min)
    stroke = size / 400.0
    curves = []
    for curve, cls in ((cam.profile, "profile"), (cam.outer, "outer"), (cam.counter, "counter")):
        points = _decimate(curve)
        if points is not None:
            curves.append(f'<path d="{_path(points)}" class="{cls}"/>')
    pitch = _decimate(cam.pitch)
    if pitch is not None:
        curves.append(f'<path d="{_path(pitch)}" class="pitch"/>')
    rb = cam.base_radius
    cam_group = (f'<g id="camcad-cam">{"".join(curves)}<circle r="{rb:.3f}" class="base"/>'
                 f'<line x1="0" y1="0" x2="{0.85 * rb:.3f}" y2="0" class="mark"/>'
                 f'<circle r="{0.12 * rb:.3f}" class="bore"/></g>')
    cross = 0.15 * rb
    fixed = (f'<line x1="{-cross:.3f}" y1="0" x2="{cross:.3f}" y2="0" class="centre"/>'
             f'<line x1="0" y1="{-cross:.3f}" x2="0" y2="{cross:.3f}" class="centre"/>{parts["guide"]}')
    trace = _path(cam.centre, closed=False)
    moving = [f'<path d="{trace}" class="trace"/>']
    if cam.kind == "oscillating":
        moving.append('<line id="camcad-arm" class="arm"/>')
    if cam.second_centre is not None:       # the second arm, or the yoke that carries both rollers past the cam
        moving.append('<polyline id="camcad-arm2" class="arm yoke"/>')
    moving.append(f'<g id="camcad-body">{body}</g>')
    if cam.roller_radius > 0.0:
        moving.append(_roller("camcad-roller", cam.roller_radius))
        if cam.second_centre is not None:
            moving.append(_roller("camcad-roller2", cam.roller_radius))
    if frames.linkage is not None:
        for a, b, what in frames.linkage.links:
            moving.append(f'<line id="camcad-link-{a}{b}" class="link"><title>{html.escape(what)}</title></line>')
        if "P" in frames.linkage.joints:
            moving.append(f'<path d="{_path(frames.linkage.joints["P"], closed=False)}" class="trace"/>')
        for name in frames.linkage.joints:
            cls = "joint fixed-joint" if name in frames.linkage.fixed else "joint"
            moving.append(f'<circle id="camcad-joint-{name}" r="{3 * stroke:.3f}" class="{cls}"/>')
    moving.append(f'<line id="camcad-normal" class="normal"/><circle id="camcad-contact" r="{2.5 * stroke:.3f}" '
                  'class="contact"/>')
    theta = cam.theta_deg
    unit = "deg" if frames.law_unit == "rad" else frames.law_unit
    s_shown = np.degrees(cam.s) if frames.law_unit == "rad" else cam.s
    law_chart, law_scale = _chart(s_shown, theta, (58, 26, 330, 120), "swing ψ" if unit == "deg" else "displacement s",
                                  unit, "camcad-law")
    phi_chart, phi_scale = _chart(cam.pressure_angle_deg, theta, (58, 196, 330, 120), "pressure angle φ", "deg",
                                  "camcad-phi", cam.pressure_angle_limit_deg)
    charts = law_chart + phi_chart
    height = 340
    if frames.working is not None:
        shown = np.degrees(frames.working) if frames.working_unit == "rad" else frames.working
        work_chart, work_scale = _chart(np.asarray(shown), theta, (58, 366, 330, 120), "working member",
                                        "deg" if frames.working_unit == "rad" else frames.working_unit,
                                        "camcad-work")
        charts += work_chart
        height = 510
    else:
        work_scale = None
    data = animation_data(frames)
    data["scales"] = {"law": law_scale, "phi": phi_scale, "work": work_scale}
    data["turn_seconds"] = TURN_SECONDS
    data["law_factor"] = 180.0 / math.pi if frames.law_unit == "rad" else 1.0
    data["normal_length"] = max(2.0 * cam.roller_radius, 0.3 * rb)
    view = f"{x_min:.3f} {-y_max:.3f} {x_max - x_min:.3f} {y_max - y_min:.3f}"
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    return _PAGE.format(
        title=html.escape(title or frames.name), subtitle=html.escape(subtitle), n=cam.count, view=view,
        fixed=fixed, cam=cam_group, moving="".join(moving), charts=charts,
        chart_height=height, data=payload, script=_SCRIPT, style=_STYLE,
        step=f"{360.0 / cam.count:g}")


def write_animation(frames: MechanismFrames | LinkageMotion, folder: Path, formats: tuple[str, ...] = ("html",), *,
                    title: str = "", subtitle: str = "") -> list[Path]:
    """Write the animation of ``frames`` (a cam mechanism, or a linkage alone) into ``folder`` as
    ``animation.html`` (and ``animation.gif``, ``animation.mp4`` when asked); returns the written paths. An MP4
    needs ffmpeg on the PATH."""
    for kind in formats:
        if kind not in FORMATS:
            raise CamcadError(f"unknown animation format {kind!r}", "--animate-format", "use html, gif or mp4")
    if "mp4" in formats and shutil.which("ffmpeg") is None:
        raise CamcadError("an MP4 needs ffmpeg, which is not installed", "--animate-format",
                          "install ffmpeg (e.g. apt-get install ffmpeg), or ask for html or gif")
    written = []
    if "html" in formats:
        page = (linkage_animation_html(frames, title, subtitle) if isinstance(frames, LinkageMotion)
                else animation_html(frames, title, subtitle))
        written.append(write_atomic(folder / "animation.html", lambda tmp: tmp.write_text(page, encoding="utf-8")))
    for kind in ("gif", "mp4"):
        if kind in formats:
            movie = _write_linkage_movie if isinstance(frames, LinkageMotion) else _write_movie
            written.append(movie(frames, folder / f"animation.{kind}", kind, title or frames.name))  # type: ignore[arg-type]
    return written


def _write_movie(frames: MechanismFrames, path: Path, kind: str, title: str) -> Path:
    """A GIF (Pillow) or MP4 (ffmpeg) of the frames: one matplotlib figure, its artists moved frame by frame."""
    from matplotlib import animation as mpl_animation
    from matplotlib.patches import Circle, Polygon

    cam = frames.cam
    fig, (ax, law_ax) = new_figure(9.6, 5.4, cols=2, layout=None, gridspec_kw={"width_ratios": [1.3, 1.0]})
    fig.set_dpi(MOVIE_DPI)
    fig.subplots_adjust(left=0.02, right=0.9, top=0.9, bottom=0.12, wspace=0.22)
    ax.set_aspect("equal")
    ax.axis("off")
    reach = [cam.centre + cam.roller_radius, cam.centre - cam.roller_radius]
    if frames.linkage is not None:
        reach += list(frames.linkage.joints.values())
    if cam.second_centre is not None:
        reach += [cam.second_centre + cam.roller_radius, cam.second_centre - cam.roller_radius]
    x_min, y_min, x_max, y_max = _bounds(frames, reach)
    ax.set_xlim(x_min, x_max)
    ax.set_ylim(y_min, y_max)
    profile = Polygon(cam.profile, closed=True, facecolor=COLOURS["cam"], edgecolor=COLOURS["cam_edge"], lw=1.5)
    ax.add_patch(profile)
    extra = [(curve, colour) for curve, colour in ((cam.outer, COLOURS["cam_edge"]), (cam.counter, COLOURS["counter"]))
             if curve is not None]
    extra_lines = [ax.plot([], [], color=colour, lw=1.2)[0] for _, colour in extra]
    mark = ax.plot([], [], color=COLOURS["cam_edge"], lw=1.0)[0]
    ax.plot(cam.centre[:, 0], cam.centre[:, 1], color=COLOURS["pitch"], lw=0.6, ls=":")
    ax.plot([0.0], [0.0], "+", color="#c00000", ms=10)
    roller = Circle((0.0, 0.0), cam.roller_radius, fill=False, color=COLOURS["follower"], lw=1.6)
    if cam.roller_radius > 0.0:
        ax.add_patch(roller)
    spoke = ax.plot([], [], color=COLOURS["follower"], lw=1.0)[0]
    body = ax.plot([], [], color=COLOURS["follower"], lw=3.0, solid_capstyle="butt")[0]
    links = ax.plot([], [], color=COLOURS["linkage"], lw=2.2, marker="o", ms=4)[0]
    normal = ax.plot([], [], color=COLOURS["contact"], lw=0.9)[0]
    contact = ax.plot([], [], "o", color=COLOURS["contact"], ms=3)[0]
    s_shown = np.degrees(cam.s) if frames.law_unit == "rad" else cam.s
    law_ax.plot(cam.theta_deg, s_shown, color=COLOURS["cam_edge"], lw=1.4)
    law_ax.set_xlim(0.0, 360.0)
    law_ax.set_xticks(range(0, 361, 90))
    law_ax.set_xlabel("cam angle θ (deg)")
    law_ax.set_ylabel("swing ψ (deg)" if frames.law_unit == "rad" else "displacement s (mm)")
    law_ax.grid(True, lw=0.4, alpha=0.6)
    phi_ax = law_ax.twinx()
    phi_ax.plot(cam.theta_deg, cam.pressure_angle_deg, color=COLOURS["contact"], lw=1.0, ls="--")
    phi_ax.set_ylabel("pressure angle φ (deg, dashed)", color=COLOURS["contact"])
    cursor = law_ax.axvline(0.0, color="black", lw=1.0)
    heading = fig.suptitle(title, fontsize=11)
    length = max(2.0 * cam.roller_radius, 0.3 * cam.base_radius)

    def show(k: int):
        angle = math.radians(float(cam.cam_turn_deg[k]))
        c, s = math.cos(angle), math.sin(angle)
        turn = np.array([[c, -s], [s, c]])
        profile.set_xy(cam.profile @ turn.T)
        for line, (curve, _) in zip(extra_lines, extra):
            line.set_data(*(curve @ turn.T).T)
        mark.set_data([0.0, 0.85 * cam.base_radius * c], [0.0, 0.85 * cam.base_radius * s])
        x, y = cam.centre[k]
        roller.center = (x, y)
        roll = math.radians(float(cam.roller_turn_deg[k]))
        r = 0.8 * cam.roller_radius
        spoke.set_data([x - r * math.cos(roll), x + r * math.cos(roll)],
                       [y - r * math.sin(roll), y + r * math.sin(roll)])
        if cam.pivot is not None:
            body.set_data([cam.pivot[0], x], [cam.pivot[1], y])
        else:
            top = float(cam.centre[:, 1].max()) + cam.roller_radius + 0.8 * cam.base_radius
            body.set_data([x, x], [y + cam.roller_radius, top + (y - float(cam.centre[0, 1]))])
        if frames.linkage is not None:
            xs, ys = [], []
            for a, b, _ in frames.linkage.links:
                xs += [frames.linkage.joints[a][k, 0], frames.linkage.joints[b][k, 0], np.nan]
                ys += [frames.linkage.joints[a][k, 1], frames.linkage.joints[b][k, 1], np.nan]
            links.set_data(xs, ys)
        kx, ky = cam.contact[k]
        nx, ny = cam.normal[k]
        normal.set_data([kx - 0.3 * length * nx, kx + length * nx], [ky - 0.3 * length * ny, ky + length * ny])
        contact.set_data([kx], [ky])
        cursor.set_xdata([cam.theta_deg[k], cam.theta_deg[k]])
        heading.set_text(f"{title} — θ = {cam.theta_deg[k]:.1f}°, φ = {cam.pressure_angle_deg[k]:.2f}°")

    def gif(tmp: Path) -> None:
        from PIL import Image

        pictures = []
        for k in range(cam.count):
            show(k)
            fig.canvas.draw()
            pictures.append(Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3]).quantize(colors=64))
        pictures[0].save(tmp, format="GIF", save_all=True, append_images=pictures[1:], duration=round(1000 / FPS),
                         loop=0)

    def mp4(tmp: Path) -> None:
        writer = mpl_animation.FFMpegWriter(fps=FPS, extra_args=["-f", "mp4"])
        with writer.saving(fig, str(tmp), fig.dpi):
            for k in range(cam.count):
                show(k)
                writer.grab_frame()

    return write_atomic(path, gif if kind == "gif" else mp4)


_STYLE = """
:root { color-scheme: light; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 0; padding: 12px 16px;
       color: #1b1b1b; background: #fafafa; }
h1 { font-size: 1.25rem; margin: 0 0 2px; }
p.subtitle { margin: 0 0 10px; color: #444; font-size: 0.9rem; }
.stage { display: flex; flex-wrap: wrap; gap: 16px; align-items: flex-start; }
.mechanism { flex: 1 1 420px; max-width: 760px; width: 100%; height: auto; max-height: calc(100vh - 150px);
             background: white;
             border: 1px solid #ddd; border-radius: 6px; }
.side { flex: 1 1 360px; max-width: 440px; }
.charts { width: 100%; height: auto; background: white; border: 1px solid #ddd; border-radius: 6px; }
.controls { display: flex; flex-wrap: wrap; gap: 8px; align-items: center; margin: 10px 0; }
.controls input[type=range] { flex: 1 1 200px; }
button, select { font-size: 0.95rem; padding: 4px 10px; }
table.readout { border-collapse: collapse; font-variant-numeric: tabular-nums; margin-top: 8px; }
table.readout td { padding: 2px 10px 2px 0; }
table.readout td.value { text-align: right; font-family: ui-monospace, monospace; }
.over { color: #c00000; font-weight: bold; }
.profile { fill: #dbe6f1; stroke: #1f4e79; stroke-width: 2; }
.outer { fill: none; stroke: #1f4e79; stroke-dasharray: 6 3; }
.counter { fill: #e6f2e6; fill-opacity: 0.5; stroke: #2e7d32; }
.pitch { fill: none; stroke: #7f7f7f; stroke-dasharray: 4 3; }
.base { fill: none; stroke: #4a7ebb; stroke-dasharray: 1 3; }
.mark { stroke: #1f4e79; }
.bore { fill: white; stroke: #1f4e79; }
.centre { stroke: #c00000; }
.trace { fill: none; stroke: #c27c0e; stroke-opacity: 0.45; stroke-dasharray: 2 3; }
.part { fill: #f3d9b1; stroke: #c27c0e; }
.fixed-part { fill: #d9d9d9; stroke: #555; }
.roller { fill: #fbe7c6; stroke: #c27c0e; stroke-width: 2; }
.spoke { stroke: #c27c0e; }
.hub { fill: #c27c0e; }
.arm { stroke: #c27c0e; stroke-width: 5; stroke-linecap: round; fill: none; }
.yoke { stroke-linejoin: round; }
.link { stroke: #2e7d32; stroke-width: 4; stroke-linecap: round; }
.joint { fill: white; stroke: #2e7d32; stroke-width: 1.5; }
.fixed-joint { fill: #555; stroke: #555; }
.normal { stroke: #c00000; stroke-width: 1.2; }
.contact { fill: #c00000; }
.mechanism * { vector-effect: non-scaling-stroke; }
.chart-box { fill: white; stroke: #999; }
.grid { stroke: #e5e5e5; }
.zero { stroke: #888; }
.curve { fill: none; stroke: #1f4e79; stroke-width: 1.6; }
.limit { fill: none; stroke: #c00000; stroke-dasharray: 5 3; }
.cursor { stroke: #000; stroke-width: 1; }
.dot { fill: #c27c0e; stroke: #000; }
.tick { font-size: 11px; fill: #555; }
.chart-title { font-size: 12px; fill: #222; }
@media (max-width: 700px) { body { padding: 8px; } .side { max-width: none; } }
@media print { .controls { display: none; } body { background: white; } }
"""

#: the player both pages share: the end of ``show`` (slider, label, the state tests read), the clock, the
#: controls and keys, the frame-count check
_PLAYER = r"""
    slider.value = frame;
    label.textContent = "frame " + (frame + 1) + " / " + n;
    shown += 1;
    document.body.dataset.frame = frame;
    window.camcadAnimation = {frames: n, frame: frame, shown: shown, playing: playing};
  }
  function tick(now) {
    if (last === null) { last = now; }
    var dt = (now - last) / 1000;
    last = now;
    if (playing) {
      clock += dt * speed * n / data.turn_seconds;
      if (clock >= 1) { var steps = Math.floor(clock); clock -= steps; show(frame + steps); }
    }
    window.requestAnimationFrame(tick);
  }
  function play(on) {
    playing = on;
    button.textContent = on ? "pause" : "play";
    last = null;
    window.camcadAnimation.playing = on;
  }
  slider.max = n - 1;
  slider.addEventListener("input", function () { play(false); show(Number(slider.value)); });
  button.addEventListener("click", function () { play(!playing); });
  el("camcad-back").addEventListener("click", function () { play(false); show(frame - 1); });
  el("camcad-forward").addEventListener("click", function () { play(false); show(frame + 1); });
  el("camcad-speed").addEventListener("change", function (e) { speed = Number(e.target.value); });
  document.addEventListener("keydown", function (e) {
    if (e.key === " ") { play(!playing); e.preventDefault(); }
    else if (e.key === "ArrowRight") { play(false); show(frame + 1); }
    else if (e.key === "ArrowLeft") { play(false); show(frame - 1); }
  });
  if (Number(svg.dataset.frames) !== n) { throw new Error("frame count mismatch"); }
""".lstrip("\n")

_SCRIPT = r"""
(function () {
  "use strict";
  // the drawing's group flips y: every coordinate below is the library's (mm, y up, angles counter-clockwise)
  var data = JSON.parse(document.getElementById("camcad-animation-data").textContent);
  var n = data.n, frame = 0, shown = 0, playing = true, speed = 1, last = null, clock = 0;
  function el(id) { return document.getElementById(id); }
  function set(node, attrs) { if (node) { for (var k in attrs) { node.setAttribute(k, attrs[k]); } } }
  function line(node, x1, y1, x2, y2) { set(node, {x1: x1, y1: y1, x2: x2, y2: y2}); }
  function place(node, x, y, turn) { set(node, {transform: "translate(" + x + "," + y + ") rotate(" + turn + ")"}); }
  var svg = el("camcad-mechanism"), cam = el("camcad-cam"), body = el("camcad-body");
  var roller = el("camcad-roller"), roller2 = el("camcad-roller2");
  var slider = el("camcad-slider"), button = el("camcad-play"), label = el("camcad-frame-label");
  var y0 = data.cy[0];
  function fmt(v, d) { return (v === null || v === undefined) ? "-" : Number(v).toFixed(d); }
  function cursor(name, scale, value, k) {
    if (!scale) { return; }
    var x = scale.x0 + scale.w * data.theta[k] / 360;
    set(el(name + "-cursor"), {x1: x, x2: x});
    if (value !== null && value !== undefined) {
      set(el(name + "-dot"), {cx: x, cy: scale.y0 + scale.h * (scale.high - value) / (scale.high - scale.low)});
    }
  }
  function linkage(k) {
    data.links.forEach(function (pair) {
      var a = data.joints[pair[0]], b = data.joints[pair[1]];
      line(el("camcad-link-" + pair[0] + pair[1]), a[0][k], a[1][k], b[0][k], b[1][k]);
    });
    for (var name in data.joints) {
      set(el("camcad-joint-" + name), {cx: data.joints[name][0][k], cy: data.joints[name][1][k]});
    }
  }
  function readout(k) {
    el("camcad-theta").textContent = fmt(data.theta[k], 1) + " deg";
    el("camcad-s").textContent = fmt(data.s[k] * data.law_factor, 4) + (data.law_unit === "rad" ? " deg" : " mm");
    var phi = el("camcad-phi-value"), limit = data.limit[k];
    phi.textContent = fmt(data.phi[k], 2) + " deg" + (limit === null ? "" : " (limit " + fmt(limit, 1) + ")");
    phi.className = "value" + (limit !== null && Math.abs(data.phi[k]) > limit ? " over" : "");
    if (data.working) { el("camcad-working").textContent = fmt(data.working[k], 4) + " " + data.working_unit; }
    if (data.mu) {
      el("camcad-mu").textContent = data.mu.map(function (m) { return fmt(m[k], 1); }).join(", ") + " deg";
    }
  }
  function show(k) {
    frame = ((k % n) + n) % n;
    set(cam, {transform: "rotate(" + data.turn[frame] + ")"});
    var cx = data.cx[frame], cy = data.cy[frame];
    if (data.kind === "oscillating") {
      line(el("camcad-arm"), data.pivot[0], data.pivot[1], cx, cy);
    } else {
      set(body, {transform: "translate(0," + (cy - y0) + ")"});
    }
    if (roller) { place(roller, cx, cy, data.roll[frame]); }
    if (data.c2x) {
      var x2 = data.c2x[frame], y2 = data.c2y[frame];
      if (roller2) { place(roller2, x2, y2, data.roll2[frame]); }
      var path = data.kind === "oscillating" ? [data.pivot, [x2, y2]]
        : [[cx, cy], [data.yoke_x, cy], [data.yoke_x, y2], [x2, y2]];
      set(el("camcad-arm2"), {points: path.map(function (p) { return p[0] + "," + p[1]; }).join(" ")});
    }
    if (data.joints) { linkage(frame); }
    var kx = data.kx[frame], ky = data.ky[frame], nx = data.nx[frame], ny = data.ny[frame];
    var L = data.normal_length;
    set(el("camcad-contact"), {cx: kx, cy: ky});
    line(el("camcad-normal"), kx - 0.3 * L * nx, ky - 0.3 * L * ny, kx + L * nx, ky + L * ny);
    cursor("camcad-law", data.scales.law, data.s[frame] * data.law_factor, frame);
    cursor("camcad-phi", data.scales.phi, data.phi[frame], frame);
    if (data.working) { cursor("camcad-work", data.scales.work, data.working[frame], frame); }
    readout(frame);
""" + _PLAYER + r"""  if (!data.working) { el("camcad-row-working").style.display = "none"; }
  if (!data.mu) { el("camcad-row-mu").style.display = "none"; }
  window.camcadAnimation = {frames: n, frame: 0, shown: 0, playing: true};
  show(0);
  window.requestAnimationFrame(tick);
})();
"""

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="camcad">
<title>{title} — camcad animation</title>
<style>{style}</style>
</head>
<body>
<h1>{title}</h1>
<p class="subtitle">{subtitle}</p>
<div class="stage">
<svg id="camcad-mechanism" class="mechanism" data-frames="{n}" viewBox="{view}" role="img"
     aria-label="the cam mechanism turning, {n} frames of {step} deg">
<g transform="scale(1,-1)">{cam}{fixed}{moving}</g>
</svg>
<div class="side">
<svg class="charts" viewBox="0 0 400 {chart_height}" role="img"
     aria-label="the law and the pressure angle">{charts}</svg>
<table class="readout">
<tr><td>cam angle θ</td><td class="value" id="camcad-theta"></td></tr>
<tr><td>follower</td><td class="value" id="camcad-s"></td></tr>
<tr><td>pressure angle φ</td><td class="value" id="camcad-phi-value"></td></tr>
<tr id="camcad-row-working"><td>working member</td><td class="value" id="camcad-working">-</td></tr>
<tr id="camcad-row-mu"><td>transmission angle μ</td><td class="value" id="camcad-mu">-</td></tr>
</table>
</div>
</div>
<div class="controls">
<button id="camcad-play" type="button">pause</button>
<button id="camcad-back" type="button" aria-label="previous frame">&#9664;</button>
<button id="camcad-forward" type="button" aria-label="next frame">&#9654;</button>
<input id="camcad-slider" type="range" min="0" max="{n}" value="0" step="1" aria-label="frame">
<select id="camcad-speed" aria-label="speed"><option value="0.25">0.25×</option>
<option value="0.5">0.5×</option><option value="1" selected>1× (a turn in 6 s)</option><option value="2">2×</option>
<option value="4">4×</option></select>
<span id="camcad-frame-label"></span>
</div>
<script type="application/json" id="camcad-animation-data">{data}</script>
<script>{script}</script>
</body>
</html>
"""


# --------------------------------------------------------------------------------------------
# A linkage alone (``camcad.scene.animation.LinkageMotion``): `camcad linkage analyse|fgen|path --animate`
# --------------------------------------------------------------------------------------------

def _line_chart(x: np.ndarray, series: list[tuple[np.ndarray, str]], box: tuple[float, float, float, float],
                label: str, unit: str, x_label: str, name: str) -> tuple[str, dict]:
    """An SVG chart of each (values, css class) of ``series`` against ``x`` in ``box`` (x, y, w, h; px), a cursor
    and a dot on the first series, and its scale for the page's script."""
    x0, y0, w, h = box
    x = np.asarray(x, dtype=float)
    order = np.argsort(x, kind="stable")
    values = np.concatenate([np.asarray(v, dtype=float) for v, _ in series])
    finite = values[np.isfinite(values)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if high - low < 1e-9 * max(1.0, abs(high)):
        low, high = low - 1.0, high + 1.0
    pad = 0.08 * (high - low)
    low, high = low - pad, high + pad
    x_low, x_high = float(x.min()), float(x.max())
    if x_high - x_low < 1e-12:
        x_high = x_low + 1.0

    def xy(t, v):
        return x0 + w * (t - x_low) / (x_high - x_low), y0 + h * (high - v) / (high - low)

    parts = [f'<rect x="{x0}" y="{y0}" width="{w}" height="{h}" class="chart-box"/>']
    for t in np.linspace(x_low, x_high, 5):
        px = xy(t, 0.0)[0]
        parts.append(f'<line x1="{px:.1f}" y1="{y0}" x2="{px:.1f}" y2="{y0 + h}" class="grid"/>'
                     f'<text x="{px:.1f}" y="{y0 + h + 14}" class="tick" text-anchor="middle">{t:.4g}°</text>')
    for v in (low + pad, high - pad):
        parts.append(f'<text x="{x0 - 4}" y="{xy(x_low, v)[1] + 4:.1f}" class="tick" text-anchor="end">{v:.4g}</text>')
    parts.append(f'<text x="{x0}" y="{y0 - 6}" class="chart-title">{html.escape(label)} ({html.escape(unit)}) '
                 f'against {html.escape(x_label)}</text>')
    for values_k, cls in series:
        ys = np.asarray(values_k, dtype=float)[order]
        line = " L".join("{:.2f},{:.2f}".format(*xy(t, y)) for t, y in zip(x[order], ys) if np.isfinite(y))
        parts.append(f'<path d="M{line}" class="{cls}"/>')
    parts.append(f'<line id="{name}-cursor" x1="{x0}" y1="{y0}" x2="{x0}" y2="{y0 + h}" class="cursor"/>'
                 f'<circle id="{name}-dot" r="4" class="dot"/>')
    return "".join(parts), {"x0": x0, "w": w, "y0": y0, "h": h, "low": low, "high": high, "xlow": x_low,
                            "xhigh": x_high}


def _ground(x: float, y: float, size: float) -> str:
    """A fixed pivot's ground mark (a triangle under the joint), mm."""
    return (f'<path d="M{x:.3f},{y:.3f} L{x - size:.3f},{y - 1.6 * size:.3f} L{x + size:.3f},{y - 1.6 * size:.3f} Z" '
            'class="fixed-part"/>')


def linkage_animation_html(motion: LinkageMotion, title: str = "", subtitle: str = "") -> str:
    """The self-contained HTML page of a linkage alone in motion (``camcad.scene.animation.LinkageMotion``).

    The links and joints (fixed pivots dark), the coupler point's path (and the curve it is to trace), and beside
    them the output's turn and the loops' transmission angles against the input, with a cursor at the frame's
    input; the same controls, ``data-frames`` and ``window.camcadAnimation`` as ``animation_html``.

    Parameters
    ----------
    motion : LinkageMotion
        The linkage's frames (mm, deg).
    title, subtitle : str
        The page's heading and the line under it.

    Returns
    -------
    str
        The page (no unit): one HTML document with its SVG, style and script inline; it loads nothing.

    Examples
    --------
    >>> import math
    >>> from camcad.linkage.analysis import Linkage, Loop
    >>> from camcad.scene.animation import linkage_motion
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1),), theta0=math.radians(80.0))
    >>> page = linkage_animation_html(linkage_motion(lk, math.radians(30.0), 1.0))
    >>> 'data-frames="60"' in page, "http" in page
    (True, False)
    """
    drawn = motion.linkage
    reach = list(drawn.joints.values()) + ([motion.target] if motion.target is not None else [])
    everything = np.vstack(reach)
    low, high = everything.min(axis=0), everything.max(axis=0)
    size = float(np.max(high - low)) or 1.0
    pad = 0.1 * size
    x_min, y_min, x_max, y_max = low[0] - pad, low[1] - pad, high[0] + pad, high[1] + pad
    stroke = size / 400.0
    fixed = []
    for name in drawn.fixed:
        x, y = drawn.joints[name][0]
        fixed.append(_ground(float(x), float(y), 0.03 * size))
    if motion.target is not None:
        fixed.append(f'<path d="{_path(motion.target[:: max(1, len(motion.target) // CURVE_POINTS)], closed=False)}" '
                     'class="target"/>')
    moving = []
    if "P" in drawn.joints:
        moving.append(f'<path d="{_path(drawn.joints["P"], closed=False)}" class="trace"/>')
        moving.append('<polygon id="camcad-coupler" class="coupler-plate"/>')
    for a, b, what in drawn.links:
        moving.append(f'<line id="camcad-link-{a}{b}" class="link"><title>{html.escape(what)}</title></line>')
    for name in drawn.joints:
        cls = "joint fixed-joint" if name in drawn.fixed else "joint"
        moving.append(f'<circle id="camcad-joint-{name}" r="{3 * stroke:.3f}" class="{cls}"><title>{name}</title>'
                      '</circle>')
    x = motion.input_deg
    series = [(motion.output_deg, "curve")]
    if motion.target_output_deg is not None:
        series.append((motion.target_output_deg, "limit"))
    out_chart, out_scale = _line_chart(x, series, (58, 26, 330, 120), motion.output_label, "deg",
                                       motion.input_label, "camcad-out")
    mu_chart, mu_scale = _line_chart(x, [(mu, "curve") for mu in drawn.transmission_deg], (58, 196, 330, 120),
                                     "transmission angle μ", "deg", motion.input_label, "camcad-mu")
    data = {"n": motion.count, "input": _rounded(x, 6), "output": _rounded(motion.output_deg, 6),
            "target": None if motion.target_output_deg is None else _rounded(motion.target_output_deg, 6),
            "joints": {name: [_rounded(xy[:, 0]), _rounded(xy[:, 1])] for name, xy in drawn.joints.items()},
            "links": [[a, b] for a, b, _ in drawn.links], "mu": [_rounded(mu, 3) for mu in drawn.transmission_deg],
            "scales": {"out": out_scale, "mu": mu_scale}, "turn_seconds": TURN_SECONDS,
            "input_label": motion.input_label, "output_label": motion.output_label}
    view = f"{x_min:.3f} {-y_max:.3f} {x_max - x_min:.3f} {y_max - y_min:.3f}"
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    step = float(abs(x[1] - x[0])) if motion.count > 1 else 0.0
    return _LINKAGE_PAGE.format(
        title=html.escape(title or motion.name), subtitle=html.escape(subtitle), n=motion.count, view=view,
        fixed="".join(fixed), moving="".join(moving), charts=out_chart + mu_chart, chart_height=340, data=payload,
        script=_LINKAGE_SCRIPT, style=_STYLE + _LINKAGE_STYLE, step=f"{step:.4g}",
        input_label=html.escape(motion.input_label), output_label=html.escape(motion.output_label))


def _write_linkage_movie(motion: LinkageMotion, path: Path, kind: str, title: str) -> Path:
    """A GIF (Pillow) or MP4 (ffmpeg) of a linkage alone: one matplotlib figure, its artists moved per frame."""
    from matplotlib import animation as mpl_animation

    drawn = motion.linkage
    fig, (ax, out_ax) = new_figure(9.6, 5.4, cols=2, layout=None, gridspec_kw={"width_ratios": [1.3, 1.0]})
    fig.set_dpi(MOVIE_DPI)
    fig.subplots_adjust(left=0.02, right=0.9, top=0.9, bottom=0.12, wspace=0.3)
    ax.set_aspect("equal")
    ax.axis("off")
    reach = np.vstack(list(drawn.joints.values()) + ([motion.target] if motion.target is not None else []))
    low, high = reach.min(axis=0), reach.max(axis=0)
    pad = 0.1 * float(np.max(high - low))
    ax.set_xlim(low[0] - pad, high[0] + pad)
    ax.set_ylim(low[1] - pad, high[1] + pad)
    if motion.target is not None:
        ax.plot(*motion.target.T, color=COLOURS["contact"], lw=1.0, ls="--")
    if "P" in drawn.joints:
        ax.plot(*drawn.joints["P"].T, color=COLOURS["follower"], lw=0.8, ls=":")
    for name in drawn.fixed:
        ax.plot(*drawn.joints[name][0], marker="^", color=COLOURS["fixed"], ms=11)
    links = ax.plot([], [], color=COLOURS["linkage"], lw=2.4, marker="o", ms=5, mfc="white")[0]
    point = ax.plot([], [], "o", color=COLOURS["follower"], ms=5)[0]
    plate = ax.fill([], [], facecolor="#e6f2e6", edgecolor=COLOURS["linkage"], lw=1.2, alpha=0.8)[0]
    labels = {name: ax.annotate(name, (0.0, 0.0), xytext=(5, 5), textcoords="offset points", fontsize=9)
              for name in drawn.joints}
    order = np.argsort(motion.input_deg, kind="stable")
    out_ax.plot(motion.input_deg[order], motion.output_deg[order], color=COLOURS["cam_edge"], lw=1.4)
    if motion.target_output_deg is not None:
        out_ax.plot(motion.input_deg[order], motion.target_output_deg[order], color=COLOURS["contact"], lw=1.0,
                    ls="--")
    out_ax.set_xlabel(f"{motion.input_label} (deg)")
    out_ax.set_ylabel(f"{motion.output_label} (deg)")
    out_ax.grid(True, lw=0.4, alpha=0.6)
    cursor = out_ax.axvline(0.0, color="black", lw=1.0)
    heading = fig.suptitle(title, fontsize=11)

    def show(k: int):
        xs, ys = [], []
        for a, b, _ in drawn.links:
            xs += [drawn.joints[a][k, 0], drawn.joints[b][k, 0], np.nan]
            ys += [drawn.joints[a][k, 1], drawn.joints[b][k, 1], np.nan]
        links.set_data(xs, ys)
        if "P" in drawn.joints:
            point.set_data([drawn.joints["P"][k, 0]], [drawn.joints["P"][k, 1]])
            plate.set_xy(np.array([drawn.joints[j][k] for j in ("A", "B", "P")]))
        for name, text in labels.items():
            text.xy = tuple(drawn.joints[name][k])
        cursor.set_xdata([motion.input_deg[k], motion.input_deg[k]])
        heading.set_text(f"{title} — {motion.input_label} = {motion.input_deg[k]:.2f}°, "
                         f"{motion.output_label} = {motion.output_deg[k]:.3f}°")

    return write_atomic(path, _movie_writer(fig, show, motion.count, kind, mpl_animation))


def _movie_writer(fig, show, count: int, kind: str, mpl_animation):
    """The writer of a GIF or MP4 of ``count`` frames drawn by ``show(k)`` on ``fig`` (for ``write_atomic``)."""

    def gif(tmp: Path) -> None:
        from PIL import Image

        pictures = []
        for k in range(count):
            show(k)
            fig.canvas.draw()
            pictures.append(Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3]).quantize(colors=64))
        pictures[0].save(tmp, format="GIF", save_all=True, append_images=pictures[1:], duration=round(1000 / FPS),
                         loop=0)

    def mp4(tmp: Path) -> None:
        writer = mpl_animation.FFMpegWriter(fps=FPS, extra_args=["-f", "mp4"])
        with writer.saving(fig, str(tmp), fig.dpi):
            for k in range(count):
                show(k)
                writer.grab_frame()

    return gif if kind == "gif" else mp4


_LINKAGE_STYLE = """
.target { fill: none; stroke: #c00000; stroke-dasharray: 6 3; stroke-width: 1.2; }
.coupler-plate { fill: #e6f2e6; fill-opacity: 0.7; stroke: #2e7d32; }
"""

_LINKAGE_SCRIPT = r"""
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("camcad-animation-data").textContent);
  var n = data.n, frame = 0, shown = 0, playing = true, speed = 1, last = null, clock = 0;
  function el(id) { return document.getElementById(id); }
  function set(node, attrs) { if (node) { for (var k in attrs) { node.setAttribute(k, attrs[k]); } } }
  var svg = el("camcad-mechanism"), slider = el("camcad-slider"), button = el("camcad-play");
  var label = el("camcad-frame-label");
  function fmt(v, d) { return (v === null || v === undefined) ? "-" : Number(v).toFixed(d); }
  function cursor(name, scale, value, k) {
    var x = scale.x0 + scale.w * (data.input[k] - scale.xlow) / (scale.xhigh - scale.xlow);
    set(el(name + "-cursor"), {x1: x, x2: x});
    if (value !== null && value !== undefined) {
      set(el(name + "-dot"), {cx: x, cy: scale.y0 + scale.h * (scale.high - value) / (scale.high - scale.low)});
    }
  }
  function show(k) {
    frame = ((k % n) + n) % n;
    data.links.forEach(function (pair) {
      var a = data.joints[pair[0]], b = data.joints[pair[1]];
      set(el("camcad-link-" + pair[0] + pair[1]), {x1: a[0][frame], y1: a[1][frame], x2: b[0][frame],
                                                     y2: b[1][frame]});
    });
    for (var name in data.joints) {
      set(el("camcad-joint-" + name), {cx: data.joints[name][0][frame], cy: data.joints[name][1][frame]});
    }
    if (data.joints.P) {
      var plate = ["A", "B", "P"].map(function (j) {
        return data.joints[j][0][frame] + "," + data.joints[j][1][frame];
      });
      set(el("camcad-coupler"), {points: plate.join(" ")});
    }
    cursor("camcad-out", data.scales.out, data.output[frame], frame);
    cursor("camcad-mu", data.scales.mu, data.mu[0][frame], frame);
    el("camcad-input").textContent = fmt(data.input[frame], 3) + " deg";
    el("camcad-output").textContent = fmt(data.output[frame], 4) + " deg" +
      (data.target ? " (wanted " + fmt(data.target[frame], 4) + ")" : "");
    el("camcad-mu").textContent = data.mu.map(function (m) { return fmt(m[frame], 1); }).join(", ") + " deg";
""" + _PLAYER + r"""  window.camcadAnimation = {frames: n, frame: 0, shown: 0, playing: true};
  show(0);
  window.requestAnimationFrame(tick);
})();
"""

_LINKAGE_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="camcad">
<title>{title} — camcad animation</title>
<style>{style}</style>
</head>
<body>
<h1>{title}</h1>
<p class="subtitle">{subtitle}</p>
<div class="stage">
<svg id="camcad-mechanism" class="mechanism" data-frames="{n}" viewBox="{view}" role="img"
     aria-label="the linkage moving over its input range and back, {n} frames of {step} deg">
<g transform="scale(1,-1)">{fixed}{moving}</g>
</svg>
<div class="side">
<svg class="charts" viewBox="0 0 400 {chart_height}" role="img"
     aria-label="the output and the transmission angle against the input">{charts}</svg>
<table class="readout">
<tr><td>{input_label}</td><td class="value" id="camcad-input"></td></tr>
<tr><td>{output_label}</td><td class="value" id="camcad-output"></td></tr>
<tr><td>transmission angle μ</td><td class="value" id="camcad-mu"></td></tr>
</table>
</div>
</div>
<div class="controls">
<button id="camcad-play" type="button">pause</button>
<button id="camcad-back" type="button" aria-label="previous frame">&#9664;</button>
<button id="camcad-forward" type="button" aria-label="next frame">&#9654;</button>
<input id="camcad-slider" type="range" min="0" max="{n}" value="0" step="1" aria-label="frame">
<select id="camcad-speed" aria-label="speed"><option value="0.25">0.25×</option>
<option value="0.5">0.5×</option><option value="1" selected>1× (there and back in 6 s)</option>
<option value="2">2×</option><option value="4">4×</option></select>
<span id="camcad-frame-label"></span>
</div>
<script type="application/json" id="camcad-animation-data">{data}</script>
<script>{script}</script>
</body>
</html>
"""
