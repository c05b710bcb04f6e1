"""The carving's expiry at a gap, from a VFH+ trace replayed through a fresh planner (main's
VFH+): left, at time T, the grid cells near the robot and their parts (black: never seen
through; orange: carved before but expired, carved longer than CARVE_MEMORY_S ago; red: carved
now); right, from T0 to T1, H^p toward the way on (the widest route's point 0.4 m past the one
nearest the robot, closers.py) as the planner has it, as it would be if no carving expired, and
with only the parts on the true surfaces kept (closers.py's counterfactuals), with the
thresholds, and whether the robot turns on the spot (commanded speed 0). MX, MY: a point to
mark (the gap's narrowest point).
PYTHONPATH=$PWD python results/baselines/vfh_s14/expiry_view.py TRACE.npz MX MY T T0 T1 OUT.png
"""
import math
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import Circle, Rectangle

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s14")
from gapwhy import widest_route
from trace_replay import load

from nav_bench.planners.carving import CARVE_MEMORY_S, PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_histogram
from nav_bench.world.draw import draw_world
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

path, mx, my, t_at, t0, t1, out = sys.argv[1], *map(float, sys.argv[2:7]), sys.argv[7]
replay = load(path)
p = replay.planner
s = p.settings
mid = np.array([mx, my])
goal = np.asarray(replay.meta["world"]["goal"], float)
world = world_from_data(replay.meta["world"])
g = static_geometry(world)
loop = replay.true[replay.t >= replay.t[-1] - 90, :2]
start = loop[int(np.argmin(np.hypot(*(loop - goal).T)))]
way = widest_route(g, tuple(start), tuple(goal))[0][1]
run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(way, axis=0).T))])
series = []
state = None
for i in range(len(replay.t)):
    if replay.t[i] > t1 + 1e-9:
        break
    p.act(replay.obs(i))
    t = replay.t[i]
    if t < t0 - 1e-9:
        continue
    xy = replay.odom[i, :2]
    radius = min(s.window_radius, float(np.hypot(*(goal - xy))))
    win = read_window(p.grid.values(copy=False), p.frame, xy, radius, s.c_max)
    ct = p.carving.carved_t.reshape(-1, PARTS)[win.rows * p.frame.cols + win.cols]
    parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)
    on_surface = (clearance(g, (parts + replay.true[i, :2] - xy).reshape(-1, 2)) < 0.03).reshape(parts.shape[:2])
    j = int(np.argmin(np.hypot(*(way - replay.true[i, :2]).T)))
    target = way[min(int(np.searchsorted(run, run[j] + 0.4)), len(way) - 1)]
    k = round((math.atan2(target[1] - xy[1], target[0] - xy[0]) % (2 * math.pi)) / p.alpha) % p.n
    hs = []
    for kept in (~np.isfinite(ct), (ct < t - CARVE_MEMORY_S) & on_surface):  # no expiry; true surfaces
        w = win.carved(kept, parts, xy)
        hs.append(window_histogram(w, w.bearings(), p.n, 0.18 + s.safety_distance, s.window_radius,
                                   s.distance_weight)[k])
    series.append((t, p.primary[k], hs[0], hs[1], 1 if abs(p.v_prev) < 1e-6 else 0))
    if abs(t - t_at) < 0.05:
        state = (xy.copy(), parts, ct.copy(), t)
series = np.array(series)
fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.2))
draw_world(ax, world)
xy, parts, ct, t = state
for (cx, cy) in parts.mean(axis=1):
    ax.add_patch(Rectangle((cx - 0.05, cy - 0.05), 0.1, 0.1, fill=False, color="0.6", lw=0.5))
now = ct >= t - CARVE_MEMORY_S
expired = np.isfinite(ct) & ~now
for sel, colour, label in ((~np.isfinite(ct), "k", "kept: never seen through"),
                           (expired, "#ff7f0e", "kept: carved, expired (> 3 s ago)"),
                           (now, "#d62728", "carved now")):
    q = parts[sel]
    ax.plot(q[:, 0], q[:, 1], ".", ms=2, color=colour, label=label)
ax.add_patch(Circle(xy, 0.18, fill=False, color="#1f77b4", lw=1.5))
ax.add_patch(Circle(xy, 0.23, fill=False, color="#1f77b4", lw=0.8, ls=":"))
ax.plot(mx, my, "x", color="#2ca02c", ms=8, label="gap midpoint")
ax.set_xlim(xy[0] - 1.0, xy[0] + 1.0)
ax.set_ylim(xy[1] - 1.0, xy[1] + 1.0)
ax.set_aspect("equal")
ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
ax.set_title(f"{replay.meta['row']['world']} t = {t:.1f} s: cells and their parts", fontsize=9)
bx.plot(series[:, 0], series[:, 1], color="k", label="H^p toward the gap (main: carving kept 3 s)")
bx.plot(series[:, 0], series[:, 2], color="#ff7f0e", label="the same if no carving expired")
bx.plot(series[:, 0], series[:, 3], color="#9467bd", label="only the parts on the true surfaces kept")
bx.axhline(s.threshold_high, color="#d62728", lw=0.8, ls="--", label="threshold_high")
bx.axhline(s.threshold_low, color="#2ca02c", lw=0.8, ls="--", label="threshold_low")
spin = series[:, 4] > 0
bx.fill_between(series[:, 0], 0, s.threshold_high * 4, where=spin, color="0.9", label="turning on the spot (v = 0)")
bx.axvline(t, color="0.5", lw=0.8)
bx.set_ylim(0, s.threshold_high * 4)
bx.set_xlabel("t, s")
bx.legend(fontsize=7)
bx.set_title("toward the way on (0.4 m along the widest route)", fontsize=9)
fig.tight_layout()
fig.savefig(out, dpi=100)
both = series[:, 1] > s.threshold_high
print(f"cycles {len(series)}: H^p over threshold_high {both.sum()}, of which under threshold_low without expiry "
      f"{(both & (series[:, 2] < s.threshold_low)).sum()}, with the true surfaces "
      f"{(both & (series[:, 3] < s.threshold_low)).sum()}")
