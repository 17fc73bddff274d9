"""The verdict of a mechanism as lines of text: the same words in the terminal and on the summary page.

Each line is (status, text): "ok" or "fail" for a check (its ``why``: figure, limit, margin, where),
"warn" for a warning and for a check that passes at its limit (no margin: never a clean "ok"), "head" for a
heading. Checks come tightest margin first; a model that ran (spectrum,
dynamics, impact, contact) adds its own tightest check, or its key figures when it reports no checks.
"""

from __future__ import annotations

import math

MODELS = ("spectrum", "dynamics", "impact", "contact")


def _fmt(x) -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return f"{x:.4g}"


def check_status(check: dict) -> str:
    """"ok", "warn" (passes at its limit: ``status`` "at limit") or "fail" for a check's JSON form."""
    if not check.get("passed"):
        return "fail"
    return "warn" if check.get("status") == "at limit" else "ok"


def model_status(data: dict) -> str:
    """"ok", "warn" (passes, its tightest check at its limit) or "fail" for a model's object of the report."""
    if not data.get("passed"):
        return "fail"
    checks = data.get("checks")
    order = data.get("tightest") or []
    if isinstance(checks, dict) and order and isinstance(checks.get(order[0]), dict):
        return check_status(checks[order[0]])
    return "ok"


def model_line(model: str, data: dict) -> str:
    """One line for a model's object of the report: its tightest check, else its key figures."""
    checks = data.get("checks")
    if isinstance(checks, dict) and checks:
        order = data.get("tightest") or list(checks)
        first = checks.get(order[0]) if order else None
        if isinstance(first, dict) and first.get("why"):
            return f"{model}: {first['why']}"
    if model == "contact" and "safety_factor" in data:
        return (f"contact: sigma_max {_fmt(data.get('sigma_max_MPa'))} MPa <= allowable "
                f"{_fmt(data.get('allowable_MPa'))} MPa, safety factor {_fmt(data.get('safety_factor'))}"
                + (" (the follower leaves the cam)" if data.get("separation") else ""))
    return model


def verdict_lines(report: dict) -> list[tuple[str, str]]:
    """(status, text) lines for one mechanism's report: checks tightest first, the models, the warnings."""
    lines: list[tuple[str, str]] = []
    checks = report.get("checks") or {}
    tightest = list(report.get("tightest") or [])
    for name in tightest + [n for n in checks if n not in tightest]:
        check = checks[name]
        lines.append((check_status(check), check.get("why", name)))
    for model in MODELS:
        data = report.get(model)
        if isinstance(data, dict) and "passed" in data:
            lines.append((model_status(data), model_line(model, data)))
            for warning in data.get("warnings") or []:
                if isinstance(warning, dict) and warning.get("what"):
                    lines.append(("warn", f"{model}: {warning['what']}"))
    for warning in report.get("warnings") or []:
        lines.append(("warn", warning["what"]))
    return lines
