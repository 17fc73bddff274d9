"""Lazy re-exports: a package's public names imported from their modules on first use (cheap start-up)."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, MutableMapping
from typing import Any


def lazy_exports(package: str, exports: Mapping[str, str],
                 namespace: MutableMapping[str, Any]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of ``package``, whose name N lives in module
    ``exports[N]``; a name is imported on first use and then kept in ``namespace`` (the package's globals).

    Examples
    --------
    >>> namespace = {}
    >>> getattr_, dir_ = lazy_exports("demo", {"sqrt": "math"}, namespace)
    >>> getattr_("sqrt")(16.0), "sqrt" in namespace, dir_()
    (4.0, True, ['sqrt'])
    """

    def __getattr__(name: str) -> Any:
        module = exports.get(name)
        if module is None:   # a submodule not imported yet (``package.name`` as an attribute)
            try:
                return importlib.import_module(f"{package}.{name}")
            except ModuleNotFoundError as missing:
                if missing.name != f"{package}.{name}":
                    raise
                raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(exports))

    return __getattr__, __dir__
