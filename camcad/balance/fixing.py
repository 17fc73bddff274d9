"""`camcad check` and `camcad fix` as library functions: one call, one report object.

``check_law`` and ``fix_law`` do everything the two commands do but parse options and print: the
command line calls one of them, prints ``report.to_text()`` or ``report.to_dict()`` (the JSON,
each key defined here once) and exits with ``report.exit_code``.

What ``fix_law`` promises (docs/fix.md):
- the drawn rise is kept (each rise's displacement, or the ``--lift`` it was scaled to) unless
  ``free_lift``; the report shows before and after for rise, return, areas and closures, and the
  change (max, RMS, and as a fraction of the law's peak);
- several edits (``moves``), each honoured or refused with its reason;
- a law already balanced within the tolerance is not written again (unless ``force``);
- the copy of a drawing keeps the original curve in an unreferenced block (``io.law_write``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

from camcad.balance.checking import BalanceReport, check, check_by_trapezoid, check_recorded
from camcad.balance.conditions import DEFAULT_MAX_STRETCH, DEFAULT_STEP_DEG, DEFAULT_TOL, valid_tol
from camcad.balance.correction import Correction, correct
from camcad.io.law_record import LawRecord
from camcad.io.output_folder import check_outputs
from camcad.verdict import note_line

# ---------------------------------------------------------------------------------------------
# check
# ---------------------------------------------------------------------------------------------

@dataclass
class CheckReport:
    """What ``camcad check`` reports: where the law came from, its balance, and the optional extras."""

    source: str
    notes: tuple[str, ...]
    balance: BalanceReport
    trapezoid: dict | None = None
    plot: str | None = None
    length_unit: str = "mm"       # the law's lengths: mm, or the drawing's in / cm (LoadedLaw.length_unit)

    @property
    def exit_code(self) -> int:
        """0 balanced, 1 not (docs/INTERFACE.md)."""
        return 0 if self.balance.balanced else 1

    def to_dict(self) -> dict:
        """The JSON of ``camcad check --json`` (docs/INTERFACE.md keys)."""
        payload = {"source": self.source, "notes": list(self.notes), **self.balance.to_dict(),
                   "length_unit": self.length_unit}
        if self.trapezoid is not None:
            payload["trapezoid"] = self.trapezoid
        if self.plot is not None:
            payload["plot"] = self.plot
        return payload

    def to_text(self) -> str:
        """The human-readable report (plain text, no markup)."""
        b, u = self.balance, self.length_unit
        lines = [self.source, *(note_line(n) for n in self.notes), "", "phases"]
        lines += _table(["phase", "from (deg)", "to (deg)", f"area + ({u}/rad)", f"area - ({u}/rad)",
                         f"v at end ({u}/rad)", f"displacement ({u})"],
                        [[p["kind"], f"{p['start_deg']:.4f}", f"{p['end_deg']:.4f}", f"{p['area_positive']:.6g}",
                          f"{p['area_negative']:.6g}", f"{p['v_end']:.3e}", f"{p['displacement']:.6g}"]
                         for p in b.phases])
        lines += ["", "balance conditions"]
        lines += _table(["condition", "residual"], [[n, f"{r:.3e}"] for n, r in zip(b.condition_names, b.residuals)])
        lines.append(f"rise {b.rise:.6g} {u}, return {b.return_:.6g} {u}, tolerance {b.tolerance_abs:.3g} "
                     f"(= {b.tolerance:g} x rise)")
        if b.basis is not None and b.basis["rule"] == "closure":
            k = b.basis
            lines.append(f"judged as {k['written_by']} judged it (its record in the file): the cycle closes, s gap "
                         f"{k['closure_s']:.3e}, v gap {k['closure_v']:.3e} (limit {k['closure_limit']:.3g}); dwell "
                         f"deviation {k['dwell_deviation']:.4g} (limit {k['dwell_tol']:.4g}"
                         + (f", at {k['dwell_deviation_at_deg']:.4g} deg" if k['dwell_deviation_at_deg'] is not None
                            else "") + "); the balance conditions above are figures only")
        elif b.basis is not None:
            lines.append(f"judged by the balance conditions, tolerance {b.basis['tolerance']:g} recorded by "
                         f"{b.basis['written_by']}")
        if self.trapezoid is not None:
            trap = self.trapezoid
            lines.append(f"source's method (trapezoid, step {trap['step_deg']:g} deg): residuals "
                         + ", ".join(f"{r:.3e}" for r in trap["residuals"])
                         + f"; differs from exact by up to {max(abs(e) for e in trap['error_vs_exact']):.2e}; "
                         + ("balanced" if trap["balanced"] else "not balanced"))
        lines.append("balanced" if b.balanced else "NOT balanced: run camcad fix")
        if self.plot:
            lines.append(f"plot: {self.plot}")
        return "\n".join(lines)


def check_law(loaded, tol: float = DEFAULT_TOL, *, trapezoid: bool = False,
              step_deg: float = DEFAULT_STEP_DEG) -> CheckReport:
    """The area balance of a law read from a file (``camcad check``).

    Parameters
    ----------
    loaded : camcad.law.source.LoadedLaw
    tol : float
        Closure tolerance, fraction of the rise (a law whose phases were restored from camcad's record is
        judged by the rule and tolerance recorded: ``balance.checking.check_recorded``).
    trapezoid : bool
        Also check by the source's method (resample with ``step_deg``, trapezoidal rule).
    step_deg : float
        Resampling step of ``trapezoid`` (deg).

    Returns
    -------
    CheckReport
    """
    if loaded.record is not None and loaded.phases_from_record:
        report = check_recorded(loaded.law, loaded.record)
    else:
        report = check(loaded.law, tol)
    extra = check_by_trapezoid(loaded.law, tol, step_deg) if trapezoid else None
    return CheckReport(loaded.source, tuple(loaded.notes), report, extra,
                       length_unit=getattr(loaded, "length_unit", "mm"))


# ---------------------------------------------------------------------------------------------
# fix
# ---------------------------------------------------------------------------------------------

@dataclass
class FixReport:
    """What ``camcad fix`` did: the correction, what was written (if anything) and every note.

    Changes and move values are reported in the input's y units (law units / ``y_scale``).
    """

    source: str
    notes: tuple[str, ...]
    correction: Correction
    y_scale: float
    output: Path | None
    status: str                      # "fixed", "already balanced" or "copied" (--force on a balanced law)
    plot: str | None = None
    write_notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def exit_code(self) -> int:
        """0 when the law is balanced after the fix (or was already), 1 when it is not."""
        return 0 if self.correction.after.balanced else 1

    def to_dict(self) -> dict:
        """The JSON of ``camcad fix --json``: the check keys of the law before, and the fix's own keys."""
        c, scale = self.correction, self.y_scale
        rises = _rises(c)
        return {
            "source": self.source,
            "notes": list(self.notes) + list(c.notes) + list(self.write_notes),
            **c.before.to_dict(),
            "status": self.status,
            "mode": c.mode, "method": c.method,
            "output": str(self.output) if self.output is not None else None,
            "written": self.output is not None,
            "max_change": c.max_change / scale, "rms_change": c.rms_change / scale,
            "iterations": c.iterations, "resampled": c.resampled,
            "change": {
                "max": c.max_change / scale, "rms": c.rms_change / scale,
                "max_vertex": c.max_vertex_change / scale, "peak": c.peak / scale,
                "max_fraction_of_peak": c.max_change / c.peak if c.peak else 0.0,
                "rms_fraction_of_peak": c.rms_change / c.peak if c.peak else 0.0,
                "max_vertex_fraction_of_peak": c.max_vertex_change / c.peak if c.peak else 0.0,
                "vertices_changed": c.vertices_changed, "max_shift_deg": c.max_shift_deg,
            },
            "lift": {"kept": c.keep_lift, "targets_mm": list(c.lift_targets), "rise_before": rises[0],
                     "rise_after": rises[1], "change_mm": rises[1] - rises[0]},
            "moves": [{"angle_deg": m.theta_deg, "value": m.value / scale, "status": m.status, "reason": m.reason,
                       "vertex": m.vertex, "vertex_deg": m.vertex_deg,
                       "old_value": None if m.old_value is None else m.old_value / scale} for m in c.moves],
            "after": c.after.to_dict(),
            **({"plot": self.plot} if self.plot is not None else {}),
        }

    def to_text(self) -> str:
        """The human-readable report (plain text: a phase string such as 0:100:dwell stays as it is)."""
        c, scale = self.correction, self.y_scale
        b, a = c.before, c.after
        lines = [self.source, *(note_line(n) for n in (*self.notes, *c.notes, *self.write_notes))]
        if self.status == "already balanced":
            lines.append(f"already balanced within {b.tolerance:g} x rise ({b.tolerance_abs:.3g} mm): nothing to fix, "
                         "no file written (--force writes a copy)")
            lines += _moves_text(c, scale)
            return "\n".join(lines)

        def yes(flag: bool) -> str:
            return "yes" if flag else "NO"

        rows = [["rise (mm)", f"{b.rise:.6g}", f"{a.rise:.6g}"],
                ["return (mm)", f"{b.return_:.6g}", f"{a.return_:.6g}"]]
        for key, label in (("rise_accel", "rise, accelerating area"), ("rise_decel", "rise, decelerating area"),
                           ("return_accel", "return, accelerating area"),
                           ("return_decel", "return, decelerating area")):
            rows.append([f"{label} (mm/rad)", f"{b.areas[key]:.6g}", f"{a.areas[key]:.6g}"])
        rows += [["velocity at the end of the rise (mm/rad)", f"{b.velocity_closure['rise']:.3e}",
                  f"{a.velocity_closure['rise']:.3e}"],
                 ["velocity at the end of the return (mm/rad)", f"{b.velocity_closure['return']:.3e}",
                  f"{a.velocity_closure['return']:.3e}"],
                 ["displacement closure (mm)", f"{b.displacement_closure:.3e}", f"{a.displacement_closure:.3e}"],
                 ["balanced", yes(b.balanced), yes(a.balanced)]]
        lines += ["", *_table(["", "before", "after"], rows), ""]
        peak = c.peak / scale
        lines.append(f"change of a: max {c.max_change / scale:.4g}, RMS {c.rms_change / scale:.4g} (input y units) = "
                     f"{100 * c.max_change / c.peak:.3g} % and {100 * c.rms_change / c.peak:.3g} % of the law's peak "
                     f"{peak:.4g}; {c.vertices_changed} vertices changed" if c.peak else "change of a: none")
        if c.max_shift_deg > 0:
            lines.append(f"  vertices moved in angle by up to {c.max_shift_deg:.4g} deg; the largest change of a "
                         f"vertex's ordinate is {c.max_vertex_change / scale:.4g}")
        rises = _rises(c)
        if c.keep_lift and c.lift_targets:
            lines.append(f"lift: the rise is kept at {rises[0]:.6g} mm (after: {rises[1]:.6g} mm); "
                         "--free-lift lets it change")
        elif not c.keep_lift:
            lines.append(f"lift: free (--free-lift): the rise went from {rises[0]:.6g} to {rises[1]:.6g} mm")
        lines += _moves_text(c, scale)
        verdict = "balanced" if a.balanced else "STILL NOT balanced"
        lines.append(f"mode {c.mode} ({c.method}): {verdict}")
        if self.output is not None:
            lines.append(f"written: {self.output}" + (f", plot {self.plot}" if self.plot else ""))
        return "\n".join(lines)


def default_output(loaded) -> Path:
    """``<name>.fixed.dxf`` beside a drawing, ``<name>.fixed<suffix>`` beside a table."""
    path = Path(loaded.path)
    return path.with_name(path.stem + ".fixed" + (path.suffix if loaded.curve is None else ".dxf"))


def plot_path(output: str | Path) -> Path:
    """Where ``camcad fix`` draws the plot of the corrected law written to ``output``: beside it, ``.png``."""
    return Path(output).with_suffix(".png")


def check_plot_output(plot: str | Path | None, law_path: str | Path) -> None:
    """The guard of ``camcad check --plot``: the plot may not replace the law (one line naming both)."""
    if plot is not None:
        check_outputs([(Path(plot), "--plot")], [(Path(law_path), "the law")], "--plot")


def fix_law(loaded, mode: str = "min-change", *, output: str | Path | None = None, tol: float = DEFAULT_TOL,
            method: str = "exact", step_deg: float = DEFAULT_STEP_DEG,
            segment_deg: tuple[float, float] | None = None, moves=(), max_stretch: float = DEFAULT_MAX_STRETCH,
            free_lift: bool = False, force: bool = False, plot: bool = False) -> FixReport:
    """Check and correct a law read from a file, and write the corrected copy (``camcad fix``).

    Parameters
    ----------
    loaded : camcad.law.source.LoadedLaw
        The law as read (``camcad.law.source.load_law``).
    mode : str
        A correction mode (``camcad.balance.MODES``).
    output : str or Path, optional
        The file to write; default ``default_output(loaded)``. Never the input.
    tol : float
        Closure tolerance, fraction of the rise.
    method : str
        "exact" or "iterate" (the source's loop).
    step_deg : float
        Resampling step of "iterate" and "extrema-resample" (deg).
    segment_deg : (float, float), optional
        The angle range mode "segment" may change (deg).
    moves : sequence of (float, float)
        Edits (θ deg, a in the input's y units): each sets the vertex nearest θ and holds it.
    max_stretch : float
        Largest relative phase stretch of "phase-keypoints".
    free_lift : bool
        Let the rise change (by default each rise keeps its drawn displacement).
    force : bool
        Write a copy even when the law is already balanced.
    plot : bool
        The caller draws the plot at ``plot_path(output)``: it is checked with the output, before anything
        is written (neither may replace the law, nor each other).

    Returns
    -------
    FixReport
    """
    from camcad.io.law_write import write_corrected  # ezdxf: only when a copy is written

    valid_tol(tol)   # before anything is written
    out = Path(output) if output is not None else default_output(loaded)
    outputs = [(out, "-o" if output is not None else "the corrected law")]
    if plot:
        outputs.append((plot_path(out), "the plot of the corrected law"))
    check_outputs(outputs, [(Path(loaded.path), "the law")], "-o")
    law_moves = [(float(theta), float(value) * loaded.y_scale) for theta, value in moves]
    result = correct(loaded.law, mode, tol=tol, method=method, step_deg=step_deg, segment_deg=segment_deg,
                     moves=law_moves, max_stretch=max_stretch, where=str(loaded.path), keep_lift=not free_lift)
    if not result.changed and not force:
        return FixReport(loaded.source, tuple(loaded.notes), result, loaded.y_scale, None, "already balanced")
    record = LawRecord.for_law(result.law, f"camcad fix --mode {mode}", unit=loaded.unit or "mm", tol=tol)
    written, notes = write_corrected(loaded, result.law, out, resampled=result.resampled, record=record)
    status = "fixed" if result.changed else "copied"
    return FixReport(loaded.source, tuple(loaded.notes), result, loaded.y_scale, Path(written), status,
                     write_notes=tuple(notes))


# --- helpers --------------------------------------------------------------------------------------

def _rises(c: Correction) -> tuple[float, float]:
    return float(c.before.rise), float(c.after.rise)


def _moves_text(c: Correction, scale: float) -> list[str]:
    lines = []
    for number, m in enumerate(c.moves, start=1):
        request = f"--move #{number} {m.theta_deg:g}:{m.value / scale:g}"
        if m.honoured:
            lines.append(f"{request}: honoured: vertex {m.vertex} at {m.vertex_deg:.6g} deg set from "
                         f"{cast(float, m.old_value) / scale:.6g} to {m.value / scale:.6g} and held")
        else:
            lines.append(f"{request}: REFUSED: {m.reason}")
    return lines


def _table(headers: list[str], rows: list[list[str]]) -> list[str]:
    """Plain-text columns: the first left-aligned, the others right-aligned."""
    cells = [headers] + rows
    widths = [max(len(str(row[i])) for row in cells) for i in range(len(headers))]

    def line(row):
        return "  ".join(str(v).ljust(w) if i == 0 else str(v).rjust(w) for i, (v, w) in enumerate(zip(row, widths)))

    return [line(headers), "  ".join("-" * w for w in widths)] + [line(r) for r in rows]


__all__ = ["CheckReport", "FixReport", "check_law", "default_output", "fix_law"]
