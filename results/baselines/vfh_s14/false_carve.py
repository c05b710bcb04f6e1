"""Parts carved inside the true obstacles: replay a VFH+ trace through a fresh planner of this
tree and, every second, count the parts within 0.6 m of the robot that are carved now (the
histogram leaves them out) although their centre lies more than 0.02 m inside a true obstacle
(a false see-through), and those carved but 0.03 m or more outside (the map's proud parts,
rightly carved). ``--time 3``: the carving's memory as on main (3 s of the episode's time).
PYTHONPATH=$PWD python results/baselines/vfh_s14/false_carve.py TRACE.npz [--time 3]
"""
import argparse
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.footprint import cell_parts
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

ap = argparse.ArgumentParser()
ap.add_argument("trace")
ap.add_argument("--time", type=float, default=None)
a = ap.parse_args()
replay = load(a.trace)
p = replay.planner
if a.time is not None:  # main's carving: memory in seconds of the episode
    p.carving.memory = a.time
    update = p.carving.update
    p.carving.update = lambda *args, clock=None: update(*args)
g = static_geometry(world_from_data(replay.meta["world"]))
false_total = right_total = 0
worst = (0, 0.0)
for i in range(len(replay.t)):
    p.act(replay.obs(i))
    if i % 10:
        continue
    xy = replay.odom[i, :2]
    noted = np.argwhere(p.carving.noted)
    if len(noted) == 0:
        continue
    centres = np.stack([p.frame.xmin + (noted[:, 1] + 0.5) * p.frame.cell,
                        p.frame.ymin + (noted[:, 0] + 0.5) * p.frame.cell], 1)
    near = np.hypot(*(centres - xy).T) < 0.6
    noted, centres = noted[near], centres[near]
    if len(noted) == 0:
        continue
    now = replay.t[i] if a.time is not None else p.travelled
    carved = p.carving.carved_t[noted[:, 0], noted[:, 1]] >= now - p.carving.memory  # (M, PARTS)
    parts = cell_parts(centres, p.frame.cell)[carved]
    if len(parts) == 0:
        continue
    c = clearance(g, parts)
    nf = int((c < -0.02).sum())
    false_total += nf
    right_total += int((c >= 0.03).sum())
    if nf > worst[0]:
        worst = (nf, float(replay.t[i]))
print(f"{replay.meta['row']['world']} {replay.meta['row']['outcome']}: carved parts within 0.6 m, summed over the "
      f"1 s samples: inside the true obstacles (< -0.02 m) {false_total}, proud (>= 0.03 m) {right_total}; "
      f"most inside at one sample: {worst[0]} at t={worst[1]:.1f}")
