"""``nav-bench run``: play a suite's episodes on an executor and keep every result.

:func:`run_suite` expands the suite (:mod:`nav_bench.batch.suite`), runs the episodes not yet done
on an executor (:mod:`nav_bench.batch.executors`) and stores each row and trace as it arrives
(:mod:`nav_bench.batch.store`). Guarantees:

* results are never lost: each row is fsync'ed before the next is awaited; ``kill -9`` of the
  runner loses at most the episodes in flight, and ``--resume DIR`` plays exactly the missing
  ones (a half-written last line is reported and cut away first);
* Ctrl-C (SIGINT) or SIGTERM stops cleanly: no new episodes start, the folder is left
  valid, run.json says ``interrupted``, and :class:`RunInterrupted` tells how to resume;
* an episode that raises, hangs past ``limits.wall_s`` or kills its worker becomes an
  ``error`` row with the reason, and the batch goes on.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import importlib
import os
import platform
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from importlib import metadata
from pathlib import Path
from typing import Any

from nav_bench import __version__, compiled
from nav_bench.batch.executors import make_executor
from nav_bench.batch.store import ResultsStore, describe_os_error, is_disk_full
from nav_bench.batch.suite import (
    EpisodeJob,
    Suite,
    default_suite_file,
    describe,
    expand,
    load_suite,
    suite_from_data,
    with_world_files,
)
from nav_bench.batch.worker import EpisodeFn, JobOutcome, run_job
from nav_bench.episode.row import ResultRow
from nav_bench.errors import InputError, NavBenchError
from nav_bench.interface import Outcome
from nav_bench.paths import source_root

RUN_FORMAT = 1


class RunInterrupted(NavBenchError):
    """The run was stopped by Ctrl-C or SIGTERM; the folder is valid and can be resumed."""

    exit_code = 130  # the shell's convention for "ended by SIGINT"

    def __init__(self, folder: Path, done: int, total: int) -> None:
        self.folder, self.done, self.total = folder, done, total
        super().__init__(f"interrupted: {done} of {total} episodes are stored in {folder}; "
                         f"finish with: nav-bench run --resume {folder}")


class RunStorageError(NavBenchError):
    """The results could not be written (a full disk, a folder gone); the rows written so far
    are kept, run.json says the session failed and why, and ``--resume`` finishes the run
    (replaying the episodes whose trace was lost)."""

    def __init__(self, folder: Path, done: int, total: int, error: OSError) -> None:
        self.folder, self.done, self.total, self.error = folder, done, total, error
        super().__init__(f"{describe_os_error(error)}; {done} of {total} episodes are stored in "
                         f"{folder}; free space, then finish with: nav-bench run --resume "
                         f"{folder}")


# --------------------------------------------------------------------------- stop requests
class _StopRequests:
    """SIGINT/SIGTERM set a flag instead of raising, so no write is ever cut in half.

    A second signal raises KeyboardInterrupt at once (the user insists)."""

    def __init__(self) -> None:
        self.requested = False
        self._previous: dict[int, Any] = {}

    def _handle(self, signum: int, frame: Any) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True

    def __call__(self) -> bool:
        return self.requested

    def __enter__(self) -> _StopRequests:
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._handle)
        return self

    def __exit__(self, *exc: object) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)


# --------------------------------------------------------------------------- progress
class _Progress:
    """A tqdm bar: done/total, successes and errors so far, elapsed and remaining time."""

    def __init__(self, total: int, done_rows: list[ResultRow], desc: str,
                 enabled: bool) -> None:
        from tqdm import tqdm

        self.ok = sum(1 for r in done_rows if r.success)
        self.errors = sum(1 for r in done_rows if r.outcome is Outcome.ERROR)
        self.bar = tqdm(total=total, initial=len(done_rows), desc=desc, unit="ep",
                        disable=not enabled, file=sys.stderr, dynamic_ncols=True)
        self._postfix()

    def _postfix(self) -> None:
        self.bar.set_postfix_str(f"reached {self.ok}, errors {self.errors}", refresh=False)

    def update(self, row: ResultRow) -> None:
        self.ok += row.success
        self.errors += row.outcome is Outcome.ERROR
        self._postfix()
        self.bar.update(1)

    def close(self) -> None:
        self.bar.close()


# --------------------------------------------------------------------------- environment
def _version(dist: str) -> str | None:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def git_state() -> dict[str, Any] | None:
    """Commit and dirtiness of the source tree nav-bench runs from, if it is a git checkout
    (the repository above the package: this module's own folder's parent was ``nav_bench/``
    once the runner moved into ``batch/``, so no run recorded its commit)."""
    root = source_root()
    if not (root / ".git").exists():
        return None
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True,
                                text=True, timeout=10, check=True).stdout.strip()
        status = subprocess.run(["git", "-C", str(root), "status", "--porcelain",
                                 "--untracked-files=no"], capture_output=True, text=True,
                                timeout=10, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    return {"commit": commit, "dirty": bool(status.strip())}


def environment() -> dict[str, Any]:
    """What produced the results: versions, host, interpreter."""
    import numpy

    return {
        "nav_bench": __version__,
        "git": git_state(),
        "host": platform.node(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "pybullet": _version("pybullet"),
        "numpy": numpy.__version__,
        "numpy_simd": numpy_simd(),
        # the compiled kernels (the 'fast' extra) give the same rows bit for bit, but not the
        # same CPU time: recorded so a run's timings can be read (None: NumPy/Python loops)
        "numba": compiled.numba_version(),
    }


def numpy_simd() -> list[str]:
    """The SIMD levels NumPy dispatches its kernels to on this machine (e.g. ``['X86_V3',
    'X86_V4', 'AVX512_ICL']``), after ``NPY_DISABLE_CPU_FEATURES``; [] if NumPy does not say.

    Recorded because rows depend on it: NumPy's AVX-512 kernels of ``exp``, ``arctan2`` and
    others differ from its AVX2 ones in the last bit, and a wall follower's long episodes
    amplify that (README, "Reproducing rows")."""
    for name in ("numpy._core._multiarray_umath", "numpy.core._multiarray_umath"):  # NumPy 2, 1
        try:
            umath = importlib.import_module(name)
            break
        except ImportError:
            continue
    else:  # a NumPy that keeps them elsewhere: say nothing rather than fail the run
        return []
    features = getattr(umath, "__cpu_features__", {})
    return [name for name in getattr(umath, "__cpu_dispatch__", ()) if features.get(name)]


def _now() -> str:
    return dt.datetime.now(dt.timezone.utc).astimezone().isoformat(timespec="seconds")


# --------------------------------------------------------------------------- the run
def _new_folder(suite: Suite, out: Path | None) -> Path:
    if out is not None:
        return Path(out)
    stamp = dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    folder = Path("results") / f"{suite.name}-{stamp}"
    n = 1
    while folder.exists():  # two runs started within the same second
        n += 1
        folder = Path("results") / f"{suite.name}-{stamp}-{n}"
    return folder


def _suite_of_run(meta: dict[str, Any], folder: Path) -> Suite:
    stored = meta.get("suite") or {}
    if "data" not in stored:
        raise InputError(f"{folder / 'run.json'} does not hold the suite it ran; cannot resume")
    return suite_from_data(stored["data"], file=stored.get("file"), cwd=stored.get("cwd"))


def _check_same_jobs(stored: list[str], jobs: list[EpisodeJob], folder: Path, why: str) -> None:
    new = {j.job_id for j in jobs}
    old = set(stored)
    if new != old:
        changed = sorted(new ^ old)
        raise InputError(f"cannot resume {folder}: {why} ({len(changed)} episodes differ, e.g. "
                         f"{changed[0]}); start a new run instead")


def _write_generated_worlds(suite: Suite, store: ResultsStore) -> dict[str, str]:
    """Generated worlds go into the results folder, so every row's world_file exists."""
    files = {}
    for world in suite.worlds:
        if world.file is None:
            from nav_bench.world.generate import write_world_yaml

            path = store.world_path(world.name)
            path.parent.mkdir(parents=True, exist_ok=True)
            write_world_yaml(world.spec.model_dump(mode="json", by_alias=True,
                                                   exclude_defaults=True), path)
            files[world.name] = str(path)
    return files


def _store_outcome(store: ResultsStore, outcome: JobOutcome) -> ResultRow:
    """Trace first (atomically), then the row: a stored row always has its trace."""
    row = outcome.row
    row.trace = None
    if outcome.trace is not None:
        path = store.trace_path(outcome.job_id)
        tmp = path.with_name(f".{path.name}.tmp")
        try:
            outcome.trace.save(tmp)
            os.replace(tmp, path)
            row.trace = f"{path.parent.name}/{path.name}"
        except Exception as exc:  # a trace that cannot be written must not cost the row
            tmp.unlink(missing_ok=True)
            row.trace_error = f"{type(exc).__name__}: {exc}"
            if isinstance(exc, OSError) and is_disk_full(exc):
                store.append(row)  # keep the row if it still fits (resume replays it)
                raise
    store.append(row)
    return row


def run_suite(suite_path: str | Path | None, *, workers: int | None = None,
              out: Path | None = None, resume: Path | None = None, executor: str = "local",
              progress: bool = True, episode_fn: EpisodeFn = run_job,
              retry_errors: bool = False) -> Path:
    """Run a suite (default: ``configs/suites/default.yaml``); returns the results folder.

    Args:
        suite_path: the suite YAML; with ``resume``, optional (if given it must expand to the
            same episodes as the stored one).
        workers: parallel episodes (default: CPU cores; for ``dask``, the LocalCluster size).
        out: results folder (default ``results/<suite>-<YYYYmmdd-HHMMSS>``); must not hold a run.
        resume: a results folder to finish: plays the episodes without a row, and those whose
            trace is missing (a full disk; the row is replaced).
        retry_errors: with ``resume``, also replay the episodes whose row is an ``error``
            (a planner that raised, a worker killed from outside, a hang past ``wall_s``).
        executor: ``local``, ``dask`` or ``dask:tcp://HOST:PORT``.
        progress: show a progress bar on stderr.
        episode_fn: plays one :class:`~nav_bench.batch.suite.EpisodeJob` (for tests and benchmarks;
            must be importable by worker processes).
    Raises:
        InputError: bad suite, executor or folder; a folder another run is writing (its
            lock is held); a new run's folder that is not empty (nothing simulated).
        RunInterrupted: Ctrl-C or SIGTERM; the folder is valid and resumable.

    Worker processes start by ``forkserver`` or ``spawn``, which import the calling script
    again: a script that calls ``run_suite`` needs the ``if __name__ == "__main__":`` guard.
    """
    runner = make_executor(executor, workers)  # an unknown executor fails before anything else
    if resume is not None:
        if out is not None:
            raise InputError("give either --out or --resume, not both")
        folder = Path(resume)
        store = ResultsStore(folder)
        store.read_run()  # is it a run at all (before the lock creates anything)?
        store.lock()
        try:
            return _run_locked(store, suite_path, resume=True, runner=runner,
                               episode_fn=episode_fn, progress=progress,
                               retry_errors=retry_errors)
        finally:
            store.unlock()
    if retry_errors:
        raise InputError("--retry-errors goes with --resume DIR")
    suite = load_suite(suite_path if suite_path is not None else default_suite_file())
    folder = _new_folder(suite, out)
    store = ResultsStore(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder} is a file, not a folder; choose another --out")
    if store.exists():
        raise InputError(f"{folder} already holds a run; finish it with --resume {folder} "
                         f"or choose another --out")
    if not store.is_empty():
        raise InputError(f"{folder} is not empty and holds no run; nav-bench writes a new run "
                         f"only into a new or empty folder (it would overwrite report.md, "
                         f"summary.csv, figures/): choose another --out")
    store.lock()
    try:
        return _run_locked(store, suite, resume=False, runner=runner, episode_fn=episode_fn,
                           progress=progress, retry_errors=False)
    finally:
        store.unlock()


def _run_locked(store: ResultsStore, suite_arg: Any, *, resume: bool, runner: Any,
                episode_fn: EpisodeFn, progress: bool, retry_errors: bool) -> Path:
    """The run itself, with the folder's lock held: resume a run or start ``suite_arg``."""
    folder = store.dir
    if resume:
        suite_path = suite_arg
        meta = store.read_run()
        suite = _suite_of_run(meta, folder)
        jobs = expand(suite)
        _check_same_jobs([j["job_id"] for j in meta.get("jobs", [])], jobs, folder,
                         "world, planner or robot files changed since it started")
        if suite_path is not None:
            _check_same_jobs([j.job_id for j in jobs], expand(load_suite(suite_path)), folder,
                             f"{suite_path} is not the suite it ran")
        store.repair()
        replay = _rows_to_replay(store, retry_errors)
        if replay:
            store.drop_rows(replay)
    else:
        suite = suite_arg
        if store.exists():  # another run took the folder between the check and the lock
            raise InputError(f"{folder} already holds a run; choose another --out")
        jobs = expand(suite)
        meta = {"format": RUN_FORMAT, "suite": describe(suite), "started": _now(), "sessions": []}

    with store:
        jobs = with_world_files(jobs, _write_generated_worlds(suite, store))
        done_rows = store.results()
        done = {r.job_id for r in done_rows}
        pending = [j for j in jobs if j.job_id not in done]
        env = environment()
        session: dict[str, Any] = {"started": _now(), "ended": None, "status": "running",
                                   "executor": runner.describe(), "episodes": 0,
                                   "host": env["host"], "nav_bench": env["nav_bench"],
                                   "git": env["git"]}
        meta.update(env)  # the latest session's; each session keeps its own host and version
        meta["jobs"] = [j.summary() for j in jobs]
        meta["total"] = len(jobs)
        meta["sessions"] = [*meta.get("sessions", []), session]
        meta["executor"] = runner.describe()
        meta["workers"] = meta["executor"].get("workers")

        def save_meta(status: str, ended: bool = False) -> None:
            session["status"] = meta["status"] = status
            if ended:
                session["ended"] = meta["ended"] = _now()
            meta["done"] = len(done_rows)
            meta["errors"] = sum(1 for r in done_rows if r.outcome is Outcome.ERROR)
            meta["reached"] = sum(1 for r in done_rows if r.success)
            store.write_run(meta)

        save_meta("running")
        # room for the session's last run.json, should the disk fill up during the run
        store.reserve(2 * store.run_path.stat().st_size + (64 << 10))
        bar = _Progress(len(jobs), done_rows, suite.name, progress)
        status = "failed"
        storage: OSError | None = None
        try:
            with _StopRequests() as stop:
                for outcome in _outcomes(runner, pending, episode_fn, stop):
                    try:
                        done_rows.append(_store_outcome(store, outcome))
                    except OSError as exc:  # disk full or gone: stop, say so, stay resumable
                        storage = exc
                        done_rows[:] = store.results()
                        break
                    session["episodes"] += 1
                    bar.update(outcome.row)
                if storage is None:
                    status = ("interrupted" if stop() and len(done_rows) < len(jobs)
                              else "complete")
                if status == "complete":  # a cluster's size is known by now
                    meta["executor"] = session["executor"] = runner.describe()
        except KeyboardInterrupt:
            status = "interrupted"
        finally:
            bar.close()
            if storage is not None:
                session["error"] = meta["error"] = describe_os_error(storage)
            try:
                save_meta(status, ended=True)
            except OSError as exc:
                storage = storage or exc
            store.release_reserve()
    if storage is not None:
        raise RunStorageError(folder, len(done_rows), len(jobs), storage)
    if status == "interrupted":
        raise RunInterrupted(folder, len(done_rows), len(jobs))
    return folder


def _rows_to_replay(store: ResultsStore, retry_errors: bool) -> set[str]:
    """job_ids whose row a resume replaces: a trace that was not written or is gone, and with
    ``retry_errors`` every ``error`` row."""
    replay = set()
    for row in store.rows():
        job = row.get("job_id")
        if not isinstance(job, str):
            continue
        trace = row.get("trace")
        lost = "trace_error" in row or (isinstance(trace, str) and not (store.dir / trace).exists())
        if lost or (retry_errors and row.get("outcome") == "error"):
            replay.add(job)
    return replay


def _outcomes(runner: Any, pending: list[EpisodeJob], episode_fn: EpisodeFn,
              stop: _StopRequests) -> Iterator[JobOutcome]:
    """The executor's outcomes until it is done or a stop is requested."""
    stream = runner.run(pending, episode_fn, should_stop=stop)
    with contextlib.closing(stream):
        for outcome in stream:
            yield outcome
            if stop():
                return
