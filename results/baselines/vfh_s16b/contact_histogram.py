"""At each contact start of a VFH+ trace (the cycle before), the planner's view of the wall it
touches: the nearest kept point (the histogram's points: cells, or a cell's kept parts) and the
true clearance; H^p in the heading's and the chosen sector under the carving as run (memory
``carve_memory_s``), and the same with the 3 s memory of main (parts carved more than 3 s ago
kept again), and with no carving at all (whole cells); thresholds 1500 / 2500.
PYTHONPATH=$PWD python results/baselines/vfh_s16b/contact_histogram.py TRACE.npz [--before S]
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_box, window_histogram
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--before", type=float, default=0.0)
    a = ap.parse_args()
    rp = load(a.trace)
    p, s = rp.planner, rp.planner.settings
    g = static_geometry(world_from_data(rp.meta["world"]))
    gap = clearance(g, rp.true[:, :2].astype(float)) - RADIUS
    touch = gap <= 0.002
    starts = [i for i in range(1, len(rp.t)) if touch[i] and not touch[i - 1]]
    looks = {max(0, i - 1 - round(a.before / 0.1)): i for i in starts}
    print(rp.meta["row"]["world"], "seed", rp.meta["row"].get("seed"), rp.meta["row"]["outcome"])
    r_rs = RADIUS + s.safety_distance
    for i in range(len(rp.t)):
        if i > max(looks, default=-1):
            break
        obs = rp.obs(i)
        p.act(obs)
        if i not in looks:
            continue
        j = looks[i]
        xy = rp.odom[i, :2].astype(float)
        yaw = float(rp.odom[i, 2])
        radius = min(s.window_radius, float(np.hypot(*(obs.goal - xy))))
        values = p.grid.values(copy=False)
        box = window_box(p.frame, xy, radius)
        win = read_window(values, p.frame, xy, radius, s.c_max, box)
        ct = p.carving.carved_t.reshape(-1, PARTS)[win.rows * p.frame.cols + win.cols]
        parts = cell_parts(np.stack([win.x, win.y], 1), p.frame.cell)
        kh, kc = round(yaw % (2 * math.pi) / p.alpha) % p.n, round(p.k_prev) % p.n
        out = []
        for name, kept in (("as run", ct < obs.t - p.carving.memory_s), ("3 s", ct < obs.t - 3.0),
                           ("whole", np.ones_like(ct, dtype=bool))):
            w = win.carved(kept, parts, xy)
            h = window_histogram(w, w.bearings(), p.n, r_rs, s.window_radius, s.distance_weight)
            near = int(np.argmin(w.dist)) if len(w) else None
            out.append(f"{name}: H^p heading {h[kh]:.0f} chosen {h[kc]:.0f}, nearest point "
                       f"{w.dist[near] - RADIUS:+.3f} m (certainty {w.certainty[near]:.0f})")
        print(f"  contact t={rp.t[j]:.1f}: cycle before t={obs.t:.1f}, true gap {gap[i]:+.3f} m, cmd v "
              f"{p.v_prev:.2f}, chosen {math.degrees(math.remainder(kc * p.alpha - yaw, 2 * math.pi)):+.0f} deg "
              f"from heading, blocked {p.blocked}, sectors free {int((~p.masked).sum())}")
        for o in out:
            print("    " + o)


main()
