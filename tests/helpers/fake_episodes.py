"""Fake episode functions for runner tests: no simulation, deterministic rows.

Each takes an :class:`~nav_bench.batch.suite.EpisodeJob` and the worker's session (unused) and
returns an object with ``row`` and ``trace`` like :func:`nav_bench.episode.loop.run_episode`'s
result. Module-level functions, so worker processes (forkserver, spawn, Dask) can import
them by name.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from nav_bench.batch.suite import EpisodeJob
from nav_bench.episode import ResultRow, Trace
from nav_bench.interface import Outcome


@dataclass
class FakeResult:
    row: ResultRow
    trace: Any = None


def fake_row(job: EpisodeJob, wall_s: float = 0.0) -> ResultRow:
    """A valid row whose numbers depend only on the job (seed and parameter set)."""
    success = job.seed % 2 == 0
    length = 10.0 + job.seed
    return ResultRow(
        world=job.world_name, world_file=job.world_file, planner=job.planner.planner,
        params=job.params, params_id=job.params_id, seed=job.seed, success=success,
        outcome=Outcome.REACHED if success else Outcome.TIMEOUT, time_s=20.0 + job.seed,
        path_length_m=length, optimal_length_m=10.0, spl=10.0 / length if success else 0.0,
        replans=job.seed, collisions=0, min_clearance_m=0.5, wall_s=wall_s,
        settings=job.settings, events={}, error=None, robot=job.robot_label,
        robot_id=job.robot_id)


def instant(job: EpisodeJob, session: Any = None) -> FakeResult:
    """Returns at once: measures the runner's own overhead."""
    return FakeResult(fake_row(job))


def sleepy(job: EpisodeJob, session: Any = None) -> FakeResult:
    """Sleeps ``NAV_BENCH_FAKE_SLEEP`` seconds (default 0.3): a slow episode to be killed."""
    time.sleep(float(os.environ.get("NAV_BENCH_FAKE_SLEEP", "0.3")))
    return FakeResult(fake_row(job))


def busy(job: EpisodeJob, session: Any = None) -> FakeResult:
    """Burns CPU for ``NAV_BENCH_FAKE_BUSY`` seconds (default 0.2): scaling with workers."""
    end = time.perf_counter() + float(os.environ.get("NAV_BENCH_FAKE_BUSY", "0.2"))
    x = 0
    while time.perf_counter() < end:
        x += 1
    return FakeResult(fake_row(job))


def seed_dependent(job: EpisodeJob, session: Any = None) -> FakeResult:
    """Seed 1 raises, seed 2 hangs, seed 3 kills its own process; others return at once."""
    if job.seed == 1:
        raise ValueError("fake episode failure")
    if job.seed == 2:
        while True:
            time.sleep(0.05)
    if job.seed == 3:
        os._exit(3)
    return FakeResult(fake_row(job))


def instant_traced(job: EpisodeJob, session: Any = None) -> FakeResult:
    """Returns at once with a real-size trace (3000 cycles, 6 sonars): the parent's cost of
    storing a 300 s episode's trace is part of the runner overhead."""
    rng = np.random.default_rng(job.seed)
    t = np.arange(3000) * 0.1
    pose = np.cumsum(rng.normal(0.0, 0.01, (3000, 3)), axis=0)
    trace = Trace(world=job.world, t=t, true_pose=pose, odom_pose=pose + 0.01, cmd=rng.random((3000, 2)),
                  ranges=rng.random((3000, 6)) * 3.0, movers=np.zeros((3000, 0, 2)))
    return FakeResult(fake_row(job), trace)
