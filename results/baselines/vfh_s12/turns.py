"""Replay a VFH+ trace through a fresh planner; at each reversal of the chosen direction
(> 100 deg from the previous cycle's choice) print what the planner saw: position, goal
bearing, valleys (free-sector runs, deg), candidates and their costs, the chosen one, factor,
and for each 30-deg direction H^p and the body's free run along the ray in the true world
(m the 0.18 m disc travels before touching).
PYTHONPATH=$PWD python results/baselines/vfh_s12/turns.py TRACE.npz [T_FROM T_TO [EVERY_S]]
"""
from __future__ import annotations

import json
import math
import sys

import numpy as np

import nav_bench.planners.vfh_plus as vfh

sys.path.insert(0, "results/baselines/vfh_s11")
from contacts import robot_info

from nav_bench.interface import Observation
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data


def free_run(geometry, xy, ang, radius, step=0.05, reach=3.0):
    s = np.arange(0, reach, step)
    pts = xy + s[:, None] * np.array([math.cos(ang), math.sin(ang)])
    c = clearance(geometry, pts) - radius
    bad = np.flatnonzero(c <= 0)
    return float(s[bad[0]]) if len(bad) else reach


def valleys(masked):
    n = len(masked)
    free = ~masked
    if free.all():
        return [(0, 360)]
    start = int(np.flatnonzero(masked)[0])
    out = []
    k = 0
    while k < n:
        i = (start + k) % n
        if free[i]:
            j = k
            while j < n and free[(start + j) % n]:
                j += 1
            out.append((((start + k) % n) * 5, ((start + j - 1) % n) * 5))
            k = j
        else:
            k += 1
    return out


def main(path, t_from=0.0, t_to=1e9, every=None):
    trace = np.load(path, allow_pickle=True)
    meta = json.loads(str(trace["meta"]))
    world = world_from_data(meta["world"])
    geometry = static_geometry(world)
    robot = robot_info()
    goal = np.asarray(meta["world"]["goal"], dtype=float)
    bounds = (0.0, 0.0, *meta["world"]["size"])
    t, odom, ranges, true, cmd = (trace[k] for k in ("t", "odom_pose", "ranges", "true_pose", "cmd"))
    params = meta["row"]["params"]
    rec = {}
    sel = vfh.select_direction
    cand = vfh.candidate_directions

    def rs(*a, **k):
        out = sel(*a, **k)
        rec["factor"] = out[2]
        return out

    def rc(masked, k_target, s_max):
        out = cand(masked, k_target, s_max)
        rec.setdefault("cands", []).append(out)
        return out
    vfh.select_direction = rs
    vfh.candidate_directions = rc
    p = vfh.VFHPlus(**params)
    def obs(i):
        return Observation(float(t[i]), odom[i].astype(float), goal, ranges[i].astype(float), robot, bounds, 0.1)
    p.reset(obs(0), np.random.default_rng(0))
    prev_k = None
    mism = 0
    for i in range(len(t)):
        rec.clear()
        c = p.act(obs(i))
        mism += abs(c.v - cmd[i, 0]) > 1e-4 or abs(c.omega - cmd[i, 1]) > 1e-4
        k = None if p.blocked else p.k_prev * 5.0
        show = False
        if every is not None:
            show = t_from <= t[i] <= t_to and round(t[i] * 10) % round(every * 10) == 0
        elif k is not None and prev_k is not None and t_from <= t[i] <= t_to:
            d = abs((k - prev_k + 180) % 360 - 180)
            show = d > 100
        if show:
            xy = true[i, :2].astype(float)
            yaw = math.degrees(true[i, 2]) % 360
            gdeg = math.degrees(math.atan2(goal[1] - odom[i, 1], goal[0] - odom[i, 0])) % 360
            print(f"t={t[i]:.1f} true ({xy[0]:.2f},{xy[1]:.2f}) yaw {yaw:.0f} goal@{gdeg:.0f} "
                  f"choice {prev_k} -> {k} factor {rec.get('factor')} v_cmd {cmd[i,0]:.2f}")
            print("   valleys:", valleys(p.masked.astype(bool)), " cands:", [round(x * 5, 1) for x in rec.get('cands', [[]])[-1]])
            hp = {a: int(p.primary[a // 5]) for a in range(0, 360, 30)}
            run = {a: round(free_run(geometry, xy, math.radians(a), robot.radius), 2) for a in range(0, 360, 30)}
            print("   H^p:", hp)
            print("   body free run (m):", run)
        if k is not None:
            prev_k = k
    print("mismatching commands:", mism)


if __name__ == "__main__":
    a = sys.argv
    main(a[1], float(a[2]) if len(a) > 2 else 0.0, float(a[3]) if len(a) > 3 else 1e9,
         float(a[4]) if len(a) > 4 else None)
