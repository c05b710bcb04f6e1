"""The Dask executor on a LocalCluster with 1 and 2 workers: throughput and scheduler overhead.

    python benchmarks/bench_dask.py [--trivial 40] [--episodes 12] [--time-s 10]
                                    [--episode-s S] [--suite-size 10000] [--hours 1]

Measures, each executor in turn (local process pool, Dask LocalCluster; 1 and 2 workers):

1. overhead per episode: ``--trivial`` episodes that return at once (the runner's test
   function ``tests.helpers.fake_episodes.instant``) after ``n0 = 5`` warm-up ones in the same
   run: ``(T(n0 + N) - T(n0)) / N`` once the cluster is up, and the cluster's start-up;
2. episodes per minute on ``--episodes`` short real episodes (goal_seek and EO/PC on the
   tiny test worlds, ``--time-s`` simulated s at most), with the cluster's start-up and from
   the first result on, and their mean wall time on a worker.

Then the arithmetic: workers for ``--suite-size`` episodes in ``--hours``, from a mean episode
time ``--episode-s`` (worker seconds; default: the issue's default-suite figure 2,007 CPU-s /
280 episodes = 7.2 s) plus the Dask overhead per episode measured with 1 worker and the
cluster's start-up: ``workers = ceil(size x (episode_s + overhead_1) / (3600 x hours -
start-up))``; and whether the client and scheduler pass that many episodes in time (the trivial
episodes' time per episode with 2 workers, x size). Wall-clock
figures: quote them with the load average printed.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # tests.helpers: the trivial episode function, the tiny worlds

from nav_bench.batch.executors import make_executor  # noqa: E402
from nav_bench.batch.suite import expand, load_suite  # noqa: E402
from nav_bench.batch.worker import run_job  # noqa: E402
from tests.helpers import fake_episodes, tiny  # noqa: E402

ISSUE_EPISODE_S = 2007.0 / 280  # the issue's default suite: worker CPU-s per episode


def timed(executor: str, workers: int, jobs, fn, n0: int) -> tuple[float, float, list[float]]:
    """Seconds to the ``n0``-th result, seconds from there to the last, and the rows' wall_s."""
    runner = make_executor(executor, workers)
    t0 = time.perf_counter()
    t_n0, walls = None, []
    for i, outcome in enumerate(runner.run(jobs, fn), start=1):
        walls.append(outcome.row.wall_s)
        if i == n0:
            t_n0 = time.perf_counter()
    end = time.perf_counter()
    assert t_n0 is not None
    return t_n0 - t0, end - t_n0, walls


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--trivial", type=int, default=40, help="trivial episodes per overhead figure")
    ap.add_argument("--episodes", type=int, default=12, help="short real episodes per figure")
    ap.add_argument("--time-s", type=float, default=10.0, help="their simulated s at most")
    ap.add_argument("--episode-s", type=float, default=ISSUE_EPISODE_S,
                    help="mean worker s of a suite episode, for the arithmetic")
    ap.add_argument("--suite-size", type=int, default=10_000)
    ap.add_argument("--hours", type=float, default=1.0)
    args = ap.parse_args()
    n0 = 5
    configs = [("local", 1), ("dask", 1), ("local", 2), ("dask", 2)]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        trivial_suite = tiny.write_suite(folder, name="trivial", seeds=n0 + args.trivial,
                                         planners="{seek: goal_seek}",
                                         worlds=f"['{folder}/worlds/tiny_open.yaml']")
        trivial = expand(load_suite(trivial_suite))
        seeds = max(1, args.episodes // 4)  # 2 worlds x 2 planners x seeds
        real_suite = tiny.write_suite(
            folder, name="real", seeds=seeds, planners="{seek: goal_seek, eopc: eopc}",
            limits=f"{{time_s: {args.time_s}, stuck_s: {args.time_s}, wall_s: 300}}")
        real = expand(load_suite(real_suite))
        print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at the start")
        print(f"{'executor':8s} {'workers':>7s} {'start-up s':>10s} {'overhead ms/ep':>14s} "
              f"{'real ep/min':>11s} {'after 1st':>9s} {'mean ep wall s':>14s}")
        figures = {}
        for executor, workers in configs:
            startup, rest, _ = timed(executor, workers, trivial, fake_episodes.instant, n0)
            overhead = rest / args.trivial
            t_first, t_rest, walls = timed(executor, workers, real, run_job, 1)
            per_min = 60.0 * len(real) / (t_first + t_rest)
            steady = 60.0 * (len(real) - 1) / t_rest  # from the first result on: no start-up
            mean_wall = sum(walls) / len(walls)
            figures[(executor, workers)] = (startup, overhead, per_min, mean_wall)
            print(f"{executor:8s} {workers:7d} {startup:10.2f} {1e3 * overhead:14.1f} "
                  f"{per_min:11.1f} {steady:9.1f} {mean_wall:14.2f}", flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} at the end")
    # Two bounds. Worker capacity: with one worker the trivial episodes' time is everything one
    # episode costs besides its own work (client, scheduler, worker, the episode process's round
    # trip) -- charged to a worker, conservatively. The client and scheduler: with two workers the
    # trivial episodes show what they pass per second; 10,000 episodes must fit through them.
    startup = figures[("dask", 2)][0]
    per_episode = figures[("dask", 1)][1]
    serial = figures[("dask", 2)][1]
    budget = 3600.0 * args.hours - startup
    need = args.suite_size * (args.episode_s + per_episode)
    workers = math.ceil(need / budget)
    print(f"\n{args.suite_size} episodes in {args.hours:g} h, episodes of {args.episode_s:.2f} "
          f"worker-s:\n  workers = {args.suite_size} x ({args.episode_s:.2f} s + "
          f"{1e3 * per_episode:.1f} ms Dask overhead, 1 worker) / ({3600 * args.hours:.0f} s - "
          f"{startup:.1f} s start-up) = {need / budget:.1f} -> {workers} workers, one core each")
    print(f"  client and scheduler: {args.suite_size} x {1e3 * serial:.1f} ms (trivial episodes, "
          f"2 workers) = {args.suite_size * serial:.0f} s of the {budget:.0f} s "
          f"({'fits' if args.suite_size * serial < budget else 'DOES NOT FIT'})")

if __name__ == "__main__":
    main()
