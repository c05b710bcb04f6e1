"""Why a VFH+ gap ending stays closed: replay a trace through a fresh planner (this tree) and,
at each cycle the robot is within NEAR m of the gap, look along the straight line from the
robot to the gap's midpoint (the route's narrowest point, found as in vfh_s12/classify.py).
Per cycle: H^p toward the midpoint (kept parts) and with whole cells, free in H^m or not, and
the kept parts within r_rs of that line (they close it), with their clearance from the TRUE
obstacles (m; < 0 inside): parts well outside (> 0.03 m) are the map's, parts at the surface
are the obstacle's.
PYTHONPATH=$PWD python results/baselines/vfh_s14/gapwhy.py TRACE.npz [--near 1.3] [--every 20]
"""
from __future__ import annotations

import argparse
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s13")
from carving_view import whole_cells
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import free_cell_near, grid_path
from nav_bench.world.raster import rasterize

RES = 0.02  # m, raster cell of the route search (vfh_s12/classify.py)


def route(g, inflate, a, b):
    """(length m, cells' centres (N, 2) m) of the 8-connected route from a to b with the
    obstacles inflated by ``inflate`` m, or None (vfh_s12/classify.py's, which runs on import)."""
    raster = rasterize(g, RES, inflate=inflate)
    s, t = free_cell_near(raster, a, 0.6), free_cell_near(raster, b, 0.6)
    found = None if s is None or t is None else grid_path(raster.occupied, s, t)
    if found is None:
        return None
    cells = found[1]
    return found[0] * RES, np.column_stack([(cells[:, 1] + 0.5) * RES, (cells[:, 0] + 0.5) * RES])


def widest_route(g, start, goal):
    """(length m, points (N, 2) m) of the route from ``start`` to ``goal`` with the largest
    inflation r* that keeps it no longer than 1.25 x the robot-radius route (bisection, 1 cm;
    vfh_s12/classify.py), and r*, m; (None, None) when there is no route."""
    base = route(g, 0.18, start, goal)
    if base is None:
        return None, None
    lo, hi, best = 0.18, 0.5, base
    while hi - lo > 0.01:
        mid = (lo + hi) / 2
        r = route(g, mid, start, goal)
        if r is not None and r[0] <= 1.25 * base[0]:
            lo, best = mid, r
        else:
            hi = mid
    return best, lo


def gap_midpoint(g, start, goal, within=None):
    """The way on's narrowest point from ``start`` and half its gap, m: the route with the
    largest inflation r* that keeps it no longer than 1.25 x (vfh_s12/classify.py's bisection,
    1 cm), and its point of least clearance (among its first ``within`` m if given)."""
    best, _ = widest_route(g, start, goal)
    if best is None:
        return None, None
    pts = best[1]
    if within is not None:
        run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
        pts = pts[run <= within]
    c = clearance(g, pts)
    i = int(np.argmin(c))
    return pts[i], float(c[i])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--near", type=float, default=1.3)
    ap.add_argument("--every", type=int, default=0, help="print every Nth near cycle (0: summary only)")
    ap.add_argument("--within", type=float, default=None, help="the narrowest point among the way on's first m")
    ap.add_argument("--mid", type=float, nargs=2, default=None, help="the gap's midpoint (m) instead")
    a = ap.parse_args()
    replay = load(a.trace)
    world = world_from_data(replay.meta["world"])
    g = static_geometry(world)
    goal = np.asarray(world.goal, float)
    true = replay.true[:, :2]
    loop = true[replay.t >= replay.t[-1] - 90]
    best = loop[int(np.argmin(np.hypot(*(loop - goal).T)))]
    if a.mid is None:
        mid, half = gap_midpoint(g, tuple(best), tuple(goal), a.within)
    else:
        mid = np.array(a.mid)
        half = float(clearance(g, mid[None])[0])
    print(f"{replay.meta['row']['world']}: gap midpoint ({mid[0]:.2f}, {mid[1]:.2f}), gap {2 * half:.3f} m")
    p = replay.planner
    s = p.settings
    r_rs = 0.18 + s.safety_distance
    n_near = n_free = 0
    blockers = []  # clearance of the closing parts from the true obstacles
    least = None
    kinds = np.zeros(4, dtype=int)  # closing parts while the way is closed: all, surface, proud expired, proud never carved
    for i in range(len(replay.t)):
        p.act(replay.obs(i))
        xy = replay.odom[i, :2]
        d = float(np.hypot(*(mid - xy)))
        if d > a.near:
            continue
        n_near += 1
        ang = math.atan2(mid[1] - xy[1], mid[0] - xy[0])
        k = round((ang % (2 * math.pi)) / p.alpha) % p.n
        free = not p.masked[k]
        n_free += free
        # kept parts within r_rs of the segment robot -> midpoint + 0.3 m beyond
        win = read_window(p.grid.values(copy=False), p.frame, xy, min(s.window_radius, float(np.hypot(*(goal - xy)))),
                          s.c_max)
        flat = win.rows * p.frame.cols + win.cols
        parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)
        carved_t = p.carving.carved_t.reshape(-1, PARTS)[flat]
        kept = carved_t < replay.t[i] - 3.0
        kp, expired = parts[kept], np.isfinite(carved_t[kept])
        u = np.array([math.cos(ang), math.sin(ang)])
        rel = kp - xy
        along = rel @ u
        across = np.abs(rel @ np.array([-u[1], u[0]]))
        close = (along > 0) & (along < d + 0.3) & (across < r_rs)
        cl = clearance(g, kp[close]) if close.any() else np.zeros(0)
        blockers.append(cl)
        if not free:
            kinds += [int(close.sum()), int((cl < 0.03).sum()), int(((cl >= 0.03) & expired[close]).sum()),
                      int(((cl >= 0.03) & ~expired[close]).sum())]
        if least is None or p.primary[k] < least[0]:
            least = (p.primary[k], replay.t[i])
        if a.every and n_near % a.every == 0:
            _, _, whole = whole_cells(p, xy)
            print(f"t={replay.t[i]:.1f} ({xy[0]:.2f},{xy[1]:.2f}) d={d:.2f} dir {math.degrees(ang) % 360:.0f} "
                  f"H^p {p.primary[k]:.0f} whole {whole[k]:.0f} free {free} chosen {p.k_prev * 5:.0f}; "
                  f"closing parts {close.sum()}, clearance from true obstacles: "
                  f"{np.round(np.sort(cl)[-3:], 3).tolist() if len(cl) else '-'} (largest 3)")
    allc = np.concatenate(blockers) if blockers else np.zeros(0)
    print(f"cycles within {a.near} m: {n_near}, free toward the midpoint: {n_free}; least H^p {least[0]:.0f} "
          f"at t={least[1]:.1f}" if least else "never near")
    if len(allc):
        print("closing parts' clearance from the true obstacles (m), quantiles 0/25/50/75/100:",
              np.round(np.quantile(allc, [0, .25, .5, .75, 1]), 3).tolist(),
              f"share > 0.03 m: {np.mean(allc > 0.03):.2f}")
        n = max(kinds[0], 1)
        print(f"while closed: closing parts {kinds[0]}: at the surface (< 0.03 m) {kinds[1] / n:.2f}, proud and "
              f"carved before (expired) {kinds[2] / n:.2f}, proud and never carved {kinds[3] / n:.2f}")


if __name__ == "__main__":
    main()
