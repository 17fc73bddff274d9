"""The built-in default design and the default design criteria, in one place.

`camcad profile` with no argument synthesises this cam: a 25 mm lift, cycloidal rise over
120°, far dwell 60°, 3-4-5 polynomial return over 120°, near dwell 60°, on a translating
roller follower with Rb = 50 mm, Rr = 10 mm and no offset. Its peak pressure angles are
about 18° on the rise and 17° on the return, well inside the limits below.
"""

from __future__ import annotations

DEFAULT_NAME = "default"

# law (deg, mm)
DEFAULT_PHASES_DEG = (("rise", 120.0), ("dwell", 60.0), ("return", 120.0), ("dwell", 60.0))
DEFAULT_LIFT_MM = 25.0
DEFAULT_RISE_SHAPE = "cycloidal"
DEFAULT_RETURN_SHAPE = "poly345"

# follower (mm)
DEFAULT_BASE_RADIUS_MM = 50.0
DEFAULT_ROLLER_RADIUS_MM = 10.0
DEFAULT_OFFSET_MM = 0.0

# design criteria (deg). 30° on the working stroke is the customary limit for a translating
# roller follower (Norton, Cam Design and Manufacturing Handbook, 2009, chapter on cam size;
# Rothbart, Cam Design Handbook, 2004). The return of a force-closed follower is driven by
# its spring, so a larger angle (here 45°) is usually allowed on that phase.
PRESSURE_ANGLE_LIMIT_RISE_DEG = 30.0
PRESSURE_ANGLE_LIMIT_RETURN_DEG = 45.0

# output
CHORD_TOLERANCE_MM = 0.001
CSV_STEP_DEG = 0.5
