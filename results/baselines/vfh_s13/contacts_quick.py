"""The contact starts of episode traces (true body clearance <= 2 mm), with no replay: the
time, the true position, the touching side (deg from the heading, CCW +), the command of the
cycle before, and the least clearance of the next 3 s.

PYTHONPATH=$PWD python results/baselines/vfh_s13/contacts_quick.py TRACE.npz [TRACE.npz ...]
"""
import json
import math
import sys

import numpy as np

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18  # m, the default robot's body


def touching_side(geometry, xy: np.ndarray, yaw: float) -> float:
    """Bearing (deg, from the heading) of the body point nearest an obstacle."""
    ang = np.radians(np.arange(0, 360, 5))
    pts = xy + (RADIUS + 0.01) * np.stack([np.cos(yaw + ang), np.sin(yaw + ang)], axis=1)
    return (math.degrees(ang[int(np.argmin(clearance(geometry, pts)))]) + 180) % 360 - 180


for path in sys.argv[1:]:
    trace = np.load(path, allow_pickle=True)
    meta = json.loads(str(trace["meta"]))
    geometry = static_geometry(world_from_data(meta["world"]))
    t, true, cmd = trace["t"], trace["true_pose"], trace["cmd"]
    gap = clearance(geometry, true[:, :2].astype(float)) - RADIUS
    touch = gap <= 0.002
    starts = [i for i in range(1, len(t)) if touch[i] and not touch[i - 1]]
    lines = [f"t={t[i]:.1f} ({true[i, 0]:.2f},{true[i, 1]:.2f}) side "
             f"{touching_side(geometry, true[i, :2].astype(float), float(true[i, 2])):+.0f} "
             f"v {cmd[i - 1, 0]:.2f} w {cmd[i - 1, 1]:+.2f} min gap {gap[i:i + 30].min():+.3f}" for i in starts]
    print(meta["row"]["world"], meta["row"]["outcome"], len(starts), *lines, sep="\n  ")
