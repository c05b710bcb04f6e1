"""Replay a stored VFH+ trace's odometry and sonar readings through a fresh planner (its
defaults) and print the histograms at the moments the robot turns back along one axis.

The planner is deterministic in its observations, so the histograms are those it had.
PYTHONPATH=$PWD python results/baselines/vfh_s6/replay_histogram.py TRACE.npz AXIS
(AXIS 0: turning points in x, 1: in y; the trace from `nav-bench episode ... --trace`).
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np

from nav_bench.interface import Observation
from nav_bench.planners.vfh_plus import VFHPlus
from nav_bench.testing.harness import default_robot


def main(path: str, axis: int) -> None:
    trace = np.load(path, allow_pickle=True)
    world = json.loads(str(trace["meta"]))["world"]
    robot, goal = default_robot(), np.asarray(world["goal"], dtype=float)
    bounds = (0.0, 0.0, *world["size"])
    t, odom, ranges, true = trace["t"], trace["odom_pose"], trace["ranges"], trace["true_pose"]

    def observation(i: int) -> Observation:
        return Observation(float(t[i]), odom[i].astype(float), goal, ranges[i].astype(float), robot, bounds, 0.1)

    planner = VFHPlus()
    planner.reset(observation(0), np.random.default_rng(0))
    c = true[:, axis]
    late = c[t > 60]
    turns = [i for i in range(5, len(c) - 5)
             if t[i] > 60 and c[i] == c[i - 5:i + 6].max() and c[i] > np.percentile(late, 90)][:2]
    for i in range(len(t)):
        planner.act(observation(i))
        if i in turns:
            goal_deg = math.degrees(math.atan2(goal[1] - odom[i, 1], goal[0] - odom[i, 0])) % 360
            print(f"t={t[i]:.1f} s at ({true[i, 0]:.2f}, {true[i, 1]:.2f}), goal at {goal_deg:.0f} deg")
            print("  free sectors (deg):", (np.flatnonzero(~planner.masked) * 5).tolist())
            print("  H^p every 15 deg:", {a: int(planner.primary[a // 5]) for a in range(0, 360, 15)})


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
