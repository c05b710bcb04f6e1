"""What sums a sector of VFH+'s primary histogram: replay a trace through a fresh planner (this
tree) up to time T and list the window's points (cells or kept parts) whose enlargement covers
the sector toward DIR (deg, world), with their distance from the robot, magnitude and
clearance from the TRUE obstacles (m; < 0 inside); every sector's H^p and the part of it from
points 0.03 m or more off the true obstacles; and how many of the kept parts covering the
sector had been carved before and expired (carved longer ago than the carving's memory) rather
than never seen through, with how long ago.
PYTHONPATH=$PWD python results/baselines/vfh_s14/sector_why.py TRACE.npz T DIR
"""
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import covered_sectors, read_window
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

replay = load(sys.argv[1])
t_at, deg = float(sys.argv[2]), float(sys.argv[3])
p = replay.planner
s = p.settings
g = static_geometry(world_from_data(replay.meta["world"]))
captured = {}
orig = p._carved_window


def spy(obs, xy, radius):
    captured["w"] = orig(obs, xy, radius)
    return captured["w"]


p._carved_window = spy
i_at = int(np.argmin(np.abs(replay.t - t_at)))
for i in range(i_at + 1):
    p.act(replay.obs(i))
w = captured["w"]
xy = replay.odom[i_at, :2]
k = round(deg / 5) % p.n
dist = np.maximum(w.dist, 1e-6)
mag = w.certainty ** 2 * (1 + s.distance_weight * (s.window_radius ** 2 - dist ** 2))
if w.weight is not None:
    mag = mag * w.weight
gamma = np.arcsin(np.minimum(1.0, 0.23 / dist))
sec, cell = covered_sectors(w.bearings(), gamma, p.n)
idx = cell[sec == k]
pts = np.stack([w.x, w.y], 1)[idx]
clr = clearance(g, pts)
print(f"t={replay.t[i_at]:.1f} odom ({xy[0]:.2f},{xy[1]:.2f}) true ({replay.true[i_at,0]:.2f},{replay.true[i_at,1]:.2f})"
      f" heading {math.degrees(replay.odom[i_at,2]) % 360:.0f}; sector {k * 5} H^p {p.primary[k]:.0f} "
      f"(points {len(idx)}, sum {mag[idx].sum():.0f}); chosen {p.k_prev * 5:.1f}; masked free: "
      f"{[j * 5 for j in np.flatnonzero(~p.masked)]}")
order = np.argsort(-mag[idx])
for j in order[:25]:
    c = idx[j]
    print(f"  ({w.x[c]:.3f},{w.y[c]:.3f}) d {dist[c]:.3f} bearing {math.degrees(w.bearings()[c]) % 360:.0f} "
          f"gamma {math.degrees(gamma[c]):.0f} cert {w.certainty[c]:.1f} weight {1 if w.weight is None else w.weight[c]:.2f} "
          f"mag {mag[c]:.0f} true clearance {clr[j]:.3f}")

# every sector: H^p, and the share of it from points more than 0.03 m off the true obstacles (the map's)
allpts = np.stack([w.x, w.y], 1)
allclr = clearance(g, allpts)
row = []
for kk in range(p.n):
    ii = cell[sec == kk]
    tot = mag[ii].sum()
    proud = mag[ii][allclr[ii] > 0.03].sum()
    row.append(f"{kk * 5}:{tot:.0f}/{proud:.0f}{'' if p.masked[kk] else '*'}")
print("sector:H^p/from points > 0.03 m off the true obstacles (* free in H^m):")
print(" ".join(row))

# the kept parts covering the sector: never carved, or carved and expired
t = replay.t[i_at]
win = read_window(p.grid.values(copy=False), p.frame, xy, s.window_radius, s.c_max)
flat = win.rows * p.frame.cols + win.cols
parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)  # (M, P, 2)
ct = p.carving.carved_t.reshape(-1, PARTS)[flat]  # (M, P)
mem = t - ct
kept = mem > 3.0  # main's CARVE_MEMORY_S
k = round(deg / 5) % p.n
pts, when, cert = parts[kept], mem[kept], np.repeat(win.certainty[:, None], PARTS, 1)[kept]
d_p = np.hypot(*(pts - xy).T)
beta = np.arctan2(pts[:, 1] - xy[1], pts[:, 0] - xy[0])
gamma = np.arcsin(np.minimum(1.0, 0.23 / np.maximum(d_p, 1e-6)))
sec_p, idx = covered_sectors(beta, gamma, p.n)
idx = idx[sec_p == k]
mag_p = cert[idx] ** 2 * (1 + s.distance_weight * (s.window_radius ** 2 - d_p[idx] ** 2))
never = ~np.isfinite(when[idx])
print(f"t={t:.1f} sector {k * 5}: kept parts covering it {len(idx)}: never carved {never.sum()} "
      f"(magnitude share {mag_p[never].sum() / max(mag_p.sum(), 1e-9):.2f}), carved and expired {(~never).sum()}; "
      f"expired ago (s): {np.round(np.sort(when[idx][~never]), 1).tolist()[:20]}")
