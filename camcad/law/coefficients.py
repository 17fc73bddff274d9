"""The dimensionless peak coefficients of a normalised rise: C_v, C_a, C_j and whether the acceleration jumps.

A rise of lift h over the angle β with the normalised shape f(u) has v_max = C_v h/β, a_max = C_a h/β²,
j_max = C_j h/β³ (R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class PeakCoefficients:
    """Dimensionless peaks of a rise: v_max = Cv h/β, a_max = Ca h/β², j_max = Cj h/β³.

    ``cj`` is sup |f'''| over the smooth pieces; ``acceleration_jumps`` is True when f''
    jumps inside (0, 1) or is non-zero at u = 0 or u = 1 (a jump against a dwell).
    """

    cv: float
    ca: float
    cj: float
    acceleration_jumps: bool

    @property
    def jerk(self) -> float:
        """The true peak jerk coefficient: +inf where the acceleration jumps (the jerk has a Dirac there),
        else ``cj``. ``cj`` itself is the sup over the smooth pieces, as the published tables give it."""
        return math.inf if self.acceleration_jumps else self.cj

    def to_dict(self) -> dict:
        """JSON form: ``cj`` is null when the jerk is infinite, with ``jerk_infinite`` saying so and
        ``cj_smooth`` the sup over the smooth pieces."""
        return {"cv": self.cv, "ca": self.ca, "cj": None if self.acceleration_jumps else self.cj,
                "cj_smooth": self.cj, "jerk_infinite": self.acceleration_jumps,
                "acceleration_jumps": self.acceleration_jumps}
