"""One job on one worker: the worker process, its pipe, and the outcome it sends back.

Every episode runs in a worker process that can be killed: an episode that exceeds its
wall-clock limit (``limits.wall_s``) -- a planner caught in an endless loop, a physics step
that never returns -- is killed with its process, recorded as outcome ``error`` with the
reason, and a fresh worker takes its place. ``concurrent.futures.ProcessPoolExecutor`` cannot
do that (killing one of its workers breaks the whole pool), hence the small pool in
:mod:`nav_bench.batch.executors`: one process per worker slot with a pipe, reused from episode
to episode (a pipe round trip costs well under a millisecond; starting a process with numpy
and PyBullet imported costs ~0.5 s). The Dask executor (:mod:`nav_bench.batch.dask`) runs the
same worker process inside each Dask task.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import logging
import math
import multiprocessing
import os
import signal
import sys
import time
import traceback
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import wait as wait_for
from typing import TYPE_CHECKING, Any

from nav_bench.batch.suite import EpisodeJob
from nav_bench.episode import EpisodeSettings, ResultRow
from nav_bench.errors import NavBenchError

if TYPE_CHECKING:  # imported for real in the workers only: PyBullet prints a banner at import
    from nav_bench.sim.session import SimSession

log = logging.getLogger(__name__)

# (job, session) -> an object with .row (dict) and .trace. ``session`` is the worker's
# SimSession, kept open from episode to episode, or None: make a client of your own.
EpisodeFn = Callable[[EpisodeJob, "SimSession | None"], Any]
POLL_S = 0.2  # how often a waiting executor checks for a stop request (s)
STARTUP_FAILURES = 3  # workers that die before they are ready, in a row, before giving up
# imported once by the forkserver (its workers start with them loaded); nothing that prints
PRELOAD = ("numpy", "nav_bench.episode", "nav_bench.world.optimal")
# imported by each worker before it is ready (imports must not eat an episode's wall_s)
WORKER_IMPORTS = ("nav_bench.episode", "nav_bench.world.optimal")
# imported with C-level output silenced: PyBullet prints a build banner to stderr at import,
# once per worker, through the middle of the progress bar
QUIET_IMPORTS = ("nav_bench.episode.loop",)


class ExecutorError(NavBenchError):
    """An executor could not run at all (workers that cannot start, no scheduler)."""


# --------------------------------------------------------------------------- jobs on a worker
@dataclass
class JobOutcome:
    """What a worker sends back: the finished row and the trace (None when the episode failed
    before it had one)."""

    job_id: str
    row: ResultRow
    trace: Any | None


def run_job(job: EpisodeJob, session: SimSession | None = None) -> Any:
    """The real episode function: play ``job`` with :func:`nav_bench.episode.loop.run_episode`,
    in ``session`` (a :class:`~nav_bench.sim.session.SimSession`) when one is given."""
    # imported here, in the worker: the parent process never imports the simulator
    from nav_bench.episode.loop import run_episode

    return run_episode(job.world, job.planner, seed=job.seed, robot=job.robot,
                       settings=EpisodeSettings(**job.settings), world_file=job.world_file,
                       session=session)


def error_row(job: EpisodeJob, error: str, wall_s: float) -> ResultRow:
    """The row of a job whose episode did not finish: outcome ``error``, measurements null."""
    return ResultRow.failure(world=job.world_name, world_file=job.world_file,
                           planner=job.planner.planner, params=job.params,
                           params_id=job.params_id, seed=job.seed, settings=job.settings,
                           error=error, wall_s=wall_s)


def finish_row(row: ResultRow, job: EpisodeJob) -> ResultRow:
    """The row as stored: with the job's identity, its robot label and its time limit."""
    return dataclasses.replace(
        row, job_id=job.job_id, label=job.label, world_file=job.world_file,
        robot=job.robot_label,  # the variant label ("diffbot[sonar.noise_std=0.02]")
        robot_id=row.robot_id or job.robot_id,
        time_limit_s=float(EpisodeSettings(**job.settings).time_limit(job.world)))


def execute_job(job: EpisodeJob, episode_fn: EpisodeFn,
                session: SimSession | None = None) -> JobOutcome:
    """Play one job (in ``session``, if given); any exception becomes an ``error`` row with
    its traceback."""
    t0 = time.perf_counter()
    try:
        result = episode_fn(job, session)
        row, trace = result.row, result.trace
    except Exception:
        row = error_row(job, traceback.format_exc(), time.perf_counter() - t0)
        trace = None
    return JobOutcome(job.job_id, finish_row(row, job), trace)


def timeout_outcome(job: EpisodeJob, waited_s: float) -> JobOutcome:
    message = (f"episode exceeded the wall-clock limit of {job.wall_s:g} s (limits.wall_s) and "
               f"its worker process was killed")
    return JobOutcome(job.job_id, finish_row(error_row(job, message, waited_s), job), None)


def died_outcome(job: EpisodeJob, exitcode: int | None, waited_s: float) -> JobOutcome:
    how = f"exit code {exitcode}"
    if exitcode is not None and exitcode < 0:
        with contextlib.suppress(ValueError):
            how = f"signal {signal.Signals(-exitcode).name}"
    message = f"the worker process died ({how}) while playing this episode"
    return JobOutcome(job.job_id, finish_row(error_row(job, message, waited_s), job), None)


@contextlib.contextmanager
def _c_output_silenced() -> Iterator[None]:
    """Point file descriptors 1 and 2 at /dev/null: C libraries write there directly."""
    try:
        sys.stdout.flush()
        sys.stderr.flush()
        saved = [os.dup(1), os.dup(2)]
    except (OSError, ValueError, AttributeError):  # no real stdout/stderr: nothing to silence
        yield
        return
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 1)
            os.dup2(null.fileno(), 2)
        yield
    finally:
        for fd, copy in zip((1, 2), saved, strict=True):
            os.dup2(copy, fd)
            os.close(copy)


def _worker_main(conn: Any, imports: Sequence[str]) -> None:
    """A worker process: play jobs from ``conn`` until it closes or sends None."""
    # Ctrl-C in a terminal reaches the whole process group; the parent decides what stops
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for module in imports:  # a module that fails here fails again, with its traceback, in
        with contextlib.suppress(ImportError):  # the episode's error row
            importlib.import_module(module)
    with _c_output_silenced():
        for module in QUIET_IMPORTS:
            with contextlib.suppress(ImportError):
                importlib.import_module(module)
    # One PyBullet client for all the worker's episodes, connected by the first (each episode
    # resets the world): connecting anew costs 1-15 ms, a tenth of a short episode's wall time.
    from nav_bench.sim.session import SimSession

    session = SimSession()
    conn.send(("ready", os.getpid()))
    try:
        while True:
            try:
                message = conn.recv()
            except (EOFError, OSError):  # the parent is gone
                return
            if message is None:
                return
            job, episode_fn = message
            outcome = execute_job(job, episode_fn, session)
            try:
                conn.send(outcome)
            except (BrokenPipeError, EOFError, OSError):
                return
            except Exception:  # the trace or row would not pickle: keep the row, say why
                outcome.row.trace_error = traceback.format_exc()
                conn.send(JobOutcome(outcome.job_id, outcome.row, None))
    finally:
        session.close()


# --------------------------------------------------------------------------- one worker
def default_start_method() -> str:
    return "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"


class WorkerProcess:
    """One worker process and its pipe; plays one job at a time; can be killed."""

    def __init__(self, ctx: Any, name: str, imports: Sequence[str] = WORKER_IMPORTS) -> None:
        self.conn, child = ctx.Pipe(duplex=True)
        self.process = ctx.Process(target=_worker_main, args=(child, tuple(imports)), name=name,
                                   daemon=True)
        self.process.start()
        child.close()
        self.ready = False
        self.dead = False
        self.job: EpisodeJob | None = None
        self.sent_at = 0.0

    @property
    def idle(self) -> bool:
        return self.ready and not self.dead and self.job is None

    def send(self, job: EpisodeJob, episode_fn: EpisodeFn) -> None:
        self.job, self.sent_at = job, time.monotonic()
        self.conn.send((job, episode_fn))

    def deadline(self) -> float:
        if self.job is None or self.job.wall_s is None:
            return math.inf
        return self.sent_at + self.job.wall_s

    def waitables(self) -> list[Any]:
        return [] if self.dead else [self.conn, self.process.sentinel]

    def collect(self, now: float) -> JobOutcome | None:
        """Read what the worker sent; detect death and overrun. Returns a finished outcome."""
        if self.dead:
            return None
        try:
            message = self.conn.recv() if self.conn.poll() else None
        except (EOFError, OSError):  # the worker closed its end: it is exiting
            message = None
            self.process.join(1.0)
        if isinstance(message, tuple) and message[:1] == ("ready",):
            self.ready = True
            return None
        if isinstance(message, JobOutcome):
            self.job = None
            return message
        if not self.process.is_alive():
            self.dead = True
            job, self.job = self.job, None
            return None if job is None else died_outcome(job, self.process.exitcode,
                                                         now - self.sent_at)
        if self.job is not None and now >= self.deadline():
            job, self.job = self.job, None
            self.kill()
            return timeout_outcome(job, now - self.sent_at)
        return None

    def kill(self) -> None:
        self.dead = True
        with contextlib.suppress(Exception):
            self.process.kill()
            self.process.join(5.0)
        self.conn.close()

    def stop(self) -> None:
        """Ask the worker to finish, kill it if it does not."""
        if self.dead:
            return
        with contextlib.suppress(Exception):
            self.conn.send(None)
            self.process.join(2.0)
        self.kill()

    def run(self, job: EpisodeJob, episode_fn: EpisodeFn) -> JobOutcome:
        """Play one job to its end, blocking (used inside Dask tasks)."""
        while not self.ready:
            wait_for(self.waitables(), 5.0)
            self.collect(time.monotonic())
            if self.dead:
                raise ExecutorError(f"worker process failed to start (exit code "
                                    f"{self.process.exitcode})")
        self.send(job, episode_fn)
        while True:
            timeout = self.deadline() - time.monotonic()
            wait_for(self.waitables(), None if math.isinf(timeout) else max(0.0, timeout))
            outcome = self.collect(time.monotonic())
            if outcome is not None:
                return outcome
