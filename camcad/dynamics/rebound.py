"""The stop impact against published figures, and why the rebound's speed dependence is what it is.

Podgorny et al. (2018) give, for the shuttle lift of the STB loom on its upper stop, the first rebound
0.022 mm at 177 rpm with a 0.25 mm preload (measured 0.02 mm) and 0.07, 0.078, 0.092, 0.105 mm at 280,
320, 370, 420 rpm, the impact force 4.137…6.2 N at 280…420 rpm, and the natural frequencies 297 Hz free and
768 Hz on the stop (measured 268 and 700 Hz). Their model (``camcad.dynamics.impact``) is linear in the
approach velocity q̇0 = ω0 (eq. 2 of the paper, the Duhamel integral), and ω0 is proportional to the speed
for a given law and preload — so for one set of inputs the rebound is proportional to the speed. The four
points 280–420 rpm are (to 2.6 %); the 177 rpm point is half of that proportion.

This module:

- ``PublishedImpact`` holds published figures (computed and measured) and says which ones a scene was
  calibrated to; ``compare_published`` lists each beside camcad's with its error and role ("calibrated" or
  "validates");
- ``rebound_study`` tries, each with one calibration at the calibration speed, the speed-dependent effects
  the paper's model leaves out — the link's elasticity during the approach (its Fig. 4), a Hertzian contact
  duration τ ∝ v0^(−1/5), a restitution that falls with the impact velocity (k ∝ v0^(−1/4)), a half-sine
  pulse instead of the triangle, a contact that lasts while the cam drives through the preload
  (τ = Δθ/ω) — and the preload each published rebound implies in the paper's own model;
- ``pulse_rebound`` is the one-mass response to a pulse of any of these shapes by numerical integration (a
  second method beside the closed-form triangle of ``camcad.dynamics.impact``).

Units: mm, rpm, N, Hz at the interface; SI inside.

References
----------
Yu. Podgorny, O. Maksimchuk, A. Kirillov, V. Skeeba, "Features of machine cyclogram optimization with the
account of interaction of mechanism links with stops", Obrabotka Metallov 20(1) (2018) 44–54.
K. L. Johnson, Contact Mechanics (1985), §11.4 (Hertzian impact: duration ∝ v^(−1/5)) and §11.5 (the
coefficient of restitution of an elastic–plastic impact, e ∝ v^(−1/4)).
W. Goldsmith, Impact (1960), ch. 4 (pulse shapes: a half-sine for an elastic impact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from camcad.dynamics.impact import StopModel, find_contact, first_rebound, impact_at
from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.dynamics.steady import steady_state
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw

PULSE_SHAPES = ("triangle", "half_sine")
#: the quantities a published figure may be (the unit is in the name)
QUANTITIES = ("rebound_mm", "force_N", "f_free_hz", "f_stop_hz")


@dataclass(frozen=True)
class PublishedFigure:
    """One published figure: ``quantity`` (one of QUANTITIES), its ``value`` (in the quantity's unit), the
    speed ``rpm`` (None for a frequency), ``kind`` "computed" or "measured", and whether the scene was
    ``calibrated`` to it (then it cannot validate)."""

    quantity: str
    value: float
    rpm: float | None = None
    kind: str = "computed"
    calibrated: bool = False

    @property
    def key(self) -> str:
        """"rebound_mm@280", "f_stop_hz", "f_stop_hz (measured)"."""
        text = self.quantity + (f"@{self.rpm:g}" if self.rpm is not None else "")
        return text + (" (measured)" if self.kind == "measured" else "")


@dataclass(frozen=True)
class PublishedImpact:
    """Published figures of a stop impact (``figures``) and where they come from (``source``).

    Parameters
    ----------
    figures : tuple of PublishedFigure
        Rebounds (mm) and forces (N) at speeds (rpm), frequencies (Hz).
    source : str
        The work they are taken from (author, year, title).

    Examples
    --------
    >>> pub = PublishedImpact((PublishedFigure("rebound_mm", 0.07, 280.0, calibrated=True),
    ...                        PublishedFigure("rebound_mm", 0.105, 420.0)), "Podgorny et al. 2018")
    >>> [f.key for f in pub.figures], [f.rpm for f in pub.validating("rebound_mm")]
    (['rebound_mm@280', 'rebound_mm@420'], [420.0])
    """

    figures: tuple[PublishedFigure, ...]
    source: str = ""

    def of(self, quantity: str, kind: str | None = None) -> list[PublishedFigure]:
        return [f for f in self.figures if f.quantity == quantity and (kind is None or f.kind == kind)]

    def validating(self, quantity: str) -> list[PublishedFigure]:
        return [f for f in self.of(quantity) if not f.calibrated]

    @property
    def calibration_rpm(self) -> float | None:
        """The speed of the calibrated rebound (else of the calibrated force), rpm."""
        for quantity in ("rebound_mm", "force_N"):
            for f in self.of(quantity, "computed"):
                if f.calibrated and f.rpm is not None:
                    return f.rpm
        return None


@dataclass(frozen=True)
class Comparison:
    """One published figure beside camcad's: ``error`` = camcad − published (the quantity's unit),
    ``relative`` = error/published; ``role`` "calibrated" (the scene was fitted to it) or "validates"."""

    figure: PublishedFigure
    camcad: float

    @property
    def error(self) -> float:
        return self.camcad - self.figure.value

    @property
    def relative(self) -> float:
        return self.error / self.figure.value

    @property
    def role(self) -> str:
        return "calibrated" if self.figure.calibrated else "validates"

    def to_dict(self) -> dict:
        return {"quantity": self.figure.quantity, "rpm": self.figure.rpm, "kind": self.figure.kind,
                "published": self.figure.value, "camcad": self.camcad, "error": self.error,
                "error_percent": 100.0 * self.relative, "role": self.role}


def compare_published(law: MotionLaw, stop: StopModel, published: PublishedImpact) -> list[Comparison]:
    """Every published figure beside camcad's, computed at its own speed (rpm) with the scene's model.

    Parameters
    ----------
    law : MotionLaw
        The law (θ rad, s mm or rad of swing).
    stop : StopModel
        The lever and its stop (kg, N/m, mm).
    published : PublishedImpact
        The figures (mm, N, Hz; speeds rpm).

    Returns
    -------
    list of Comparison
        In the order of ``published.figures``: camcad's value in the figure's unit (mm, N, Hz), the error
        in that unit and relative (a fraction), the role.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> rows = compare_published(law, stop, PublishedImpact((PublishedFigure("f_free_hz", 100.0),)))
    >>> round(rows[0].camcad, 3), round(100 * rows[0].relative, 3), rows[0].role
    (100.658, 0.658, 'validates')
    """
    contact = None
    rows = []
    for figure in published.figures:
        if figure.quantity == "f_free_hz":
            value = stop.f_free_hz
        elif figure.quantity == "f_stop_hz":
            value = stop.f_stop_hz
        else:
            if figure.rpm is None:
                raise CamcadError(f"published {figure.quantity} without a speed", "[stops.published]",
                                  "give [[rpm, value], ...]")
            contact = contact or find_contact(law, stop.stop, stop.preload_mm, stop.ratio)
            impact = impact_at(law, stop, figure.rpm, contact=contact)
            value = impact.rebound_mm if figure.quantity == "rebound_mm" else impact.force_n
        rows.append(Comparison(figure, float(value)))
    return rows


# --------------------------------------------------------------------------------------------
# The one-mass response to a pulse of any shape (numerical: a second method)
# --------------------------------------------------------------------------------------------

def pulse_force(shape: str, t, impulse_ns: float, duration_s: float) -> np.ndarray:
    """The stop's force (N) at ``t`` (s) for a pulse of impulse S (N·s) lasting ``duration_s`` (2τ):
    "triangle" rising to 2S/D over D/2 and back (the paper's), "half_sine" S·π/(2D)·sin(πt/D)."""
    t = np.asarray(t, dtype=float)
    inside = (t >= 0.0) & (t <= duration_s)
    if shape == "triangle":
        half = 0.5 * duration_s
        force = (impulse_ns / half) * np.clip(np.minimum(t, duration_s - t) / half, 0.0, None)
    elif shape == "half_sine":
        force = impulse_ns * math.pi / (2.0 * duration_s) * np.sin(math.pi * np.clip(t, 0.0, duration_s) / duration_s)
    else:
        raise CamcadError(f"unknown pulse shape {shape!r}", "pulse", f"choose one of {', '.join(PULSE_SHAPES)}")
    return np.where(inside, force, 0.0)


def pulse_rebound(stop: StopModel, approach_velocity_m_s: float, *, duration_s: float | None = None,
                  restitution: float | None = None, shape: str = "triangle", samples: int = 4001) -> float:
    """The first rebound (mm) of the one-mass model on the stop, q̈ + 2ζω q̇ + ω² q = −Q(t)/m from q = 0,
    q̇ = v0, for a pulse of impulse S = m v0 (1 + k) of the given shape lasting ``duration_s`` (default 2τ of
    the model: one period on the stop), by numerical integration (solve_ivp, DOP853, rtol 1e-11) through
    the pulse and the closed-form free vibration after it: the largest −q within the pulse and one period
    after (s, m/s inside; mm out)."""
    from scipy.integrate import solve_ivp

    omega = stop.omega_stop
    zeta = stop.damping_ratio
    k = stop.restitution if restitution is None else restitution
    duration = 2.0 * stop.pulse_s if duration_s is None else duration_s
    impulse = stop.mass_kg * approach_velocity_m_s * (1.0 + k)

    def rhs(t, y):
        return [y[1], -2.0 * zeta * omega * y[1] - omega**2 * y[0]
                - float(pulse_force(shape, t, impulse, duration)) / stop.mass_kg]

    step = min(duration, 2.0 * math.pi / omega) / 50.0
    sol = solve_ivp(rhs, (0.0, duration), [0.0, approach_velocity_m_s], method="DOP853", rtol=1e-11,
                    atol=1e-14 * max(1.0, approach_velocity_m_s), dense_output=True, max_step=step)
    during = sol.sol(np.linspace(0.0, duration, samples))[0]
    q_end, v_end = sol.y[:, -1]
    n = zeta * omega
    k1 = omega * math.sqrt(1.0 - zeta**2)
    t = np.linspace(0.0, 2.0 * math.pi / omega, samples)
    after = np.exp(-n * t) * (q_end * np.cos(k1 * t) + (v_end + n * q_end) / k1 * np.sin(k1 * t))
    return max(0.0, -float(min(during.min(), after.min()))) * 1e3


# --------------------------------------------------------------------------------------------
# The study of the speed dependence
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Variant:
    """One model of the rebound against speed, calibrated once (``scale`` × its raw values, fitted at the
    calibration speed): ``values_mm`` and ``errors`` (fractions) at the published speeds (rpm)."""

    name: str
    what: str
    speeds_rpm: tuple[float, ...]
    values_mm: tuple[float, ...]
    published_mm: tuple[float, ...]
    scale: float = 1.0

    @property
    def errors(self) -> tuple[float, ...]:
        return tuple((v - p) / p for v, p in zip(self.values_mm, self.published_mm))

    def to_dict(self) -> dict:
        return {"name": self.name, "what": self.what, "scale": self.scale,
                "rebound_mm": dict(zip((f"{s:g}" for s in self.speeds_rpm), self.values_mm)),
                "error_percent": dict(zip((f"{s:g}" for s in self.speeds_rpm), (100 * e for e in self.errors)))}


@dataclass(frozen=True)
class ReboundStudy:
    """What ``rebound_study`` found: the variants, the preload (mm) each published rebound implies in the
    paper's model (with the calibrated lever), the proportionality of the published points to the speed and
    the conclusion in words."""

    speeds_rpm: tuple[float, ...]
    published_mm: tuple[float, ...]
    calibration_rpm: float
    variants: tuple[Variant, ...]
    implied_preload_mm: dict[float, float | None] = field(default_factory=dict)
    per_rpm_mm: tuple[float, ...] = ()
    conclusion: str = ""

    def to_dict(self) -> dict:
        return {"speeds_rpm": list(self.speeds_rpm), "published_mm": list(self.published_mm),
                "calibration_rpm": self.calibration_rpm,
                "published_per_rpm_mm": list(self.per_rpm_mm),
                "variants": [v.to_dict() for v in self.variants],
                "implied_preload_mm": {f"{k:g}": v for k, v in self.implied_preload_mm.items()},
                "conclusion": self.conclusion}


def elastic_approach(law: MotionLaw, stop: StopModel, rpm: float, natural_frequency_hz: float,
                     damping_ratio: float, samples: int = 1 << 14) -> float:
    """The approach velocity (m/s) of the elastic follower (``ElasticFollower`` at fn, ζ: the link's
    elasticity during the approach, as in the paper's Fig. 4) where its steady-state displacement reaches
    the stop (lift − preload for the upper stop), at ``rpm``."""
    contact = find_contact(law, stop.stop, stop.preload_mm, stop.ratio)
    response = steady_state(law, ElasticFollower(natural_frequency_hz, damping_ratio), rpm, samples=samples)
    theta, y = response.theta, response.displacement_elastic
    phase = contact.phase
    s_end = float(law.kinematics(np.array([phase.end])).s[0])
    target = s_end - stop.preload_mm / stop.ratio if stop.stop == "upper" else s_end + stop.preload_mm / stop.ratio
    inside = np.flatnonzero((theta >= phase.start) & (theta <= phase.end))
    sign = 1.0 if stop.stop == "upper" else -1.0
    reached = inside[sign * (y[inside] - target) >= 0.0]
    if not len(reached):
        return abs(contact.velocity_analog) * rpm_to_rad_s(rpm) * stop.ratio * 1e-3
    i = int(reached[0])
    rate = np.gradient(y, theta)
    # linear interpolation of the velocity analog to the crossing
    j = max(i - 1, 0)
    frac = 0.0 if i == j else float((target - y[j]) / (y[i] - y[j]))
    analog = rate[j] + frac * (rate[i] - rate[j])
    return abs(float(analog)) * rpm_to_rad_s(rpm) * stop.ratio * 1e-3


def implied_preload(law: MotionLaw, stop: StopModel, rpm: float, target_mm: float) -> float | None:
    """The preload (mm at the contact point) at which the paper's model gives the rebound ``target_mm`` at
    ``rpm``: the contact moves along the approach phase, where the law's velocity falls to zero at its end
    (brentq between a vanishing preload and the one where the approach is fastest). None when no preload
    reaches the target."""
    from scipy.optimize import brentq

    contact = find_contact(law, stop.stop, stop.preload_mm, stop.ratio)
    phase = contact.phase
    theta = np.linspace(phase.start, phase.end, 2001)
    kin = law.kinematics(theta)
    s_end = kin.s[-1]
    fastest = int(np.argmax(np.abs(kin.v)))
    deepest = abs(s_end - kin.s[fastest]) * stop.ratio          # preload at the fastest point, mm

    def excess(preload: float) -> float:
        model = replace(stop, preload_mm=preload)
        return impact_at(law, model, rpm).rebound_mm - target_mm

    low = deepest * 1e-9
    try:
        if excess(low) > 0.0 or excess(deepest * (1 - 1e-9)) < 0.0:
            return None
        return float(brentq(excess, low, deepest * (1 - 1e-9), xtol=1e-12))
    except CamcadError:
        return None


def rebound_study(law: MotionLaw, stop: StopModel, published: PublishedImpact, *,
                  follower_hz: float | None = None, follower_damping: float | None = None) -> ReboundStudy:
    """The paper's rebound against speed beside the effects its model leaves out, each calibrated once.

    Each variant (module docstring) is scaled once to the published rebound at the calibration speed and
    compared with the others; the preload each published rebound implies in the paper's own model is found.

    Parameters
    ----------
    law : MotionLaw
        The law (θ rad, s mm or rad of swing).
    stop : StopModel
        The lever and its stop as the scene gives them (kg, N/m, mm).
    published : PublishedImpact
        The published rebounds (mm at rpm); the calibrated one sets the calibration speed.
    follower_hz, follower_damping : float, optional
        The elastic follower for the elastic-approach variant (Hz, dimensionless); default the stop model's
        free frequency and damping ratio.

    Returns
    -------
    ReboundStudy
        Per variant: the rebound (mm) at each published speed (rpm) and its error (a fraction); the implied
        preloads (mm); the conclusion (no unit: words with figures).

    Examples
    --------
    A model linear in the speed cannot give rebounds that are not: 0.02 mm at 100 rpm and 0.08 at 200 rpm
    are 2:1 per rpm; calibrated at 200 rpm the model gives half the rebound at 100 rpm, 0.04 mm (+100 %):

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> pub = PublishedImpact((PublishedFigure("rebound_mm", 0.02, 100.0),
    ...                        PublishedFigure("rebound_mm", 0.08, 200.0, calibrated=True)))
    >>> study = rebound_study(law, stop, pub)
    >>> base = study.variants[0]
    >>> [round(v, 6) for v in base.values_mm], [round(100 * e, 3) for e in base.errors]
    ([0.04, 0.08], [100.0, 0.0])
    """
    figures = sorted(published.of("rebound_mm", "computed"), key=lambda f: f.rpm or 0.0)
    if len(figures) < 2:
        raise CamcadError("the study needs two or more published rebounds", "[stops.published]",
                          "give rebound_mm = [[rpm, mm], ...]")
    speeds = tuple(float(f.rpm or 0.0) for f in figures)
    values = tuple(f.value for f in figures)
    calibration = published.calibration_rpm or speeds[len(speeds) // 2]
    if calibration not in speeds:
        calibration = min(speeds, key=lambda s: abs(s - calibration))
    k_cal = speeds.index(calibration)
    contact = find_contact(law, stop.stop, stop.preload_mm, stop.ratio)

    def v0(rpm: float) -> float:
        return abs(contact.velocity_analog) * rpm_to_rad_s(rpm) * stop.ratio * 1e-3

    tau = stop.pulse_s
    k_ref = stop.restitution
    fn = stop.f_free_hz if follower_hz is None else follower_hz
    zeta = stop.damping_ratio if follower_damping is None else follower_damping
    remaining = abs(contact.phase.end - contact.theta)    # rad of cam angle from contact to the end of the phase
    raw = {
        "paper": ("the paper's model: triangle 2τ = one period on the stop, k constant, rigid approach",
                  [first_rebound(stop, v0(n))[0] * 1e3 for n in speeds]),
        "elastic approach": (f"v0 of the elastic follower ({fn:.4g} Hz, ζ {zeta:.3g}) where it reaches the stop "
                             "(link elasticity during the approach, the paper's Fig. 4)",
                             [first_rebound(stop, elastic_approach(law, stop, n, fn, zeta))[0] * 1e3 for n in speeds]),
        "Hertz duration": ("contact duration τ ∝ v0^(−1/5) (Hertzian impact), τ at the calibration speed as the paper",
                           [pulse_rebound(stop, v0(n), duration_s=2 * tau * (n / calibration) ** -0.2)
                            for n in speeds]),
        "restitution(v)": ("k ∝ v0^(−1/4) (elastic-plastic impact), k = 5/9 at the calibration speed",
                           [pulse_rebound(stop, v0(n), restitution=min(1.0, k_ref * (n / calibration) ** -0.25))
                            for n in speeds]),
        "half-sine pulse": ("a half-sine pulse of the same impulse and duration instead of the triangle",
                            [pulse_rebound(stop, v0(n), shape="half_sine") for n in speeds]),
        "cam-driven contact": ("the contact lasts while the cam drives through the preload, 2τ = Δθ/ω "
                               f"(Δθ = {math.degrees(remaining):.4g} deg)",
                               [pulse_rebound(stop, v0(n), duration_s=remaining / rpm_to_rad_s(n)) for n in speeds]),
    }
    variants = []
    for name, (what, found) in raw.items():
        scale = values[k_cal] / found[k_cal] if found[k_cal] > 0 else float("nan")
        variants.append(Variant(name, what, speeds, tuple(scale * f for f in found), values, scale))
    implied = {n: implied_preload(law, stop, n, v) for n, v in zip(speeds, values)}
    per_rpm = tuple(v / n for v, n in zip(values, speeds))
    study = ReboundStudy(speeds, values, calibration, tuple(variants), implied, per_rpm)
    return replace(study, conclusion=_conclusion(study, stop))


def _conclusion(study: ReboundStudy, stop: StopModel) -> str:
    speeds, per_rpm = study.speeds_rpm, study.per_rpm_mm
    k_cal = study.speeds_rpm.index(study.calibration_rpm)
    ratio = [p / per_rpm[k_cal] for p in per_rpm]
    worst = {v.name: max(abs(e) for e, s in zip(v.errors, speeds) if s != study.calibration_rpm)
             for v in study.variants}
    best = min(worst, key=lambda name: worst[name])
    outliers = [s for s, r in zip(speeds, ratio) if abs(r - 1.0) > 0.1]
    others = [abs(r - 1.0) for s, r in zip(speeds, ratio) if s not in outliers]
    text = (f"Per rpm the published rebounds are {', '.join(f'{r:.3f}' for r in ratio)} of the one at "
            f"{study.calibration_rpm:g} rpm (speeds {', '.join(f'{s:g}' for s in speeds)} rpm): ")
    if outliers:
        text += (f"proportional to the speed within {100 * max(others, default=0.0):.1f} % except at "
                 f"{', '.join(f'{s:g}' for s in outliers)} rpm. ")
    else:
        text += "proportional to the speed within 10 %. "
    text += (f"Every variant is smooth in the speed; calibrated once, the best ({best}) still misses by "
             f"{100 * worst[best]:.0f} % at worst. ")
    implied = {s: p for s, p in study.implied_preload_mm.items() if p is not None}
    if implied:
        text += ("In the paper's own model the published rebounds imply the contact at a preload of "
                 + ", ".join(f"{p:.3g} mm at {s:g} rpm" for s, p in implied.items())
                 + f" (the scene: {stop.preload_mm:g} mm): the outlying point needs other inputs, not another "
                   "speed law.")
    return text
