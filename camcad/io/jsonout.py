"""Plain JSON from numerical results: numpy scalars and arrays, paths and tuples → JSON types."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from camcad.io.atomic import write_text_atomic


def to_jsonable(value: Any) -> Any:
    """numpy scalars and arrays, paths and tuples → plain JSON types; NaN/inf → null (JSON has neither)."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "tolist"):  # numpy array or scalar
        return to_jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_json(path, payload) -> Path:
    """``payload`` as indented JSON, written atomically (camcad.io.atomic)."""
    import json

    return write_text_atomic(path, json.dumps(to_jsonable(payload), indent=2) + "\n")
