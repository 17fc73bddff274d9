"""The scene's sections, one module per ``[section]``: each reads its TOML table into a validated settings
object (unknown keys, missing values, wrong types and units are one-line errors naming the file and section).

A section module imports only the analysis layer below it and ``camcad.scene.fields``: never the pipeline,
never a command (tests/project/test_layering.py).
"""
