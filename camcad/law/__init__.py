"""Motion laws: the common interface, drawn (piecewise-linear) laws, standard closed forms, phases."""

from camcad.law.law import Kinematics, MotionLaw, Phase, PiecewiseLinearLaw, integrate_exact, integrate_trapezoid

__all__ = ["Kinematics", "MotionLaw", "Phase", "PiecewiseLinearLaw", "integrate_exact",
           "integrate_trapezoid"]
