"""``python -m camcad`` is the ``camcad`` command."""

from .cli import main

main()
