"""Replay office_11's trace through a fresh planner; each cycle the robot is within 1.3 m of a
gap's midpoint, the histogram in the direction of the midpoint (H^p, masked free?).
PYTHONPATH=$PWD python results/baselines/vfh_s12/gapview.py office_11_TRACE.npz
"""
import json
import math
import sys

import numpy as np

import nav_bench.planners.vfh_plus as vfh

sys.path.insert(0, "results/baselines/vfh_s11")
from contacts import robot_info

from nav_bench.interface import Observation

path = sys.argv[1]
gaps = {"SE": (10.33, 4.99), "NE": (10.155, 5.924)}
tr = np.load(path, allow_pickle=True)
meta = json.loads(str(tr["meta"]))
robot = robot_info()
goal = np.asarray(meta["world"]["goal"], float)
bounds = (0.0, 0.0, *meta["world"]["size"])
t, odom, ranges, true = (tr[k] for k in ("t", "odom_pose", "ranges", "true_pose"))
p = vfh.VFHPlus(**meta["row"]["params"])
def obs(i):
    return Observation(float(t[i]), odom[i].astype(float), goal, ranges[i].astype(float), robot, bounds, 0.1)
p.reset(obs(0), np.random.default_rng(0))
stats = {g: [0, 0, 1e9] for g in gaps}
for i in range(len(t)):
    p.act(obs(i))
    xy = odom[i, :2]
    for g, m in gaps.items():
        d = math.hypot(m[0] - xy[0], m[1] - xy[1])
        if d < 1.3:
            k = round((math.atan2(m[1] - xy[1], m[0] - xy[0]) % (2 * math.pi)) / p.alpha) % p.n
            free = not p.masked[k]
            stats[g][0] += 1
            stats[g][1] += free
            stats[g][2] = min(stats[g][2], p.primary[k])
            if i % 50 == 0:
                print(f"t={t[i]:.1f} at ({xy[0]:.2f},{xy[1]:.2f}) gap {g} d={d:.2f} dir {k*5} H^p {p.primary[k]:.0f}"
                      f" (+-1: {p.primary[(k-1)%p.n]:.0f},{p.primary[(k+1)%p.n]:.0f}) free {free} chosen {p.k_prev*5:.0f}")
print({g: f"cycles within 1.3 m {s[0]}, free toward midpoint {s[1]}, least H^p {s[2]:.0f}" for g, s in stats.items()})
