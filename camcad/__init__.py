"""camcad: cam mechanism design from drawn acceleration laws.

Units at every interface: cam angle in degrees, lengths in mm, speeds in rpm,
forces in N, stresses in MPa. Inside the library, angles are radians unless a
name ends in ``_deg``.
"""

from camcad.version import __version__ as __version__
