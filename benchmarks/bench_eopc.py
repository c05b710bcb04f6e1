"""EO/PC per-cycle costs: the grid update and the PC decision, on a 10 m and a 40 m world.

    python benchmarks/bench_eopc.py [--reps 3000] [--seed 0]

Prints median and 99th percentile (microseconds) of

1. one grid update per control cycle: ``OccupancyGrid.update`` (6 sonars, 25 deg cones,
   3 m range, 30% no-echo readings) + ``VisitGrid.add``;
2. one PC decision: all 16 neighbours scored and one chosen (``choose_neighbour`` on a
   grid already mapped from many poses);
3. one blocked-path check at the arrival at Pi (``goal_path_blocked``, the straight path from a
   point near the centre to the far corner: 7 m / 28 m long), on the segment and on a corridor
   of the robot's width; it runs at most once per arrival at Pi;
4. one whole ``EOPC.act`` while driving (grids + EO, no re-plan),

on a 100 x 100 grid (10 m world, cell 0.1 m) and a 400 x 400 grid (40 m).
Targets: 1 and 2 under 1 ms median at 100 x 100; the PC decision independent of grid size;
3 under 0.2 ms at 400 x 400.
The machine's other jobs show up in the 99th percentile: note the load average printed.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from collections.abc import Callable

import numpy as np

from nav_bench.interface import Observation, RobotInfo, SonarInfo
from nav_bench.mapping import OccupancyGrid, VisitGrid
from nav_bench.planners.eopc import EOPC, choose_neighbour, goal_path_blocked


def diffbot() -> RobotInfo:
    """The default robot's sonar ring: -90..90 deg on the body edge (0.18 m)."""
    angles = np.radians([-90.0, -45.0, -15.0, 15.0, 45.0, 90.0])
    sonar = SonarInfo(angles=angles, offsets=0.18 * np.stack([np.cos(angles), np.sin(angles)], 1),
                      cone=math.radians(25.0), min_range=0.05, max_range=3.0)
    return RobotInfo(radius=0.18, wheel_base=0.26, v_max=0.6, omega_max=2.0, sonar=sonar)


def readings(rng: np.random.Generator) -> np.ndarray:
    """Six readings: 30% no echo (max range: the largest cone to update), else 0.2..2.9 m."""
    return np.where(rng.random(6) < 0.3, 3.0, rng.uniform(0.2, 2.9, 6))


def percentiles(fn: Callable[[int], object], reps: int) -> tuple[float, float]:
    """(median, p99) in microseconds of ``fn(i)`` over ``reps`` calls (after 50 warm-up calls)."""
    for i in range(50):
        fn(i)
    times = np.empty(reps)
    for i in range(reps):
        t0 = time.perf_counter_ns()
        fn(i)
        times[i] = time.perf_counter_ns() - t0
    return float(np.median(times) / 1e3), float(np.percentile(times, 99) / 1e3)


def bench_world(size: float, reps: int, seed: int) -> dict[str, tuple[float, float]]:
    rng = np.random.default_rng(seed)
    robot = diffbot()
    bounds = (0.0, 0.0, size, size)
    pmo, pmt = OccupancyGrid(bounds), VisitGrid(bounds)
    poses = np.column_stack([rng.uniform(1.0, size - 1.0, reps + 50),
                             rng.uniform(1.0, size - 1.0, reps + 50),
                             rng.uniform(-math.pi, math.pi, reps + 50)])
    scans = np.array([readings(rng) for _ in range(reps + 50)])

    def update(i: int) -> None:
        pmo.update(poses[i], scans[i], robot.sonar)
        pmt.add(poses[i, :2])

    out = {"grid update (PMO + PMT)": percentiles(update, reps)}

    # a mapped neighbourhood for the decision: the robot has looked around its breakpoint
    centre = np.array([size / 2, size / 2])
    for _ in range(300):
        pose = np.array([*(centre + rng.uniform(-1.5, 1.5, 2)), rng.uniform(-math.pi, math.pi)])
        pmo.update(pose, readings(rng), robot.sonar)
        pmt.add(pose[:2])
    values, counts, settings = pmo.values(copy=False), pmt.counts, EOPC.Settings()
    goal = np.array([size - 0.5, size - 0.5])
    headings = rng.uniform(-math.pi, math.pi, reps + 50)
    out["PC decision (16 neighbours)"] = percentiles(
        lambda i: choose_neighbour(values, counts, pmo.frame, centre, headings[i], goal, settings),
        reps)

    starts = centre + rng.uniform(-0.5, 0.5, (reps + 50, 2))
    for name, half_width in (("segment", 0.0), ("corridor 0.18 m", 0.18)):
        out[f"blocked-path check, {name}"] = percentiles(
            lambda i, w=half_width: goal_path_blocked(values, pmo.frame, starts[i], goal,
                                                      settings.occupied_above, w), reps)

    planner = EOPC()
    obs = [Observation(t=0.1 * i, pose=np.array([1.0 + 0.05 * i % (size - 2), size / 2, 0.0]),
                       goal=goal, ranges=np.full(6, 3.0), robot=robot, bounds=bounds, dt=0.1)
           for i in range(reps + 50)]
    planner.reset(obs[0], rng)
    out["EOPC.act, driving"] = percentiles(lambda i: planner.act(obs[i]), reps)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=3000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    results = {f"{round(s / 0.1)} x {round(s / 0.1)} ({s:g} m)": bench_world(s, args.reps, args.seed)
               for s in (10.0, 40.0)}
    grids = list(results)
    rows = list(next(iter(results.values())))
    print(f"EO/PC per-cycle costs, {args.reps} repetitions, load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; microseconds, median / p99")
    print(f"{'':30s}" + "".join(f"{g:>26s}" for g in grids))
    for row in rows:
        cells = "".join(f"{results[g][row][0]:>14.0f} / {results[g][row][1]:>7.0f}  " for g in grids)
        print(f"{row:30s}{cells}")


if __name__ == "__main__":
    main()
