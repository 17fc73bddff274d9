"""Scenes: a machine's mechanisms described in a TOML file, and the pipeline that analyses them.

Modules, one concept each: ``file`` (reading the file: the scene, its mechanisms, the machine's speeds),
``fields`` (the validated reading of a section's keys, shared by every section), one module per section
(``law``, ``follower``, ``filter``, ``dynamics``, ``stops``, ``contact``, ``cyclogram``), ``mechanism``
(the analyses that need a mechanism's law, profile and other sections together) and ``pipeline``
(what ``camcad profile SCENE.toml`` runs, in SPEC.md's order).
"""

from __future__ import annotations

from camcad.scene.file import Mechanism, Scene, mechanism_law, read_scene

__all__ = ["Mechanism", "Scene", "mechanism_law", "read_scene"]
