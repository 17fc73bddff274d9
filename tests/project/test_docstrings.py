"""The public API's docstrings (numpydoc): every parameter documented, units stated, an example given.

Like python-control's docstring test: for every name in ``camcad.__all__``, and every function and class a
subpackage exports in its own ``__all__`` (``camcad.fourier``, ``camcad.dynamics``, …: public too, and
imported by users from there), the docstring is parsed with numpydoc's own parser, and

- it has a one-line summary;
- every parameter of the function (or of the class's constructor: its dataclass fields) appears in its
  Parameters section (for a result class, which users receive rather than build, Attributes counts);
- every number-valued parameter (typed float or array) states its unit in its type or description, or
  says it has none ("dimensionless", "no unit", a fraction, a ratio); the Returns section of a function
  states units too;
- every function and every class users build has an Examples section (run by ``tests/project/test_doctests.py``).

The names whose module another engineer owns (``OWNED_ELSEWHERE``) are expected to fail until their
docstrings land; the test turns green for them without a change here (non-strict xfail).
"""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

import camcad

numpydoc_docscrape = pytest.importorskip("numpydoc.docscrape")

#: names whose modules are being finished (and documented) by another engineer
OWNED_ELSEWHERE: set[str] = set()
#: classes that the library returns and users only read: their fields may be documented as Attributes,
#: and they need no Examples section of their own (the function that returns them has one)
RESULT_TYPES = {"BalanceReport", "Correction", "LoadedLaw", "ProfileResult", "CamFrames", "MechanismFrames"}

#: a unit as the docstrings write it, or words saying there is none
UNIT = re.compile(
    r"(?<![\w/])(mm|mm/rad|mm/rad²|deg|degrees?|rad|radians?|rpm|N|N/m|N/mm|N·s|MPa|Hz|kg|kg·m²|m/s|s|seconds?)"
    r"(?![\w])|mm/|/rad|dimensionless|no unit|fraction|ratio|law units|follower units|drawing units")
NUMBER_TYPE = re.compile(r"\b(float|array_like|ndarray|array)\b")


#: the subpackages whose ``__all__`` is public API too
SUBPACKAGES = ("law", "balance", "fourier", "profile", "dynamics", "cyclogram", "linkage", "scene", "sweep", "report",
               "edit", "io")
#: subpackage classes that the library returns and users only read (as RESULT_TYPES)
SUBPACKAGE_RESULT_TYPES = {
    "law": {"Kinematics"},
    "balance": {"Move"},
    "cyclogram": {"CyclogramResult", "MachineResult", "PhaseLimit", "SlackPlan", "Constraint"},
    "dynamics": {"Impact", "ImpactSweep", "LawSpectrum", "MultiMassResult", "Residual", "Response", "StartLoad",
                 "Sweep", "ResonanceError"},
    "fourier": {"ExportedLaw", "FilterResult", "LeadInResult", "Spectrum", "Synthesis", "ResonanceBand",
                "MotionPattern", "Piece"},
    "profile": {"BaseRadiusDesign"},
    "scene": {"Scene", "Mechanism"},
}


def public_names() -> list[str]:
    return [name for name in camcad.__all__ if name != "__version__"]


def subpackage_names() -> list[tuple[str, str]]:
    """(subpackage, name) of every function and class a subpackage's ``__all__`` exports, less those that
    ``camcad.__all__`` exports too (the same object: tested once, under its top-level name)."""
    top = {id(resolve(name)) for name in public_names()}
    found = []
    for package in SUBPACKAGES:
        module = importlib.import_module(f"camcad.{package}")
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name)
            if (inspect.isfunction(obj) or inspect.isclass(obj)) and id(obj) not in top:
                found.append((package, name))
    return found


def marks(name: str):
    if name in OWNED_ELSEWHERE:
        return [pytest.mark.xfail(reason="docstring written by the balance/fix engineer", strict=False)]
    return []


def params():
    return [pytest.param(name, marks=marks(name), id=name) for name in public_names()]


def resolve(name: str):
    """The object behind a public name. ``camcad.report`` is looked up in its own module: the name is
    shadowed by the ``camcad.report`` subpackage once that has been imported (see the README section)."""
    return getattr(importlib.import_module(camcad._EXPORTS[name]), name)


def parsed(obj) -> numpydoc_docscrape.NumpyDocString:
    return numpydoc_docscrape.NumpyDocString(inspect.getdoc(obj) or "")


def signature_names(obj) -> list[str]:
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p.name for p in signature.parameters.values()
            if p.name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]


def documented(entries) -> dict[str, tuple[str, str]]:
    """{name: (type, description)}; numpydoc allows "x, y : float" for two names with one description."""
    out = {}
    for entry in entries:
        for part in entry.name.split(","):
            out[part.strip().lstrip("*")] = (entry.type, " ".join(entry.desc))
    return out


def check_documented(label: str, obj, result_type: bool) -> None:
    """The one-line summary, every parameter in Parameters (or Attributes, for a result type) with its unit,
    and for a function a Returns section with its unit."""
    doc = parsed(obj)
    summary = doc["Summary"]
    assert summary and summary[0].strip(), f"{label}: no one-line summary"
    assert len(summary) == 1, f"{label}: the summary is {len(summary)} lines, numpydoc wants one"
    entries = documented(doc["Parameters"])
    if inspect.isclass(obj) and result_type:
        entries.update(documented(doc["Attributes"]))
    missing = [p for p in signature_names(obj) if p not in entries]
    assert not missing, f"{label}: parameters not in the docstring's Parameters section: {missing}"
    unitless = [p for p, (kind, desc) in entries.items()
                if NUMBER_TYPE.search(kind) and not UNIT.search(kind + " " + desc)]
    assert not unitless, f"{label}: number-valued parameters without a unit (or 'dimensionless'): {unitless}"
    if not inspect.isclass(obj):
        returns = " ".join(f"{r.type} {' '.join(r.desc)}" for r in doc["Returns"])
        assert returns.strip(), f"{label}: no Returns section"
        assert UNIT.search(returns), f"{label}: the Returns section states no unit (or 'no unit')"


def check_example(label: str, obj) -> None:
    examples = "\n".join(parsed(obj)["Examples"])
    assert ">>>" in examples, f"{label}: no Examples section with a doctest"


@pytest.mark.parametrize("name", params())
def test_every_parameter_is_documented_with_its_unit(name):
    check_documented(name, resolve(name), name in RESULT_TYPES)


@pytest.mark.parametrize("name", params())
def test_every_function_and_buildable_class_has_an_example(name):
    obj = resolve(name)
    if name in RESULT_TYPES:
        pytest.skip("a result type: the function returning it carries the example")
    check_example(name, obj)


SUBPACKAGE_PARAMS = [pytest.param(package, name, id=f"{package}.{name}") for package, name in subpackage_names()]


@pytest.mark.parametrize("package,name", SUBPACKAGE_PARAMS)
def test_every_subpackage_export_is_documented_with_its_units_and_an_example(package, name):
    # a result type (users read it, the function returning it carries the example) needs no example of its own
    obj = getattr(importlib.import_module(f"camcad.{package}"), name)
    result_type = name in SUBPACKAGE_RESULT_TYPES.get(package, ())
    check_documented(f"camcad.{package}.{name}", obj, result_type)
    if not result_type:
        check_example(f"camcad.{package}.{name}", obj)


def test_the_subpackages_exports_are_reached():
    # every subpackage with an __all__ contributes; the names camcad.__all__ exports too are tested once there
    packages = {package for package, _ in subpackage_names()}
    assert {"law", "balance", "fourier", "profile", "dynamics", "cyclogram", "scene", "edit"} <= packages
    assert len(SUBPACKAGE_PARAMS) >= 100


def test_the_checks_catch_an_undocumented_parameter():
    def sample(length_mm: float, angle: float) -> float:
        """Something.

        Parameters
        ----------
        length_mm : float
            A length, mm.

        Returns
        -------
        float
            A length, mm.
        """
        return length_mm

    entries = documented(parsed(sample)["Parameters"])
    assert [p for p in signature_names(sample) if p not in entries] == ["angle"]


def test_the_checks_catch_a_missing_unit():
    def sample(length: float) -> float:
        """Something.

        Parameters
        ----------
        length : float
            How long it is.
        """
        return length

    entries = documented(parsed(sample)["Parameters"])
    assert [p for p, (kind, desc) in entries.items() if not UNIT.search(kind + " " + desc)] == ["length"]
