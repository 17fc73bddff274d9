"""The README's (and docs/fix.md's) table of what each `camcad fix` mode changes on the unbalanced samples.

For each sample and each mode (exact solves, the drawn rise kept): the RMS and the largest change of the
acceleration as a function of the cam angle, in the input's y units, and the largest change of a vertex's
ordinate as a fraction of the law's peak (phase modes move vertices in angle instead: their largest shift
in degrees is given). Below the table: the largest error of the kept rise and of the balance over all cells.

Run: python benchmarks/fix_modes_table.py        (prints the markdown; paste it as it is)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from camcad import balance  # noqa: E402 - after the sys.path line
from camcad.errors import CamcadError  # noqa: E402
from camcad.law.source import load_law  # noqa: E402

SAMPLES = ["dxf/fig2_rise_area_too_large.dxf", "dxf/drrd_return_short.dxf", "dxf/constant_accel_jumps.dxf",
           "dxf/r12_polyline_harmonic.dxf", "dxf/spline_law.dxf", "dxf/line_chain_trapezoid.dxf",
           "dxf/drawing_with_axes_grid_text.dxf", "law_table.csv"]
MODES = ["min-change", "extrema", "extrema-resample", "keypoints", "phase", "phase-keypoints"]


def cell(loaded, mode: str) -> tuple[str, float, float]:
    """The table cell, the relative error of the kept rise and the largest closure residual (fraction of the rise)."""
    try:
        result = balance.correct(loaded.law, mode)
    except CamcadError as err:
        return f"refused: {err.what}", 0.0, 0.0
    scale = loaded.y_scale
    text = f"{result.rms_change / scale:.3g} / {result.max_change / scale:.3g}"
    if mode.startswith("phase"):
        text += f" ({result.max_shift_deg:.2g} deg"
        text += f", {100 * result.max_vertex_change / result.peak:.2g} %)" if result.max_vertex_change else ")"
    else:
        text += f" ({100 * result.max_vertex_change / result.peak:.2g} %)"
    rise = result.before.rise
    lift_error = abs(result.after.rise - rise) / rise
    closure = max(abs(r) for r in result.after.residuals) / rise
    return text, lift_error, closure


def main() -> None:
    rows = []
    worst_lift = worst_closure = 0.0
    for name in SAMPLES:
        loaded = load_law(ROOT / "samples" / name)
        peak = float(np.max(np.abs(loaded.law.a))) / loaded.y_scale
        cells = []
        for mode in MODES:
            text, lift_error, closure = cell(loaded, mode)
            cells.append(text)
            worst_lift, worst_closure = max(worst_lift, lift_error), max(worst_closure, closure)
        rows.append(f"| {Path(name).name} | {peak:.4g} | " + " | ".join(cells) + " |")
    print("| sample | peak | " + " | ".join(MODES) + " |")
    print("|---|---|" + "---|" * len(MODES))
    print("\n".join(rows))
    print()
    print("Each cell: RMS / largest change of a(θ) (input y units), and in brackets the largest change of one "
          "vertex's ordinate as a fraction of the law's peak (phase modes: the largest shift of a vertex in angle, "
          "then that fraction). Exact solves, the drawn rise kept; over the whole table the rise is kept within "
          f"{worst_lift:.1e} of itself and every balance condition is met within {worst_closure:.1e} of the rise "
          "(`python benchmarks/fix_modes_table.py`).")


if __name__ == "__main__":
    main()
