"""Contact starts of a gate's VFH+ traces (true body clearance <= 2 mm), by kind, with no replay.

Kinds, from the commands of the 5 cycles (0.5 s) before the start:
* ``brake``: the cycle before commanded (0, 0) (G6's straight brake before a turn on the spot);
* ``turn``: the cycle before commanded v = 0 with a turn (a turn on the spot rolling on);
* ``drive``: the cycle before commanded v > 0;
and ``wall`` when the touching point lies on the world's outer boundary (within 1 cm).
``brake`` and ``drive`` also note whether a turn on the spot was commanded in the 0.5 s
before (``after turn``). Prints one line per start and the totals by kind.

python results/baselines/vfh_s18/contact_kinds.py TRACES_DIR [WORLD_PREFIX]
"""
import collections
import glob
import json
import math
import sys

import numpy as np

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18  # m


def touching(geometry, xy, yaw):
    """The body point nearest an obstacle (2,) and its bearing from the heading, deg."""
    ang = np.radians(np.arange(0, 360, 5))
    pts = xy + (RADIUS + 0.01) * np.stack([np.cos(yaw + ang), np.sin(yaw + ang)], axis=1)
    j = int(np.argmin(clearance(geometry, pts)))
    point = xy + RADIUS * np.array([math.cos(yaw + ang[j]), math.sin(yaw + ang[j])])
    return point, (math.degrees(ang[j]) + 180) % 360 - 180


def kinds_of(path):
    trace = np.load(path, allow_pickle=True)
    meta = json.loads(str(trace["meta"]))
    world = meta["world"]
    size = np.asarray(world["size"], dtype=float)
    geometry = static_geometry(world_from_data(world))
    t, true, cmd, odom = trace["t"], trace["true_pose"].astype(float), trace["cmd"], trace["odom_pose"]
    gap = clearance(geometry, true[:, :2]) - RADIUS
    touch = gap <= 0.002
    out = []
    for i in range(1, len(t)):
        if not touch[i] or touch[i - 1]:
            continue
        point, side = touching(geometry, true[i, :2], float(true[i, 2]))
        on_wall = bool(min(point[0], point[1], size[0] - point[0], size[1] - point[1]) < 0.01)
        v, w = float(cmd[i - 1, 0]), float(cmd[i - 1, 1])
        before = cmd[max(0, i - 6):i - 1]
        spun = bool(((before[:, 0] == 0) & (before[:, 1] != 0)).any())
        kind = "brake" if v == 0 and w == 0 else "turn" if v == 0 else "drive"
        yaw = float(odom[i - 1, 2])
        mv = odom[i - 1, :2] - odom[max(0, i - 2), :2]
        speed = float(mv[0] * math.cos(yaw) + mv[1] * math.sin(yaw)) / 0.1
        out.append(dict(world=meta["row"]["world"], seed=meta["row"]["seed"], i=i, t=float(t[i]),
                        x=float(true[i, 0]), y=float(true[i, 1]), side=side, v=v, w=w, speed=speed,
                        kind="wall" if on_wall else kind, after_turn=spun))
    return out


def main():
    folder, prefix = sys.argv[1], (sys.argv[2] if len(sys.argv) > 2 else "")
    rows = []
    for path in sorted(glob.glob(f"{folder}/{prefix}*.npz")):
        trace = np.load(path, allow_pickle=True)
        if json.loads(str(trace["meta"]))["row"].get("collisions", 0) == 0:
            continue
        rows += kinds_of(path)
    for r in rows:
        print(f"{r['world']} s{r['seed']} t={r['t']:.1f} ({r['x']:.2f},{r['y']:.2f}) side {r['side']:+.0f} "
              f"cmd ({r['v']:.2f},{r['w']:+.2f}) speed {r['speed']:+.2f} {r['kind']}"
              f"{' after turn' if r['after_turn'] else ''}")
    count = collections.Counter(r["kind"] + (" after turn" if r["after_turn"] and r["kind"] != "turn" else "")
                                for r in rows)
    episodes = len({(r["world"], r["seed"]) for r in rows})
    print(f"total {len(rows)} contact starts in {episodes} episodes:", dict(sorted(count.items())))


if __name__ == "__main__":
    main()
