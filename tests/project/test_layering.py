"""The one-way layering of camcad (STYLE.md): io ← law ← balance ← analyses ← scene ← report ← edit ← cli.

A module may import only from its own layer or from layers to its left, anywhere in the module
(function-level imports included). Analyses may import each other but not in a cycle. Among modules
(issue 33):

- no cycle in the import graph, function-level imports counted (``if TYPE_CHECKING:`` blocks left out);
- no ``_private`` name imported from another module (make it public or move it);
- no camcad import inside a function, except in ``camcad/cli/`` (a command loads its library when it runs),
  in a package's ``__init__.py`` (lazy exports) and in ``ALLOWED_FUNCTION_IMPORTS``: each entry a start-up
  cost measured on the commands that would pay it.

The rules are checked on the source (AST); each has a test that plants a violation and sees it fail
(``test_the_check_fails_on_an_upward_import``, ``test_each_module_rule_fails_on_a_planted_violation``).
"""

from __future__ import annotations

import ast
import fnmatch
from pathlib import Path
from typing import NamedTuple

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


# --- among modules: cycles, private names, function-level imports ------------------------------------------

#: (importing module, imported module) glob patterns -> why the import stays inside its function. Measured
#: as CPU time (time.process_time) and modules added by importing the module after the command named has
#: run in a fresh interpreter (the command's own modules loaded), on the shared 2-core machine, 2026-11.
PLOTS_OF_THE_MODELS = ("the plots of one model: +42 to +45 modules (the scene commands and the analyses "
                       "behind them), 57-65 ms CPU, for camcad profile --no-plots, which draws nothing")
ALLOWED_FUNCTION_IMPORTS = {
    ("camcad.report.scene", "camcad.report.dynamics"): PLOTS_OF_THE_MODELS,
    ("camcad.report.scene", "camcad.report.contact"): PLOTS_OF_THE_MODELS,
    ("camcad.report.scene", "camcad.report.cyclogram"): PLOTS_OF_THE_MODELS,
    ("camcad.scene.pipeline", "camcad.scene.models"):
        "the models of a scene (dynamics, contact, stops, cyclogram, linkage): +36 modules, 51 ms CPU for camcad "
        "profile --no-plots of a scene without models",
    ("*", "camcad.io.law_write"):
        "the law writers (DXF and CSV, unicodedata): +3 modules, 5 ms CPU for camcad check and camcad spectrum, "
        "which write no law unless asked",
    ("camcad.dynamics.runs", "camcad.dynamics.*"):
        "each model's module loaded when a scene has that model (residual vibration, start load, multi-mass "
        "drive): +3 modules, 5 ms CPU for camcad spectrum",
    ("camcad.linkage.adjust", "camcad.linkage.qmethod"):
        "the Q-method's solvers for an adjustment only (+3 modules with cmath, 5 ms CPU for camcad spectrum, "
        "which loads the linkage section's parser)",
    ("camcad.edit.app", "camcad.edit.*"):
        "the editor loads the front end it runs: the window (matplotlib, PIL: +219 modules, 350 ms CPU) or "
        "the web server (asyncio, ssl: +38 modules, 17 ms CPU), never both",
}


class Import(NamedTuple):
    path: str
    module: str
    line: int
    target: str          #: the camcad module imported (the deepest that exists)
    names: tuple         #: the names taken from it ("from ... import a, b"), () for "import ..."
    in_function: bool
    type_checking: bool


def camcad_imports(files: dict[str, str]) -> list[Import]:
    """Every import of a camcad module in ``{path: source}``, with where it sits."""
    modules = {module_name(Path(path)) for path in files}

    def deepest(name: str) -> str:
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name

    found = []
    for path, source in files.items():
        module = module_name(Path(path))
        tree = ast.parse(source)
        parents = {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "camcad" and not node.level:
                base = node.module or ""
                pairs = [(deepest(f"{base}.{a.name}") if f"{base}.{a.name}" in modules else deepest(base),
                          (a.name,)) for a in node.names]
            elif isinstance(node, ast.Import):
                pairs = [(deepest(a.name), ()) for a in node.names if a.name.split(".")[0] == "camcad"]
            else:
                continue
            in_function = type_checking = False
            above = node
            while above in parents:
                above = parents[above]
                in_function |= isinstance(above, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
                type_checking |= isinstance(above, ast.If) and "TYPE_CHECKING" in ast.unparse(above.test)
            found.extend(Import(path, module, node.lineno, target, names, in_function, type_checking)
                         for target, names in pairs if target)
    return found


def import_cycles(files: dict[str, str]) -> list[list[str]]:
    """The strongly connected components (more than one module) of the module import graph."""
    graph: dict[str, set[str]] = {}
    for item in camcad_imports(files):
        if not item.type_checking and item.target != item.module:
            graph.setdefault(item.module, set()).add(item.target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles = []
    for start in sorted(graph):        # Tarjan's algorithm, iterative (the graph has hundreds of modules)
        if start in index:
            continue
        work = [(start, iter(sorted(graph.get(start, ()))))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    cycles.append(sorted(component))
    return cycles


def private_imports(files: dict[str, str]) -> list[str]:
    """``from camcad.x import _name`` where camcad.x is another module (dunder names are not private)."""
    return [f"{item.path}:{item.line}: {item.module} imports {name} from {item.target}"
            for item in camcad_imports(files) if item.target != item.module
            for name in item.names if name.startswith("_") and not name.startswith("__")]


def allowed_reason(module: str, target: str) -> str | None:
    for (importer, imported), reason in ALLOWED_FUNCTION_IMPORTS.items():
        if fnmatch.fnmatchcase(module, importer) and fnmatch.fnmatchcase(target, imported):
            return reason
    return None


def function_level_imports(files: dict[str, str]) -> list[str]:
    """camcad imports inside functions outside camcad/cli/, the packages' __init__.py and the allow-list."""
    return [f"{item.path}:{item.line}: {item.module} imports {item.target} inside a function"
            for item in camcad_imports(files)
            if item.in_function and not item.type_checking and item.target != item.module
            and not item.module.startswith("camcad.cli.") and Path(item.path).name != "__init__.py"
            and allowed_reason(item.module, item.target) is None]


def test_no_import_cycle_among_modules_counting_function_level_imports():
    assert import_cycles(package_sources()) == []


def test_no_private_name_is_imported_from_another_module():
    assert private_imports(package_sources()) == []


def test_camcad_imports_sit_at_module_top_outside_the_command_line_and_the_allow_list():
    assert function_level_imports(package_sources()) == []


def test_every_allowed_function_level_import_is_still_made():
    # an entry no import needs any more is removed, so the list says only what is true
    made = {(item.module, item.target) for item in camcad_imports(package_sources())
            if item.in_function and not item.module.startswith("camcad.cli.")}
    unused = [key for key in ALLOWED_FUNCTION_IMPORTS
              if not any(fnmatch.fnmatchcase(m, key[0]) and fnmatch.fnmatchcase(t, key[1]) for m, t in made)]
    assert unused == []


def test_each_module_rule_fails_on_a_planted_violation():
    sources = package_sources()
    law = str(PACKAGE / "law" / "law.py")
    phases = str(PACKAGE / "law" / "phases.py")
    # a cycle made only by a function-level import: law.phases imports law.law at its top
    planted = dict(sources)
    planted[law] += "\n\ndef _cycle():\n    from camcad.law.phases import sign_runs  # noqa: F401\n"
    assert any({"camcad.law.law", "camcad.law.phases"} <= set(cycle) for cycle in import_cycles(planted))
    # ... and the same import under TYPE_CHECKING makes none
    planted = dict(sources)
    planted[law] += "\nif TYPE_CHECKING:\n    from camcad.law.phases import sign_runs  # noqa: F401\n"
    assert import_cycles(planted) == []
    # a private name from another module
    planted = dict(sources)
    planted[phases] += "\nfrom camcad.balance.modes import _free_vertices  # noqa: F401\n"
    found = private_imports(planted)
    assert len(found) == 1 and "imports _free_vertices from camcad.balance.modes" in found[0]
    # a camcad import inside a function of the library, not on the allow-list
    planted = dict(sources)
    planted[phases] += "\n\ndef _late():\n    from camcad.arrays import unique  # noqa: F401\n"
    found = function_level_imports(planted)
    assert len(found) == 1 and "camcad.law.phases imports camcad.arrays inside a function" in found[0]
    # ... which the command line may do
    cli = str(PACKAGE / "cli" / "check.py")
    planted = dict(sources)
    planted[cli] += "\n\ndef _late():\n    from camcad.arrays import unique  # noqa: F401\n"
    assert function_level_imports(planted) == []


# --- the command line: thin commands ---------------------------------------------------------------------

#: the longest a command function may be, decorators and option declarations included (STYLE.md)
COMMAND_LINES = 60
#: commands still longer (their lines today): each is the next to become parse, call one function, print
COMMANDS_NOT_YET_THIN = {"profile": 101, "spectrum": 70}


def command_lengths() -> dict[str, int]:
    """Lines of every ``@app.command`` function in camcad/cli/, from its first decorator to its last line."""
    lengths = {}
    for path in sorted((PACKAGE / "cli").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef) and any("command" in ast.unparse(d) for d in node.decorator_list):
                start = min([d.lineno for d in node.decorator_list] + [node.lineno])
                lengths[f"{path.stem}.{node.name}"] = node.end_lineno - start + 1
    return lengths


def test_every_command_function_is_at_most_60_lines_with_its_options():
    lengths = command_lengths()
    assert "sweep.sweep" in lengths and len(lengths) > 20
    long = {name.split(".")[1]: count for name, count in lengths.items() if count > COMMAND_LINES}
    assert long.keys() == COMMANDS_NOT_YET_THIN.keys(), long


def test_the_linkage_commands_module_is_at_most_300_lines():
    assert len((PACKAGE / "cli" / "linkage.py").read_text(encoding="utf-8").splitlines()) <= 300
