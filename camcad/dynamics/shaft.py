"""Several cams on one elastic main shaft: the shaft's torsion distorts every follower's law.

Podgorny et al. (2018) recall their earlier model of the loom's group of cam mechanisms "with redundant
coordinates", which "reveals the distortions of the driven links' ideal kinematic functions caused by the
torsional vibration of the main shaft". Here the main shaft is driven at one end at a constant speed (the
motor and flywheel: φ0 = ωt) and carries N cams at stations along it; between station k − 1 and k the shaft
has torsional stiffness c_k (N·m/rad) and damping b_k. Cam k (inertia J_k, angle φ_k) drives its follower
chain as in ``camcad.dynamics.multimass`` (the law Π_k at the cam's own angle, chain stiffness c2_k, damping
b2_k, driven mass m_k, coordinate q_k). Lagrange's equations (T = Σ ½J_k φ̇_k² + ½m_k q̇_k²,
V = Σ ½c_k (φ_{k−1} − φ_k)² + ½c2_k (Π_k(φ_k) − q_k)²):

    J_k φ̈_k = M_k − M_{k+1} − Π_k'(φ_k) F_k,      M_k = c_k (φ_{k−1} − φ_k) + b_k (φ̇_{k−1} − φ̇_k)
    m_k q̈_k = F_k,                                 F_k = c2_k (Π_k − q_k) + b2_k (Π_k' φ̇_k − q̇_k)

(M_{N+1} = 0: the shaft ends at the last cam). The coordinates are redundant in the source's sense: every
cam has its own angle, so the law each follower actually gets is Π_k(φ_k(t)), not Π_k(ωt). Per cam:

- the shaft's twist at the cam, ωt − φ_k (deg, the cam lagging the drive > 0);
- the law's distortion by the twist, s_k(φ_k) − s_k(ωt) (law units): the follower's kinematic function at
  the twisted cam angle, what a rigid follower would do;
- the whole dynamic error q_k/scale − s_k(ωt): the twist and the chain's own elasticity.

With one cam this is ``multimass.simulate`` with a speed drive (tested against it). The model runs only
when the scene gives the shaft's stiffness ("model only what a scene needs"). Units: SI inside (kg·m²,
N·m/rad, N/m, s); the law's displacement scaled by ``position_scale`` (1e-3 for mm → m, 1 for rad).

References
----------
Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54 (the redundant-coordinate model of the group);
I. I. Vulfson, Dynamics of Cyclic Machines, Springer (2015), ch. 3–4 (cams on an elastic main shaft).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw


@dataclass(frozen=True)
class ShaftCam:
    """One cam on the shaft and its follower chain.

    Parameters
    ----------
    name : str
        The mechanism's name (no unit).
    law : MotionLaw
        Its law (θ rad; s in mm or rad of swing).
    cam_inertia_kg_m2 : float
        J_k of the cam and its hub, kg·m².
    follower : ElasticFollower
        The chain: natural frequency (Hz), damping ratio, ``mass_kg`` (kg, or kg·m² for a law in rad).
    position_scale : float
        Output units per law unit (dimensionless: 1e-3 for mm → m, 1.0 for rad).

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> cam = ShaftCam("a", law, 0.01, camcad.ElasticFollower(80.0, 0.05, 1.0))
    >>> round(cam.chain_stiffness)      # c2 = m (2π fn)², N/m
    252662
    """

    name: str
    law: MotionLaw
    cam_inertia_kg_m2: float
    follower: ElasticFollower
    position_scale: float = 1e-3

    @property
    def chain_stiffness(self) -> float:
        """c2 = m ωn², N/m (N·m/rad for a law in rad)."""
        if self.follower.mass_kg is None:
            raise CamcadError(f"cam {self.name}: the chain needs its mass", "[shaft]", "give mass_kg in [dynamics]")
        return self.follower.mass_kg * self.follower.omega_n**2

    @property
    def chain_damping(self) -> float:
        """b2 = 2ζ√(c2 m), N·s/m."""
        return 2.0 * self.follower.damping_ratio * math.sqrt(self.chain_stiffness * float(self.follower.mass_kg or 0.0))


@dataclass(frozen=True)
class ElasticShaft:
    """The main shaft: its cams in order from the driven end and the torsional stiffness of each segment.

    Parameters
    ----------
    cams : tuple of ShaftCam
        The cams, in order from the drive.
    stiffness_n_m_per_rad : tuple of float
        c_k of the segment before cam k (from the drive, or the previous cam), N·m/rad.
    damping_ratio : float
        ζ of each segment (dimensionless), b_k = 2ζ√(c_k J_k).

    Examples
    --------
    One cam of 0.01 kg·m² on a 10⁴ N·m/rad shaft: the shaft alone rings at √(c/J)/(2π) = 159.155 Hz:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> cam = ShaftCam("a", law, 0.01, camcad.ElasticFollower(80.0, 0.05, 1.0))
    >>> [round(f, 3) for f in ElasticShaft((cam,), (1e4,)).torsional_frequencies_hz()]
    [159.155]
    """

    cams: tuple[ShaftCam, ...]
    stiffness_n_m_per_rad: tuple[float, ...]
    damping_ratio: float = 0.0

    def __post_init__(self) -> None:
        if not self.cams or len(self.cams) != len(self.stiffness_n_m_per_rad):
            raise CamcadError(f"{len(self.cams)} cams need as many shaft stiffnesses, got "
                              f"{len(self.stiffness_n_m_per_rad)}", "[shaft]",
                              "give stiffness_N_m_per_rad: one per segment, from the drive to each cam in turn")

    def segment_damping(self) -> np.ndarray:
        """b_k = 2ζ√(c_k J_k), N·m·s/rad."""
        return np.array([2.0 * self.damping_ratio * math.sqrt(c * cam.cam_inertia_kg_m2)
                         for c, cam in zip(self.stiffness_n_m_per_rad, self.cams)])

    def torsional_frequencies_hz(self) -> list[float]:
        """The shaft's own natural frequencies with the cams as its inertias and the drive held (Hz): the
        eigenvalues of J⁻¹K of the torsional chain, the followers left off."""
        n = len(self.cams)
        stiff = np.zeros((n, n))
        for k, c in enumerate(self.stiffness_n_m_per_rad):
            stiff[k, k] += c
            if k > 0:
                stiff[k - 1, k - 1] += c
                stiff[k - 1, k] -= c
                stiff[k, k - 1] -= c
        inertia = np.array([cam.cam_inertia_kg_m2 for cam in self.cams])
        scaled = stiff / np.sqrt(np.outer(inertia, inertia))
        return sorted(float(math.sqrt(max(w, 0.0)) / (2.0 * math.pi)) for w in np.linalg.eigvalsh(scaled))


@dataclass(frozen=True)
class ShaftResult:
    """The shaft and its followers over ``time`` (s), each row one cam: cam angles ``phi`` (rad), their
    rates, the followers' ``q`` (output units) and rates, ``ddq`` (output units/s²), the drive angle
    ``drive`` = ωt (rad)."""

    shaft: ElasticShaft
    rpm: float
    time: np.ndarray
    drive: np.ndarray
    phi: np.ndarray
    dphi: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray

    def twist_deg(self, k: int) -> np.ndarray:
        """ωt − φ_k, deg (the cam lags the drive > 0)."""
        return np.degrees(self.drive - self.phi[k])

    def twist_distortion(self, k: int) -> np.ndarray:
        """s_k(φ_k) − s_k(ωt): the law at the twisted cam angle against the ideal, law units."""
        law = self.shaft.cams[k].law
        return law.kinematics(self.phi[k]).s - law.kinematics(self.drive).s

    def dynamic_error(self, k: int) -> np.ndarray:
        """q_k/scale − s_k(ωt): the follower against the ideal law, law units (the twist and the chain)."""
        cam = self.shaft.cams[k]
        return self.q[k] / cam.position_scale - cam.law.kinematics(self.drive).s

    def accel_ratio(self, k: int) -> float:
        """max|q̈_k| / max|s̈_k at ωt| (elastic over rigid), dimensionless."""
        cam = self.shaft.cams[k]
        omega = rpm_to_rad_s(self.rpm)
        rigid = np.max(np.abs(cam.law.kinematics(self.drive).a)) * omega**2 * cam.position_scale
        return float(np.max(np.abs(self.ddq[k])) / rigid) if rigid > 0 else math.nan

    def summary(self) -> list[dict]:
        """Per cam: the largest twist (deg), the law's largest distortion by the twist and the whole dynamic
        error (law units), the peak acceleration ratio, over the samples kept."""
        out = []
        for k, cam in enumerate(self.shaft.cams):
            twist = self.twist_deg(k)
            distortion = self.twist_distortion(k)
            error = self.dynamic_error(k)
            out.append({"mechanism": cam.name, "twist_max_deg": float(np.max(np.abs(twist))),
                        "twist_mean_deg": float(np.mean(twist)),
                        "law_distortion_max": float(np.max(np.abs(distortion))),
                        "dynamic_error_max": float(np.max(np.abs(error))),
                        "peak_accel_ratio": self.accel_ratio(k)})
        return out


def simulate_shaft(shaft: ElasticShaft, rpm: float, *, revolutions: float = 3.0, keep: float = 1.0,
                   samples: int = 2048, method: str = "DOP853", rtol: float = 1e-9,
                   initial: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None) -> ShaftResult:
    """March the shaft and its followers (module docstring) with solve_ivp; keep the last ``keep`` turns.

    Parameters
    ----------
    shaft : ElasticShaft
        Cams (kg·m²), chains (Hz, kg), segment stiffnesses (N·m/rad).
    rpm : float
        The drive's speed, rpm.
    revolutions : float
        Turns simulated from the rigid start (a count), so that the start's transient can decay.
    keep : float
        The last turns returned (a count, dimensionless).
    samples : int
        Samples per kept turn (a count).
    method : str
        solve_ivp's method ("DOP853", "RK45", "Radau", "BDF", "LSODA").
    rtol : float
        Relative tolerance (dimensionless).
    initial : tuple of arrays, optional
        (φ, φ̇, q, q̇) at t = 0 (rad, rad/s, output units, per s); default: every cam at the drive's angle and
        speed, every follower on its law (the rigid state).

    Returns
    -------
    ShaftResult
        Time (s), drive and cam angles (rad), follower coordinates (output units), their rates.

    Examples
    --------
    A stiff shaft barely twists: one cam of 0.01 kg·m² on 10⁷ N·m/rad under a 1 kg, 80 Hz follower at 100 rpm:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> cam = ShaftCam("a", law, 0.01, camcad.ElasticFollower(80.0, 0.1, 1.0))
    >>> found = simulate_shaft(ElasticShaft((cam,), (1e7,), 0.05), 100.0, revolutions=1.0, samples=256)
    >>> found.summary()[0]["twist_max_deg"] < 1e-3
    True
    """
    from scipy.integrate import solve_ivp

    cams = shaft.cams
    n = len(cams)
    omega = rpm_to_rad_s(rpm)
    stiff = np.asarray(shaft.stiffness_n_m_per_rad, dtype=float)
    damp = shaft.segment_damping()
    inertia = np.array([c.cam_inertia_kg_m2 for c in cams])
    mass = np.array([float(c.follower.mass_kg) if c.follower.mass_kg is not None else math.nan for c in cams])
    if np.any(~np.isfinite(mass)):
        bad = cams[int(np.flatnonzero(~np.isfinite(mass))[0])].name
        raise CamcadError(f"cam {bad}: the follower chain needs its mass", "[shaft]", "give mass_kg in its [dynamics]")
    c2 = np.array([c.chain_stiffness for c in cams])
    b2 = np.array([c.chain_damping for c in cams])
    scale = np.array([c.position_scale for c in cams])
    motion = [getattr(c.law, "motion_at", None) for c in cams]

    def law_at(k: int, angle: float) -> tuple[float, float]:
        fast = motion[k]
        if fast is not None:
            s, v = fast(angle)
            return float(s), float(v)
        kin = cams[k].law.kinematics(np.array([angle]))
        return float(kin.s[0]), float(kin.v[0])

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        phi, q, dphi, dq = y[:n], y[n:2 * n], y[2 * n:3 * n], y[3 * n:]
        upstream = np.concatenate(([omega * t], phi[:-1]))
        upstream_rate = np.concatenate(([omega], dphi[:-1]))
        torque = stiff * (upstream - phi) + damp * (upstream_rate - dphi)          # M_k
        after = np.append(torque[1:], 0.0)                                           # M_{k+1}
        ddphi = np.empty(n)
        ddq = np.empty(n)
        for k in range(n):
            s, v = law_at(k, phi[k])
            pi, dpi = s * scale[k], v * scale[k]
            force = c2[k] * (pi - q[k]) + b2[k] * (dpi * dphi[k] - dq[k])
            ddphi[k] = (torque[k] - after[k] - dpi * force) / inertia[k]
            ddq[k] = force / mass[k]
        return np.concatenate((dphi, dq, ddphi, ddq))

    if initial is None:
        phi0 = np.zeros(n)
        dphi0 = np.full(n, omega)
        q0 = np.array([law_at(k, 0.0)[0] * scale[k] for k in range(n)])
        dq0 = np.array([law_at(k, 0.0)[1] * scale[k] * omega for k in range(n)])
    else:
        phi0, dphi0, q0, dq0 = (np.asarray(a, dtype=float) for a in initial)
    period = 2.0 * math.pi / omega if omega > 0 else 1.0
    end = revolutions * period
    start = max(0.0, end - keep * period)
    time = np.linspace(start, end, max(2, round(samples * (end - start) / period)) + 1)
    sol = solve_ivp(rhs, (0.0, end), np.concatenate((phi0, q0, dphi0, dq0)), method=method, rtol=rtol,
                    atol=rtol * 1e-3, t_eval=time)
    if not sol.success:
        raise CamcadError(f"the shaft's integration failed: {sol.message}", "[shaft]",
                          "loosen rtol or choose another solver")
    rates = np.array([rhs(t, y) for t, y in zip(time, sol.y.T)]).T
    return ShaftResult(shaft, float(rpm), time, omega * time, sol.y[:n], sol.y[2 * n:3 * n], sol.y[n:2 * n],
                       sol.y[3 * n:], rates[3 * n:])
