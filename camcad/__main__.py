"""``python -m camcad`` is the ``camcad`` command."""

from camcad.cli import main

main()
