"""Fair peers for ``camcad bench``: the best straightforward use of the tool a user would pick for each job.

Nothing here imports camcad; each peer gets the same input as camcad and its error is measured against the
same independent reference (``camcad.bench.references``).

- ``solve_ivp_sweep``: the steady state over a speed range by ``scipy.integrate.solve_ivp`` with all speeds
  as one vectorised system (RK45 or DOP853): one cycle of the particular and the two homogeneous solutions
  at once gives each speed's cycle map, the periodic start solves a 2×2 system per speed, and one more
  cycle from there gives the response.
- ``paper_loop``: the balance paper's own correction loop written plainly (Dupliak & Kotsiyba 2018): the
  drawn law resampled at a step, integrated by the cumulative trapezoid, one scale factor per condition
  (the last lobe of each motion, the return, the rise) found by the secant method, the conditions taken in
  turn until all close within the tolerance.
- ``mechanism``: the PyPI package ``mechanism`` with the normal-offset fix, in its own virtual environment
  (``peer_python``, ``run_mechanism``; the script is ``camcad/bench/peer_mechanism.py``).
- ``fft_adaptive``: ``numpy.fft.rfft`` of the displacement sampled at M points, M doubled until two
  samplings agree on every amplitude within the tolerance.
- ``csv_reader``: the standard library's ``csv`` module and ``float``.
"""

from __future__ import annotations

import csv
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

TWO_PI = 2.0 * math.pi
PEER_NAME, PEER_VERSION = "mechanism", "1.1.10"
HELPER = Path(__file__).resolve().parent / "peer_mechanism.py"


# =============================================================================================
# Dynamics: solve_ivp over all speeds as one system
# =============================================================================================


def solve_ivp_sweep(accel, fn_hz: float, zeta: float, speeds_rpm, *, method: str = "RK45", rtol: float = 1e-8,
                    grid: int = 256) -> np.ndarray:
    """ÿ (mm/s²) at θ_j = 2πj/grid for every speed (shape (speeds, grid)) of x'' + 2ζρ x' + ρ² x = −a(θ)
    (ρ = ωn/ω, θ-domain; ÿ = −ω²(ρ² x + 2ζρ x')), ``accel(θ)`` the law's a (mm/rad², a function of one
    float); atol = rtol × 1e-3 × max|a|."""
    from scipy.integrate import solve_ivp

    speeds = np.asarray(speeds_rpm, dtype=float)
    omega = TWO_PI * speeds / 60.0
    ratio = TWO_PI * fn_hz / omega
    k, c = ratio**2, 2.0 * zeta * ratio
    count = len(speeds)
    scale = max(abs(accel(t)) for t in np.linspace(0.0, TWO_PI, 721))
    atol = rtol * 1e-3 * scale

    def three(t, z):      # columns: particular (forced, from rest) and the two homogeneous solutions
        z = z.reshape(3, 2, count)
        x, xp = z[:, 0], z[:, 1]
        out = np.empty_like(z)
        out[:, 0] = xp
        out[:, 1] = -k * x - c * xp
        out[0, 1] -= accel(t)
        return out.ravel()

    start = np.zeros((3, 2, count))
    start[1, 0] = 1.0
    start[2, 1] = 1.0
    cycle = solve_ivp(three, (0.0, TWO_PI), start.ravel(), method=method, rtol=rtol, atol=atol)
    end = cycle.y[:, -1].reshape(3, 2, count)
    b = end[0]                                              # (2, speeds)
    monodromy = np.stack((end[1], end[2]), axis=1)          # (2, 2, speeds): columns from the unit starts
    system = np.eye(2)[:, :, None] - monodromy
    z0 = np.linalg.solve(np.moveaxis(system, -1, 0), b.T[:, :, None])[:, :, 0].T

    def one(t, z):
        x, xp = z.reshape(2, count)
        return np.concatenate((xp, -k * x - c * xp - accel(t)))

    theta = TWO_PI * np.arange(grid) / grid
    done = solve_ivp(one, (0.0, TWO_PI), z0.ravel(), method=method, rtol=rtol, atol=atol, t_eval=theta)
    x, xp = done.y.reshape(2, count, grid)
    return -(omega**2)[:, None] * (k[:, None] * x + c[:, None] * xp)


# =============================================================================================
# Balance: the paper's loop, plainly
# =============================================================================================


def paper_loop(x: np.ndarray, a: np.ndarray, motions, rise, knob_ranges, step_deg: float = 0.1,
               tol: float = 1e-5, max_integrations: int = 400) -> dict:
    """Balance the drawn law (x rad, a mm/rad²) by the paper's loop (module docstring).

    ``motions``: the end angle of each motion (rad), where v must be 0; ``rise``: (start, end) of the rise
    whose displacement stays (rad); ``knob_ranges``: per condition (each motion's velocity, the cycle's
    displacement, the rise), the (from, to) angles (rad) of the vertices its knob scales. Returns ``a`` (the
    corrected ordinates at the drawn vertices), ``integrations`` (trapezoid integrations done) and ``lift``.
    """
    cycle = float(x[-1])
    grid = np.unique(np.concatenate((np.arange(0.0, cycle, math.radians(step_deg)), [cycle], list(motions), rise)))
    ends = np.searchsorted(grid, np.array(list(motions)))
    rise_at = np.searchsorted(grid, np.array(rise))
    h = np.diff(grid)

    def integrate(values: np.ndarray) -> np.ndarray:
        sampled = np.interp(grid, x, values)
        v = np.concatenate(([0.0], np.cumsum(h * (sampled[1:] + sampled[:-1]) / 2.0)))
        s = np.concatenate(([0.0], np.cumsum(h * (v[1:] + v[:-1]) / 2.0)))
        return np.concatenate((v[ends], [s[-1], s[rise_at[1]] - s[rise_at[0]]]))

    knobs = [((x >= lo) & (x <= hi)).astype(float) for lo, hi in knob_ranges]
    first = integrate(a)
    lift = first[-1]
    target = np.zeros(len(first))
    target[-1] = lift
    limit = tol * abs(lift)
    values, count = a.copy(), 1
    while count < max_integrations:
        residual = integrate(values) - target
        count += 1
        if np.all(np.abs(residual) <= limit):
            return {"a": values, "integrations": count, "lift": lift}
        for i, knob in enumerate(knobs):
            r0 = residual[i]
            if abs(r0) <= limit:
                continue
            trial = values * (1.0 + 0.01 * knob)
            r1 = integrate(trial)[i] - target[i]
            count += 1
            if r1 == r0:
                continue
            t = -0.01 * r0 / (r1 - r0)          # the secant step (the residual is linear in the scale)
            values = values * (1.0 + t * knob)
            residual = integrate(values) - target
            count += 1
    return {"a": values, "integrations": count, "lift": lift}


# =============================================================================================
# Profiles: the package mechanism, in its own environment
# =============================================================================================


class PeerUnavailable(Exception):
    """The peer could not be installed or run; the message says why."""


def peer_venv() -> Path:
    """Where the peer's virtual environment lives: $CAMCAD_PEER_VENV, else ~/.cache/camcad/peer-mechanism-V."""
    given = os.environ.get("CAMCAD_PEER_VENV")
    if given:
        return Path(given)
    return Path.home() / ".cache" / "camcad" / f"peer-{PEER_NAME}-{PEER_VERSION}"


def _python(venv: Path) -> Path:
    unix = venv / "bin" / "python"
    return unix if unix.exists() or os.name != "nt" else venv / "Scripts" / "python.exe"


def _version(python: Path) -> str | None:
    if not python.exists():
        return None
    probe = subprocess.run([str(python), "-c", f"import importlib.metadata as m; print(m.version({PEER_NAME!r}))"],
                           capture_output=True, text=True, timeout=120)
    return probe.stdout.strip() if probe.returncode == 0 else None


def peer_python(install: bool, timeout_s: float = 900.0) -> Path:
    """The python of the peer's environment; made (``pip install mechanism==1.1.10``) when ``install`` and
    missing. Raises PeerUnavailable saying why."""
    venv = peer_venv()
    python = _python(venv)
    if _version(python) == PEER_VERSION:
        return python
    if not install:
        raise PeerUnavailable(f"{PEER_NAME} {PEER_VERSION} is not installed in {venv} (a full `camcad bench` "
                              "installs it there; or set CAMCAD_PEER_VENV)")
    staging = venv.with_name(f"{venv.name}.tmp-{os.getpid()}")
    shutil.rmtree(staging, ignore_errors=True)
    try:
        made = subprocess.run([sys.executable, "-m", "venv", str(staging)], capture_output=True, text=True,
                              timeout=timeout_s)
        if made.returncode != 0:
            raise PeerUnavailable(f"python -m venv failed: {(made.stderr or made.stdout).strip()[-200:]}")
        pip = subprocess.run([str(_python(staging)), "-m", "pip", "install", "--disable-pip-version-check", "--quiet",
                              f"{PEER_NAME}=={PEER_VERSION}"], capture_output=True, text=True, timeout=timeout_s)
        if pip.returncode != 0:
            raise PeerUnavailable(f"pip install {PEER_NAME}=={PEER_VERSION} failed: {pip.stderr.strip()[-200:]}")
        shutil.rmtree(venv, ignore_errors=True)
        venv.parent.mkdir(parents=True, exist_ok=True)
        os.rename(staging, venv)
    except (OSError, subprocess.TimeoutExpired) as err:
        raise PeerUnavailable(f"cannot build {venv}: {err}") from err
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return _python(venv)


def run_mechanism(python: Path, lift: float, base_radius: float, roller_radius: float, steps, repeats: int) -> dict:
    """The peer script's JSON answer (see ``camcad/bench/peer_mechanism.py``)."""
    settings = {"lift_mm": lift, "base_radius_mm": base_radius, "roller_radius_mm": roller_radius,
                "steps_rad": list(steps), "repeats": repeats}
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("PYTHONPATH", None)
    done = subprocess.run([str(python), str(HELPER)], input=json.dumps(settings), capture_output=True, text=True,
                          timeout=600, env=env)
    if done.returncode != 0:
        raise PeerUnavailable(f"the peer script failed: {done.stderr.strip()[-200:]}")
    return json.loads(done.stdout)


def mechanism_to_camcad_frame(points) -> np.ndarray:
    """The package's points (follower on +x, the point of angle θ at polar angle −θ) turned by +90° into
    camcad's frame (follower on +y): (x, y) → (−y, x)."""
    p = np.asarray(points, dtype=float)
    return np.stack((-p[:, 1], p[:, 0]), axis=-1)


# =============================================================================================
# Fourier and tables
# =============================================================================================


def fft_adaptive(displacement, harmonics: int, tol: float, start: int = 1024, limit: int = 1 << 22) -> dict:
    """A_k = 2|c_k| (k = 1..N) of s sampled at M points (``displacement(θ)``), M doubled until two
    samplings agree within ``tol`` (mm)."""
    previous, samples = None, start
    while True:
        c = np.fft.rfft(displacement(np.arange(samples) * (TWO_PI / samples))) / samples
        amplitudes = 2.0 * np.abs(c[1:harmonics + 1])
        if previous is not None and (np.max(np.abs(amplitudes - previous)) <= tol or samples >= limit):
            return {"amplitudes": amplitudes, "coefficients": c[1:harmonics + 1], "samples": samples}
        previous, samples = amplitudes, samples * 2


def csv_reader(path) -> np.ndarray:
    """Rows of a comma-separated table with one header line, by the ``csv`` module and ``float``."""
    with open(path, newline="") as handle:
        rows = csv.reader(line for line in handle if not line.startswith("#"))
        next(rows)
        return np.array([[float(value) for value in row] for row in rows])
