"""What keeps the way on closed at a gap ending, by counterfactual histograms: replay a VFH+
trace through a fresh planner (main's VFH+) and, at each cycle the robot is within NEAR m of
the way on's narrowest point (gapwhy.py), take the direction to the point of the way on
(the widest route to the goal, gapwhy.widest_route: along the middle of its gaps) LOOK m past the route point nearest the robot. Count the
cycles that direction's sector is over threshold_high as the planner has it, and of those the
ones it would be under threshold_low
  * no expiry: if no carving expired (the parts carved before, more than CARVE_MEMORY_S ago,
    left out too), and
  * true surfaces: if every part 0.03 m or more off the true obstacles were carved (only the
    parts on or in the obstacles kept, the best a carving can do).
The first measures the carving's memory, the second the map's proud parts; what neither opens
is closed by the obstacles themselves within r_rs of the ray (VFH+'s enlargement).
--at X Y (the fifteenth session): the gap's midpoint, m, in place of the route's least-clearance point, which
lands on a one-sided hug where the widest route keeps r* from one obstacle over a stretch (vfh_s15).
PYTHONPATH=$PWD python results/baselines/vfh_s14/closers.py TRACE.npz [--near 1.3] [--look 0.8] [--at X Y]
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s14")
from gapwhy import gap_midpoint, widest_route
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_histogram
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

ap = argparse.ArgumentParser()
ap.add_argument("trace")
ap.add_argument("--near", type=float, default=1.3)
ap.add_argument("--look", type=float, default=0.8)
ap.add_argument("--at", type=float, nargs=2, default=None)
a = ap.parse_args()
replay = load(a.trace)
world = world_from_data(replay.meta["world"])
g = static_geometry(world)
goal = np.asarray(world.goal, float)
loop = replay.true[replay.t >= replay.t[-1] - 90, :2]
best = loop[int(np.argmin(np.hypot(*(loop - goal).T)))]
mid, half = gap_midpoint(g, tuple(best), tuple(goal), 1.5)
if a.at is not None:  # the two-sided constriction
    mid = np.asarray(a.at, float)
    half = float(clearance(g, mid[None])[0])
way = widest_route(g, tuple(best), tuple(goal))[0][1]  # along the middle of the gaps
run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(way, axis=0).T))])
p = replay.planner
s = p.settings
r_rs = 0.18 + s.safety_distance
n_near = closed = open_noexp = open_true = open_both = 0
for i in range(len(replay.t)):
    p.act(replay.obs(i))
    xy = replay.odom[i, :2]
    if np.hypot(*(mid - xy)) > a.near:
        continue
    n_near += 1
    j = int(np.argmin(np.hypot(*(way - replay.true[i, :2]).T)))
    target = way[min(int(np.searchsorted(run, run[j] + a.look)), len(way) - 1)]
    k = round((math.atan2(target[1] - xy[1], target[0] - xy[0]) % (2 * math.pi)) / p.alpha) % p.n
    if p.primary[k] <= s.threshold_high:
        continue
    closed += 1
    radius = min(s.window_radius, float(np.hypot(*(goal - xy))))
    win = read_window(p.grid.values(copy=False), p.frame, xy, radius, s.c_max)
    ct = p.carving.carved_t.reshape(-1, PARTS)[win.rows * p.frame.cols + win.cols]
    parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)
    # the map in the odometry frame against the true obstacles: shift by the odometry error
    err = replay.true[i, :2] - xy
    on_surface = (clearance(g, (parts + err).reshape(-1, 2)) < 0.03).reshape(parts.shape[:2])
    kept_now = ct < replay.t[i] - 3.0
    h = {}
    for name, kept in (("noexp", ~np.isfinite(ct)), ("true", kept_now & on_surface),
                       ("both", ~np.isfinite(ct) & on_surface)):
        w = win.carved(kept, parts, xy)
        h[name] = window_histogram(w, w.bearings(), p.n, r_rs, s.window_radius, s.distance_weight)[k]
    open_noexp += h["noexp"] < s.threshold_low
    open_true += h["true"] < s.threshold_low
    open_both += h["both"] < s.threshold_low
print(f"{replay.meta['row']['world']}: narrowest point ({mid[0]:.2f}, {mid[1]:.2f}), gap {2 * half:.3f} m; cycles "
      f"within {a.near} m {n_near}, the way on closed (> threshold_high) {closed}; of those open (< threshold_low) "
      f"with no expiry {open_noexp}, with true surfaces {open_true}, with both {open_both}")
