"""Where a sweep's chunks run: this process, a local pool of processes, or a Dask cluster.

Every engine takes the same work — chunks of consecutive design ids, each an ``evaluate_chunk(task, chunk,
start, stop)`` call — and yields each chunk's result as it completes; the caller writes it to disk at once
(``camcad.sweep.store``), so results stream and nothing computed is lost when a run stops.

- ``InProcess``: one worker, this process (``--workers 1``).
- ``LocalPool``: a ``concurrent.futures.ProcessPoolExecutor`` of N processes (default: every core this process
  may use). The processes start before any progress display (a fork never copies a running thread). They die
  with the run and hold no copy of the folder's lock (``camcad.io.output_folder.init_worker``), so after
  ``kill -9`` of the run ``--resume`` finds the folder free; a worker that dies (killed, out of memory) stops
  the run with one line saying to resume (the chunks written are kept).
- ``DaskCluster``: a ``dask.distributed`` scheduler (``tcp://HOST:PORT``, or a scheduler file). The task —
  the scene's tables and its law files' bytes — is scattered to the workers once; no shared file system is
  assumed. The workers must have camcad installed (the same version: checked before any work is sent). A
  cluster that loses every worker, or its scheduler, stops the run with one line saying what to do.

At most ``window`` chunks are in flight at once (a few per worker), so a sweep of 10⁵ chunks neither floods
the scheduler nor keeps 10⁵ futures in memory.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

from camcad.errors import CamcadError
from camcad.io.output_folder import init_worker
from camcad.sweep.evaluate import ChunkResult, SweepTask, evaluate_chunk, worker_version
from camcad.sweep.store import INSTALL_FIX
from camcad.version import __version__

#: chunks in flight per worker
IN_FLIGHT_PER_WORKER = 3
#: seconds to wait for a Dask scheduler (and for its first worker); a cluster left without workers this long
#: stops the sweep
CONNECT_TIMEOUT_S = 10.0
#: how often the cluster's workers are counted while a sweep runs (s)
WORKER_POLL_S = 1.0


def local_cores() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


class Engine:
    """What every engine offers: ``workers`` (parallel slots), ``name``, ``run(task, chunks)``, ``close()``."""

    name = "engine"
    workers = 1

    def run(self, task: SweepTask, chunks: list[tuple[int, int, int]]) -> Iterator[ChunkResult]:
        raise NotImplementedError

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def describe(self) -> dict:
        return {"engine": self.name, "workers": self.workers}


class InProcess(Engine):
    """Chunks computed one after the other in this process."""

    name = "in-process"

    def run(self, task, chunks):
        for chunk, start, stop in chunks:
            yield evaluate_chunk(task, chunk, start, stop)


class LocalPool(Engine):
    """A pool of ``workers`` processes on this machine."""

    name = "local pool"

    def __init__(self, workers: int) -> None:
        from concurrent.futures import ProcessPoolExecutor

        if workers < 1:
            raise CamcadError(f"--workers must be at least 1, got {workers}", "--workers", "give --workers N, N >= 1")
        self.workers = workers
        self.pool = ProcessPoolExecutor(max_workers=workers, initializer=init_worker, initargs=(os.getpid(),))
        # start the processes now, before the caller shows a progress bar (its thread is not forked)
        for future in [self.pool.submit(worker_version) for _ in range(workers)]:
            future.result()

    def run(self, task, chunks):
        from concurrent.futures import FIRST_COMPLETED, wait
        from concurrent.futures.process import BrokenProcessPool

        pending = iter(chunks)
        running = set()
        window = max(IN_FLIGHT_PER_WORKER * self.workers, 2)
        try:
            while True:
                while len(running) < window:
                    item = next(pending, None)
                    if item is None:
                        break
                    running.add(self.pool.submit(evaluate_chunk, task, *item))
                if not running:
                    return
                done, running = wait(running, return_when=FIRST_COMPLETED)
                for future in sorted(done, key=lambda f: (f.exception() is not None, _chunk_of(f))):
                    yield future.result()
        except BrokenProcessPool:
            self.broken = True
            raise CamcadError("a worker process of the local pool died (killed, or out of memory)", "camcad sweep",
                              "the chunks written are kept: rerun the same command with --resume") from None
        finally:
            for future in running:
                future.cancel()

    broken = False

    def close(self) -> None:
        self.pool.shutdown(wait=not self.broken, cancel_futures=True)


class DaskCluster(Engine):
    """The chunks on a ``dask.distributed`` cluster.

    Parameters
    ----------
    address : str
        ``tcp://HOST:PORT`` (or ``tls://``, ``ucx://``) of the scheduler, or the path of a scheduler file
        (JSON, as ``dask scheduler --scheduler-file`` writes it).
    timeout_s : float
        Seconds to wait for the scheduler and for its first worker.
    """

    name = "dask"

    def __init__(self, address: str, timeout_s: float = CONNECT_TIMEOUT_S) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise CamcadError("running on a Dask cluster needs dask.distributed, which is not installed",
                              "--scheduler", INSTALL_FIX) from None
        self.address = address
        self.timeout_s = float(timeout_s)
        where = "--scheduler"
        # the client logs its reconnection attempts on stderr; what went wrong is said in one line instead
        _quiet_distributed()
        is_file = os.path.isfile(address)
        if not is_file and "://" not in address:
            raise CamcadError(f"{address[:60]!r} is neither tcp://HOST:PORT nor a scheduler file", where,
                              "give --scheduler tcp://HOST:PORT, or the path of the scheduler's JSON file")
        try:
            if is_file:
                self.client = Client(scheduler_file=address, timeout=f"{timeout_s}s", set_as_default=False)
            else:
                self.client = Client(address, timeout=f"{timeout_s}s", set_as_default=False)
        except Exception as err:  # noqa: BLE001 - OSError, TimeoutError, a bad scheduler file: all unreachable
            text = " ".join(str(err).split())[:80] or type(err).__name__
            raise CamcadError(f"cannot reach the Dask scheduler at {address[:80]} ({text})", where,
                              "start it (dask scheduler; dask worker ADDRESS) or check the address and the network") \
                from None
        _quiet_distributed()   # the loggers the client made (distributed.client keeps its own level)
        try:
            self.client.wait_for_workers(1, timeout=timeout_s)
        except Exception:  # noqa: BLE001 - a timeout
            self.client.close()
            raise CamcadError(f"the Dask scheduler at {address[:80]} has no workers", where,
                              "start workers with: dask worker ADDRESS") from None
        self._check_workers(timeout_s)
        self.workers = sum(self.client.nthreads().values())

    def _check_workers(self, timeout_s: float) -> None:
        try:
            theirs = self.client.submit(worker_version, pure=False).result(timeout=max(timeout_s, 30.0))
        except Exception as err:  # noqa: BLE001 - ModuleNotFoundError on the worker, a timeout
            self.client.close()
            raise CamcadError(f"the cluster's workers cannot run camcad ({type(err).__name__}: "
                              f"{' '.join(str(err).split())[:60]})", "--scheduler",
                              f"install camcad {__version__} with its sweep extra on every worker") from None
        if theirs != __version__:
            self.client.close()
            raise CamcadError(f"the cluster's workers run camcad {theirs}, this is camcad {__version__}",
                              "--scheduler", f"install camcad {__version__} on the workers")

    def describe(self) -> dict:
        return {"engine": self.name, "workers": self.workers, "scheduler": self.address,
                "hosts": len({w.split("://")[-1].rsplit(":", 1)[0] for w in self.client.nthreads()})}

    def run(self, task, chunks):
        from distributed import as_completed

        shared = self.client.scatter(task, broadcast=True, hash=False)
        pending = iter(chunks)
        window = max(IN_FLIGHT_PER_WORKER * self.workers, 2)

        def submit(item):
            chunk, start, stop = item
            return self.client.submit(evaluate_chunk, shared, chunk, start, stop, retries=1,
                                      key=f"camcad-sweep-{task.digest[:16]}-{chunk}")

        first = [submit(item) for item in _take(pending, window)]
        if not first:
            return
        finished = as_completed(first, with_results=True, raise_errors=False, loop=self.client.loop)
        stop_watch = self._watch_workers(finished)
        try:
            for future, result in finished:
                status = future.status
                future.release()
                if status != "finished" or isinstance(result, BaseException):
                    self._lost(result, status)
                yield result
                item = next(pending, None)
                if item is not None:
                    finished.add(submit(item))
        finally:
            stop_watch.set()
            for future in list(finished.futures):
                future.cancel()
            shared.release()

    def _watch_workers(self, finished):
        """A thread that cancels the chunks in flight when the cluster has had no worker for ``timeout_s``
        (their futures then come back cancelled, and ``_lost`` says so): a cluster whose workers all left
        would otherwise keep the sweep waiting for ever. Returns the event that stops the thread."""
        import threading
        import time

        stop = threading.Event()

        def watch() -> None:
            empty_since = None
            while not stop.wait(WORKER_POLL_S):
                try:
                    count = len(self.client.nthreads())
                except Exception:  # noqa: BLE001 - the scheduler is gone: the futures come back cancelled
                    return
                if count:
                    empty_since = None
                    continue
                empty_since = empty_since if empty_since is not None else time.monotonic()
                if time.monotonic() - empty_since > self.timeout_s:
                    for future in list(finished.futures):
                        future.cancel()
                    return

        threading.Thread(target=watch, name="camcad-dask-workers", daemon=True).start()
        return stop

    def _lost(self, error, status: str) -> None:
        """A chunk that did not come back: the cluster lost its workers or its scheduler (exit 2 with what to do),
        or the chunk's own code failed on a worker (re-raised: an internal error)."""
        kind = type(error).__name__ if isinstance(error, BaseException) else status
        if isinstance(error, BaseException) and not _cluster_loss(error):
            raise error
        try:
            alive = len(self.client.nthreads())
        except Exception:  # noqa: BLE001 - the scheduler itself is gone
            alive = -1
        where = "its scheduler is gone" if alive < 0 else f"{alive} workers are left"
        raise CamcadError(f"the Dask cluster at {self.address[:80]} lost the workers computing a chunk ({kind}; "
                          f"{where})", "--scheduler",
                          "start workers (dask worker ADDRESS) or the scheduler again, then rerun the same command "
                          "with --resume: the chunks written are kept")

    def close(self) -> None:
        import contextlib

        with contextlib.suppress(Exception):  # closing a client whose scheduler went away
            self.client.close()


def _cluster_loss(error: BaseException) -> bool:
    """True when a Dask future's error says the cluster lost the task (a killed worker, a cancelled future, a
    closed connection), not that the task's own code failed."""
    import asyncio
    import concurrent.futures

    names = {"KilledWorker", "FutureCancelledError", "CancelledError", "CommClosedError", "FutureLostError"}
    return type(error).__name__ in names or isinstance(
        error, (asyncio.CancelledError, concurrent.futures.CancelledError, ConnectionError, TimeoutError))


def _chunk_of(future) -> int:
    return future.result().chunk if future.exception() is None else -1


def _take(items, count: int) -> list:
    out = []
    for item in items:
        out.append(item)
        if len(out) >= count:
            break
    return out


def make_engine(workers: int | None = None, scheduler: str | None = None,
                timeout_s: float = CONNECT_TIMEOUT_S) -> Engine:
    """The engine the options ask for: a Dask cluster with ``scheduler``, else a local pool of ``workers``
    processes (default every core), or this process for one worker."""
    if scheduler is not None:
        if workers is not None:
            raise CamcadError("--workers sizes the local pool; a Dask cluster's workers are started with it",
                              "--workers", "drop --workers when giving --scheduler")
        return DaskCluster(scheduler, timeout_s)
    count = local_cores() if workers is None else workers
    if count < 1:
        raise CamcadError(f"--workers must be at least 1, got {count}", "--workers", "give --workers N, N >= 1")
    return InProcess() if count == 1 else LocalPool(count)


def _quiet_distributed() -> None:
    """Silence every ``distributed`` logger (dask's configuration gives ``distributed.client`` and others their
    own levels, so the parent's level is not enough): a lost worker or scheduler is said in camcad's one line."""
    import logging

    names = [name for name in logging.root.manager.loggerDict if name.split(".")[0] == "distributed"]
    for name in ["distributed", *names]:
        logging.getLogger(name).setLevel(logging.CRITICAL)
