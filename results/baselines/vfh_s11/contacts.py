"""Replay a VFH+ episode trace through a fresh planner and describe each wall contact.

For each contact (true body clearance <= 2 mm): when, where, the touching side (bearing of
the nearest wall point from the heading), the commands and true speed of the 3 s before, and
what the planner saw then (relax factor, blocked, chosen sector, free sectors, H^p ahead).
PYTHONPATH=$PWD python results/baselines/vfh_s11/contacts.py TRACE.npz [key=value ...]
(key=value: planner parameters, as `--planner vfh_plus:key=value`).
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np

import nav_bench.planners.vfh_plus as vfh
from nav_bench.episode.stepper import EpisodeStepper
from nav_bench.interface import Observation
from nav_bench.sim.session import SimSession
from nav_bench.specs import load_robot
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data


def robot_info():
    with SimSession() as session:
        return EpisodeStepper.robot_info_of(session, load_robot())


def contact_side(geometry, xy, yaw, radius):
    """Bearing (deg, from the heading, CCW +) of the body point nearest a wall."""
    ang = np.radians(np.arange(0, 360, 5))
    pts = xy + (radius + 0.01) * np.stack([np.cos(yaw + ang), np.sin(yaw + ang)], axis=1)
    d = clearance(geometry, pts)
    a = math.degrees(ang[int(np.argmin(d))])
    return (a + 180) % 360 - 180


def main(path: str, overrides: dict[str, float]) -> None:
    trace = np.load(path, allow_pickle=True)
    meta = json.loads(str(trace["meta"]))
    world = world_from_data(meta["world"])
    params = {**meta["row"]["params"], **overrides}
    robot = robot_info()
    geometry = static_geometry(world)
    goal = np.asarray(meta["world"]["goal"], dtype=float)
    bounds = (0.0, 0.0, *meta["world"]["size"])
    t, odom, ranges, true, cmd = (trace[k] for k in ("t", "odom_pose", "ranges", "true_pose", "cmd"))
    gap = clearance(geometry, true[:, :2].astype(float)) - robot.radius
    touching = gap <= 0.002
    starts = [i for i in range(1, len(t)) if touching[i] and not touching[i - 1]]

    factors: list[float] = []
    select = vfh.select_direction

    def recording(*a, **k):
        out = select(*a, **k)
        factors.append(out[2] if out[0] is not None else math.nan)
        return out

    vfh.select_direction = recording
    planner = vfh.VFHPlus(**{k: v for k, v in params.items()})

    def observation(i: int) -> Observation:
        return Observation(float(t[i]), odom[i].astype(float), goal, ranges[i].astype(float), robot, bounds, 0.1)

    planner.reset(observation(0), np.random.default_rng(0))
    log = []
    mismatch = 0
    for i in range(len(t)):
        c = planner.act(observation(i))
        mismatch += abs(c.v - cmd[i, 0]) > 1e-4 or abs(c.omega - cmd[i, 1]) > 1e-4
        log.append((factors[-1], planner.blocked, planner.k_prev * 5.0,
                    np.flatnonzero(~planner.masked.astype(bool)) * 5, planner.primary.copy()))
    print(f"{meta['row']['world']}: {len(starts)} contact starts, replay mismatching cmds: {mismatch}")
    speed = np.r_[0, np.hypot(*np.diff(true[:, :2], axis=0).T) / np.diff(t)]
    for i in starts:
        yaw = float(true[i, 2])
        side = contact_side(geometry, true[i, :2].astype(float), yaw, robot.radius)
        print(f"\n t={t[i]:.1f} s at ({true[i, 0]:.2f}, {true[i, 1]:.2f}) yaw {math.degrees(yaw):.0f} deg, "
              f"touching at {side:+.0f} deg from the heading")
        for j in range(max(0, i - 30), min(len(t), i + 3), 3):
            f, blocked, k, free, prim = log[j]
            hd = round(math.degrees(float(odom[j, 2])) / 5) % 72
            print(f"  t={t[j]:6.1f} v_cmd {cmd[j, 0]:+.2f} w_cmd {cmd[j, 1]:+.2f} v_true {speed[j]:.2f} "
                  f"gap {gap[j]:+.3f} yaw {math.degrees(float(true[j, 2])):6.0f} f={f} blk={int(blocked)} "
                  f"dir {k:5.1f} H^p(head) {prim[hd]:7.0f} free {free.tolist()[:40]}")


if __name__ == "__main__":
    kv = dict(a.split("=") for a in sys.argv[2:])
    main(sys.argv[1], {k: float(v) for k, v in kv.items()})
