"""How many of the kept parts that close a sector had been carved before and expired (carved
longer ago than the carving's memory) rather than never seen through: replay a trace through a
fresh planner (this tree) to time T and split the points covering the sector toward DIR (deg)
by their part's carved_t (never / expired, with how long ago), and their magnitude.
PYTHONPATH=$PWD python results/baselines/vfh_s14/expired.py TRACE.npz T DIR
"""
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import covered_sectors, read_window

replay = load(sys.argv[1])
t_at, deg = float(sys.argv[2]), float(sys.argv[3])
p = replay.planner
s = p.settings
i_at = int(np.argmin(np.abs(replay.t - t_at)))
for i in range(i_at + 1):
    p.act(replay.obs(i))
t = replay.t[i_at]
xy = replay.odom[i_at, :2]
win = read_window(p.grid.values(copy=False), p.frame, xy, s.window_radius, s.c_max)
flat = win.rows * p.frame.cols + win.cols
parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)  # (M, P, 2)
ct = p.carving.carved_t.reshape(-1, PARTS)[flat]  # (M, P)
mem = t - ct
kept = mem > 3.0
k = round(deg / 5) % p.n
pts, when, cert = parts[kept], mem[kept], np.repeat(win.certainty[:, None], PARTS, 1)[kept]
d = np.hypot(*(pts - xy).T)
beta = np.arctan2(pts[:, 1] - xy[1], pts[:, 0] - xy[0])
gamma = np.arcsin(np.minimum(1.0, 0.23 / np.maximum(d, 1e-6)))
sec, idx = covered_sectors(beta, gamma, p.n)
idx = idx[sec == k]
mag = cert[idx] ** 2 * (1 + s.distance_weight * (s.window_radius ** 2 - d[idx] ** 2))
never = ~np.isfinite(when[idx])
print(f"t={t:.1f} sector {k * 5}: kept parts covering it {len(idx)}: never carved {never.sum()} "
      f"(magnitude share {mag[never].sum() / max(mag.sum(), 1e-9):.2f}), carved and expired {(~never).sum()}; "
      f"expired ago (s): {np.round(np.sort(when[idx][~never]), 1).tolist()[:20]}")
