"""docs/examples/api_walkthrough.py runs with only ``import camcad`` and prints figures that agree with
closed forms and published values computed here, independently of the script and of camcad."""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "docs" / "examples" / "api_walkthrough.py"


@pytest.fixture(scope="module")
def printed(tmp_path_factory) -> str:
    text = SCRIPT.read_text(encoding="utf-8")
    assert "from camcad." not in text
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path_factory.mktemp("walk"))], capture_output=True,
                          text=True, timeout=300, env=env, cwd=ROOT, check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout


def number(text: str, pattern: str) -> float:
    found = re.search(pattern, text)
    assert found, pattern
    return float(found.group(1))


def test_every_group_of_the_api_is_shown(printed):
    groups = re.findall(r"^== (\w+)$", printed, flags=re.MULTILINE)
    assert groups == ["laws", "balance", "profile", "fourier", "dynamics", "contact", "cyclogram", "scenes",
                      "plots", "errors"]


def test_laws_and_profile_figures(printed):
    # Norton (2009): cycloidal Cv = 2, Ca = 2π
    assert number(printed, r"Cv = ([\d.]+)") == pytest.approx(2.0, abs=1e-6)
    assert number(printed, r"Ca = ([\d.]+)") == pytest.approx(2.0 * math.pi, abs=1e-6)
    # flat face on the harmonic law: s + a = h/2, so Rb = rho_min - h/2
    assert number(printed, r"Rb >= ([\d.]+) mm") == pytest.approx(25.0 - 10.0, abs=1e-8)
    # the pressure angle at its peak, tan φ = v/(Rp + s) with v, s of a cycloidal rise written out here
    h, beta, rp = 20.0, math.pi / 2.0, 50.0
    best = 0.0
    for i in range(1, 200_000):
        u = i / 200_000
        s = h * (u - math.sin(2 * math.pi * u) / (2 * math.pi))
        v = h * (1 - math.cos(2 * math.pi * u)) / beta
        best = max(best, math.degrees(math.atan(v / (rp + s))))
    assert number(printed, r"pressure angle max ([\d.]+) deg") == pytest.approx(best, abs=1e-5)


def test_fourier_dynamics_contact_cyclogram_figures(printed):
    assert number(printed, r"mean ([\d.]+) mm") == pytest.approx(10.0, abs=1e-9)
    assert number(printed, r"A1 ([\d.]+) mm") == pytest.approx(10.0, abs=1e-9)
    assert number(printed, r"phase (-[\d.]+) deg") == pytest.approx(-90.0, abs=1e-6)
    assert "resonant [15, 16, 17, 18, 19, 20, 21]" in printed          # 60·100·0.95/400 = 14.25, 60·100·1.05/300 = 21
    r = 0.4
    assert number(printed, r"peak acceleration ratio ([\d.]+)") == pytest.approx(1.0 / (1.0 - r * r), rel=1e-8)
    r = 2.5
    closed = 20.0 * abs(math.sin(math.pi * r)) / (math.pi * r * (r * r - 1.0))
    assert number(printed, r"residual vibration after the rise ([\d.]+) mm") == pytest.approx(closed, rel=1e-8)
    assert number(printed, r"ratio ([\d.]+) \(the speed ratio") == pytest.approx(420.0 / 280.0, rel=1e-9)
    e_star = 2.1e5 / (2.0 * (1.0 - 0.3**2))
    sigma = math.sqrt(1000.0 * e_star / (math.pi * 10.0 * (20.0 * 10.0 / 30.0)))
    assert number(printed, r"sigma_H ([\d.]+) MPa") == pytest.approx(sigma, abs=0.05)
    assert number(printed, r"makespan ([\d.]+) deg") == pytest.approx(100.0, abs=1e-6)


def test_published_impact_figures_of_the_shuttle_scene(printed):
    # Podgorny et al. (2018): F = 4.137 N and a first rebound of 0.07 mm at 280 rpm
    assert number(printed, r"impact force at 280 rpm ([\d.]+) N") == pytest.approx(4.137, abs=0.001)
    assert number(printed, r"first rebound ([\d.]+) mm") == pytest.approx(0.07, abs=0.001)


def test_balance_and_errors(printed):
    assert "drawn law balanced: False" in printed
    assert "after min-change: balanced True" in printed
    assert re.search(r"^CamcadError: follower: offset \|e\| = 60 mm", printed, flags=re.MULTILINE)
