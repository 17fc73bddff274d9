"""Designs that share a law, evaluated together: the sweep's batch over a follower's dimensions.

A sweep that varies only a mechanism's follower dimensions and limits (``BATCH_FIELDS``) runs the same law for
every design. ``evaluate_batch`` takes such a group of designs: the first runs through the scene pipeline as
any design does (its row is the template), the law it built is kept, every design's follower is read from its
own [follower] table, and all followers are synthesised at once (``camcad.profile.batch.synthesize_many``); each
design's report comes from the same ``profile_report`` the pipeline uses, so its row has the same figures. The
law is computed again only when a key that shapes it varies (a new group).

A group is batched only when its scene is one mechanism whose pipeline runs the law (and its balance check)
and the profile and nothing else, with a translating roller follower; and only when the batch reproduces the
template design's row exactly. Anything else — and any design whose follower the batch cannot take — goes
through ``evaluate_design`` one at a time.
"""

from __future__ import annotations

from typing import Any

from camcad.errors import CamcadError
from camcad.profile.batch import supports, synthesize_many
from camcad.profile.summary import profile_report
from camcad.scene.file import scene_from_dict
from camcad.scene.follower import follower_for_law
from camcad.scene.pipeline import PipelineOptions, analyse_scene

#: follower keys a batch varies (the law does not depend on them for a translating follower)
BATCH_FIELDS = ("base_radius", "roller_radius", "offset", "pressure_angle_limit_rise", "pressure_angle_limit_return",
                "rho_min")
#: the pipeline steps a batched scene may run (the rest is per design)
BATCH_STEPS = {"law", "balance", "profile"}


def batch_keys(prep) -> set[str]:
    """The varied keys a batch may differ in: a single mechanism's [follower] dimensions and limits."""
    return {path for path, key in prep.keys.items()
            if tuple(key.tables) == ("follower",) and key.name in BATCH_FIELDS and not getattr(key, "phase", False)}


def groups(prep, designs: list[int]) -> list[list[int]]:
    """The designs in groups that share every varied value outside ``batch_keys`` (so they share the law)."""
    free = batch_keys(prep)
    found: dict[tuple, list[int]] = {}
    for design in designs:
        values = prep.space.values(design)
        key = tuple(sorted((k, repr(v)) for k, v in values.items() if k not in free))
        found.setdefault(key, []).append(design)
    return list(found.values())


def evaluate_batch(prep, designs: list[int], evaluate_design, with_files, row_of) -> list[dict]:
    """Rows of ``designs`` (one group of ``groups``), batched where the module docstring allows, else one at a
    time by ``evaluate_design(prep, design)``; ``with_files`` and ``row_of`` are the sweep's own helpers
    (``camcad.sweep.evaluate``)."""
    if len(designs) < 2 or not batch_keys(prep):
        return [evaluate_design(prep, d) for d in designs]
    template = evaluate_design(prep, designs[0])
    plan = _plan(prep, designs[0], with_files)
    if template["status"] != "ok" or plan is None:
        return [template] + [evaluate_design(prep, d) for d in designs[1:]]
    law, settings, name, phases, where = plan
    followers: dict[int, Any] = {}
    for design in designs:
        try:
            values, tables = prep.scene_tables(design)
            follower, law_d, _, notes = follower_for_law(with_files(tables, prep)["follower"], where, law)
        except CamcadError:
            continue               # its own run says why (a bad-input row)
        if law_d is law and not notes:
            followers[design] = (values, follower)
    batched = [d for d in designs if d in followers]
    if designs[0] not in followers or not supports([f for _, f in followers.values()], settings):
        return [template] + [evaluate_design(prep, d) for d in designs[1:]]
    try:
        results = synthesize_many(law, [followers[d][1] for d in batched], settings, name=name)
    except (CamcadError, ValueError):
        return [template] + [evaluate_design(prep, d) for d in designs[1:]]
    rows: dict[int, dict] = {}
    for design, result in zip(batched, results):
        if result is None:       # chords that do not meet the tolerance: its own run says why
            continue
        report = profile_report(result, phases)
        row: dict[str, Any] = {"design": int(design)}
        if prep.space.samples > 1:
            row["sample"] = int(design) % prep.space.samples
        row.update(followers[design][0])
        rows[design] = row_of(row, {"checks": report["checks"]}, bool(report["passed"]))
    if designs[0] not in rows or _comparable(rows[designs[0]]) != _comparable(template):
        return [template] + [evaluate_design(prep, d) for d in designs[1:]]   # the batch must agree with it
    rows[designs[0]] = template
    return [rows[d] if d in rows else evaluate_design(prep, d) for d in designs]


def _plan(prep, design: int, with_files):
    """(law, settings, name, phase source, where) of a design's profile when its scene qualifies, else None."""
    try:
        _, tables = prep.scene_tables(design)
        scene = scene_from_dict(with_files(tables, prep), prep.scene_path, from_file=False)
        result = analyse_scene(scene, PipelineOptions(plots=(), checks_only=True))
    except CamcadError:
        return None
    if result.group or len(result.runs) != 1 or result.cyclogram is not None:
        return None
    (run,) = result.runs.values()
    if run.profile is None or not set(run.ran) <= BATCH_STEPS or run.linkage is not None:
        return None
    where = scene.mechanisms[0].where(scene.path, "follower")
    phases = "the law's own phase angles"
    if profile_report(run.profile, phases)["checks"] != result.report.get("checks"):
        return None
    return run.profile.law, run.profile.settings, run.profile.name, phases, where


def _comparable(row: dict) -> dict:
    return {k: v for k, v in row.items() if not k.startswith("_")}
