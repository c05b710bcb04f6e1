"""The Dask executor: episodes on a Dask cluster, results written by the client (this process).

Kept apart from :mod:`nav_bench.batch.executors` because importing ``distributed`` takes ~0.5 s,
which local runs and their worker processes should not pay.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import multiprocessing
import os
import threading
import traceback
import uuid
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from distributed.diagnostics.plugin import WorkerPlugin

from nav_bench.batch.suite import EpisodeJob
from nav_bench.batch.worker import (
    POLL_S,
    PRELOAD,
    EpisodeFn,
    ExecutorError,
    JobOutcome,
    WorkerProcess,
    default_start_method,
    error_row,
    execute_job,
    finish_row,
)
from nav_bench.errors import InputError

log = logging.getLogger(__name__)

PLUGIN_NAME = "nav-bench-episode-hosts"


class _EpisodeHosts(WorkerPlugin):
    """Dask worker plugin: killable worker processes for the episodes of one Dask worker.

    A Dask task cannot be interrupted, so each task plays its episode in a child process of
    the Dask worker (kept between tasks) that can be killed at the wall-clock limit. Dask
    starts its workers as daemonic processes by default, and daemonic processes may not have
    children: the LocalCluster of ``--executor dask`` sets ``distributed.worker.daemon:
    false``; for your own cluster start the workers with
    ``DASK_DISTRIBUTED__WORKER__DAEMON=False``. Otherwise episodes run inside the Dask worker
    itself, and a hung episode cannot be stopped (a warning is logged).
    """

    name = PLUGIN_NAME
    idempotent = True

    def __init__(self, start_method: str, preload: Sequence[str]) -> None:
        self.start_method = start_method
        self.preload = tuple(preload)

    def setup(self, worker: Any = None) -> None:
        self._lock = threading.Lock()
        self._names = itertools.count()
        self._idle: list[WorkerProcess] = []
        self._all: list[WorkerProcess] = []
        self.killable = not multiprocessing.current_process().daemon
        if not self.killable:
            log.warning("nav-bench: this Dask worker is a daemonic process; episodes run in it "
                        "and wall_s cannot stop a hung one. Start workers with "
                        "DASK_DISTRIBUTED__WORKER__DAEMON=False.")
            return
        # start one host per task slot now, while the client waits for the registration, so
        # its start-up (~0.5 s) is not paid inside the first episodes
        slots = getattr(getattr(worker, "state", None), "nthreads", None) or 1
        self._idle = [self._new_host() for _ in range(slots)]
        self._all = list(self._idle)

    def _new_host(self) -> WorkerProcess:
        ctx = multiprocessing.get_context(self.start_method)
        if self.start_method == "forkserver":
            ctx.set_forkserver_preload(list(self.preload))
        return WorkerProcess(ctx, f"nav-bench-host-{next(self._names)}")

    def teardown(self, worker: Any = None) -> None:
        with self._lock:
            hosts, self._all, self._idle = self._all, [], []
        for host in hosts:
            host.stop()

    def run(self, job: EpisodeJob, episode_fn: EpisodeFn) -> JobOutcome:
        if not self.killable:
            return execute_job(job, episode_fn)
        with self._lock:
            host = self._idle.pop() if self._idle else None
            if host is None:
                host = self._new_host()
                self._all.append(host)
        outcome = host.run(job, episode_fn)
        with self._lock:
            if host.dead:
                self._all.remove(host)
            else:
                self._idle.append(host)
        return outcome


def _dask_episode(job: EpisodeJob, episode_fn: EpisodeFn) -> JobOutcome:
    """The Dask task: one episode in a killable child process of the Dask worker."""
    from distributed import get_worker

    hosts = get_worker().plugins.get(PLUGIN_NAME)
    if hosts is None:
        return execute_job(job, episode_fn)
    return hosts.run(job, episode_fn)


class DaskExecutor:
    """Episodes on a Dask cluster: a LocalCluster on 127.0.0.1, or an existing scheduler.

    Why Dask rather than Ray: a lighter, pure-Python install (``distributed``); dask-jobqueue
    reaches SLURM, PBS, SGE and LSF clusters with the same code; its futures API matches
    ``concurrent.futures``; and a cluster is just a scheduler address, so one
    ``--executor dask:tcp://HOST:PORT`` serves a laptop, a lab server or an HPC allocation.

    Results still go through the client (this process): the same folder, the same resume,
    the same rows as the local pool. Workers need nav-bench installed and the world, robot and
    URDF paths of the suite readable (a shared file system on clusters).
    """

    def __init__(self, workers: int | None = None, address: str | None = None,
                 start_method: str | None = None) -> None:
        if workers is not None and workers < 1:
            raise InputError(f"--workers must be at least 1, got {workers}")
        self.workers = workers or os.cpu_count() or 1
        self.address = address
        self.start_method = start_method or default_start_method()
        self.cluster_workers: int | None = None

    def describe(self) -> dict[str, Any]:
        return {"name": "dask", "scheduler": self.address or "LocalCluster(127.0.0.1)",
                "workers": self.cluster_workers if self.address else self.workers,
                "start_method": self.start_method}

    def _client(self, stack: contextlib.ExitStack) -> Any:
        import dask
        from distributed import Client, LocalCluster

        if self.address:
            try:
                client = stack.enter_context(Client(self.address, timeout="20s"))
            except OSError as exc:
                raise ExecutorError(f"cannot reach the Dask scheduler at {self.address}: "
                                    f"{exc}") from None
            self.cluster_workers = len(client.scheduler_info().get("workers", {}))
            return client
        # non-daemonic workers may start the killable episode processes (see _EpisodeHosts)
        stack.enter_context(dask.config.set({"distributed.worker.daemon": False}))
        cluster = stack.enter_context(LocalCluster(
            host="127.0.0.1", n_workers=self.workers, threads_per_worker=1, processes=True,
            dashboard_address=None, silence_logs=logging.ERROR))
        return stack.enter_context(Client(cluster))

    def run(self, jobs: Sequence[EpisodeJob], episode_fn: EpisodeFn, *,
            should_stop: Callable[[], bool] = lambda: False) -> Iterator[JobOutcome]:
        if not jobs:
            return
        from distributed import wait

        with contextlib.ExitStack() as stack:
            client = self._client(stack)
            client.register_plugin(_EpisodeHosts(self.start_method, PRELOAD), name=PLUGIN_NAME)
            token = uuid.uuid4().hex[:8]
            futures = {client.submit(_dask_episode, job, episode_fn, pure=False,
                                     key=f"nav-bench-{token}-{job.job_id}"): job for job in jobs}
            pending = set(futures)
            try:
                while pending:
                    if should_stop():
                        return
                    try:
                        done, pending = wait(pending, timeout=POLL_S,
                                             return_when="FIRST_COMPLETED")
                    except TimeoutError:
                        continue
                    for future in done:
                        yield self._outcome(future, futures[future])
            finally:
                if pending:
                    client.cancel(list(pending))

    @staticmethod
    def _outcome(future: Any, job: EpisodeJob) -> JobOutcome:
        try:
            return future.result()
        except Exception as exc:  # the task itself failed (a worker lost, a KilledWorker...)
            text = "".join(traceback.format_exception_only(type(exc), exc)).strip()
            message = f"the Dask task failed: {text}"
            return JobOutcome(job.job_id, finish_row(error_row(job, message, 0.0), job), None)
