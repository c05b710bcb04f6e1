"""First-pass class of every non-reached VFH+ episode from its trace (no planner replay).

From the point of the robot's last 90 s nearest the goal ("best"), the shortest way on to the
goal (robot radius 0.18 m); how far it climbs above best's straight-line goal distance
(rise > 0: the robot must first go farther from the goal than its loop ever gets), and the
narrowest gap on it (2 r*, r* the largest obstacle inflation that keeps a route no longer than
1.25 x). Class: 'local minimum' if rise > 0.3 m; else 'gap' if the gap is < 0.66 m
(= 2 (r_rs + one cell): closed in VFH+'s histogram once the shared sonar map widens each side
by a cell); else 'other'.
PYTHONPATH=$PWD python results/baselines/vfh_s12/classify.py ROWS.jsonl TRACES_DIR > endings.tsv
(TRACES_DIR: the gate's traces/ of those rows, named JOB_ID.npz, or WORLD.npz)
"""
import itertools
import json
import sys
from pathlib import Path

import numpy as np

from nav_bench.world.geometry import static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import free_cell_near, grid_path
from nav_bench.world.raster import rasterize


def densify(pts, step=0.05):
    out = [pts[0]]
    for a, b in itertools.pairwise(pts):
        n = max(1, int(np.hypot(*(b - a)) / step))
        out += [a + (b - a) * k / n for k in range(1, n + 1)]
    return np.array(out)


RES = 0.02  # m, raster cell of the route search


def route(g, inflate, a, b):
    """(length m, cells' centres (N, 2) m) of the 8-connected grid route from a to b with the
    obstacles inflated by ``inflate`` m (None: no route)."""
    raster = rasterize(g, RES, inflate=inflate)
    s, t = free_cell_near(raster, a, 0.6), free_cell_near(raster, b, 0.6)
    if s is None or t is None:
        return None
    found = grid_path(raster.occupied, s, t)
    if found is None:
        return None
    cells = found[1]
    return found[0] * RES, np.column_stack([(cells[:, 1] + 0.5) * RES, (cells[:, 0] + 0.5) * RES])


def analyse(trace_path):
    tr = np.load(trace_path, allow_pickle=True)
    meta = json.loads(str(tr["meta"]))
    world = world_from_data(meta["world"])
    g = static_geometry(world)
    goal = tuple(float(v) for v in world.goal)
    t, true = tr["t"], tr["true_pose"]
    end = tuple(float(v) for v in true[-1, :2])
    last = t >= t[-1] - 30
    loop = true[t >= t[-1] - 90, :2]
    dl = np.hypot(loop[:, 0] - goal[0], loop[:, 1] - goal[1])
    best = tuple(float(v) for v in loop[int(np.argmin(dl))])  # the loop's point nearest the goal
    box = (true[last, 0].min(), true[last, 0].max(), true[last, 1].min(), true[last, 1].max())
    base = route(g, 0.18, best, goal)
    if base is None:
        return end, box, None, None, None
    length, d = base
    gd = np.hypot(d[:, 0] - goal[0], d[:, 1] - goal[1])
    rise = float(gd.max() - gd[0])
    lo, hi = 0.18, 0.5
    while hi - lo > 0.01:
        mid = (lo + hi) / 2
        r = route(g, mid, best, goal)
        lo, hi = (mid, hi) if (r is not None and r[0] <= 1.25 * length) else (lo, mid)
    return end, box, length, rise, 2 * lo


with open(sys.argv[1]) as fh:
    rows = [json.loads(line) for line in fh]
tdir = Path(sys.argv[2])
print("world\toutcome\ttime_s\tcontacts\tend_x\tend_y\tlast30_box\tgoal_d\tway_on_m\trise_m\tgap_m\tclass")
for r in rows:
    if r["outcome"] == "reached":
        continue
    tp = tdir / f"{r['job_id']}.npz"
    if not tp.exists():
        tp = tdir / f"{r['world']}.npz"
    end, box, L, rise, gap = analyse(tp)
    cls = ("unreachable?" if L is None else "local minimum" if rise > 0.3 else
           "gap" if gap < 0.66 else "other")
    bx = f"x {box[0]:.2f}-{box[1]:.2f} y {box[2]:.2f}-{box[3]:.2f}"
    print(f"{r['world']}\t{r['outcome']}\t{r['time_s']}\t{r['collisions']}\t{end[0]:.2f}\t{end[1]:.2f}\t{bx}\t"
          f"{r['goal_distance_m']:.2f}\t{L if L is None else round(L, 2)}\t{rise if rise is None else round(rise, 2)}\t"
          f"{gap if gap is None else round(gap, 2)}\t{cls}", flush=True)
