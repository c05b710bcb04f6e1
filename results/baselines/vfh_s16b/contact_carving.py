"""At each contact start of a VFH+ trace, what the carving held carved that is a true surface,
and what carved it. Replays the trace through a fresh planner (the row's parameters), noting for
every part the cycle and the source of its last carving (the body: the part lies within the
radius of the odometry pose; else a view: seen through from two views). At the cycle before each
contact start it lists the carved parts within 0.5 m of the robot whose centre lies more than
1 cm inside a true obstacle (mapped to the world by the odometry -> true transform of that
cycle), and, for each, whether it was inside under the transform of the cycle that carved it
(wrong when carved) or only now (odometry drifted since), its age and the drift between.
It also counts the grid's occupied cells and the kept parts within 0.15 m of the touching point.
PYTHONPATH=$PWD python results/baselines/vfh_s16b/contact_carving.py TRACE.npz [--before S]
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

from nav_bench.mapping.occupancy import UNKNOWN
from nav_bench.planners.footprint import cell_parts
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18  # m


def to_true(points, odom, true):
    """(K, 2) odometry-frame points (m) in the world, by the transform of one cycle."""
    a = float(true[2] - odom[2])
    c, s = math.cos(a), math.sin(a)
    d = points - odom[:2]
    return np.stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]], 1) + true[:2]


def touch_point(g, xy, yaw):
    ang = np.radians(np.arange(0, 360, 5))
    pts = xy + (RADIUS + 0.01) * np.stack([np.cos(yaw + ang), np.sin(yaw + ang)], 1)
    j = int(np.argmin(clearance(g, pts)))
    return xy + RADIUS * np.array([math.cos(yaw + ang[j]), math.sin(yaw + ang[j])]), \
        (math.degrees(ang[j]) + 180) % 360 - 180


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--before", type=float, default=0.0, help="look this many s before each contact start")
    a = ap.parse_args()
    rp = load(a.trace)
    p = rp.planner
    g = static_geometry(world_from_data(rp.meta["world"]))
    gap = clearance(g, rp.true[:, :2].astype(float)) - RADIUS
    touch = gap <= 0.002
    starts = [i for i in range(1, len(rp.t)) if touch[i] and not touch[i - 1]]
    looks = {max(0, i - 1 - round(a.before / 0.1)): i for i in starts}
    shape = p.carving.carved_t.shape
    carve_i = np.full(shape, -1, dtype=np.int32)  # the cycle of each part's last carving
    by_body = np.zeros(shape, dtype=bool)
    f = p.frame
    print(rp.meta["row"]["world"], "seed", rp.meta["row"].get("seed"), rp.meta["row"]["outcome"])
    for i in range(len(rp.t)):
        if i > max(looks, default=-1):
            break
        obs = rp.obs(i)
        p.act(obs)
        now = np.float32(obs.t)
        new = np.argwhere((p.carving.carved_t == now).any(axis=2))
        if len(new):
            cen = np.stack([f.xmin + (new[:, 1] + 0.5) * f.cell, f.ymin + (new[:, 0] + 0.5) * f.cell], 1)
            parts = cell_parts(cen, f.cell)
            hit = p.carving.carved_t[new[:, 0], new[:, 1]] == now
            body = np.hypot(parts[..., 0] - obs.pose[0], parts[..., 1] - obs.pose[1]) <= RADIUS
            for k, (r, c) in enumerate(new):
                carve_i[r, c][hit[k]] = i
                by_body[r, c][hit[k]] = body[k][hit[k]]
        if i not in looks:
            continue
        j = looks[i]
        tp, side = touch_point(g, rp.true[j, :2].astype(float), float(rp.true[j, 2]))
        t = obs.t
        noted = np.argwhere(p.carving.noted)
        cen = np.stack([f.xmin + (noted[:, 1] + 0.5) * f.cell, f.ymin + (noted[:, 0] + 0.5) * f.cell], 1)
        near = np.hypot(*(cen - rp.odom[i, :2]).T) < 0.6
        noted, cen = noted[near], cen[near]
        parts = cell_parts(cen, f.cell)
        ct = p.carving.carved_t[noted[:, 0], noted[:, 1]]
        carved = ct >= t - p.carving.memory_s
        ci, bb = carve_i[noted[:, 0], noted[:, 1]], by_body[noted[:, 0], noted[:, 1]]
        flat = parts.reshape(-1, 2)
        tr_now = to_true(flat, rp.odom[i], rp.true[i]).reshape(parts.shape)
        inside = clearance(g, tr_now.reshape(-1, 2)).reshape(parts.shape[:2]) < -0.01
        near_r = np.hypot(*(parts - rp.odom[i, :2]).transpose(2, 0, 1)) < 0.5
        near_tp = np.hypot(*(tr_now - tp).transpose(2, 0, 1)) < 0.15
        sel = carved & inside & near_r
        vals = p.grid.values(copy=False)
        occ = np.argwhere(vals > UNKNOWN)
        occ_xy = np.stack([f.xmin + (occ[:, 1] + 0.5) * f.cell, f.ymin + (occ[:, 0] + 0.5) * f.cell], 1)
        occ_tp = int((np.hypot(*(to_true(occ_xy, rp.odom[i], rp.true[i]) - tp).T) < 0.15).sum())
        kept_tp = int((~carved & near_tp).sum())
        drift = float(np.hypot(*(rp.odom[i, :2] - rp.true[i, :2])))
        print(f"  contact t={rp.t[j]:.1f} true ({rp.true[j,0]:.2f},{rp.true[j,1]:.2f}) side {side:+.0f}; looked at "
              f"t={t:.1f}; odometry off by {drift:.3f} m, {math.degrees(rp.true[i,2]-rp.odom[i,2]):+.1f} deg")
        print(f"    at the touching point (0.15 m): occupied cells {occ_tp}, kept parts {kept_tp}, "
              f"carved parts {int((carved & near_tp).sum())}, of them inside the wall {int((sel & near_tp).sum())}")
        if not sel.any():
            print("    no carved part within 0.5 m lies inside a true obstacle")
            continue
        rows = []
        for m, q in zip(*np.nonzero(sel), strict=True):
            c0 = ci[m, q]
            then = to_true(parts[m, q][None], rp.odom[c0], rp.true[c0])[0] if c0 >= 0 else tr_now[m, q]
            rows.append((bool(bb[m, q]), t - float(ct[m, q]), clearance(g, then[None])[0] < -0.01,
                         float(np.hypot(*(then - tr_now[m, q]))), bool(near_tp[m, q]),
                         float(clearance(g, tr_now[m, q][None])[0])))
        rows = np.array(rows, dtype=float)
        for name, s in (("body", rows[:, 0] > 0), ("view", rows[:, 0] == 0)):
            if not s.any():
                continue
            r = rows[s]
            print(f"    {name}: {int(s.sum())} parts inside (of them {int(r[:, 4].sum())} at the touching point); "
                  f"inside when carved {int(r[:, 2].sum())}; age {r[:, 1].min():.1f}-{r[:, 1].max():.1f} s "
                  f"(> 3 s: {int((r[:, 1] > 3).sum())}); drift since {r[:, 3].min():.3f}-{r[:, 3].max():.3f} m; "
                  f"depth {-r[:, 5].max():.3f}-{-r[:, 5].min():.3f} m")


main()
