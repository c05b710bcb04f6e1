"""A stored VFH+ trace set up for replay through a fresh planner (shared by gapview.py and
wayon_free.py): the trace's arrays, the world's goal and bounds, and the planner reset on the
first observation.
"""
import json
import sys
from dataclasses import dataclass

import numpy as np

import nav_bench.planners.vfh_plus as vfh
from nav_bench.interface import Observation

sys.path.insert(0, "results/baselines/vfh_s11")
from contacts import robot_info


@dataclass
class TraceReplay:
    meta: dict
    t: np.ndarray  # (N,) s
    odom: np.ndarray  # (N, 3) odometry poses
    ranges: np.ndarray  # (N, 6) m
    true: np.ndarray  # (N, 3) true poses
    planner: vfh.VFHPlus

    def obs(self, i: int) -> Observation:
        """The observation of cycle ``i``, as the episode gave it."""
        goal = np.asarray(self.meta["world"]["goal"], float)
        bounds = (0.0, 0.0, *self.meta["world"]["size"])
        return Observation(float(self.t[i]), self.odom[i].astype(float), goal, self.ranges[i].astype(float),
                           robot_info(), bounds, 0.1)


def load(path: str) -> TraceReplay:
    """The trace at ``path`` and a VFH+ with its row's parameters, reset on cycle 0."""
    tr = np.load(path, allow_pickle=True)
    meta = json.loads(str(tr["meta"]))
    t, odom, ranges, true = (tr[k] for k in ("t", "odom_pose", "ranges", "true_pose"))
    replay = TraceReplay(meta, t, odom, ranges, true, vfh.VFHPlus(**meta["row"]["params"]))
    replay.planner.reset(replay.obs(0), np.random.default_rng(0))
    return replay
