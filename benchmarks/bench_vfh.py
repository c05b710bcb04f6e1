"""VFH+ per-cycle planning cost on a 400 x 400 grid (issue 16: median under 1 ms, p99 under 10 ms).

    python benchmarks/bench_vfh.py [--cycles 600] [--seed 0]

A 40 m x 40 m room (cell 0.1 m: 400 x 400) with random boxes on ~8 % of the area; the robot
drives with VFH+'s own commands (kinematic integration, perfect odometry, the default sonar
ring of the test harness) toward a goal at the far corner; a new goal is drawn when it
arrives. Timed per control cycle, separately: the sonar update of the shared occupancy grid
(``OccupancyGrid.update``, owned by the mapping module) and VFH+'s planning (``act`` with the
update already done: active window, histograms, mask, valley choice).
Prints median and 99th percentile, ms.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from nav_bench.planners.vfh_plus import VFHPlus
from nav_bench.testing.harness import BoxWorld, default_robot, observe


def cluttered_room(size: float, rng: np.random.Generator) -> BoxWorld:
    """A ``size`` m square room with random boxes 0.3..1.5 m on ~8 % of its area, the
    corners kept free."""
    boxes: list[tuple[float, float, float, float]] = []
    area = 0.0
    while area < 0.08 * size * size:
        w, h = rng.uniform(0.3, 1.5, 2)
        x, y = rng.uniform(0.0, size - w), rng.uniform(0.0, size - h)
        if min(math.hypot(x - c, y - d) for c in (1, size - 2) for d in (1, size - 2)) < 2.5:
            continue
        boxes.append((x, y, x + w, y + h))
        area += w * h
    return BoxWorld.room((size, size), boxes)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=600)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    world = cluttered_room(40.0, rng)
    robot = default_robot()
    planner = VFHPlus()
    pose, goal, dt = np.array([1.0, 1.0, math.pi / 4]), np.array([38.0, 38.0]), 0.1
    planner.reset(observe(world, pose, goal, robot, 0.0, dt), np.random.default_rng(0))
    print(f"grid {planner.grid.shape[0]} x {planner.grid.shape[1]} cells of {planner.grid.cell} m")
    grid = planner.grid
    update = grid.update
    plan_ms, update_ms = [], []
    for i in range(args.cycles):
        obs = observe(world, pose, goal, robot, i * dt, dt)
        t0 = time.perf_counter()
        update(obs.pose, obs.ranges, obs.robot.sonar)
        update_ms.append((time.perf_counter() - t0) * 1e3)
        grid.update = lambda *a: None  # act() without its (already done) sonar update
        t0 = time.perf_counter()
        cmd = planner.act(obs)
        plan_ms.append((time.perf_counter() - t0) * 1e3)
        del grid.update
        pose = pose + dt * np.array([cmd.v * math.cos(pose[2]), cmd.v * math.sin(pose[2]), cmd.omega])
        if world.clearance(pose[:2]) < robot.radius:  # a collision: step back and turn
            pose = pose - dt * np.array([cmd.v * math.cos(pose[2]), cmd.v * math.sin(pose[2]), 0.0])
        if math.hypot(*(goal - pose[:2])) < 0.3:
            goal = rng.uniform(1.0, 39.0, 2)
    plan, upd = np.array(plan_ms), np.array(update_ms)
    for name, v in (("planning (act without update)", plan), ("sonar update (shared grid)", upd),
                    ("whole cycle", plan + upd)):
        print(f"{name:30s} median {np.median(v):6.3f} ms   p99 {np.percentile(v, 99):6.3f} ms")


if __name__ == "__main__":
    main()
