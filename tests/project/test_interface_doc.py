"""docs/INTERFACE.md stays true: its commands, options and JSON keys against the CLI, and its pressure-angle
sign convention against an independent geometric construction.

- Every command and linkage subcommand that `camcad --help` / `camcad linkage --help` lists is named in the
  document, and every `camcad CMD [SUB]` the document names (in code) exists.
- Every option of every command (the click tree `--help` is printed from; hidden options excepted) appears in
  the document, with the exceptions in ``UNDOCUMENTED`` (none).
- The keys listed between ``<!-- keys: profile -->`` / ``<!-- keys: check -->`` and ``<!-- /keys -->`` are in
  the real `--json` output of `camcad profile` (built-in default, --no-plots) and `camcad check` (samples).
- The pressure angle: the cam is turned by hand, the roller centre placed from the pivot, the arm and the
  swing (or on the translating axis), the common normal taken from the roller-centre path in the cam's frame
  (numerical derivative), the follower point's velocity from its own motion; φ is the angle between the two,
  signed as INTERFACE.md states (positive when the normal is turned from the outward direction of motion in the
  sense the cam turns). camcad's ``CamGeometry.pressure_angle`` must agree to ``TOL_RAD`` for both turning
  senses, rise and return (positive and negative swing velocity), dwells, and the second roller of a pair.
  No formula of camcad's is reused: the base-circle arm angle is found by bisection, derivatives by finite
  differences.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from conftest import ROOT, SAMPLES

DOC = ROOT / "docs" / "INTERFACE.md"
#: options of the CLI that the document need not name (none at present)
UNDOCUMENTED: set[str] = set()
#: agreement of camcad's pressure angle with the independent construction (rad)
TOL_RAD = 1e-8


@pytest.fixture(scope="module")
def doc() -> str:
    return DOC.read_text(encoding="utf-8")


def _code(text: str) -> list[str]:
    """The document's code: inline code spans and the lines of fenced blocks."""
    fenced = re.findall(r"^```[^\n]*\n(.*?)^```", text, flags=re.S | re.M)
    without = re.sub(r"^```[^\n]*\n.*?^```", "", text, flags=re.S | re.M)
    return re.findall(r"`([^`\n]+)`", without) + [line for block in fenced for line in block.splitlines()]


def _mentions(text: str, option: str) -> bool:
    return re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", text) is not None


def _listed(help_text: str) -> list[str]:
    """Names in the 'Commands:' section of a click help page."""
    section = help_text.split("Commands:", 1)[1]
    return re.findall(r"^  ([a-z][\w-]*)\s", section, flags=re.M)


def _command_tree():
    """{"check": click command, ..., "linkage atlas": ...} and the root group."""
    import typer

    from camcad.cli import app, register_all

    register_all()
    root = typer.main.get_command(app)
    tree = {}
    for name, command in root.commands.items():
        if hasattr(command, "commands"):  # the linkage group
            tree[name] = command
            for sub, subcommand in command.commands.items():
                tree[f"{name} {sub}"] = subcommand
        else:
            tree[name] = command
    return root, tree


# --------------------------------------------------------------------------------------------
# commands and options
# --------------------------------------------------------------------------------------------

def test_every_command_is_documented_and_every_documented_command_exists(cli, doc):
    from camcad.cli import COMMANDS

    top = cli("--help")
    assert top.code == 0, top.err
    commands = _listed(top.out)
    assert commands == list(COMMANDS), (commands, list(COMMANDS))
    group = cli("linkage", "--help")
    assert group.code == 0, group.err
    subcommands = _listed(group.out)
    assert {"atlas", "fgen", "analyse", "adjust", "family", "tune"} <= set(subcommands)

    named: set[tuple[str, str | None]] = set()
    for code in _code(doc):
        for first, second in re.findall(r"(?:^|[\s(\[])camcad ([a-z][\w-]*)(?: ([a-z][\w-]*))?", code):
            named.add((first, second if first == "linkage" and second else None))
    named_commands = {first for first, _ in named}
    named_subcommands = {second for first, second in named if second}
    assert named_commands - set(commands) == set(), f"INTERFACE.md names commands camcad lacks: {named_commands}"
    assert named_subcommands - set(subcommands) == set(), f"unknown linkage subcommands: {named_subcommands}"
    assert set(commands) - named_commands == set(), "commands missing from INTERFACE.md"
    assert set(subcommands) - named_subcommands == set(), "linkage subcommands missing from INTERFACE.md"


def test_every_option_of_every_command_is_documented(cli, doc):
    _root, tree = _command_tree()
    assert len(tree) >= 18
    missing = []
    for option in ("--version", "--debug", "-h", "--help"):
        if not _mentions(doc, option):
            missing.append(f"camcad {option}")
    for name, command in tree.items():
        if hasattr(command, "commands"):
            continue
        shown = cli(*name.split(), "--help")
        assert shown.code == 0, shown.err
        for param in command.params:
            if param.param_type_name != "option" or getattr(param, "hidden", False):
                continue
            for option in [*param.opts, *param.secondary_opts]:
                # the option is what --help shows (the tree is the one the help is printed from) ...
                assert _mentions(shown.out, option), (name, option)
                # ... and the document names it
                if option not in UNDOCUMENTED and not _mentions(doc, option):
                    missing.append(f"camcad {name} {option}")
    assert not missing, "options missing from docs/INTERFACE.md: " + ", ".join(missing)


# --------------------------------------------------------------------------------------------
# JSON keys
# --------------------------------------------------------------------------------------------

def _documented_keys(doc: str, block: str) -> list[str]:
    match = re.search(rf"<!-- keys: {block} -->\n(.*?)<!-- /keys -->", doc, flags=re.S)
    assert match, f"no keys block {block!r} in INTERFACE.md"
    keys = []
    for line in match.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if not line.startswith("|") or set(cells[0]) <= set("-: ") or cells[0] == "key":
            continue
        keys.extend(re.findall(r"`([^`]+)`", cells[0]))
    return keys


def _missing(payload, path: str) -> list[str]:
    """The parts of ``path`` (dots; ``*`` = every member of a dict or list) absent from ``payload``."""
    def walk(node, parts, where):
        if not parts:
            return []
        head, rest = parts[0], parts[1:]
        if head == "*":
            members = list(node.values()) if isinstance(node, dict) else node if isinstance(node, list) else None
            if not members:
                return [f"{where}.* (no members)"]
            return [m for index, member in enumerate(members) for m in walk(member, rest, f"{where}[{index}]")]
        if not isinstance(node, dict) or head not in node:
            return [f"{where}.{head}"]
        return walk(node[head], rest, f"{where}.{head}")

    return walk(payload, path.split("."), "")


def test_documented_profile_keys_are_in_the_real_output(cli, doc, tmp_path):
    keys = _documented_keys(doc, "profile")
    assert len(keys) >= 60, keys
    result = cli("profile", "--no-plots", "-o", tmp_path / "out", "--json")
    assert result.code == 0, result.err
    payload = result.json()
    missing = [m for key in keys for m in _missing(payload, key)]
    assert not missing, missing
    # the written report.json is the same object
    assert json.loads((tmp_path / "out" / "report.json").read_text()).keys() == payload.keys()
    # the check objects carry the fields section 4 names
    for check in payload["checks"].values():
        assert {"value", "limit", "margin", "margin_ratio", "unit", "sense", "passed", "why"} <= set(check)


@pytest.mark.parametrize("sample, code", [("balanced_drdr_cycloidal.dxf", 0), ("fig2_rise_area_too_large.dxf", 1)])
def test_documented_check_keys_are_in_the_real_output(cli, doc, sample, code):
    keys = _documented_keys(doc, "check")
    assert len(keys) >= 15, keys
    result = cli("check", SAMPLES / "dxf" / sample, "--json")
    assert result.code == code, result.err
    payload = result.json()
    missing = [m for key in keys for m in _missing(payload, key)]
    assert not missing, missing


# --------------------------------------------------------------------------------------------
# the pressure-angle sign, independently
# --------------------------------------------------------------------------------------------

SWING = math.radians(20.0)        # ψ of the oscillating law, rad
LIFT = 20.0                       # s of the translating law, mm
#: test angles (deg), away from the phase boundaries 0, 100, 180, 300: rise (ψ' > 0), far dwell,
#: return (ψ' < 0), near dwell
RISE, FAR, RETURN, NEAR = (20.0, 50.0, 77.0), (140.0,), (200.0, 240.0, 290.0), (330.0,)
THETAS = RISE + FAR + RETURN + NEAR


def _law(lift: float):
    import camcad

    return camcad.compose([("rise", 100.0), ("dwell", 80.0), ("return", 120.0), ("dwell", 60.0)], lift,
                          "cycloidal", "poly345")


def _motion(theta_deg: float, lift: float) -> float:
    """The same law written out: cycloidal rise 0-100 deg, dwell, 3-4-5 return 180-300 deg, dwell."""
    t = theta_deg % 360.0
    if t < 100.0:
        u = t / 100.0
        return lift * (u - math.sin(2.0 * math.pi * u) / (2.0 * math.pi))
    if t < 180.0:
        return lift
    if t < 300.0:
        u = (t - 180.0) / 120.0
        return lift * (1.0 - (10.0 * u**3 - 15.0 * u**4 + 6.0 * u**5))
    return 0.0


def _turn(angle: float, p: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


def _derivative(f, x: float, h: float) -> np.ndarray:
    """Five-point central difference."""
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)


def _bisect(f, a: float, b: float) -> float:
    fa = f(a)
    for _ in range(200):
        m = 0.5 * (a + b)
        fm = f(m)
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
    return 0.5 * (a + b)


def independent_pressure_angle(point, coordinate, theta_deg: float, sigma: float) -> float:
    """φ (rad) by construction, signed as INTERFACE.md states.

    ``point(q)``: the roller centre (fixed frame, mm) at follower coordinate q (ψ or s);
    ``coordinate(theta_deg)``: q at the cam angle. The cam has turned by σθ, so the roller centre in the
    cam's frame is R(−σθ)·B; the common normal is normal to that path (the pitch curve), pointing away
    from the cam centre, turned back into the fixed frame. The follower point moves along dB/dq: its
    velocity where it moves, the direction it can move in a dwell; u is that line's sense in which the
    point moves away from the cam centre.
    """
    h = 1e-3  # deg

    def cam_frame(td: float) -> np.ndarray:
        return _turn(-sigma * math.radians(td), point(coordinate(td)))

    tangent = _derivative(cam_frame, theta_deg, h)
    normal = np.array([tangent[1], -tangent[0]]) / np.linalg.norm(tangent)
    if normal @ cam_frame(theta_deg) < 0.0:
        normal = -normal
    normal = _turn(sigma * math.radians(theta_deg), normal)  # back into the fixed frame

    velocity = _derivative(lambda td: point(coordinate(td)), theta_deg, h)
    q = coordinate(theta_deg)
    path = _derivative(point, q, 1e-6)
    line = velocity if np.linalg.norm(velocity) > 1e-9 * np.linalg.norm(path) else path
    line = line / np.linalg.norm(line)
    eps = 1e-6
    out = line if np.linalg.norm(point(q) + eps * line) > np.linalg.norm(point(q) - eps * line) else -line
    turned = out[0] * normal[1] - out[1] * normal[0]  # > 0: the normal is counter-clockwise of u
    magnitude = math.atan2(abs(turned), abs(float(normal @ out)))  # the acute angle between the two lines
    return math.copysign(magnitude, sigma * turned)


C, L, RB, RR = 120.0, 80.0, 45.0, 12.0   # pivot distance, arm, base radius, roller radius (mm)
PAIR = 100.0                              # angle between the two arms of a conjugate pair (deg)


@pytest.mark.parametrize("cw", [False, True], ids=["ccw", "cw"])
@pytest.mark.parametrize("second", [False, True], ids=["main roller", "second roller"])
def test_oscillating_pressure_angle_sign_against_an_independent_construction(cw, second):
    from camcad.profile.followers import Follower
    from camcad.profile.geometry import CamGeometry

    law = _law(SWING)
    theta = np.radians(THETAS)
    # the law camcad uses is the one written out here (positions only)
    assert np.allclose(law.kinematics(theta).s, [_motion(t, SWING) for t in THETAS], rtol=0, atol=1e-13)

    sigma = -1.0 if cw else 1.0
    rp = RB + RR

    def centre(gamma: float) -> np.ndarray:  # B = A + L(−cos γ, sin γ), A = (C, 0): INTERFACE.md section 1
        return np.array([C - L * math.cos(gamma), L * math.sin(gamma)])

    gamma0 = _bisect(lambda g: np.linalg.norm(centre(g)) - rp, 1e-9, math.pi - 1e-9)   # roller on the base circle
    turn = math.radians(PAIR) if second else 0.0

    expected = np.array([independent_pressure_angle(lambda psi: centre(gamma0 + psi - turn),
                                                    lambda td: _motion(td, SWING), t, sigma) for t in THETAS])
    follower = Follower("oscillating", base_radius=RB, roller_radius=RR, pivot=C, arm=L, cw=cw,
                        pair_angle_deg=PAIR if second else None)
    got = CamGeometry(law, follower).pressure_angle(theta, second=second)
    assert np.max(np.abs(got - expected)) < TOL_RAD, (np.degrees(got), np.degrees(expected))

    # the closed form INTERFACE.md states: φ = atan((Lψ′ − σ(C cos γ − L)) / (C sin γ))
    for t, phi in zip(THETAS, expected):
        gamma = gamma0 + _motion(t, SWING) - turn
        dpsi = float(_derivative(lambda td: _motion(td, SWING), t, 1e-3)) * 180.0 / math.pi   # rad/rad
        stated = math.atan((L * dpsi - sigma * (C * math.cos(gamma) - L)) / (C * math.sin(gamma)))
        assert abs(stated - phi) < TOL_RAD, (t, stated, phi)

    # dwells: φ_dwell = −σ·atan((C cos γ − L)/(C sin γ)) changes sign with the turning sense
    for t, phi in zip(THETAS, expected):
        if t in FAR + NEAR:
            gamma = gamma0 + _motion(t, SWING) - turn
            assert abs(phi + sigma * math.atan((C * math.cos(gamma) - L) / (C * math.sin(gamma)))) < TOL_RAD


@pytest.mark.parametrize("cw", [False, True], ids=["ccw", "cw"])
@pytest.mark.parametrize("offset", [0.0, 12.0, -12.0])
@pytest.mark.parametrize("second", [False, True], ids=["main roller", "second roller"])
def test_translating_pressure_angle_sign_against_an_independent_construction(cw, offset, second):
    from camcad.profile.followers import Follower
    from camcad.profile.geometry import CamGeometry

    law = _law(LIFT)
    theta = np.radians(THETAS)
    sigma = -1.0 if cw else 1.0
    rp = RB + RR
    d = math.sqrt(rp**2 - offset**2)
    shift = 130.0 if second else 0.0   # the second roller 130 mm lower: below the cam centre

    expected = np.array([independent_pressure_angle(lambda s: np.array([offset, d + s - shift]),
                                                    lambda td: _motion(td, LIFT), t, sigma) for t in THETAS])
    follower = Follower("roller", base_radius=RB, roller_radius=RR, offset=offset, cw=cw,
                        pair_distance=shift if second else None)
    got = CamGeometry(law, follower).pressure_angle(theta, second=second)
    assert np.max(np.abs(got - expected)) < TOL_RAD, (np.degrees(got), np.degrees(expected))

    # INTERFACE.md: atan((v − σe)/(d + s − D)); with e = 0 positive while the roller moves away from the centre
    for t, phi in zip(THETAS, expected):
        v = float(_derivative(lambda td: _motion(td, LIFT), t, 1e-3)) * 180.0 / math.pi
        assert abs(math.atan((v - sigma * offset) / (d + _motion(t, LIFT) - shift)) - phi) < TOL_RAD
        if offset == 0.0:
            away = (t in RISE) != second      # the second roller comes back while the first rises
            still = t in FAR + NEAR
            assert (abs(phi) < TOL_RAD) if still else ((phi > 0) == away), (t, phi)


def test_flat_face_pressure_angle_is_zero():
    from camcad.profile.followers import Follower
    from camcad.profile.geometry import CamGeometry

    geometry = CamGeometry(_law(LIFT), Follower("flat", base_radius=RB, offset=7.0))
    assert np.all(geometry.pressure_angle(np.radians(THETAS)) == 0.0)


def test_the_oscillating_example_of_the_document(doc):
    """The table of INTERFACE.md section 1 (camcad profile --follower oscillating --pivot 120 --arm 80
    --swing 20: the default law scaled to a 20 deg swing, Rb 50, Rr 10) against camcad's geometry."""
    import camcad
    from camcad.profile.followers import Follower
    from camcad.profile.geometry import CamGeometry

    law = camcad.compose([("rise", 120.0), ("dwell", 60.0), ("return", 120.0), ("dwell", 60.0)], math.radians(20.0),
                         "cycloidal", "poly345")
    rows = {0.0: (-27.280, 27.280), 60.0: (8.044, 31.296), 180.0: (-1.832, 1.832)}
    for cw, column in ((False, 0), (True, 1)):
        geometry = CamGeometry(law, Follower("oscillating", base_radius=50.0, roller_radius=10.0, pivot=120.0,
                                             arm=80.0, cw=cw))
        for t, values in rows.items():
            phi = math.degrees(float(geometry.pressure_angle(np.radians([t]))[0]))
            assert round(phi, 3) == values[column], (t, cw, phi)
            text = f"{values[column]:+.3f}".replace("-", "−")   # the document writes a minus sign
            assert text in doc, text
