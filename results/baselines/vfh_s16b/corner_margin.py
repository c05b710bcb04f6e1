"""How near VFH+ believes the wall is, against the truth, while the robot is within 0.4 m of a
spot (the convex corner it touches): every cycle there, the believed gap (the nearest of the
histogram's points, whole cells or a cell's kept parts, less the radius, in the odometry frame)
and the true gap (the body's clearance). Replays the trace through the planner of the tree on
PYTHONPATH (run main's traces with main's tree, D's with D's).
PYTHONPATH=TREE python results/baselines/vfh_s16b/corner_margin.py SX SY TRACE.npz...
"""
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_box
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18
spot = np.array([float(sys.argv[1]), float(sys.argv[2])])
for path in sys.argv[3:]:
    rp = load(path)
    p, s = rp.planner, rp.planner.settings
    memory = getattr(p.carving, "memory_s", 3.0)
    g = static_geometry(world_from_data(rp.meta["world"]))
    true_gap = clearance(g, rp.true[:, :2].astype(float)) - RADIUS
    there = np.hypot(*(rp.true[:, :2] - spot).T) < 0.4
    last = int(np.flatnonzero(there)[-1]) if there.any() else -1
    rows = []
    for i in range(last + 1):
        obs = rp.obs(i)
        p.act(obs)
        if not there[i]:
            continue
        xy = rp.odom[i, :2].astype(float)
        radius = min(s.window_radius, float(np.hypot(*(obs.goal - xy))))
        win = read_window(p.grid.values(copy=False), p.frame, xy, radius, s.c_max, window_box(p.frame, xy, radius))
        if len(win) == 0:
            continue
        ct = p.carving.carved_t.reshape(-1, PARTS)[win.rows * p.frame.cols + win.cols]
        w = win.carved(ct < obs.t - memory, cell_parts(np.stack([win.x, win.y], 1), p.frame.cell), xy)
        rows.append((true_gap[i], float(w.dist.min()) - RADIUS, float(win.dist.min()) - RADIUS))
    r = np.array(rows)
    close = r[:, 0] < 0.03
    print(f"{rp.meta['row']['world']} seed {rp.meta['row'].get('seed')} ({rp.meta['row']['outcome']}, memory {memory:g} s):"
          f" {len(r)} cycles near the corner; true gap < 3 cm in {int(close.sum())};"
          f" believed - true gap median {np.median(r[:, 1] - r[:, 0]):+.3f} m"
          + (f", where true < 3 cm: believed gap median {np.median(r[close, 1]):+.3f} m"
             f" (whole cells {np.median(r[close, 2]):+.3f})" if close.any() else ""))
