"""D* Lite repair after a sonar update vs. A* from scratch, on 100 x 100 and 400 x 400 grids.

    python benchmarks/bench_dstar.py [--updates 300] [--seed 0]

The setting imitates what :class:`~nav_bench.planners.dstar_lite.DStarLite` does each cycle:

* a cluttered map (random boxes 0.3..1.5 m on 8 % of the area, cell 0.1 m), inflated by
  3 cells (robot radius 0.2 m + margin 0.1 m); start and goal near opposite corners;
  the planner initially knows only the boxes (freespace assumption elsewhere);
* the robot walks its current path 0.5 m (5 cells) between updates; near the goal a new
  episode starts from a random free cell (its initial plan is not timed);
* a *typical sonar update*: a handful (3..8) of cells become occupied on an arc
  1..2.5 m ahead of the robot, within +-30 deg of its heading (an unseen obstacle
  showing up in a front sonar cone); with 30 % chance a few old arc cells are freed again.
  Their inflation changes a few dozen cell costs, which go to ``set_costs``.

Timed per update: D* Lite ``set_costs`` + ``compute`` (the repair) and then the path
extraction; A* from scratch (``astar``) on the same cost grid. Prints median and 99th
percentile (milliseconds) and the ratio A* / D* Lite of the medians.
Target: D* Lite repair under 5 ms median on 100 x 100.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

from nav_bench.planners.dstar_lite import DStarLiteSearch, astar, cell_costs

INFLATE = 3.0  # cells
INFLATED_COST = 20.0


def cluttered(n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, n) bool occupancy with random boxes covering ~8 % of the grid, corners kept free."""
    occ = np.zeros((n, n), dtype=bool)
    while occ.mean() < 0.08:
        h, w = rng.integers(3, 16, 2)
        r, c = rng.integers(0, n - h), rng.integers(0, n - w)
        occ[r:r + h, c:c + w] = True
    occ[:12, :12] = occ[-12:, -12:] = False
    return occ


def arc_cells(pos: tuple[int, int], heading: float, n: int, rng: np.random.Generator) -> np.ndarray:
    """(k, 2) cells of a short sonar echo arc ahead of ``pos`` (3..8 cells)."""
    dist = rng.uniform(10, 25)
    centre = heading + rng.uniform(-math.radians(30), math.radians(30))
    k = int(rng.integers(3, 9))
    ang = centre + (np.arange(k) - (k - 1) / 2) / dist
    rc = np.stack([pos[0] + dist * np.sin(ang), pos[1] + dist * np.cos(ang)], axis=1)
    rc = np.unique(np.rint(rc).astype(int), axis=0)
    return rc[(rc >= 0).all(axis=1) & (rc < n).all(axis=1)]


def run(n: int, updates: int, seed: int) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    occ = cluttered(n, rng)
    start, goal = (5, 5), (n - 6, n - 6)
    cost = cell_costs(occ, INFLATE, INFLATED_COST)
    search = DStarLiteSearch(cost, start, goal)
    t0 = time.perf_counter()
    search.compute()
    initial = time.perf_counter() - t0
    repair, extract, scratch, changed, expansions = [], [], [], [], []
    arcs: list[np.ndarray] = []
    pos = start
    for _ in range(updates):
        path = search.path()
        if len(path) < 30:  # near the goal (or cut off): a new episode from a random free cell
            free = np.argwhere(cost == 1.0)
            pos = tuple(int(v) for v in free[rng.integers(len(free))])
            search = DStarLiteSearch(cost, pos, goal)  # not timed: the episode's initial plan
            search.compute()
            path = search.path()
            if len(path) < 30:
                continue
        pos = path[5]
        ahead = path[min(15, len(path) - 1)] if len(path) > 1 else goal
        heading = math.atan2(ahead[0] - pos[0], ahead[1] - pos[1])
        search.move_start(pos)
        new = arc_cells(pos, heading, n, rng)
        new = new[[tuple(c) not in (pos, goal) for c in new]] if len(new) else new
        occ[new[:, 0], new[:, 1]] = True
        arcs.append(new)
        if len(arcs) > 3 and rng.random() < 0.3:  # an old arc turns out to be a sonar ghost
            old = arcs.pop(0)
            occ[old[:, 0], old[:, 1]] = False
        new_cost = cell_costs(occ, INFLATE, INFLATED_COST)
        new_cost[pos] = min(new_cost[pos], INFLATED_COST)  # the robot's own cell stays passable
        new_cost[goal] = min(new_cost[goal], INFLATED_COST)
        rr, cc = np.nonzero(new_cost != cost)
        cost = new_cost
        changed.append(len(rr))
        before = search.expansions
        t0 = time.perf_counter()
        search.set_costs(rr, cc, cost[rr, cc])
        search.compute()
        t1 = time.perf_counter()
        search.path()
        t2 = time.perf_counter()
        expansions.append(search.expansions - before)
        c_star, _ = astar(cost, pos, goal)
        t3 = time.perf_counter()
        assert math.isinf(c_star) == math.isinf(search.path_cost)
        assert math.isinf(c_star) or abs(c_star - search.path_cost) < 1e-6, "repair != A*"
        repair.append(t1 - t0)
        extract.append(t2 - t1)
        scratch.append(t3 - t2)
    ms = 1e3
    return {"initial": initial * ms,
            "repair_med": float(np.median(repair)) * ms, "repair_p99": float(np.percentile(repair, 99)) * ms,
            "extract_med": float(np.median(extract)) * ms,
            "astar_med": float(np.median(scratch)) * ms, "astar_p99": float(np.percentile(scratch, 99)) * ms,
            "changed": float(np.median(changed)), "expanded": float(np.median(expansions))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--updates", type=int, default=300, help="sonar updates per grid size")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}; {args.updates} updates per grid; times in ms")
    head = (f"{'grid':>9} {'initial':>8} {'cells chg':>9} {'expanded':>8} {'D* med':>7} {'D* p99':>7} "
            f"{'path':>6} {'A* med':>7} {'A* p99':>7} {'A*/D*':>6}")
    print(head)
    print("-" * len(head))
    for n in (100, 400):
        r = run(n, args.updates, args.seed)
        print(f"{n:>4}x{n:<4} {r['initial']:8.1f} {r['changed']:9.0f} {r['expanded']:8.0f} "
              f"{r['repair_med']:7.2f} {r['repair_p99']:7.2f} {r['extract_med']:6.2f} "
              f"{r['astar_med']:7.2f} {r['astar_p99']:7.2f} {r['astar_med'] / r['repair_med']:6.1f}")
    print("D* med/p99: set_costs + compute (the repair); path: extracting the cell path afterwards;"
          " A*: planning from scratch on the same costs.")


if __name__ == "__main__":
    main()
