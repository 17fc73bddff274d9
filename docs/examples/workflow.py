"""The main workflow through the public API only (``import camcad``), as a notebook would run it.

A drawn acceleration law (a DXF from the samples, unbalanced: its rise area is too large) is read,
checked, corrected with the least change, turned into a cam for a translating roller follower, plotted,
and written as DXF. Run: python docs/examples/workflow.py [OUTPUT_FOLDER]   (tests/project/test_api.py runs it)
"""

import sys
from pathlib import Path

import camcad

ROOT = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("camcad-out") / "workflow"

# 1. read the law the designer drew (x: the cycle, y: the acceleration analog, scaled to a 10 mm rise)
loaded = camcad.load_law(ROOT / "samples" / "dxf" / "fig2_rise_area_too_large.dxf", lift=10.0)
print(loaded.source)

# 2. the area balance: does the velocity come back to zero, does the follower come back down?
before = camcad.check(loaded.law)
print("balanced before:", before.balanced, "- displacement closure", f"{before.displacement_closure:.4g} mm")

# 3. the least change of the drawn curve that balances it
fixed = camcad.correct(loaded.law, "min-change")
print("balanced after:", fixed.after.balanced, "- RMS change", f"{fixed.rms_change:.4g} mm/rad^2")

# 4. the cam: a translating roller follower, Rb 40 mm, Rr 10 mm
follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0)
result = camcad.synthesize(fixed.law, follower, camcad.ProfileSettings(plots=False), name="workflow")
figures = camcad.profile_report(result)
print(f"pressure angle max {figures['pressure_angle_max_deg']:.2f} deg; verdict:",
      "passed" if figures["passed"] else "FAILED")
for name in figures["tightest"]:
    print("  ", figures["checks"][name]["why"])

# 5. a plot (a matplotlib Figure: saving it is the caller's choice) and the profile DXF
out.mkdir(parents=True, exist_ok=True)
camcad.plot_summary(result).savefig(out / "summary.png", dpi=80)
written = camcad.write_outputs(result, out)
print("wrote", ", ".join(p.name for p in written))
