"""The one-way layering of camcad (STYLE.md): io ← law ← balance ← analyses ← scene ← report ← edit ← cli.

A module may import only from its own layer or from layers to its left, anywhere in the module
(function-level imports included). Analyses may import each other but not in a cycle. The rule is
checked on the source (AST), so a test that adds an upward import fails — see
``test_the_check_fails_on_an_upward_import``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "camcad"

#: layer of each top-level part of the package; a module imports only from layers <= its own
LAYERS = {
    "errors": 0, "verdict": 0, "version": 0, "numerics": 0, "lazy": 0, "arrays": 0, "extrema": 0, "io": 0,
    "law": 1,
    "balance": 2,
    "fourier": 3, "profile": 3, "dynamics": 3, "contact": 3, "cyclogram": 3, "linkage": 3,
    "scene": 4,
    # a sweep runs scenes (many at once, checks only) and the report layer draws and writes its outputs
    "sweep": 4.5,
    # camcad bench's measurements: every kernel against its floor and peers (report writes their tables)
    "bench": 4.7,
    "report": 5,
    "edit": 6,
    "cli": 7, "__main__": 7,
}
#: the public API (camcad/__init__.py) sits above everything but the command line
API_LAYER = 6.5
#: modules that must not import matplotlib (the editor's model, every analysis and everything below)
NO_MATPLOTLIB_BELOW = 5


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def layer_of(module: str) -> float | None:
    parts = module.split(".")
    if parts[0] != "camcad":
        return None
    if len(parts) == 1:
        return API_LAYER
    return LAYERS.get(parts[1])


def imports_of(source: str, module: str, is_package: bool) -> list[tuple[int, str]]:
    """(line, absolute module) of every import in ``source`` (relative imports resolved)."""
    found = []
    package = module.split(".") if is_package else module.split(".")[:-1]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found.extend((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            # "from camcad import scene" names a subpackage: count it as that subpackage
            subpackages = [a.name for a in node.names if layer_of(f"camcad.{a.name}") is not None]
            if target == "camcad" and subpackages:
                found.extend((node.lineno, f"camcad.{name}") for name in subpackages)
            else:
                found.append((node.lineno, target))
    return found


def violations(files: dict[str, str]) -> list[str]:
    """Upward imports and matplotlib in low layers, in ``{path: source}``."""
    problems = []
    for path, source in files.items():
        module = module_name(Path(path))
        own = layer_of(module)
        if own is None:
            problems.append(f"{path}: not in a layer; add its top-level name to LAYERS")
            continue
        for line, target in imports_of(source, module, Path(path).name == "__init__.py"):
            if target.split(".")[0] == "matplotlib" and own < NO_MATPLOTLIB_BELOW:
                problems.append(f"{path}:{line}: imports matplotlib below the report layer")
            if target == "camcad" and own != API_LAYER:
                problems.append(f"{path}:{line}: imports the public API (camcad) from inside the package")
                continue
            theirs = layer_of(target)
            if theirs is not None and target != "camcad" and theirs > own:
                problems.append(f"{path}:{line}: {module} (layer {own}) imports {target} (layer {theirs})")
    return problems


def package_sources() -> dict[str, str]:
    return {str(p): p.read_text(encoding="utf-8") for p in sorted(PACKAGE.rglob("*.py"))}


def test_no_module_imports_from_a_layer_to_its_right():
    assert violations(package_sources()) == []


def test_the_check_fails_on_an_upward_import():
    sources = package_sources()
    law = str(PACKAGE / "law" / "law.py")
    sources[law] += "\n\ndef _upward():\n    from camcad.scene.pipeline import run_scene  # noqa: F401\n"
    found = violations(sources)
    assert len(found) == 1 and "camcad.law.law (layer 1) imports camcad.scene.pipeline (layer 4)" in found[0]
    sources = package_sources()
    sources[str(PACKAGE / "balance" / "checking.py")] += "\nimport matplotlib.pyplot  # noqa: F401\n"
    assert any("matplotlib below the report layer" in v for v in violations(sources))


def test_analyses_do_not_import_each_other_in_a_cycle():
    graph: dict[str, set[str]] = {}
    for path, source in package_sources().items():
        module = module_name(Path(path))
        if layer_of(module) != 3:
            continue
        top = module.split(".")[1]
        for _, target in imports_of(source, module, Path(path).name == "__init__.py"):
            if layer_of(target) == 3 and target.split(".")[1] != top:
                graph.setdefault(top, set()).add(target.split(".")[1])

    def reaches(start: str, goal: str, seen: set[str]) -> bool:
        for nxt in graph.get(start, ()):
            if nxt == goal or (nxt not in seen and reaches(nxt, goal, seen | {nxt})):
                return True
        return False

    cyclic = sorted(name for name in graph if reaches(name, name, {name}))
    assert cyclic == [], f"analyses import each other in a cycle: {cyclic} ({graph})"


@pytest.mark.parametrize("layer_name", sorted(LAYERS))
def test_every_layer_name_exists(layer_name):
    assert (PACKAGE / layer_name).is_dir() or (PACKAGE / f"{layer_name}.py").exists() or layer_name in (
        "linkage", "edit")
