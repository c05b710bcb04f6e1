"""gapstat.py CX CY R TRACE...: per trace, the time within R m of (CX, CY), how far the body
moved there in cycles commanded v = 0 (turns on the spot, incl. (0,0)) and in cycles commanded v > 0,
the net progress along the passage (first entry to last exit), least true gap, and the time it left."""

import json
import sys

import numpy as np

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

cx, cy, R = map(float, sys.argv[1:4])
for path in sys.argv[4:]:
    tr = np.load(path, allow_pickle=True)
    world = world_from_data(json.loads(str(tr["meta"]))["world"])
    t, p, c = tr["t"], tr["true_pose"].astype(float), tr["cmd"]
    gap = clearance(static_geometry(world), p[:, :2]) - 0.18
    near = np.linalg.norm(p[:, :2] - [cx, cy], axis=1) < R
    step = np.r_[
        np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1), 0
    ]  # movement over the cycle after
    v0 = np.abs(c[:, 0]) < 1e-9
    idx = np.flatnonzero(near)
    if not len(idx):
        print(f"{path.split('/')[-1][:-4]:34s} never within R")
        continue
    print(
        f"{path.split('/')[-1][:-4]:34s} near {near.sum() / 10:5.1f} s | moved v=0 {step[near & v0].sum():5.2f} m "
        f"({(near & v0).sum()} cyc), v>0 {step[near & ~v0].sum():5.2f} m ({(near & ~v0).sum()} cyc) | "
        f"least gap near {gap[near].min() * 100:4.1f} cm | first in {t[idx[0]]:.1f} last {t[idx[-1]]:.1f}"
    )
