"""Gaps (m) between pairs of static obstacles within 1 m of where a robot spent its last 30 s.

    python results/baselines/bugs_s8/gaps.py WORLD.yaml RECORD.npz

RECORD.npz is instr.py's per-cycle record (column 0 time s, 1-2 position m). The gap between
two obstacles is the minimum over a 1 cm grid of the sum of the distances to both (for convex
shapes, their distance).
"""

import sys

import numpy as np

from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world


def gaps_near(world_path: str, record_path: str) -> str:
    world = load_world(world_path)
    rec = np.load(record_path)["rec"]
    xy = rec[rec[:, 0] >= rec[-1, 0] - 30, 1:3]
    c = xy.mean(axis=0)
    geo = static_geometry(world)
    grid = np.mgrid[c[0] - 1.5:c[0] + 1.5:0.01, c[1] - 1.5:c[1] + 1.5:0.01].reshape(2, -1).T
    d = np.concatenate(signed_distances(geo, grid), axis=1)  # (G, obstacles)
    near = np.nonzero(np.min(np.concatenate(signed_distances(geo, xy), axis=1), axis=0) < 1.0)[0]
    found = []
    for a, i in enumerate(near):
        for j in near[a + 1:]:
            outside = (d[:, i] >= 0) & (d[:, j] >= 0)
            total = d[outside, i] + d[outside, j]
            if len(total):
                k = int(np.argmin(total))
                found.append((float(total[k]), grid[outside][k]))
    gaps = sorted(g for g in found if 0.3 < g[0] < 0.9)
    return (f"centre ({c[0]:.2f},{c[1]:.2f}); gaps 0.3-0.9 m between obstacles within 1 m of the last 30 s: "
            + ", ".join(f"{s:.2f} at ({p[0]:.2f},{p[1]:.2f})" for s, p in gaps))


if __name__ == "__main__":
    print(gaps_near(sys.argv[1], sys.argv[2]))
