"""The search alone, main's against this tree's, alternating in one process: one fixed script of
150 cycles on a 400 x 400 clearance-cost map (2-7 cells flip within 2.5 m of the robot, the
robot moves 5 cells along its path, ``set_costs`` + ``compute(250)`` + ``descend(160)``), CPU
seconds of those calls only.

    PYTHONPATH=. python results/speed/dstar_kernel_s14/ab_replay.py MAIN_TREE [python|numba] [ROUNDS]

``python``: this tree's DStarLiteSearch (the fallback), ``numba``: its CompiledSearch.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from nav_bench.planners.dstar_lite import (
    CompiledSearch,
    DStarLiteSearch,
    clearance_costs,
    obstacle_distance,
)

N, START, GOAL = 400, (5, 5), (390, 390)


def load_main(tree: str) -> type:
    sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "benchmarks"))
    import bench_dstar

    return bench_dstar.load_module(f"{tree}/nav_bench/planners/dstar_lite.py").DStarLiteSearch


def costs(occ: np.ndarray) -> np.ndarray:
    cost = clearance_costs(obstacle_distance(occ, 5.0), 2.0, 3.5, 1000.0, 5.0)
    cost[START] = cost[GOAL] = 1.0
    return cost


def script(seed: int = 5) -> tuple[np.ndarray, list]:
    """The first map and the cycles (start, rows, cols, new costs), recorded once."""
    rng = np.random.default_rng(seed)
    occ = rng.random((N, N)) < 0.01
    first = costs(occ)
    ref = DStarLiteSearch(first, START, GOAL)
    ref.plan_from_scratch()
    cycles, cur, start = [], first, START
    for _ in range(150):
        ahead = ref.descend(12)
        if len(ahead) > 5:
            start = ref.graph.cell(ahead[5])
        for _ in range(int(rng.integers(2, 8))):
            r, c = start[0] + int(rng.integers(-25, 26)), start[1] + int(rng.integers(-25, 26))
            if 0 <= r < N and 0 <= c < N:
                occ[r, c] ^= True
        occ[start] = occ[GOAL] = False
        new = costs(occ)
        rows, cols = np.nonzero(new != cur)
        cur = new
        cycles.append((start, rows, cols, new[rows, cols]))
        ref.move_start(start)
        ref.set_costs(rows, cols, new[rows, cols])
        ref.compute(250)
    return first, cycles


def play(cls: type, first: np.ndarray, cycles: list) -> tuple[float, int]:
    search = cls(first, START, GOAL)
    search.plan_from_scratch()
    cpu = 0.0
    for start, rows, cols, vals in cycles:
        t0 = time.process_time()
        search.move_start(start)
        search.set_costs(rows, cols, vals)
        search.compute(250)
        search.descend(160)
        cpu += time.process_time() - t0
    return cpu, search.expansions


def main() -> None:
    main_cls = load_main(sys.argv[1])
    kernel = sys.argv[2] if len(sys.argv) > 2 else "python"
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    ours = CompiledSearch if kernel == "numba" else DStarLiteSearch
    first, cycles = script()
    total = {"main": 0.0, kernel: 0.0}
    for rnd in range(rounds):
        pair = [("main", main_cls), (kernel, ours)]
        for label, cls in pair if rnd % 2 == 0 else pair[::-1]:
            cpu, expansions = play(cls, first, cycles)
            total[label] += cpu
            print(f"round {rnd} {label:6s} {cpu:6.3f} s CPU, {expansions} expansions", flush=True)
    print(f"totals: main {total['main']:.3f} s, {kernel} {total[kernel]:.3f} s, "
          f"ratio {kernel}/main {total[kernel] / total['main']:.3f}")


if __name__ == "__main__":
    main()
