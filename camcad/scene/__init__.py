"""Scenes: a machine's mechanisms described in a TOML file, and the pipeline that analyses them.

Three tiers, data flowing one way (tests/project/test_layering.py forbids cycles between modules):

- **reading**: ``file`` (the scene, its mechanisms, the machine's speeds), ``fields`` (the validated reading
  of a section's keys) and ``sections/`` — one module per ``[section]``, each turning its TOML table into a
  settings object (``law``, ``follower``, ``filter``, ``dynamics``, ``stops``, ``contact``, ``cyclogram``,
  ``linkage``);
- **the machine**: ``laws`` (a mechanism's law built, retimed, its unit), ``follower`` (the follower on its
  law), ``linkage`` (the chain after the follower), ``mechanism`` and ``stretch`` (contact geometry and the least
  phase angles), the steps ``filtering``, ``contact`` and ``phase_angles`` (the cyclogram), ``analysis_report``
  (what an analysis returns) and ``pipeline`` (what ``camcad profile SCENE.toml`` runs, in docs/INTERFACE.md's order);
- **commands**: ``commands/`` — one ``run_<command>(request) -> report`` per stand-alone analysis command,
  each computing the machine the pipeline computes (``commands/source``).
"""

from __future__ import annotations

from camcad.scene.file import Mechanism, Scene, read_scene
from camcad.scene.laws import mechanism_law

__all__ = ["Mechanism", "Scene", "mechanism_law", "read_scene"]
