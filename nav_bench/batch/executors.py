"""Where episodes run: worker processes on this machine, or a Dask cluster beyond it.

An executor takes the jobs still to play and yields one :class:`JobOutcome` per job as it
finishes, in completion order. It never writes results: the runner (the parent process, or
the Dask client) does, so a folder has exactly one writer wherever the episodes ran.

Every episode runs in a worker process that can be killed: an episode that exceeds its
wall-clock limit (``limits.wall_s``) -- a planner caught in an endless loop, a physics step
that never returns -- is killed with its process, recorded as outcome ``error`` with the
reason, and a fresh worker takes its place. ``concurrent.futures.ProcessPoolExecutor`` cannot
do that (killing one of its workers breaks the whole pool), hence the small pool here: one
process per worker slot with a pipe, reused from episode to episode (a pipe round trip costs
well under a millisecond; starting a process with numpy and PyBullet imported costs ~0.5 s).

Processes start with ``forkserver`` where available (a server process imports nav-bench once,
then forks clean workers from it: fast, and no PyBullet client is ever forked), else ``spawn``.
Plain ``fork`` is not used: it would copy the parent's threads and state (a Dask client, an
open PyBullet connection) into the child.

Executors are named: ``local`` (this machine, ``--workers N``), ``dask`` (a Dask LocalCluster
on 127.0.0.1 with N worker processes) and ``dask:tcp://HOST:PORT`` (an existing scheduler);
the Dask executor lives in :mod:`nav_bench.batch.dask`, imported only when asked for
(importing ``distributed`` costs ~0.5 s, which every local worker would otherwise pay).
"""

from __future__ import annotations

import itertools
import math
import multiprocessing
import os
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import wait as wait_for
from typing import Any, Protocol

from nav_bench.batch.suite import EpisodeJob
from nav_bench.batch.worker import (
    POLL_S,
    PRELOAD,
    STARTUP_FAILURES,
    EpisodeFn,
    ExecutorError,
    JobOutcome,
    WorkerProcess,
    default_start_method,
)
from nav_bench.errors import InputError, UnknownNameError


# --------------------------------------------------------------------------- executors
class Executor(Protocol):
    """Runs jobs and yields outcomes as they finish."""

    def describe(self) -> dict[str, Any]: ...

    def run(self, jobs: Sequence[EpisodeJob], episode_fn: EpisodeFn, *,
            should_stop: Callable[[], bool]) -> Iterator[JobOutcome]: ...


class LocalPool:
    """Episodes on ``workers`` processes of this machine (default: one per CPU core)."""

    def __init__(self, workers: int | None = None, start_method: str | None = None,
                 preload: Sequence[str] = PRELOAD) -> None:
        if workers is not None and workers < 1:
            raise InputError(f"--workers must be at least 1, got {workers}")
        self.workers = workers or os.cpu_count() or 1
        self.start_method = start_method or default_start_method()
        self.preload = tuple(preload)

    def describe(self) -> dict[str, Any]:
        return {"name": "local", "workers": self.workers, "start_method": self.start_method}

    def _context(self) -> Any:
        ctx = multiprocessing.get_context(self.start_method)
        if self.start_method == "forkserver":
            # takes effect when the server starts (once per process); later calls are no-ops
            ctx.set_forkserver_preload(list(self.preload))
        return ctx

    def run(self, jobs: Sequence[EpisodeJob], episode_fn: EpisodeFn, *,
            should_stop: Callable[[], bool] = lambda: False) -> Iterator[JobOutcome]:
        if not jobs:
            return
        ctx = self._context()
        queue = deque(jobs)
        count = min(self.workers, len(jobs))
        names = (f"nav-bench-worker-{i}" for i in itertools.count())
        workers = [WorkerProcess(ctx, next(names)) for _ in range(count)]
        failed_starts = 0
        try:
            while queue or any(w.job is not None for w in workers):
                if should_stop():
                    return
                for w in workers:
                    if w.idle and queue:
                        w.send(queue.popleft(), episode_fn)
                deadline = min((w.deadline() for w in workers), default=math.inf)
                timeout = min(POLL_S, max(0.0, deadline - time.monotonic()))
                wait_for([x for w in workers for x in w.waitables()], timeout)
                now = time.monotonic()
                for i, w in enumerate(workers):
                    was_ready = w.ready
                    outcome = w.collect(now)
                    if outcome is not None:
                        yield outcome
                    if w.dead:
                        failed_starts = 0 if was_ready else failed_starts + 1
                        if failed_starts >= STARTUP_FAILURES:
                            raise ExecutorError(
                                f"{failed_starts} worker processes died while starting (last "
                                f"exit code {w.process.exitcode}); see the messages above")
                        if queue:
                            workers[i] = WorkerProcess(ctx, next(names))
                    elif w.ready and not was_ready:
                        failed_starts = 0
                workers = [w for w in workers if not (w.dead and not queue)]
        finally:
            for w in workers:
                if should_stop():
                    w.kill()  # in-flight episodes are dropped; a resume plays them again
                else:
                    w.stop()


EXECUTORS = ("local", "dask")


def make_executor(spec: str, workers: int | None = None) -> Executor:
    """``local``, ``dask`` or ``dask:tcp://HOST:PORT``; unknown names get a did-you-mean."""
    name, _, arg = spec.partition(":")
    if name not in EXECUTORS:
        raise UnknownNameError("executor", name, EXECUTORS)
    if name == "local":
        if arg:
            raise InputError(f"the local executor takes no address, got {spec!r}")
        return LocalPool(workers)
    try:
        from nav_bench.batch.dask import DaskExecutor
    except ModuleNotFoundError as exc:
        if (exc.name or "").split(".")[0] not in ("dask", "distributed"):
            raise
        raise InputError("the dask executor needs the 'distributed' package: "
                         "pip install 'nav-bench[dask]'") from None
    return DaskExecutor(workers, address=arg or None)
