"""Planning cost per control cycle of every shipped planner, over real episodes.

    python benchmarks/bench_planning.py [--planners P,P] [--big-only] [--worlds W,W]
                                        [--time-s 60] [--seed 0] [--rounds 1]

``P``: a planner name, or a name with overrides (``dstar_lite:search_kernel=python``).

Plays each shipped planner (:data:`nav_bench.planners.registry.BUILTIN`) for ``--time-s``
simulated seconds (or until the episode ends) in

* ``clutter_40m``: a 40 m x 40 m world from the ``clutter`` generator (seed 0, density 0.12),
  whose grids are 400 x 400 cells at the planners' 0.1 m cell: the issue's size;
* the paper's worlds (``worlds/paper/``; ``--worlds`` picks some, ``--big-only`` none),

and measures each cycle's planning time: the CPU time of the planner's ``act()`` (everything it
does in a cycle: sensing updates of its maps, search, control; the process CPU clock, which a
loaded machine does not inflate) and the wall-clock time the trace records (``plan_s``).
Prints per planner and world: cycles, median, p99 and max (ms), and per planner on the 400 x 400
grid whether it meets the target (median < 1 ms, p99 < 10 ms). Wall-clock figures: on a shared
machine they include other processes' interference; quote them with the load average printed.

``--rounds N`` plays the whole list N times, planner after planner in each round, and pools each
planner's cycles over the rounds (the same episode each time: the same cycles, timed N times).
On a machine whose speed drifts within minutes (a shared VM: the same code's median moved 2x
between runs a minute apart) one round times each planner in a few seconds of its own, so a
slow spell lands on one planner; pooled rounds spread every planner over the whole run. Each
round's median is printed too, to show the spread.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from nav_bench.episode import EpisodeSettings  # noqa: E402
from nav_bench.episode.loop import run_episode  # noqa: E402
from nav_bench.planners.base import Planner  # noqa: E402
from nav_bench.planners.registry import BUILTIN, make_planner, parse_planner_arg  # noqa: E402
from nav_bench.specs import WorldSpec  # noqa: E402
from nav_bench.world.generate import generate_world  # noqa: E402
from nav_bench.world.load import load_world  # noqa: E402

BIG = "clutter_40m"
TARGET_MEDIAN_MS, TARGET_P99_MS = 1.0, 10.0


def big_world() -> WorldSpec:
    """40 m x 40 m of clutter: 400 x 400 grid cells of 0.1 m."""
    data = generate_world("clutter", seed=0, settings={"size": (40.0, 40.0), "density": 0.12})
    data["name"] = BIG
    return WorldSpec.model_validate(data)


class CpuTimed:
    """Wraps a planner's ``act`` to record the CPU time of each call (s, the process's
    ``time.process_time``): on a loaded machine the wall clock also counts the time other
    processes held the core."""

    def __init__(self, agent: Planner) -> None:
        self.cpu_s: list[float] = []
        act = agent.act

        def timed_act(obs):
            t0 = time.process_time()
            cmd = act(obs)
            self.cpu_s.append(time.process_time() - t0)
            return cmd

        agent.act = timed_act  # type: ignore[method-assign]


class EpisodeTimes(NamedTuple):
    """One episode's per-cycle planning times and its outcome.

    Attributes:
        wall_ms: (N,) wall-clock ms per cycle (the trace's ``plan_s``, finite ones only).
        cpu_ms: (M,) CPU ms per call of ``act``.
        outcome: the row's outcome, e.g. ``reached``.
    """

    wall_ms: np.ndarray
    cpu_ms: np.ndarray
    outcome: str


def plan_ms(world: WorldSpec, planner: str, time_s: float, seed: int) -> EpisodeTimes:
    """Per-cycle planning times (ms) of one episode, wall clock and CPU, and its outcome."""
    spec = parse_planner_arg(planner)
    agent = make_planner(spec)
    timer = CpuTimed(agent)
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=time_s),
                         planner_instance=agent)
    wall = 1e3 * np.asarray(result.trace.plan_s, dtype=float)
    return EpisodeTimes(wall[np.isfinite(wall)], 1e3 * np.asarray(timer.cpu_s),
                        str(result.row.outcome))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--planners", help="comma-separated planner names (default: every shipped one)")
    ap.add_argument("--worlds", help="comma-separated paper world names (default: all)")
    ap.add_argument("--big-only", action="store_true", help="only the 40 m x 40 m world")
    ap.add_argument("--time-s", type=float, default=60.0, help="simulated s per episode (60)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--rounds", type=int, default=1,
                    help="play the list this many times, pooling each planner's cycles (1)")
    args = ap.parse_args()
    if args.rounds < 1:
        sys.exit(f"error: --rounds must be at least 1, got {args.rounds}")
    planners = args.planners.split(",") if args.planners else sorted(BUILTIN)
    unknown = sorted({p.partition(":")[0] for p in planners} - set(BUILTIN))
    if unknown:
        sys.exit(f"error: unknown planner {unknown[0]!r}; shipped: {', '.join(sorted(BUILTIN))}")
    worlds = [big_world()]
    if not args.big_only:
        names = args.worlds.split(",") if args.worlds else None
        for path in sorted((ROOT / "worlds" / "paper").glob("*.yaml")):
            if names is None or path.stem in names:
                worlds.append(load_world(path))
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at the start; "
          f"{args.time_s:g} simulated s per episode at most, seed {args.seed}")
    print(f"{'':37s} {'CPU ms per cycle':^26s}   {'wall-clock ms per cycle':^26s}")
    print(f"{'planner':12s} {'world':14s} {'outcome':8s} {'cycles':>6s} " + 2 * (
        f"{'median':>8s} {'p99':>8s} {'max':>8s}   "))
    verdict = {}
    t0 = time.perf_counter()
    pooled: dict[tuple[str, str], list[EpisodeTimes]] = {}
    for _ in range(args.rounds):
        for planner in planners:
            for world in worlds:
                pooled.setdefault((planner, world.name), []).append(
                    plan_ms(world, planner, args.time_s, args.seed))
    for (planner, world_name), runs in pooled.items():
        cpu = np.concatenate([r.cpu_ms for r in runs])
        wall = np.concatenate([r.wall_ms for r in runs])
        outcome = runs[0].outcome
        stats = [(float(np.median(ms)), float(np.percentile(ms, 99)), float(ms.max()))
                 for ms in (cpu, wall)]
        print(f"{planner:12s} {world_name:14s} {outcome:8s} {len(cpu):6d} " + "".join(
            f"{a:8.3f} {b:8.3f} {c:8.3f}   " for a, b, c in stats), flush=True)
        if len(runs) > 1:
            print(f"{'':37s} CPU median per round: "
                  + " ".join(f"{np.median(r.cpu_ms):.3f}" for r in runs))
        if world_name == BIG:
            verdict[planner] = stats
    print(f"\non {BIG} (400 x 400 cells), target median < {TARGET_MEDIAN_MS:g} ms and "
          f"p99 < {TARGET_P99_MS:g} ms:")
    for planner, stats in verdict.items():
        line = []
        for what, (med, p99, _) in zip(("CPU", "wall"), stats, strict=True):
            ok = med < TARGET_MEDIAN_MS and p99 < TARGET_P99_MS
            line.append(f"{what}: median {med:7.3f} ms p99 {p99:7.3f} ms {'meets' if ok else 'MISSES'}")
        print(f"  {planner:12s} " + ";  ".join(line))
    print(f"load average {os.getloadavg()[0]:.1f} at the end; {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
