"""The whole planner, main's DStarLite against this tree's with each kernel, alternating in one
process: bench_planning's 400 x 400 episode (40 s, seed 0) per tree and round, each cycle's
act() CPU split into parts by ``benchmarks/bench_dstar.py``'s ``episode_parts``.

    PYTHONPATH=. python results/speed/dstar_kernel_s14/ab_episode.py MAIN_TREE [ROUNDS]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from nav_bench.planners.dstar_lite import DStarLite

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "benchmarks"))
import bench_dstar


class PythonKernel(DStarLite):
    def __init__(self, **params: object) -> None:
        super().__init__(search_kernel="python", **params)


class NumbaKernel(DStarLite):
    def __init__(self, **params: object) -> None:
        super().__init__(search_kernel="numba", **params)


def main() -> None:
    main_cls = bench_dstar.load_module(f"{sys.argv[1]}/nav_bench/planners/dstar_lite.py").DStarLite
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    runs: dict[str, list[dict[str, np.ndarray]]] = {"main": [], "python": [], "numba": []}
    for rnd in range(rounds):
        order = [("main", main_cls), ("python", PythonKernel), ("numba", NumbaKernel)]
        for label, cls in order if rnd % 2 == 0 else order[::-1]:
            ms, _ = bench_dstar.episode_parts(cls, 40.0, 0)
            runs[label].append(ms)
            print(f"round {rnd} {label:6s} act median {np.median(ms['act']):.3f} p99 "
                  f"{np.percentile(ms['act'], 99):.3f}; repair median {np.median(ms['repair']):.3f} "
                  f"mean {np.mean(ms['repair']):.3f}", flush=True)
    for label, parts in runs.items():
        act = np.concatenate([m["act"] for m in parts])
        repair = np.concatenate([m["repair"] for m in parts])
        print(f"{label:6s} pooled: act median {np.median(act):.3f} mean {act.mean():.3f} p99 "
              f"{np.percentile(act, 99):.3f}; repair median {np.median(repair):.3f} mean {repair.mean():.3f}")


if __name__ == "__main__":
    main()
