"""Why a VFH+ robot rocks where it rocks: replay a trace through a fresh planner (this tree,
main's VFH+) and print, every EVERY cycles from FROM s on, the true pose, the goal's bearing,
the chosen direction (or `blocked`), the open valleys of the masked histogram (deg, world),
and the direction to the way on (the widest route to the goal, vfh_s14/gapwhy.widest_route,
LOOK m past the route point nearest the robot) with its H^p three ways: as the planner has
it (main), with only the kept parts on the true surfaces (< 0.03 m off: perfect carving),
and with no carving expired. Angles in degrees, world frame; H^p in VFH+'s units.
PYTHONPATH=$PWD python results/baselines/vfh_s15/rock_why.py TRACE.npz [--from T] [--every 5] [--look 0.4]
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s14")
from gapwhy import widest_route
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_histogram
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data


def valleys(masked: np.ndarray, alpha: float) -> str:
    """The free runs of ``masked`` (True = blocked) as 'a..b' degree ranges."""
    n = len(masked)
    if masked.all():
        return "none"
    start = int(np.argmax(masked))  # begin the walk on a blocked sector so runs do not wrap
    runs, run = [], []
    for j in range(n):
        k = (start + j) % n
        if not masked[k]:
            run.append(k)
        elif run:
            runs.append(run)
            run = []
    if run:
        runs.append(run)
    deg = math.degrees(alpha)
    return " ".join(f"{r[0] * deg:.0f}..{r[-1] * deg:.0f}" for r in runs)


def way_on_histograms(p, replay, g, i, xy, k, r_rs):
    """H^p of sector ``k`` with only the kept parts on the true surfaces, and with no expiry."""
    s = p.settings
    goal = np.asarray(replay.meta["world"]["goal"], float)
    radius = min(s.window_radius, float(np.hypot(*(goal - xy))))
    win = read_window(p.grid.values(copy=False), p.frame, xy, radius, s.c_max)
    ct = p.carving.carved_t.reshape(-1, PARTS)[win.rows * p.frame.cols + win.cols]
    parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)
    err = replay.true[i, :2] - xy  # the odometry frame against the true obstacles
    on_surface = (clearance(g, (parts + err).reshape(-1, 2)) < 0.03).reshape(parts.shape[:2])
    kept_now = ct < replay.t[i] - 3.0
    out = []
    for kept in (kept_now & on_surface, ~np.isfinite(ct)):
        w = win.carved(kept, parts, xy)
        out.append(window_histogram(w, w.bearings(), p.n, r_rs, s.window_radius, s.distance_weight)[k])
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--from", dest="t0", type=float, default=0.0)
    ap.add_argument("--every", type=int, default=5)
    ap.add_argument("--look", type=float, default=0.4)
    ap.add_argument("--dump", type=float, nargs="*", default=[],
                    help="times (s) at which to print every sector's H^p, main and true surfaces")
    a = ap.parse_args()
    replay = load(a.trace)
    world = world_from_data(replay.meta["world"])
    g = static_geometry(world)
    goal = np.asarray(world.goal, float)
    p = replay.planner
    s = p.settings
    r_rs = 0.18 + s.safety_distance
    deg = math.degrees(p.alpha)
    print("t s | true x y yaw | goal | chosen | valleys | way on: dir, H^p main / true surfaces / no expiry")
    for i in range(len(replay.t)):
        p.act(replay.obs(i))
        if replay.t[i] < a.t0 or i % a.every:
            continue
        xy = replay.odom[i, :2]
        tx, ty, tyaw = replay.true[i]
        way = widest_route(g, (tx, ty), tuple(goal))[0][1]
        run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(way, axis=0).T))])
        j = int(np.argmin(np.hypot(*(way - (tx, ty)).T)))
        target = way[min(int(np.searchsorted(run, run[j] + a.look)), len(way) - 1)]
        k = round((math.atan2(target[1] - xy[1], target[0] - xy[0]) % (2 * math.pi)) / p.alpha) % p.n
        h_true, h_noexp = way_on_histograms(p, replay, g, i, xy, k, r_rs)
        if any(abs(replay.t[i] - t) < 0.05 for t in a.dump):
            full = np.array([way_on_histograms(p, replay, g, i, xy, m, r_rs)[0] for m in range(p.n)])
            print(f"  t {replay.t[i]:.1f}: sector deg: H^p main / true surfaces")
            for m in range(p.n):
                print(f"    {m * deg:5.1f}: {p.primary[m]:6.0f} / {full[m]:6.0f}")
        k_goal = math.degrees(math.atan2(goal[1] - xy[1], goal[0] - xy[0])) % 360
        chosen = "blocked" if p.blocked else f"{p.k_prev * deg:.0f}"
        print(f"{replay.t[i]:6.1f} | {tx:.2f} {ty:.2f} {math.degrees(tyaw) % 360:3.0f} | {k_goal:3.0f} | {chosen:>7} | "
              f"{valleys(p.masked, p.alpha):<24} | {k * deg:3.0f}, {p.primary[k]:6.0f} / {h_true:6.0f} / {h_noexp:6.0f}"
              f" route {run[-1] - run[j]:.2f} m")


if __name__ == "__main__":
    main()
