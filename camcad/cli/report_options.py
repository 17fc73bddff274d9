"""The options of `camcad profile` that hand a design over: the animation and the report (docs/report.md)."""

from __future__ import annotations

from typing import Annotated, Any

import typer

AnimateOpt = Annotated[bool, typer.Option(
    "--animate", help="Also write animation.html: the cam turning, the follower and the linkage after it, with "
                      "the law's and the pressure angle's cursor (one self-contained page).")]
AnimateFormatOpt = Annotated[str | None, typer.Option(
    "--animate-format", help="Animation files: a comma list of html (default), gif, mp4 (mp4 needs ffmpeg); "
                             "implies --animate.")]
AnimateStepOpt = Annotated[float | None, typer.Option(
    "--animate-step", help="Cam angle between the animation's frames (deg, default 1: 360 frames); implies "
                           "--animate.")]
ReportOpt = Annotated[bool, typer.Option(
    "--report", help="Also write report.html: inputs, law, profile, every check with its margin, plots, "
                     "animation and models, and how to reproduce the run (one self-contained page).")]
ReportPdfOpt = Annotated[bool, typer.Option(
    "--report-pdf", help="Also print report.html to report.pdf with headless Chromium; implies --report.")]


def handover_options(*, animate: bool, animate_format: str | None, animate_step: float | None, report: bool,
                     report_pdf: bool) -> dict[str, Any]:
    """The ``PipelineOptions`` fields the options ask for (``animate``, ``animate_step_deg``, ``report``,
    ``command``); refused here, before any work, when a format is unknown, the step does not divide 360, or an
    MP4 or a PDF cannot be made on this machine."""

    from camcad.errors import CamcadError

    formats, step = animate_options(animate, animate_format, animate_step)
    pages: tuple[str, ...] = ("html", "pdf") if report_pdf else ("html",) if report else ()
    if report_pdf:
        from camcad.report.design_report import chromium

        if chromium() is None:
            raise CamcadError("a PDF report is printed by Chromium, which is not installed", "--report-pdf",
                              "install chromium (or chromium-headless-shell), or set CAMCAD_CHROMIUM; --report "
                              "alone writes report.html")
    return {"animate": formats, "animate_step_deg": step, "report": pages, "command": command_line()}


def animate_options(animate: bool, animate_format: str | None,
                    animate_step: float | None) -> tuple[tuple[str, ...], float]:
    """(the animation formats, the step between frames in deg) of ``--animate``, ``--animate-format`` and
    ``--animate-step``; () when none is given. Refused here, before any work, when a format is unknown, the step
    does not divide 360 or an MP4 cannot be made on this machine."""
    import shutil

    from camcad.errors import CamcadError
    from camcad.profile.animation import FRAME_STEP_DEG, frame_angles

    formats: tuple[str, ...] = ()
    if animate or animate_format is not None or animate_step is not None:
        formats = tuple(dict.fromkeys(k.strip().lower() for k in (animate_format or "html").split(",") if k.strip()))
        for kind in formats:
            if kind not in ("html", "gif", "mp4"):
                raise CamcadError(f"unknown animation format {kind!r}", "--animate-format", "use html, gif or mp4")
        if not formats:
            raise CamcadError("no animation format given", "--animate-format", "give html, gif or mp4")
        if "mp4" in formats and shutil.which("ffmpeg") is None:
            raise CamcadError("an MP4 needs ffmpeg, which is not installed", "--animate-format",
                              "install ffmpeg (e.g. apt-get install ffmpeg), or ask for html or gif")
    step = FRAME_STEP_DEG if animate_step is None else animate_step
    frame_angles(step)                       # a step that does not divide 360: refused now
    return formats, float(step)


def command_line() -> str:
    """The running command as a user would type it again: ``camcad`` and its arguments as given (the
    options left at their defaults are left out)."""
    import shlex

    try:  # typer >= 0.16 runs its own copy of click
        from typer._click.globals import get_current_context
    except ImportError:  # pragma: no cover - older typer uses click itself
        from click import get_current_context  # type: ignore[no-redef]

    ctx = get_current_context(silent=True)
    if ctx is None:
        return ""
    words = ["camcad", *ctx.command_path.split()[1:]]
    for param in ctx.command.params:
        if not param.name:
            continue
        value = ctx.params.get(param.name)
        source = ctx.get_parameter_source(param.name)
        if source is None or source.name != "COMMANDLINE" or value is None:
            continue
        if param.param_type_name == "argument":
            words.append(str(value))
            continue
        flag = max(param.opts, key=len)
        if getattr(param, "is_flag", False):
            if value:
                words.append(flag)
            elif param.secondary_opts:
                words.append(max(param.secondary_opts, key=len))
        elif isinstance(value, (list, tuple)):
            for item in value:
                words += [flag, str(item)]
        else:
            words += [flag, str(value)]
    return shlex.join(words)
