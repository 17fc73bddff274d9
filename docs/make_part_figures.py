"""The pictures of docs/part.md: the contour program's path and the solid (python docs/make_part_figures.py).

Runs `camcad profile` on the built-in design with the part's options, then draws from the files it wrote:
the G-code as a small interpreter of this script reads it (lines and arcs in two colours, the lead-in and
lead-out, the start), over the profile of profile_points.csv; and, with FreeCAD and Xvfb installed, cam.step
opened in FreeCAD's window (a screenshot) and what freecadcmd reads from it.
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
IMG = ROOT / "docs" / "img"
OPTIONS = ["--export", "points,cutter,gcode,step,stl", "--cutter-radius", "5", "--feed", "300", "--depth", "12",
           "--thickness", "12", "--bore", "20", "--keyway", "6,2.8", "--tol-mm", "0.01"]


def run(folder: Path) -> None:
    subprocess.run([sys.executable, "-m", "camcad", "profile", "--no-plots", "-o", str(folder), *OPTIONS],
                   check=True, cwd=ROOT, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})


def moves(text: str):
    """(G-code, comment, points) of every XY move (G0/G1/G2/G3 with I, J; mm)."""
    mode, label, x, y = None, "", 0.0, 0.0
    out = []
    for raw in text.splitlines():
        note = re.findall(r"\(([^)]*)\)", raw)
        label = note[-1] if note else label
        line = re.sub(r"\([^)]*\)", "", raw)
        words = {w[0]: float(w[1:]) for w in re.findall(r"[A-Z][-.0-9]+", line) if w[0] != "G"}
        for g in re.findall(r"G(\d+)", line):
            mode = int(g) if int(g) in (0, 1, 2, 3) else mode
        if "X" not in words and "Y" not in words:
            continue
        nx, ny = words.get("X", x), words.get("Y", y)
        if mode in (0, 1):
            pts = np.array([[x, y], [nx, ny]])
        else:
            cx, cy = x + words["I"], y + words["J"]
            a0, a1 = math.atan2(y - cy, x - cx), math.atan2(ny - cy, nx - cx)
            sweep = (a1 - a0) % (2 * math.pi) if mode == 3 else -((a0 - a1) % (2 * math.pi))
            t = np.linspace(0, 1, 60)
            r = math.hypot(x - cx, y - cy)
            pts = np.column_stack((cx + r * np.cos(a0 + sweep * t), cy + r * np.sin(a0 + sweep * t)))
        out.append((mode, label, pts))
        x, y = nx, ny
    return out


def table(path: Path) -> dict[str, np.ndarray]:
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {name: data[:, k] for k, name in enumerate(lines[0].split(","))}


def toolpath_figure(folder: Path) -> Path:
    rows = table(folder / "profile_points.csv")
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(11, 5.6), gridspec_kw={"width_ratios": [1.25, 1]})
    program = moves((folder / "profile.nc").read_text())
    for axis in (ax, zoom):
        axis.fill(rows["x_mm"], rows["y_mm"], color="0.88", zorder=0)
        axis.plot(np.append(rows["x_mm"], rows["x_mm"][0]), np.append(rows["y_mm"], rows["y_mm"][0]), color="k",
                  lw=1.2, label="profile (profile_points.csv)")
        axis.add_patch(plt.Circle((0, 0), 10, fill=True, color="white", ec="k", lw=0.8))
        drawn = set()
        for mode, label, pts in program[1:]:   # the first rapid comes from wherever the tool was
            if mode == 0:
                kind, style = "rapid G0", dict(color="tab:gray", ls=":", lw=1)
            elif "lead" in label or "to the start" in label:
                kind, style = "lead-in / lead-out", dict(color="tab:green", lw=2)
            elif mode == 1:
                kind, style = "G1 line", dict(color="tab:red", lw=1.6)
            else:
                kind, style = "G2/G3 arc", dict(color="tab:blue", lw=1.6)
            axis.plot(pts[:, 0], pts[:, 1], label=kind if kind not in drawn else None, **style)
            drawn.add(kind)
        ends = np.array([pts[-1] for mode, label, pts in program if mode in (2, 3) and "the contour" not in label
                         and "lead" not in label])
        if len(ends):
            axis.plot(ends[:, 0], ends[:, 1], ".", color="tab:blue", ms=3)
        axis.set_aspect("equal")
        axis.grid(alpha=0.3)
        axis.set_xlabel("x (mm)")
    start = program[0][2][-1]
    ax.plot(*start, "o", color="tab:green", ms=6)
    ax.annotate("start of the lead-in\n(the middle of the near dwell)", start, xytext=(-62, 30), fontsize=8,
                ha="left", color="tab:green", arrowprops=dict(arrowstyle="->", color="tab:green"))
    ax.set_ylabel("y (mm)")
    ax.set_title("profile.nc: cutter centre, R 5 mm, climb milling (clockwise)", fontsize=10)
    ax.legend(loc="lower left", fontsize=8)
    touch = next(pts[-1] for mode, label, pts in program if mode in (2, 3) and label == "lead-in")
    zoom.set_xlim(touch[0] - 14, touch[0] + 14)
    zoom.set_ylim(touch[1] - 12, touch[1] + 12)
    zoom.set_title("the lead-in and lead-out: tangent quarter arcs", fontsize=10)
    fig.tight_layout()
    path = IMG / "part_toolpath.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def freecad_picture(folder: Path) -> Path | None:
    """cam.step opened in FreeCAD's window (under Xvfb), isometric view, saved as docs/img/part_freecad.png."""
    freecad, xvfb = shutil.which("freecad"), shutil.which("xvfb-run")
    if freecad is None or xvfb is None:
        return None
    path = IMG / "part_freecad.png"
    macro = folder / "shot.py"
    macro.write_text("import os, FreeCAD, FreeCADGui, Part\n"
                     "doc = FreeCAD.newDocument('cam')\n"
                     f"Part.insert({str(folder / 'cam.step')!r}, doc.Name)\n"
                     "doc.recompute()\n"
                     "view = FreeCADGui.activeDocument().activeView()\n"
                     "view.viewIsometric()\n"
                     "view.fitAll()\n"
                     f"view.saveImage({str(path)!r}, 1000, 620, 'White')\n"
                     "os._exit(0)\n")
    # FreeCAD's window holds a web view (Chromium), which refuses to run as root inside its sandbox
    env = {"PATH": "/usr/bin:/bin", "HOME": str(folder), "QTWEBENGINE_DISABLE_SANDBOX": "1",
           "QTWEBENGINE_CHROMIUM_FLAGS": "--no-sandbox"}
    subprocess.run([xvfb, "-a", "-s", "-screen 0 1280x1024x24", freecad, str(macro)], env=env, timeout=300,
                   capture_output=True)
    return path if path.exists() else None


def freecad_reads(folder: Path) -> str | None:
    freecad = shutil.which("freecadcmd")
    if freecad is None:
        return None
    script = folder / "read.py"
    script.write_text("import Part\n"
                      f"s = Part.read({str(folder / 'cam.step')!r})\n"
                      "print('FreeCAD:', s.ShapeType, 'valid' if s.isValid() else 'NOT valid', len(s.Faces), 'faces,',"
                      " 'volume %.3f mm3,' % s.Volume, 'box', s.BoundBox)\n")
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300)
    return next((line for line in done.stdout.splitlines() if line.startswith("FreeCAD:")), done.stdout[-500:])


def main() -> None:
    IMG.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        run(folder)
        print("wrote", toolpath_figure(folder))
        print("wrote", freecad_picture(folder) or "nothing: FreeCAD or Xvfb is not installed")
        print(freecad_reads(folder) or "freecadcmd not installed")


if __name__ == "__main__":
    main()
