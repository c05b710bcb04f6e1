"""For each contact start of kind `turn` (contact_kinds.py), the spot turn it belongs to: how
many cycles the turn had run, the odometric forward speed when it began and at the touch, and
the true clearance 1 s before. python turn_contacts.py TRACES_DIR"""
import glob
import json
import math
import sys

import numpy as np

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

RADIUS = 0.18


def speed_at(odom, i):
    yaw = float(odom[i, 2])
    mv = odom[i, :2] - odom[max(0, i - 1), :2]
    return float(mv[0] * math.cos(yaw) + mv[1] * math.sin(yaw)) / 0.1


for path in sorted(glob.glob(f"{sys.argv[1]}/*.npz")):
    tr = np.load(path, allow_pickle=True)
    meta = json.loads(str(tr["meta"]))
    if meta["row"].get("collisions", 0) == 0:
        continue
    geometry = static_geometry(world_from_data(meta["world"]))
    t, true, cmd, odom = tr["t"], tr["true_pose"].astype(float), tr["cmd"], tr["odom_pose"]
    gap = clearance(geometry, true[:, :2]) - RADIUS
    size = np.asarray(meta["world"]["size"], dtype=float)
    for i in range(1, len(t)):
        if not (gap[i] <= 0.002 < gap[i - 1]):
            continue
        v, w = cmd[i - 1]
        if not (v == 0 and w != 0):
            continue
        x, y = true[i, :2]
        if min(x, y, size[0] - x, size[1] - y) < RADIUS + 0.01:
            continue  # the outer wall (contact_kinds: wall)
        j = i - 1
        while j > 0 and cmd[j - 1, 0] == 0 and np.sign(cmd[j - 1, 1]) == np.sign(w):
            j -= 1
        k = max(0, i - 10)
        print(f"{meta['row']['world']} s{meta['row']['seed']} t={t[i]:.1f} omega {w:+.2f}: turn ran {i - j} cycles; "
              f"speed at start {speed_at(odom, j):+.2f}, at touch {speed_at(odom, i - 1):+.2f} m/s; "
              f"clearance 1 s before {gap[k] * 100:.1f} cm, min over the turn {gap[j:i].min() * 100:.1f} cm")
