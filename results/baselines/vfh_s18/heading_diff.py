"""Which cells make the heading sector's H^p differ between the carving's memory (the row's,
10 s under D/G6) and main's 3 s, at given times of a VFH+ trace: for each cell of the window,
its magnitude in the heading sector with the parts carved within memory_s removed vs within 3 s
removed; prints the cells that differ, with where they lie from the robot (m, deg from the
heading), their carved parts' ages (s), source (body / view), and whether those parts lie in a
true obstacle (the odometry -> true transform of that cycle).

PYTHONPATH=$PWD python results/baselines/vfh_s18/heading_diff.py TRACE.npz T [T ...]
"""
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s18")
from replay_common import RADIUS, CarveLog, odom_to_true
from trace_replay import load

from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import ActiveWindow, read_window, window_box, window_histogram
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data


def cell_magnitudes(p, window, kept, parts, xy, k):
    """(M,) each cell's magnitude in sector k with only its ``kept`` parts."""
    out = np.zeros(len(window))
    r_rs = RADIUS + p.settings.safety_distance
    for m in range(len(window)):
        one = ActiveWindow(window.x[m:m + 1], window.y[m:m + 1], window.certainty[m:m + 1], window.dx[m:m + 1],
                           window.dy[m:m + 1], window.dist[m:m + 1])
        w = one.carved(kept[m:m + 1], parts[m:m + 1], xy, False)
        if len(w):
            out[m] = window_histogram(w, w.bearings(), p.n, r_rs, p.settings.window_radius,
                                      p.settings.distance_weight)[k]
    return out


def main():
    rp = load(sys.argv[1])
    times = sorted(float(x) for x in sys.argv[2:])
    p = rp.planner
    f = p.frame
    g = static_geometry(world_from_data(rp.meta["world"]))
    log = CarveLog(p)
    for i in range(len(rp.t)):
        if not times:
            break
        obs = rp.obs(i)
        p.act(obs)
        log.note(i, obs)
        if obs.t + 1e-6 < times[0]:
            continue
        times.pop(0)
        xy = np.asarray(obs.pose[:2], dtype=float)
        yaw = float(obs.pose[2])
        k = round((yaw % (2 * math.pi)) / p.alpha) % p.n
        radius = min(p.settings.window_radius, float(np.hypot(*(np.asarray(obs.goal) - xy))))
        window = read_window(p.grid.values(copy=False), f, xy, radius, p.settings.c_max,
                             window_box(f, xy, radius), False)
        centres = np.stack([f.xmin + (window.cols + 0.5) * f.cell, f.ymin + (window.rows + 0.5) * f.cell], 1)
        parts = cell_parts(centres, f.cell)
        ct = p.carving.carved_t[window.rows, window.cols]
        kept_now = ct < np.float32(obs.t - p.carving.memory_s)
        kept_main = ct < np.float32(obs.t - 3.0)
        a = cell_magnitudes(p, window, kept_now, parts, xy, k)
        b = cell_magnitudes(p, window, kept_main, parts, xy, k)
        print(f"t={obs.t:.1f} heading sector {k}: H^p {a.sum():.0f} (3 s memory: {b.sum():.0f}); "
              f"planner's {p.primary[k]:.0f}")
        for m in np.argsort(-(b - a)):
            if abs(b[m] - a[m]) < 50:
                break
            d = float(window.dist[m])
            bear = (math.degrees(math.atan2(window.dy[m], window.dx[m]) - yaw) + 180) % 360 - 180
            extra = ~kept_main[m] ^ ~kept_now[m]  # carved now, kept under 3 s
            ci = log.cycle[window.rows[m], window.cols[m]][extra]
            bb = log.body[window.rows[m], window.cols[m]][extra]
            ages = obs.t - ct[m][extra]
            true_now = odom_to_true(parts[m][extra], rp.odom[i].astype(float), rp.true[i].astype(float))
            inside = clearance(g, true_now) < -0.005
            srcs = []
            for c0 in sorted(set(ci.tolist())):
                if c0 < 0:
                    continue
                pc = rp.odom[c0].astype(float)
                pb = (math.degrees(math.atan2(centres[m, 1] - pc[1], centres[m, 0] - pc[0]) - pc[2]) + 180) % 360 - 180
                srcs.append(f"t={rp.t[c0]:.1f} from {np.hypot(*(centres[m] - pc[:2])):.2f} m at {pb:+.0f} deg")
            print(f"   cell {d:.2f} m at {bear:+.0f} deg: {a[m]:.0f} vs {b[m]:.0f}; {int(extra.sum())} parts carved"
                  f" {ages.min():.1f}-{ages.max():.1f} s ago ({int(bb.sum())} by the body), {int(inside.sum())} in"
                  f" a true obstacle; carved {'; '.join(srcs[:3])}")


main()
