"""Smallest body clearance (m: centre distance to the nearest static obstacle minus 0.18 m) per
planner mode over one episode, from its trace and tbinstr.py record.

usage: PYTHONPATH=<tree> python clear_by_mode.py NAME,WORLD.yaml,TRACE.npz,REC.npz ...
Modes as in tbinstr.py: 0 goal free, 1 toward an endpoint (1J: its edge a rho jump), 2 approach,
3 following, 4 strict lap.
"""
import sys

import numpy as np

from nav_bench.episode.trace import Trace
from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world

BODY = 0.18


def main() -> None:
    print("episode: min clearance (m) [share of cycles] by mode")
    for spec in sys.argv[1:]:
        name, wpath, tpath, rpath = spec.split(",")
        geo = static_geometry(load_world(wpath))
        tr = Trace.load(tpath)
        R = np.load(rpath)["rec"]
        db, dc = signed_distances(geo, tr.true_pose[:, :2].astype(float))
        clear = np.concatenate([db, dc], axis=1).min(axis=1) - BODY
        idx = np.clip(np.searchsorted(R[:, 0], tr.t, side="right") - 1, 0, len(R) - 1)
        code = R[idx, 4].astype(int)
        key = np.where((code == 1) & (R[idx, 5] == 1), 10, code)  # 10: toward a jump endpoint
        parts = []
        for c, label in ((0, "goal-free"), (1, "endpoint"), (10, "endpoint@jump"), (2, "approach"),
                         (3, "follow"), (4, "strict")):
            k = key == c
            if k.any():
                parts.append(f"{label} {clear[k].min():.3f} [{k.mean():.2f}]")
        print(f"{name}: " + ", ".join(parts))


if __name__ == "__main__":
    main()
