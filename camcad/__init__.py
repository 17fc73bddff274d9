"""camcad: cam mechanism design from drawn acceleration laws.

The public API, in the order of the main workflow (degrees and mm at the boundary, as at the command line;
a name that takes radians says so)::

    import camcad
    loaded = camcad.load_law("accel.dxf", lift=25.0)            # a drawn law (DXF or table)
    report = camcad.check(loaded.law)                             # area balance
    fixed = camcad.correct(loaded.law, "min-change")              # the least change that balances it
    follower = camcad.Follower("roller", base_radius=50.0, roller_radius=10.0)
    result = camcad.synthesize(fixed.law, follower)               # the cam profile and its checks
    figure = camcad.plot_summary(result)                          # a matplotlib Figure
    camcad.write_outputs(result, "out/")                          # profile.dxf, law.csv, report.json

Laws: ``load_law``, ``compose`` (standard shapes), ``parse_phases``, ``kinematics_deg``. Balance: ``check``,
``correct``, ``write_corrected``. Profile: ``Follower``, ``ProfileSettings``, ``synthesize``, ``profile_report``,
``min_base_radius``, ``write_outputs``. Fourier: ``analyse``, ``resonant_harmonics``, ``filter_law``.
Dynamics: ``ElasticFollower``, ``steady_state``, ``residual_vibration``, ``StopModel``, ``impact_sweep``.
Contact: ``ContactParams``, ``contact_stress``. Cyclogram: ``Operation``, ``make_network``, ``optimise``.
Scenes: ``read_scene``, ``PipelineOptions``, ``analyse_scene``, ``run_scene``. Linkages (Sunkuev 1984): a request in,
a report out (``to_dict()``, ``exit_code``, ``lines()``) — ``run_linkage_atlas`` (``AtlasRequest``),
``run_linkage_fgen`` (``FgenRequest``), ``run_linkage_path`` (``PathRequest``), ``run_linkage_family``
(``FamilyRequest``), ``run_linkage_analyse`` (``AnalyseRequest``), ``run_linkage_adjust`` (``AdjustRequest``),
``run_linkage_tune`` (``TuneRequest``) with ``LinkageSource`` and ``ElementSpec``; ``linkage_command`` runs one and
writes its files. Plots (each returns a Figure):
``plot_summary``, ``plot_kinematics``, ``plot_pressure_angle``, ``plot_curvature``, ``plot_profile``,
``plot_hodograph``.

Every name loads on first use, so ``import camcad`` costs almost nothing (the command line's start-up
depends on it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camcad.lazy import lazy_exports
from camcad.version import __version__ as __version__

if TYPE_CHECKING:  # the names for type checkers and IDEs; at run time they load on first use
    from camcad.balance.checking import BalanceReport, check
    from camcad.balance.correction import Correction, correct
    from camcad.contact import ContactParams, contact_stress
    from camcad.cyclogram.lp import optimise
    from camcad.cyclogram.network import Operation, make_network
    from camcad.dynamics.impact import StopModel, impact_sweep
    from camcad.dynamics.model import ElasticFollower
    from camcad.dynamics.residual import residual_vibration
    from camcad.dynamics.steady import steady_state
    from camcad.errors import CamcadError
    from camcad.fourier.analysis import analyse
    from camcad.fourier.filter import filter_law
    from camcad.fourier.resonance import resonant_harmonics
    from camcad.io.law_write import write_corrected
    from camcad.law.kinematics_deg import kinematics_deg
    from camcad.law.phases import parse_phases
    from camcad.law.source import LoadedLaw, load_law
    from camcad.law.standard import compose
    from camcad.linkage.runners import (
        AtlasRequest,
        FamilyRequest,
        FgenRequest,
        PathRequest,
        run_linkage_atlas,
        run_linkage_family,
        run_linkage_fgen,
        run_linkage_path,
    )
    from camcad.profile.design import min_base_radius
    from camcad.profile.followers import Follower
    from camcad.profile.summary import profile_report
    from camcad.profile.synth import ProfileResult, ProfileSettings, synthesize
    from camcad.report.linkage_commands import linkage_command
    from camcad.report.profile import (
        plot_curvature,
        plot_hodograph,
        plot_kinematics,
        plot_pressure_angle,
        plot_profile,
        plot_summary,
    )
    from camcad.report.profile_files import write_outputs
    from camcad.report.scene import run_scene
    from camcad.scene.file import read_scene
    from camcad.scene.linkage_commands import (
        AdjustRequest,
        AnalyseRequest,
        ElementSpec,
        LinkageSource,
        TuneRequest,
        run_linkage_adjust,
        run_linkage_analyse,
        run_linkage_tune,
    )
    from camcad.scene.pipeline import PipelineOptions, analyse_scene

#: public name -> the module that defines it
_EXPORTS: dict[str, str] = {
    "CamcadError": "camcad.errors",
    "load_law": "camcad.law.source", "LoadedLaw": "camcad.law.source",
    "compose": "camcad.law.standard", "parse_phases": "camcad.law.phases",
    "kinematics_deg": "camcad.law.kinematics_deg",
    "check": "camcad.balance.checking", "BalanceReport": "camcad.balance.checking",
    "correct": "camcad.balance.correction", "Correction": "camcad.balance.correction",
    "write_corrected": "camcad.io.law_write",
    "Follower": "camcad.profile.followers", "ProfileSettings": "camcad.profile.synth",
    "ProfileResult": "camcad.profile.synth", "synthesize": "camcad.profile.synth",
    "profile_report": "camcad.profile.summary",
    "PipelineOptions": "camcad.scene.pipeline", "min_base_radius": "camcad.profile.design",
    "write_outputs": "camcad.report.profile_files",
    "analyse": "camcad.fourier.analysis", "resonant_harmonics": "camcad.fourier.resonance",
    "filter_law": "camcad.fourier.filter",
    "ElasticFollower": "camcad.dynamics.model", "steady_state": "camcad.dynamics.steady",
    "residual_vibration": "camcad.dynamics.residual", "StopModel": "camcad.dynamics.impact",
    "impact_sweep": "camcad.dynamics.impact",
    "ContactParams": "camcad.contact", "contact_stress": "camcad.contact",
    "Operation": "camcad.cyclogram.network", "make_network": "camcad.cyclogram.network",
    "optimise": "camcad.cyclogram.lp",
    "read_scene": "camcad.scene.file", "analyse_scene": "camcad.scene.pipeline", "run_scene": "camcad.report.scene",
    "plot_summary": "camcad.report.profile", "plot_kinematics": "camcad.report.profile",
    "plot_pressure_angle": "camcad.report.profile", "plot_curvature": "camcad.report.profile",
    "plot_profile": "camcad.report.profile", "plot_hodograph": "camcad.report.profile",
    **{name: "camcad.linkage.runners" for name in (
        "AtlasRequest", "FgenRequest", "PathRequest", "FamilyRequest", "run_linkage_atlas", "run_linkage_fgen",
        "run_linkage_path", "run_linkage_family")},
    **{name: "camcad.scene.linkage_commands" for name in (
        "LinkageSource", "ElementSpec", "AnalyseRequest", "AdjustRequest", "TuneRequest", "run_linkage_analyse",
        "run_linkage_adjust", "run_linkage_tune")},
    "linkage_command": "camcad.report.linkage_commands",
}


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


__all__ = [
    "AdjustRequest",
    "AnalyseRequest",
    "AtlasRequest",
    "BalanceReport",
    "CamcadError",
    "ContactParams",
    "Correction",
    "ElasticFollower",
    "ElementSpec",
    "FamilyRequest",
    "FgenRequest",
    "Follower",
    "LinkageSource",
    "LoadedLaw",
    "Operation",
    "PathRequest",
    "PipelineOptions",
    "ProfileResult",
    "ProfileSettings",
    "StopModel",
    "TuneRequest",
    "__version__",
    "analyse",
    "analyse_scene",
    "check",
    "compose",
    "contact_stress",
    "correct",
    "filter_law",
    "impact_sweep",
    "kinematics_deg",
    "linkage_command",
    "load_law",
    "make_network",
    "min_base_radius",
    "optimise",
    "parse_phases",
    "plot_curvature",
    "plot_hodograph",
    "plot_kinematics",
    "plot_pressure_angle",
    "plot_profile",
    "plot_summary",
    "profile_report",
    "read_scene",
    "residual_vibration",
    "resonant_harmonics",
    "run_linkage_adjust",
    "run_linkage_analyse",
    "run_linkage_atlas",
    "run_linkage_family",
    "run_linkage_fgen",
    "run_linkage_path",
    "run_linkage_tune",
    "run_scene",
    "steady_state",
    "synthesize",
    "write_corrected",
    "write_outputs",
]
