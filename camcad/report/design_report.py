"""One report per design: ``report.html``, a self-contained page to hand a design over (and ``report.pdf``,
the same page printed by headless Chromium).

The page is written from ``report.json`` as written (so every figure on it is the figure of the JSON) and the
files of the run: the inputs (the scene's text, the law and the follower), the law and its balance, the
profile, every check with its value, limit, margin and where it applies (tightest first), the plots (the
PNG files of the run, inline), the animation (inline, when the run wrote one), a section for every model the
run has (dynamics, impact, contact, cyclogram, linkage, drive, the part's files), what was skipped and why,
the files written, the command that reproduces the run and camcad's version. It reads on a phone (one
column, tables scroll sideways) and prints (print CSS: A4, no controls, no split tables or figures).

Each check is a table row ``<tr data-check="NAME" data-path='["checks", "NAME"]' data-value=… data-limit=…
data-margin=…>``: NAME is the check's key in report.json, ``data-path`` the keys that lead to it there, and
the figures are report.json's own numbers (JSON text: ``null`` where the JSON has null).
"""

from __future__ import annotations

import base64
import html
import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic
from camcad.version import __version__

#: the sections of a mechanism's report shown as a model of their own, in this order, with their headings
MODEL_SECTIONS = (("spectrum", "Resonance filtering (spectrum)"), ("dynamics", "Elastic dynamics"),
                  ("impact", "Impact on the stops"), ("contact", "Contact stress"),
                  ("linkage", "Linkage after the follower"), ("drive", "Camshaft drive"),
                  ("polydyne", "Polydyne design"), ("servo", "Servo table"), ("animation", "Animation files"),
                  ("export", "Part files"), ("design", "Smallest base radius"), ("phase_limits", "Least phase angles"))
#: keys of the JSON that are not figures to list (shown elsewhere, or bookkeeping)
HIDDEN = {"checks", "tightest", "outputs", "passed", "notes", "warnings", "skipped", "models_run", "checks_by_model"}
#: units named by the end of a JSON key
UNITS = (("_mm3", "mm³"), ("_mm", "mm"), ("_deg", "deg"), ("_MPa", "MPa"), ("_N_per_m", "N/m"), ("_Nm", "N·m"),
         ("_Ns", "N·s"), ("_N", "N"), ("_hz", "Hz"), ("_Hz", "Hz"), ("_rpm", "rpm"), ("_kg", "kg"), ("_W", "W"),
         ("_s", "s"), ("_rad_s2", "rad/s²"), ("_rad", "rad"), ("_kg_m2", "kg·m²"))
#: where Chromium may be (first found is used); CAMCAD_CHROMIUM overrides
CHROMIUM = ("chromium", "chromium-browser", "chromium-headless-shell", "google-chrome", "google-chrome-stable")


def chromium() -> str | None:
    """The path of a Chromium (or Chrome) that can print a page to PDF headless, or None."""
    for candidate in (os.environ.get("CAMCAD_CHROMIUM"), *CHROMIUM):
        if not candidate:
            continue
        found = shutil.which(candidate)
        if found:
            return found
    return None


def check_rows(report: dict) -> list[tuple[list[str], dict]]:
    """Every check of a report (a dict with "value", "limit" and "margin" under a "checks" object), with the keys
    that lead to it, in the report's order.

    Examples
    --------
    >>> rows = check_rows({"checks": {"a": {"value": 1.0, "limit": 2.0, "margin": 1.0}},
    ...                    "contact": {"checks": {"b": {"value": 3.0, "limit": 2.0, "margin": -1.0}}}})
    >>> [path for path, _ in rows]
    [['checks', 'a'], ['contact', 'checks', 'b']]
    """
    found: list[tuple[list[str], dict]] = []

    def walk(node, path: list[str]) -> None:
        if isinstance(node, dict):
            for key, value in node.items():
                if (isinstance(value, dict) and path and path[-1] == "checks"
                        and {"value", "limit", "margin"} <= set(value)):
                    found.append(([*path, key], value))
                elif key != "outputs":
                    walk(value, [*path, key])

    walk(report, [])
    return found


def _label(key: str) -> str:
    for suffix, unit in UNITS:
        if key.endswith(suffix) and len(key) > len(suffix):
            return f"{key[: -len(suffix)].replace('_', ' ')} ({unit})"
    return key.replace("_", " ")


def _number(value) -> str:
    if isinstance(value, bool) or value is None:
        return {True: "yes", False: "no", None: "—"}[value]
    if isinstance(value, float):
        return f"{value:.6g}"
    return html.escape(str(value))


def _value(value) -> str:
    """A JSON value as table text: numbers to 6 digits, short lists inline, long ones cut."""
    if isinstance(value, list):
        if all(not isinstance(v, (dict, list)) for v in value):
            shown = ", ".join(_number(v) for v in value[:12])
            return shown + (f", … ({len(value)} values)" if len(value) > 12 else "")
        return f"{len(value)} entries"
    if isinstance(value, dict):
        return ", ".join(f"{html.escape(str(k))}: {_value(v)}" for k, v in list(value.items())[:12])
    return _number(value)


def _figures(data: dict, depth: int = 0) -> str:
    """A table of a JSON object's figures (nested objects as sub-tables, two levels)."""
    rows, nested = [], []
    for key, value in data.items():
        if key in HIDDEN:
            continue
        if isinstance(value, dict) and depth < 1 and value and not (
                {"value", "limit", "margin"} <= set(value)):
            nested.append(f"<h4>{html.escape(_label(key))}</h4>{_figures(value, depth + 1)}")
        else:
            rows.append(f"<tr><th scope=\"row\">{html.escape(_label(key))}</th><td>{_value(value)}</td></tr>")
    table = f'<div class="scroll"><table class="figures">{"".join(rows)}</table></div>' if rows else ""
    return table + "".join(nested)


def _status(check: dict) -> tuple[str, str]:
    if not check.get("passed"):
        return "fail", "FAIL"
    if check.get("status") == "at limit":
        return "warn", "at limit"
    return "ok", "ok"


def _checks_table(rows: list[tuple[list[str], dict]]) -> str:
    """Every check, tightest margin first (by margin ratio; checks without one last)."""
    def order(row):
        ratio = row[1].get("margin_ratio")
        return (0 if ratio is not None else 1, ratio if ratio is not None else 0.0)

    body = []
    for path, check in sorted(rows, key=order):
        cls, word = _status(check)
        unit = html.escape(str(check.get("unit") or ""))
        attrs = " ".join(f'data-{key}="{html.escape(json.dumps(check.get(key)))}"'
                         for key in ("value", "limit", "margin"))
        where = check.get("applies") or ""
        owner = " / ".join(p for p in path[:-2] if p != "mechanisms")
        ratio = check.get("margin_ratio")
        body.append(
            f'<tr class="{cls}" data-check="{html.escape(path[-1])}" data-path="{html.escape(json.dumps(path))}" '
            f'{attrs}><td class="status">{word}</td><td>{html.escape(path[-1])}'
            + (f'<br><span class="owner">{html.escape(owner)}</span>' if owner else "")
            + f'</td><td class="num" data-label="value">{_number(check.get("value"))} {unit}</td>'
            f'<td class="num" data-label="limit">{_number(check.get("limit"))} {unit}</td>'
            f'<td class="num" data-label="margin">{_number(check.get("margin"))} {unit}'
            + (f" ({100.0 * ratio:.3g} %)" if isinstance(ratio, (int, float)) else "")
            + f'</td><td class="where" data-label="where">{html.escape(str(where))}</td></tr>')
    head = ("<tr><th>verdict</th><th>check</th><th>value</th><th>limit</th><th>margin</th>"
            "<th>where (cam angle, phase, speeds)</th></tr>")
    return (f'<div class="scroll"><table class="checks"><thead>{head}</thead><tbody>{"".join(body)}</tbody>'
            "</table></div>")


def _image(path: Path) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    name = html.escape(path.name)
    return (f'<figure><img src="data:image/png;base64,{data}" alt="{name}" loading="lazy">'
            f"<figcaption>{name}</figcaption></figure>")


def _law_section(mech: dict) -> str:
    law = mech.get("law") or {}
    parts = []
    if mech.get("phases"):
        parts.append(f"<p>Phases (deg): {html.escape(str(mech['phases']))}"
                     + (f" — {html.escape(str(mech['phase_angles']))}" if mech.get("phase_angles") else "") + "</p>")
    notes = law.get("notes") or []
    if notes:
        parts.append("<ul>" + "".join(f"<li>{html.escape(str(n))}</li>" for n in notes) + "</ul>")
    balance = law.get("balance")
    if isinstance(balance, dict):
        parts.append("<h4>Balance of the law</h4>" + _figures(balance))
    if isinstance(law.get("fixed"), dict):
        parts.append("<h4>Correction of the law</h4>" + _figures(law["fixed"]))
    if not isinstance(balance, dict) and (mech.get("skipped") or {}).get("balance"):
        parts.append(f"<p>Balance: {html.escape(str(mech['skipped']['balance']))}.</p>")
    return "".join(parts)


def _profile_section(mech: dict) -> str:
    keys = ("follower", "lift_mm", "swing_deg", "lobes", "pressure_angle_max_deg", "pressure_angle_max_at_deg",
            "pressure_angle_min_deg", "pressure_angle_min_at_deg", "rho_pitch_min_mm", "rho_pitch_min_at_deg",
            "rho_profile_min_mm", "rho_profile_min_at_deg", "undercut", "closed", "closure_gap_mm",
            "closure_kink_deg", "profile_points", "profile_representation", "chord_tolerance_mm", "max_deviation_mm")
    shown = {key: mech[key] for key in keys if key in mech}
    follower = shown.pop("follower", None)
    given = {k: v for k, v in follower.items() if v is not None} if isinstance(follower, dict) else {}
    text = _figures(given) if given else ""
    return ("<h4>Follower</h4>" + text if text else "") + "<h4>Profile</h4>" + _figures(shown)


def _mechanism(name: str, mech: dict, folder: Path, animation: str | None, heading: str,
               prefix: list[str]) -> str:
    rows = [([*prefix, *path], check) for path, check in check_rows(mech)]
    verdict = "all checks passed" if mech.get("passed") else "FAILED"
    parts = [f'<section class="mechanism" id="mechanism-{html.escape(name)}">',
             f'<h2>{html.escape(heading)} <span class="badge {"ok" if mech.get("passed") else "fail"}">'
             f"{verdict}</span></h2>"]
    parts.append("<h3>Checks, tightest margin first</h3>")
    parts.append(_checks_table(rows) if rows else "<p>No check with a limit.</p>")
    warnings = [w.get("what", "") for w in mech.get("warnings") or [] if isinstance(w, dict)]
    if warnings:
        parts.append("<h4>Warnings</h4><ul>" + "".join(f"<li>{html.escape(w)}</li>" for w in warnings) + "</ul>")
    parts.append("<h3>The law</h3>" + _law_section(mech))
    if "profile_points" in mech:
        parts.append("<h3>The profile</h3>" + _profile_section(mech))
    images = [Path(p) for p in mech.get("outputs") or [] if str(p).endswith(".png")]
    images = [p if p.is_absolute() else folder / p for p in images]
    images = [p for p in images if p.is_file()]
    if images:
        parts.append("<h3>Plots</h3>" + "".join(_image(p) for p in images))
    if animation is not None:
        parts.append('<h3>Animation</h3><iframe class="animation" title="the mechanism turning" '
                     f'srcdoc="{html.escape(animation, quote=True)}"></iframe>')
    for key, title in MODEL_SECTIONS:
        data = mech.get(key)
        if key == "export" and isinstance(data, dict) and not data.get("files"):
            continue       # no part file was asked for
        if isinstance(data, dict) and data:
            parts.append(f"<h3>{html.escape(title)}</h3>" + _figures(data))
    skipped = mech.get("skipped") or {}
    if skipped:
        parts.append("<h3>Not run</h3><ul>" + "".join(
            f"<li><b>{html.escape(str(k))}</b>: {html.escape(str(v))}</li>" for k, v in skipped.items()) + "</ul>")
    notes = mech.get("notes") or []
    if notes:
        parts.append("<h3>Notes</h3><ul>" + "".join(f"<li>{html.escape(str(n))}</li>" for n in notes) + "</ul>")
    parts.append("</section>")
    return "".join(parts)


def design_report_html(report: dict, folder: Path, *, command: str = "", scene_text: str | None = None,
                       animations: dict[str, str] | None = None) -> str:
    """The report page of a scene run (module docstring).

    Parameters
    ----------
    report : dict
        The run's report.json, as read back from the file (angles deg, lengths mm, speeds rpm, forces N,
        stresses MPa).
    folder : Path
        The output folder (its PNG plots are embedded).
    command : str
        The command that reproduces the run ("" for a run from Python: the report then gives the
        equivalent ``camcad profile`` of the scene file).
    scene_text : str, optional
        The scene file's text (TOML), shown as the run's input.
    animations : dict, optional
        Each mechanism's animation page (``camcad.report.animation.animation_html``) by name, embedded.

    Returns
    -------
    str
        One HTML document (no unit) with its style, images and animation inline.

    Examples
    --------
    >>> page = design_report_html({"name": "cam", "passed": True, "checks": {"pressure angle, rise": {
    ...     "value": 18.4, "limit": 30.0, "margin": 11.6, "margin_ratio": 0.387, "passed": True, "unit": "deg"}}},
    ...     Path("."))
    >>> 'data-check="pressure angle, rise"' in page, 'data-value="18.4"' in page
    (True, True)
    """
    animations = animations or {}
    name = str(report.get("name") or "design")
    mechanisms = report.get("mechanisms")
    passed = bool(report.get("passed"))
    body = [f"<header><h1>{html.escape(name)}</h1>"]
    if report.get("description"):
        body.append(f'<p class="description">{html.escape(str(report["description"]))}</p>')
    body.append(f'<p class="verdict {"ok" if passed else "fail"}">'
                f'{"All checks passed" if passed else "FAILED: see the checks below"}</p>')
    scene = report.get("scene")
    body.append(f'<p class="meta">camcad {html.escape(__version__)}'
                + (f" · scene {html.escape(str(scene))}" if scene not in (None, "command line")
                   else " · from the command's options")
                + (f" · speeds {_value(report['speeds_rpm'])} rpm" if report.get("speeds_rpm") else "")
                + "</p></header>")
    if isinstance(mechanisms, dict):
        body.append("<nav><ul>" + "".join(
            f'<li><a href="#mechanism-{html.escape(n)}">{html.escape(n)}</a> '
            f'{"ok" if m.get("passed") else "FAILED"}</li>' for n, m in mechanisms.items()) + "</ul></nav>")
        for mech_name, mech in mechanisms.items():
            body.append(_mechanism(mech_name, mech, folder / mech_name, animations.get(mech_name), mech_name,
                                   ["mechanisms", mech_name]))
        cyclogram = report.get("cyclogram")
        if isinstance(cyclogram, dict):
            rows = check_rows({"cyclogram": cyclogram})
            body.append('<section id="cyclogram"><h2>Cyclogram</h2>')
            if rows:
                body.append("<h3>Checks, tightest margin first</h3>" + _checks_table(rows))
            body.append(_figures(cyclogram))
            images = [folder / f for f in ("cyclogram.png", "network.png") if (folder / f).is_file()]
            body.append("".join(_image(p) for p in images) + "</section>")
    else:
        only = next(iter(animations.values()), None)      # a single mechanism: its one animation
        body.append(_mechanism(name, report, folder, only, "The design", []))
    if scene_text:
        body.append('<section id="scene"><h2>Appendix: the scene (the run\'s input)</h2>'
                    f'<pre class="scene">{html.escape(scene_text)}</pre></section>')
    outputs = [Path(p) for p in report.get("outputs") or []]
    if outputs:
        names = []
        for path in outputs:
            try:
                names.append(str(path.relative_to(folder)))
            except ValueError:
                names.append(path.name)
        body.append('<section id="outputs"><h2>Files written</h2><ul class="files">'
                    + "".join(f"<li>{html.escape(n)}</li>" for n in names) + "</ul></section>")
    again = command or (f"camcad profile {scene} --report" if scene not in (None, "command line")
                        else "camcad profile --report")
    body.append('<section id="reproduce"><h2>To reproduce it</h2>'
                f"<pre>{html.escape(again)}</pre><p>with camcad {html.escape(__version__)} "
                "(<code>camcad --version</code>); the run is deterministic: the same inputs give the same "
                "report.json.</p></section>")
    return _PAGE.format(title=html.escape(name), style=_STYLE, body="\n".join(body))


def write_design_report(report_json: Path, html_path: Path, *, pdf_path: Path | None = None, command: str = "",
                        scene_text: str | None = None, animations: dict[str, str] | None = None) -> list[Path]:
    """Write ``report.html`` from the written ``report.json`` (and ``report.pdf`` through headless Chromium
    when ``pdf_path`` is given); returns the written paths."""
    report = json.loads(Path(report_json).read_text(encoding="utf-8"))
    page = design_report_html(report, Path(report_json).parent, command=command, scene_text=scene_text,
                              animations=animations)
    written = [write_atomic(html_path, lambda tmp: tmp.write_text(page, encoding="utf-8"))]
    if pdf_path is not None:
        written.append(print_pdf(html_path, pdf_path))
    return written


def print_pdf(html_path: Path, pdf_path: Path, timeout_s: float = 120.0) -> Path:
    """Print the page ``html_path`` to ``pdf_path`` with headless Chromium (its print CSS: A4)."""
    browser = chromium()
    if browser is None:
        raise CamcadError("a PDF report is printed by Chromium, which is not installed", "--report-pdf",
                          "install chromium (or chromium-headless-shell), set CAMCAD_CHROMIUM, or open "
                          "report.html and print it from a browser")

    def run(tmp: Path) -> None:
        with tempfile.TemporaryDirectory(prefix="camcad-chromium-") as profile:
            done = subprocess.run(
                [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--no-pdf-header-footer",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 f"--user-data-dir={profile}", f"--print-to-pdf={tmp}", Path(html_path).resolve().as_uri()],
                capture_output=True, text=True, timeout=timeout_s)
        if done.returncode != 0 or tmp.stat().st_size == 0:
            raise CamcadError(f"Chromium could not print the report (exit {done.returncode}: "
                              f"{' '.join(done.stderr.split())[-200:]})", str(pdf_path),
                              "open report.html and print it from a browser")

    return write_atomic(pdf_path, run)


_STYLE = """
:root { color-scheme: light; --ok: #2e7d32; --fail: #c00000; --warn: #b35900; }
* { box-sizing: border-box; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 0 auto; padding: 16px;
       max-width: 1100px; line-height: 1.4; color: #1b1b1b; background: white; }
h1 { font-size: 1.6rem; margin: 0 0 4px; }
h2 { font-size: 1.3rem; margin: 28px 0 8px; border-bottom: 2px solid #1f4e79; padding-bottom: 2px; }
h3 { font-size: 1.1rem; margin: 20px 0 6px; color: #1f4e79; }
h4 { font-size: 1rem; margin: 12px 0 4px; }
.description { margin: 0 0 6px; color: #333; }
.meta { color: #555; font-size: 0.9rem; }
.verdict { font-weight: bold; font-size: 1.15rem; padding: 6px 10px; border-radius: 4px; display: inline-block; }
.verdict.ok, .badge.ok { background: #e3f1e4; color: var(--ok); }
.verdict.fail, .badge.fail { background: #fbe3e3; color: var(--fail); }
.badge { font-size: 0.85rem; padding: 2px 8px; border-radius: 10px; vertical-align: middle; }
.scroll { overflow-x: auto; -webkit-overflow-scrolling: touch; }
table { border-collapse: collapse; margin: 4px 0 10px; font-size: 0.92rem; }
th, td { border: 1px solid #d6d6d6; padding: 4px 8px; vertical-align: top; text-align: left; }
thead th { background: #eef3f8; }
table.figures th { font-weight: normal; color: #333; background: #fafafa; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.status { font-weight: bold; white-space: nowrap; }
tr.ok td.status { color: var(--ok); }
tr.fail td.status { color: var(--fail); }
tr.warn td.status { color: var(--warn); }
tr.fail { background: #fff3f3; }
.owner { color: #666; font-size: 0.85rem; }
td.where { font-size: 0.85rem; color: #333; min-width: 12em; }
figure { margin: 10px 0; }
figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 0.85rem; color: #555; }
iframe.animation { width: 100%; height: 760px; border: 1px solid #ddd; border-radius: 6px; }
pre { background: #f6f8fa; padding: 8px 10px; overflow-x: auto; font-size: 0.85rem; white-space: pre-wrap; }
nav ul { padding-left: 18px; }
ul.files { columns: 2; font-family: ui-monospace, monospace; font-size: 0.85rem; }
p, li, td, pre { overflow-wrap: anywhere; }
@media (max-width: 640px) {
  body { padding: 10px; }
  table.checks thead { display: none; }
  table.checks, table.checks tbody, table.checks tr, table.checks td { display: block; width: 100%; }
  table.checks tr { border: 1px solid #d6d6d6; margin-bottom: 8px; }
  table.checks td { border: none; padding: 2px 8px; text-align: left; white-space: normal; }
  table.checks td[data-label]::before { content: attr(data-label) ": "; color: #555; }
  h1 { font-size: 1.3rem; }
  table { font-size: 0.85rem; }
  ul.files { columns: 1; }
  iframe.animation { height: 1100px; }
}
@media print {
  @page { size: A4; margin: 14mm 12mm; }
  body { max-width: none; padding: 0; font-size: 10pt; }
  h2 { break-after: avoid; page-break-after: avoid; }
  h3, h4 { break-after: avoid; page-break-after: avoid; }
  table, figure, tr, pre { break-inside: avoid; page-break-inside: avoid; }
  .scroll { overflow: visible; }
  table.checks { width: 100%; }
  td.num { white-space: normal; }
  td.where { min-width: 0; }
  iframe.animation { height: 620px; break-inside: avoid; }
  nav { display: none; }
  a { color: inherit; text-decoration: none; }
}
"""

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="camcad">
<title>{title} — camcad report</title>
<style>{style}</style>
</head>
<body>
{body}
</body>
</html>
"""
