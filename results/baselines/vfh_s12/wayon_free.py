"""At each reversal of VFH+'s chosen direction in the last 90 s (replayed from the trace), is
the way on open in the masked histogram? The way-on bearing: from the robot to the point
0.6 m along the shortest path to the goal with the obstacles inflated by INFLATE_M (default
the 0.18 m radius, a route that hugs corners; 0.3 m keeps it 0.3 m off them). Prints per reversal: t, position,
way-on bearing, whether its sector is free, the chosen direction and the goal bearing.
PYTHONPATH=$PWD python results/baselines/vfh_s12/wayon_free.py TRACE.npz [INFLATE_M]
"""
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.world.geometry import static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import free_cell_near, grid_path
from nav_bench.world.raster import rasterize

replay = load(sys.argv[1])
meta, t, true, p, obs = replay.meta, replay.t, replay.true, replay.planner, replay.obs
world = world_from_data(meta["world"])
inflate = float(sys.argv[2]) if len(sys.argv) > 2 else 0.18  # m: 0.3 keeps the route off the corners
raster = rasterize(static_geometry(world), 0.05, inflate=inflate)
goal = np.asarray(meta["world"]["goal"], float)
prev = None
n_rev = n_open = 0
for i in range(len(t)):
    p.act(obs(i))
    k = None if p.blocked else p.k_prev * 5.0
    if k is not None and prev is not None and t[i] >= t[-1] - 90 and abs((k - prev + 180) % 360 - 180) > 100:
        xy = true[i, :2].astype(float)
        s = free_cell_near(raster, tuple(xy), 0.6)
        g = free_cell_near(raster, tuple(goal), 0.6)
        found = grid_path(raster.occupied, s, g)
        cells = found[1]
        pts = np.column_stack([(cells[:, 1] + 0.5) * 0.05, (cells[:, 0] + 0.5) * 0.05])
        along = np.r_[0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
        aim = pts[min(np.searchsorted(along, 0.6), len(pts) - 1)]
        bearing = math.degrees(math.atan2(aim[1] - xy[1], aim[0] - xy[0])) % 360
        ks = round(bearing / 5) % 72
        free = not bool(p.masked[ks])
        gb = math.degrees(math.atan2(goal[1] - xy[1], goal[0] - xy[0])) % 360
        n_rev += 1
        n_open += free
        print(f"  t={t[i]:.1f} ({xy[0]:.2f},{xy[1]:.2f}) way on {bearing:.0f} deg free={free} "
              f"H^p {p.primary[ks]:.0f}; chosen {prev:.0f} -> {k:.0f}; goal {gb:.0f}")
    if k is not None:
        prev = k
print(f"{meta['row']['world']}: reversals in the last 90 s {n_rev}, way on free at {n_open}")
