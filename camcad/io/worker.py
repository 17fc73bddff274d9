"""Worker processes that die with the run that started them.

A pool's worker (a sweep's chunks, a scene's plots) is forked from the run. Two things must not outlive
that run when it is killed (``kill -9`` gives it no chance to clean up):

- the worker itself: on Linux the kernel kills it when its parent dies (``prctl(PR_SET_PDEATHSIG,
  SIGKILL)``); elsewhere a thread of the worker checks once a second that its parent is still the same
  process and ends the worker when it is not;
- the output folder's lock: the worker closes its inherited copy of the lock descriptor
  (``output_folder.release_inherited_locks``), so the lock is held by the run alone and an orphaned
  worker can never keep ``--resume`` out of the folder.

``init_worker(parent)`` does both; give it as a pool's ``initializer`` with ``initargs=(os.getpid(),)``.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time

from camcad.io.output_folder import release_inherited_locks

#: prctl option: the signal this process gets when its parent dies (linux/prctl.h)
PR_SET_PDEATHSIG = 1
#: how often a worker without prctl checks that its parent is alive (s)
PARENT_POLL_S = 1.0


def die_with_parent(parent: int) -> str:
    """Arrange for this process to end when process ``parent`` (its parent) ends; returns how ("prctl" or
    "watchdog"). A process whose parent is already gone ends at once."""
    how = "watchdog"
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0:
                how = "prctl"
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:   # the parent died before the line above took effect
        os._exit(1)
    if how == "watchdog":
        def watch() -> None:
            while True:
                time.sleep(PARENT_POLL_S)
                if os.getppid() != parent:
                    os._exit(1)

        threading.Thread(target=watch, name="camcad-parent-watch", daemon=True).start()
    return how


def init_worker(parent: int) -> None:
    """A pool worker's initializer: release the run's folder locks and die with the run (module docstring)."""
    release_inherited_locks()
    die_with_parent(parent)


__all__ = ["die_with_parent", "init_worker"]
