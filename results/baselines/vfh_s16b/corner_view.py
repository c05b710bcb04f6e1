"""A contact (or closest approach) at a convex corner, from a VFH+ trace replayed through the
planner of the tree on PYTHONPATH: left, at cycle time T, the grid's occupied cells near the
robot and their parts (black: kept; red: carved), mapped to the world by that cycle's odometry
-> true transform, the true walls and the body; right, from T - 8 s to T, the true gap, the
believed gap (nearest histogram point less the radius) and H^p in the heading's sector / 1e4.
PYTHONPATH=TREE python results/baselines/vfh_s16b/corner_view.py TRACE.npz T TITLE OUT.png
"""
import math
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.patches import Circle

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_box, window_histogram
from nav_bench.world.draw import draw_world
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18
path, t_at, title, out = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
rp = load(path)
p, s = rp.planner, rp.planner.settings
memory = getattr(p.carving, "memory_s", 3.0)
world = world_from_data(rp.meta["world"])
g = static_geometry(world)
true_gap = clearance(g, rp.true[:, :2].astype(float)) - RADIUS
series, state = [], None
for i in range(len(rp.t)):
    if rp.t[i] > t_at + 1e-9:
        break
    obs = rp.obs(i)
    p.act(obs)
    if rp.t[i] < t_at - 8 - 1e-9:
        continue
    xy, yaw = rp.odom[i, :2].astype(float), float(rp.odom[i, 2])
    radius = min(s.window_radius, float(np.hypot(*(obs.goal - xy))))
    win = read_window(p.grid.values(copy=False), p.frame, xy, radius, s.c_max, window_box(p.frame, xy, radius))
    ct = p.carving.carved_t.reshape(-1, PARTS)[win.rows * p.frame.cols + win.cols]
    parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)
    kept = ct < obs.t - memory
    w = win.carved(kept, parts, xy)
    h = window_histogram(w, w.bearings(), p.n, RADIUS + s.safety_distance, s.window_radius, s.distance_weight)
    kh = round(yaw % (2 * math.pi) / p.alpha) % p.n
    series.append((rp.t[i], true_gap[i], float(w.dist.min()) - RADIUS, h[kh]))
    state = (i, parts, kept)
i, parts, kept = state
a = float(rp.true[i, 2] - rp.odom[i, 2])
c, sn = math.cos(a), math.sin(a)


def world_of(q):
    d = q - rp.odom[i, :2]
    return np.stack([c * d[..., 0] - sn * d[..., 1], sn * d[..., 0] + c * d[..., 1]], -1) + rp.true[i, :2]


series = np.array(series)
fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
draw_world(ax, world)
q = world_of(parts)
ax.plot(q[kept][:, 0], q[kept][:, 1], "k.", ms=3, label="kept part")
ax.plot(q[~kept][:, 0], q[~kept][:, 1], ".", color="#d62728", ms=3, label="carved part")
ax.add_patch(Circle(rp.true[i, :2], RADIUS, fill=False, color="#1f77b4", lw=1.5))
ax.add_patch(Circle(rp.true[i, :2], RADIUS + s.safety_distance, fill=False, color="#1f77b4", lw=0.8, ls=":"))
ax.arrow(*rp.true[i, :2], 0.2 * math.cos(rp.true[i, 2]), 0.2 * math.sin(rp.true[i, 2]), width=0.01)
tail = rp.true[max(0, i - 80):i + 1, :2]
ax.plot(tail[:, 0], tail[:, 1], "-", color="#1f77b4", lw=0.8, label="last 8 s (true)")
ax.set_xlim(rp.true[i, 0] - 0.7, rp.true[i, 0] + 0.7)
ax.set_ylim(rp.true[i, 1] - 0.7, rp.true[i, 1] + 0.7)
ax.set_aspect("equal")
ax.legend(fontsize=7, loc="lower left")
ax.set_title(f"{title}: t = {rp.t[i]:.1f} s (memory {memory:g} s, r_rs dotted)", fontsize=9)
bx.plot(series[:, 0], series[:, 1], color="#1f77b4", label="true gap, m")
bx.plot(series[:, 0], series[:, 2], color="k", label="believed gap (nearest point - r), m")
bx.plot(series[:, 0], series[:, 3] / 1e4, color="#ff7f0e", label="H^p heading / 1e4")
for th, col in ((s.threshold_low, "#2ca02c"), (s.threshold_high, "#d62728")):
    bx.axhline(th / 1e4, color=col, lw=0.8, ls="--")
bx.axhline(0, color="0.5", lw=0.8)
bx.set_ylim(-0.05, 0.5)
bx.set_xlabel("t, s")
bx.legend(fontsize=7)
bx.set_title("thresholds 1500 / 2500 dashed", fontsize=9)
fig.tight_layout()
fig.savefig(out, dpi=90)
