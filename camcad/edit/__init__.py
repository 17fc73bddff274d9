"""The graphical point editor of a drawn acceleration law (``camcad edit``).

``session`` is the model (no matplotlib): the law, the operations on it, undo/redo, the balance
report, corrections with preview/accept/reject, saving and the edit script. ``view`` turns mouse
and key events of a matplotlib figure into session operations and redraws; ``web`` serves the
same view in a browser through matplotlib's WebAgg (127.0.0.1 only); ``app`` picks the desktop
window or the browser and runs a script headless.
"""

from camcad.edit.session import (
                      OPERATIONS,
                      EditSession,
                      load_script,
                      normalize_operation,
                      sampled_law,
                      validate_script,
)

__all__ = ["OPERATIONS", "EditSession", "load_script", "normalize_operation", "sampled_law", "validate_script"]
