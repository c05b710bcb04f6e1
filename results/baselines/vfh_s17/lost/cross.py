"""cross.py AX AY BX BY TRACE...: each crossing of the segment A-B (the passage's narrowest line,
between two obstacles' centres), the commands in the 1 s before it, and the true gap then."""

import json
import sys

import numpy as np

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

A, B = np.array(sys.argv[1:3], float), np.array(sys.argv[3:5], float)
for path in sys.argv[5:]:
    tr = np.load(path, allow_pickle=True)
    world = world_from_data(json.loads(str(tr["meta"]))["world"])
    t, p, c = tr["t"], tr["true_pose"].astype(float), tr["cmd"]
    gap = clearance(static_geometry(world), p[:, :2]) - 0.18
    d = B - A
    side = np.sign(d[0] * (p[:, 1] - A[1]) - d[1] * (p[:, 0] - A[0]))
    s = ((p[:, :2] - A) @ d) / (d @ d)
    ks = [k for k in np.flatnonzero(side[1:] != side[:-1]) if 0 < s[k] < 1]
    print(
        path.split("/")[-1][:-4],
        f"least gap within 0.3 m of the line's middle: "
        f"{gap[np.linalg.norm(p[:, :2] - (A + B) / 2, axis=1) < 0.3].min() * 100 if (np.linalg.norm(p[:, :2] - (A + B) / 2, axis=1) < 0.3).any() else float('nan'):.1f} cm",
    )
    for k in ks:
        w = slice(max(0, k - 10), k + 1)
        v0 = (np.abs(c[w, 0]) < 1e-9).sum()
        print(
            f"   crosses at t {t[k]:.1f} at {np.round(p[k, :2], 2)}, gap {gap[k] * 100:.1f} cm, heading {np.degrees(p[k, 2]):.0f} deg; "
            f"cycles commanded v=0 in the 1 s before: {v0}/11; cmd v {np.round(c[w, 0], 2)}"
        )
