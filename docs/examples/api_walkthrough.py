"""A walk through the public API, one group at a time, with only ``import camcad`` (and numpy).

Each group shows its functions in a few lines and prints a figure the reader can check by hand (a closed
form, a published value, or a simple fact). tests/project/test_api_walkthrough.py runs it and checks those
figures independently; the documentation (docs/walkthrough.rst) shows it with its output.
Run: python docs/examples/api_walkthrough.py [OUTPUT_FOLDER]
"""

import math
import sys
import tempfile
from pathlib import Path

import numpy as np

import camcad

ROOT = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="camcad-walkthrough-"))
out.mkdir(parents=True, exist_ok=True)

# --- Laws: standard shapes composed into a cycle, kinematics in degrees, phases, drawn laws -------------
print("== laws")
law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0, "cycloidal")
k = camcad.kinematics_deg(law, np.linspace(0.0, 90.0, 9001))       # θ in deg; v, a per rad of cam angle
beta = math.radians(90.0)
print(f"cycloidal rise: Cv = {k.v.max() * beta / 20.0:.6f} (2), Ca = {k.a.max() * beta**2 / 20.0:.6f} (2π = 6.283185)")
phases = camcad.parse_phases("0:90:rise,90:180:dwell,180:270:return,270:360:dwell", 360.0)
print("phases (deg):", [(p.kind, math.degrees(p.start), math.degrees(p.end)) for p in phases])
loaded = camcad.load_law(ROOT / "samples" / "law_table.csv", lift=10.0)
print("read:", loaded.source, "|", "; ".join(loaded.notes))

# --- Balance: the area check and the least change that restores it -------------------------------------
print("== balance")
drawn = camcad.load_law(ROOT / "samples" / "dxf" / "fig2_rise_area_too_large.dxf", lift=10.0)
before = camcad.check(drawn.law)
print(f"drawn law balanced: {before.balanced}; the follower ends {before.displacement_closure:.4g} mm off its start")
fixed = camcad.correct(drawn.law, "min-change")
print(f"after min-change: balanced {fixed.after.balanced}, RMS change {fixed.rms_change:.4g} mm/rad^2")
written, _ = camcad.write_corrected(drawn, fixed.law, out / "fixed.csv")
print("corrected law written:", written.name)

# --- Profile: a follower, the synthesis, its report, the least base radius, the files --------------------
print("== profile")
follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0)
result = camcad.synthesize(law, follower, camcad.ProfileSettings(plots=False))
kk = camcad.kinematics_deg(law, np.linspace(0.0, 360.0, 360001))
by_hand = np.degrees(np.arctan(kk.v / (40.0 + 10.0 + kk.s))).max()    # tan φ = v/(Rb + Rr + s), e = 0
print(f"pressure angle max {np.degrees(result.pressure_angle.maximum.value):.6f} deg "
      f"(by hand on a 0.001 deg grid: {by_hand:.6f})")

figures = camcad.profile_report(result)
print(f"lift {figures['lift_mm']:g} mm, passed {figures['passed']}, tightest check: {figures['tightest'][0]}")
flat = camcad.min_base_radius(camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic"),
                              camcad.Follower("flat", base_radius=1.0, rho_min=25.0))
print(f"flat face on s = 10(1 - cos θ), rho_min 25 mm: Rb >= {flat.rb_min:.9f} mm (25 - h/2 = 15)")
print("files:", ", ".join(p.name for p in camcad.write_outputs(result, out / "profile")))

# --- Fourier: the spectrum, the resonance band, the filtered law -----------------------------------------
print("== fourier")
harmonic = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")
spectrum = camcad.analyse(harmonic, 8)
print(f"s = 10 - 10 cos θ: mean {spectrum.mean:.9f} mm, A1 {spectrum.amplitudes[0]:.9f} mm, "
      f"phase {math.degrees(spectrum.phases[0]):.6f} deg, "
      f"A2..A8 < 1e-12: {bool(spectrum.amplitudes[1:].max() < 1e-12)}")
band = camcad.resonant_harmonics(100.0, (300.0, 400.0))
print(f"fn 100 Hz over 300-400 rpm, ±5 %: k in [{band.k_low:g}, {band.k_high:g}], resonant {list(band.core)}")
filtered = camcad.filter_law(law, band, harmonics=32)
after = camcad.analyse(filtered.law, 32)
print(f"filtered: removed harmonics' largest amplitude {max(after.amplitudes[k - 1] for k in band.removed):.1e} mm, "
      f"dwell deviation {filtered.dwell_deviation:.3g} mm (tolerance {filtered.dwell_tol:g} mm)")

# --- Dynamics: the elastic follower, its steady state, residual vibration, impacts on a stop --------------
print("== dynamics")
response = camcad.steady_state(harmonic, camcad.ElasticFollower(10.0), 240.0)   # r = 4 Hz / 10 Hz = 0.4
print(f"peak acceleration ratio {response.peak_accel_ratio:.9f} (1/(1 - r^2) = {1 / (1 - 0.16):.9f})")
rise, _ = camcad.residual_vibration(law, camcad.ElasticFollower(10.0), 60.0)
r = 0.25 * 10.0
print(f"residual vibration after the rise {rise.amplitude:.9f} mm "
      f"(closed form h|sin πr|/(πr|r²-1|) = {20 * abs(math.sin(math.pi * r)) / (math.pi * r * (r * r - 1)):.9f})")
stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6, restitution=5 / 9,
                        damping_ratio=0.05, preload_mm=0.25)
sweep = camcad.impact_sweep(law, stop, [280.0, 420.0])
print(f"impact force {sweep.force_n[0]:.4g} -> {sweep.force_n[1]:.4g} N from 280 to 420 rpm: "
      f"ratio {sweep.force_n[1] / sweep.force_n[0]:.9f} (the speed ratio 1.5)")

# --- Contact: Hertz stress along the profile ---------------------------------------------------------------
print("== contact")
steel = camcad.ContactParams(cam_modulus=2.1e5, cam_poisson=0.3, follower_modulus=2.1e5, follower_poisson=0.3,
                             width=10.0, mass=0.0, allowable_stress=1000.0, preload=1000.0)
zero = np.zeros(3)
still = camcad.contact_stress(zero, zero, zero, zero, zero, np.full(3, 20.0), 10.0, 300.0, steel)
print(f"1000 N, R' = 20·10/30 mm, steel: sigma_H {still.sigma_max:.1f} MPa (Johnson, by hand 742.2)")
table = result.table
stress = camcad.contact_stress(table.theta, table.s, table.v, table.a, table.pressure_angle, table.rho_profile,
                               10.0, 300.0, steel)
print(f"along the profile at 300 rpm: sigma_max {stress.sigma_max:.1f} MPa at {math.degrees(stress.at):.1f} deg")

# --- Cyclogram: a network of operations and its least makespan -------------------------------------------
print("== cyclogram")
network = camcad.make_network([camcad.Operation("a", "b", 30.0, 90.0), camcad.Operation("b", "c", 45.0, 60.0),
                               camcad.Operation("a", "c", 100.0)])
best = camcad.optimise(network)
print(f"makespan {best.makespan_deg:g} deg (max(30 + 45, 100)), times {best.event_times_deg}, "
      f"active {best.active_bounds}")

# --- Scenes: a file, its analyses, its outputs --------------------------------------------------------------
print("== scenes")
scene = camcad.read_scene(ROOT / "samples" / "scenes" / "shuttle_lift.toml")
found = camcad.analyse_scene(scene)
impact = found.report["impact"]
print(f"{scene.name}: ran {found.report['models_run']}; impact force at 280 rpm {impact['force_N'][0]:.4g} N "
      f"(published 4.137 N), first rebound {impact['rebound_mm'][0]:.3g} mm (published 0.07 mm)")

# --- Plots: each returns a matplotlib Figure ---------------------------------------------------------------
print("== plots")
for plot in (camcad.plot_summary, camcad.plot_kinematics, camcad.plot_pressure_angle, camcad.plot_curvature,
             camcad.plot_profile, camcad.plot_hodograph):
    figure = plot(result)
    figure.savefig(out / f"{plot.__name__}.png", dpi=50)
    print(f"{plot.__name__}: {len(figure.axes)} axes, y axis of the first: {figure.axes[0].get_ylabel()!r}")

# --- Errors: bad input is one CamcadError, one line ----------------------------------------------------------
print("== errors")
try:
    camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, offset=60.0).validate()
except camcad.CamcadError as err:
    print("CamcadError:", err)
