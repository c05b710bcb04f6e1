"""For each contact start of kind `turn` (``../vfh_s18/contact_kinds.py``: a turn on the spot
commanded the cycle before, off the outer wall), the spot turn it belongs to: how many cycles
it had run, its rate, the odometric forward speed when it began and at the touch, and the true
clearance 1 s before and over the turn. python turn_contacts.py TRACES_DIR"""
import glob
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "vfh_s18"))
from contact_kinds import RADIUS, kinds_of

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data


def speed_at(odom, i):
    """Forward speed over the cycle ending at ``i``, m/s (contact_kinds' figure, 0.1 s cycles)."""
    yaw = float(odom[i, 2])
    mv = odom[i, :2] - odom[max(0, i - 1), :2]
    return float(mv[0] * math.cos(yaw) + mv[1] * math.sin(yaw)) / 0.1


for path in sorted(glob.glob(f"{sys.argv[1]}/*.npz")):
    tr = np.load(path, allow_pickle=True)
    meta = json.loads(str(tr["meta"]))
    if meta["row"].get("collisions", 0) == 0:
        continue
    starts = [c for c in kinds_of(path) if c["kind"] == "turn"]
    if not starts:
        continue
    t, cmd, odom = tr["t"], tr["cmd"], tr["odom_pose"]
    gap = clearance(static_geometry(world_from_data(meta["world"])), tr["true_pose"][:, :2].astype(float)) - RADIUS
    for c in starts:
        i, w = c["i"], c["w"]
        j = i - 1  # back to the first cycle of this turn on the spot
        while j > 0 and cmd[j - 1, 0] == 0 and np.sign(cmd[j - 1, 1]) == np.sign(w):
            j -= 1
        k = max(0, i - 10)
        print(f"{c['world']} s{c['seed']} t={t[i]:.1f} omega {w:+.2f}: turn ran {i - j} cycles; "
              f"speed at start {speed_at(odom, j):+.2f}, at touch {speed_at(odom, i - 1):+.2f} m/s; "
              f"clearance 1 s before {gap[k] * 100:.1f} cm, min over the turn {gap[j:i].min() * 100:.1f} cm")
