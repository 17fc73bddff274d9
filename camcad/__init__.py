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

Laws: ``load_law``, ``compose`` (standard shapes), ``parse_phases``, ``kinematics_deg``, ``motion_law`` and
``radius_to_motion`` (tables of the motion, ``ProfileFollower``), ``LawRecord`` (the phases a written law
carries); designed from scratch:
``solve_segments`` (``SegmentSpec``, ``parse_segments``) and the VDI 2143 catalogue (``catalogue_table``,
``rest_shape``). Balance: ``check``,
``correct``, ``write_corrected``. Profile: ``Follower``, ``ProfileSettings``, ``synthesize`` (``synthesize_many``: many
followers on one law at once), ``profile_report``,
``min_base_radius``, ``write_outputs``. The part: ``ExportSettings``, ``part_files``, ``cutter_paths``,
``contour_program``. Fourier: ``analyse``, ``resonant_harmonics``, ``filter_law``, ``tachogram_phases``,
``synthesise_tachogram``.
Dynamics: ``ElasticFollower``, ``steady_state``, ``residual_vibration``, ``StopModel``, ``impact_sweep``, ``LeverBeam``
(the lever on its stop), ``PublishedImpact``, ``compare_published``, ``rebound_study``; cams on an elastic main
shaft: ``ShaftCam``, ``ElasticShaft``, ``simulate_shaft``; ``harmonic_beats``, ``compare_laws`` (two laws side by
side).
Contact: ``ContactParams``, ``contact_stress``. Drive: ``CamDrive`` (camshaft torque),
``energy_fluctuation`` (flywheel), ``run_drive``/``DriveRequest`` (``camcad drive``), ``servo_table``,
``polydyne_law``. Cyclogram: ``Operation``, ``make_network``, ``optimise``; a machine of
groups: ``Group``, ``make_machine``, ``optimise_machine``.
Scenes: ``read_scene``, ``PipelineOptions``, ``analyse_scene``, ``run_scene``; a design space swept:
``run_sweep``/``SweepRequest`` (``camcad sweep``). Speed against error:
``run_bench``/``BenchRequest`` (``camcad bench``). Linkages (Sunkuev 1984): a request in,
a report out (``to_dict()``, ``exit_code``, ``lines()``) — ``run_linkage_atlas`` (``AtlasRequest``),
``run_linkage_fgen`` (``FgenRequest``), ``run_linkage_path`` (``PathRequest``), ``run_linkage_family``
(``FamilyRequest``), ``run_linkage_analyse`` (``AnalyseRequest``), ``run_linkage_adjust`` (``AdjustRequest``),
``run_linkage_tune`` (``TuneRequest``) with ``LinkageSource`` and ``ElementSpec``; ``linkage_command`` runs one and
writes its files. Plots (each returns a Figure):
``plot_summary``, ``plot_kinematics``, ``plot_pressure_angle``, ``plot_curvature``, ``plot_profile``,
``plot_hodograph``. Handing a design over: ``cam_frames`` (``CamFrames``) and ``mechanism_frames``
(``MechanismFrames``), the mechanism frame by frame; ``animation_html`` (the animation page) and
``design_report_html`` (the report page).

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
    from camcad.cyclogram.machine import Group, make_machine, optimise_machine
    from camcad.cyclogram.network import Operation, make_network
    from camcad.dynamics.beats import harmonic_beats
    from camcad.dynamics.compare import compare_laws
    from camcad.dynamics.flywheel import energy_fluctuation
    from camcad.dynamics.impact import LeverBeam, StopModel, impact_sweep
    from camcad.dynamics.model import ElasticFollower
    from camcad.dynamics.polydyne import polydyne_law
    from camcad.dynamics.rebound import PublishedImpact, compare_published, rebound_study
    from camcad.dynamics.residual import residual_vibration
    from camcad.dynamics.shaft import ElasticShaft, ShaftCam, simulate_shaft
    from camcad.dynamics.steady import steady_state
    from camcad.dynamics.torque import CamDrive
    from camcad.errors import CamcadError
    from camcad.fourier.analysis import analyse
    from camcad.fourier.filter import filter_law
    from camcad.fourier.resonance import resonant_harmonics
    from camcad.fourier.synth import synthesise_tachogram, tachogram_phases
    from camcad.io.law_record import LawRecord
    from camcad.io.law_write import write_corrected
    from camcad.law.kinematics_deg import kinematics_deg
    from camcad.law.motion_table import ProfileFollower, motion_law, radius_to_motion
    from camcad.law.phases import parse_phases
    from camcad.law.segments import SegmentSpec, parse_segments, solve_segments
    from camcad.law.source import LoadedLaw, load_law
    from camcad.law.standard import compose
    from camcad.law.vdi import catalogue_table, rest_shape
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
    from camcad.profile.animation import CamFrames, cam_frames
    from camcad.profile.batch import synthesize_many
    from camcad.profile.design import min_base_radius
    from camcad.profile.followers import Follower
    from camcad.profile.servo import servo_table
    from camcad.profile.summary import profile_report
    from camcad.profile.synth import ProfileResult, ProfileSettings, synthesize
    from camcad.profile.toolpath import contour_program, cutter_paths
    from camcad.report.animation import animation_html
    from camcad.report.bench import BenchRequest, run_bench
    from camcad.report.design_report import design_report_html
    from camcad.report.linkage_commands import linkage_command
    from camcad.report.part_files import part_files
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
    from camcad.report.sweep_command import SweepRequest, run_sweep
    from camcad.scene.animation import MechanismFrames, mechanism_frames
    from camcad.scene.commands.drive import DriveRequest, run_drive
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
    from camcad.scene.sections.export import ExportSettings

#: public name -> the module that defines it
_EXPORTS: dict[str, str] = {
    "CamcadError": "camcad.errors",
    "load_law": "camcad.law.source", "LoadedLaw": "camcad.law.source",
    "compose": "camcad.law.standard", "parse_phases": "camcad.law.phases",
    "kinematics_deg": "camcad.law.kinematics_deg",
    "SegmentSpec": "camcad.law.segments", "solve_segments": "camcad.law.segments",
    "parse_segments": "camcad.law.segments", "catalogue_table": "camcad.law.vdi", "rest_shape": "camcad.law.vdi",
    "motion_law": "camcad.law.motion_table", "radius_to_motion": "camcad.law.motion_table",
    "ProfileFollower": "camcad.law.motion_table", "LawRecord": "camcad.io.law_record",
    "tachogram_phases": "camcad.fourier.synth", "synthesise_tachogram": "camcad.fourier.synth",
    "harmonic_beats": "camcad.dynamics.beats", "compare_laws": "camcad.dynamics.compare",
    "check": "camcad.balance.checking", "BalanceReport": "camcad.balance.checking",
    "correct": "camcad.balance.correction", "Correction": "camcad.balance.correction",
    "write_corrected": "camcad.io.law_write",
    "Follower": "camcad.profile.followers", "ProfileSettings": "camcad.profile.synth",
    "ProfileResult": "camcad.profile.synth", "synthesize": "camcad.profile.synth",
    "profile_report": "camcad.profile.summary", "synthesize_many": "camcad.profile.batch",
    "BenchRequest": "camcad.report.bench", "run_bench": "camcad.report.bench",
    "SweepRequest": "camcad.report.sweep_command", "run_sweep": "camcad.report.sweep_command",
    "PipelineOptions": "camcad.scene.pipeline", "min_base_radius": "camcad.profile.design",
    "write_outputs": "camcad.report.profile_files",
    "ExportSettings": "camcad.scene.sections.export", "part_files": "camcad.report.part_files",
    "cutter_paths": "camcad.profile.toolpath", "contour_program": "camcad.profile.toolpath",
    "analyse": "camcad.fourier.analysis", "resonant_harmonics": "camcad.fourier.resonance",
    "filter_law": "camcad.fourier.filter",
    "ElasticFollower": "camcad.dynamics.model", "steady_state": "camcad.dynamics.steady",
    "residual_vibration": "camcad.dynamics.residual", "StopModel": "camcad.dynamics.impact",
    "impact_sweep": "camcad.dynamics.impact", "LeverBeam": "camcad.dynamics.impact",
    "PublishedImpact": "camcad.dynamics.rebound", "compare_published": "camcad.dynamics.rebound",
    "rebound_study": "camcad.dynamics.rebound",
    "ElasticShaft": "camcad.dynamics.shaft", "ShaftCam": "camcad.dynamics.shaft",
    "simulate_shaft": "camcad.dynamics.shaft",
    "CamDrive": "camcad.dynamics.torque", "energy_fluctuation": "camcad.dynamics.flywheel",
    "polydyne_law": "camcad.dynamics.polydyne", "servo_table": "camcad.profile.servo",
    "DriveRequest": "camcad.scene.commands.drive", "run_drive": "camcad.scene.commands.drive",
    "ContactParams": "camcad.contact", "contact_stress": "camcad.contact",
    "Operation": "camcad.cyclogram.network", "make_network": "camcad.cyclogram.network",
    "optimise": "camcad.cyclogram.lp",
    "Group": "camcad.cyclogram.machine", "make_machine": "camcad.cyclogram.machine",
    "optimise_machine": "camcad.cyclogram.machine",
    "read_scene": "camcad.scene.file", "analyse_scene": "camcad.scene.pipeline", "run_scene": "camcad.report.scene",
    "plot_summary": "camcad.report.profile", "plot_kinematics": "camcad.report.profile",
    "plot_pressure_angle": "camcad.report.profile", "plot_curvature": "camcad.report.profile",
    "plot_profile": "camcad.report.profile", "plot_hodograph": "camcad.report.profile",
    "CamFrames": "camcad.profile.animation", "cam_frames": "camcad.profile.animation",
    "MechanismFrames": "camcad.scene.animation", "mechanism_frames": "camcad.scene.animation",
    "animation_html": "camcad.report.animation", "design_report_html": "camcad.report.design_report",
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
    "BenchRequest",
    "CamDrive",
    "CamFrames",
    "CamcadError",
    "ContactParams",
    "Correction",
    "DriveRequest",
    "ElasticFollower",
    "ElasticShaft",
    "ElementSpec",
    "ExportSettings",
    "FamilyRequest",
    "FgenRequest",
    "Follower",
    "Group",
    "LawRecord",
    "LeverBeam",
    "LinkageSource",
    "LoadedLaw",
    "MechanismFrames",
    "Operation",
    "PathRequest",
    "PipelineOptions",
    "ProfileFollower",
    "ProfileResult",
    "ProfileSettings",
    "PublishedImpact",
    "SegmentSpec",
    "ShaftCam",
    "StopModel",
    "SweepRequest",
    "TuneRequest",
    "__version__",
    "analyse",
    "analyse_scene",
    "animation_html",
    "cam_frames",
    "catalogue_table",
    "check",
    "compare_laws",
    "compare_published",
    "compose",
    "contact_stress",
    "contour_program",
    "correct",
    "cutter_paths",
    "design_report_html",
    "energy_fluctuation",
    "filter_law",
    "harmonic_beats",
    "impact_sweep",
    "kinematics_deg",
    "linkage_command",
    "load_law",
    "make_machine",
    "make_network",
    "mechanism_frames",
    "min_base_radius",
    "motion_law",
    "optimise",
    "optimise_machine",
    "parse_phases",
    "parse_segments",
    "part_files",
    "plot_curvature",
    "plot_hodograph",
    "plot_kinematics",
    "plot_pressure_angle",
    "plot_profile",
    "plot_summary",
    "polydyne_law",
    "profile_report",
    "radius_to_motion",
    "read_scene",
    "rebound_study",
    "residual_vibration",
    "resonant_harmonics",
    "rest_shape",
    "run_bench",
    "run_drive",
    "run_linkage_adjust",
    "run_linkage_analyse",
    "run_linkage_atlas",
    "run_linkage_family",
    "run_linkage_fgen",
    "run_linkage_path",
    "run_linkage_tune",
    "run_scene",
    "run_sweep",
    "servo_table",
    "simulate_shaft",
    "solve_segments",
    "steady_state",
    "synthesise_tachogram",
    "synthesize",
    "synthesize_many",
    "tachogram_phases",
    "write_corrected",
    "write_outputs",
]
