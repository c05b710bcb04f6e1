"""Per-update CPU time of OccupancyGrid.update, NumPy path against the compiled one, alternated
call by call in one process (both see the same load), along a smooth random walk (as a robot
moves: 3 cm and a few degrees per cycle) and at random poses (every update in a new place:
cold caches); both models; checks the maps are equal bit for bit; draws update_cpu.png.

    PYTHONPATH=<tree> python results/speed/sonar_kernel_s15/update_cpu.py [--reps 4000]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2] / "benchmarks"))
from bench_sonar_map import diffbot_sonar  # noqa: E402

from nav_bench.mapping import OccupancyGrid  # noqa: E402


def poses(rng: np.random.Generator, n: int, size: float) -> dict[str, np.ndarray]:
    """``walk``: 3 cm steps, heading noise 0.1 rad; ``random``: anywhere, any heading."""
    walk = [np.array([size / 2, size / 2, 0.0])]
    for _ in range(n - 1):
        p = walk[-1].copy()
        p[2] += rng.normal(0.0, 0.1)
        p[:2] = np.clip(p[:2] + 0.03 * np.array([math.cos(p[2]), math.sin(p[2])]), 1.0, size - 1.0)
        walk.append(p)
    rand = np.column_stack([rng.uniform(1.0, size - 1.0, n), rng.uniform(1.0, size - 1.0, n),
                            rng.uniform(-math.pi, math.pi, n)])
    return {"walk": np.array(walk), "random": rand}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=4000)
    args = parser.parse_args()
    rng, size, sonar = np.random.default_rng(0), 40.0, diffbot_sonar()
    scans = np.where(rng.random((args.reps, 6)) < 0.3, 3.0, rng.uniform(0.2, 2.9, (args.reps, 6)))
    fig, axes = plt.subplots(2, 2, figsize=(10, 6), sharex=True)
    print(f"OccupancyGrid.update, 400 x 400, 6 sonars, {args.reps} updates per variant, CPU time "
          f"(process_time_ns); load average at start {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    for row, (walk, path) in enumerate(poses(rng, args.reps, size).items()):
        for col, model in enumerate(("elfes", "band")):
            grids = {k: OccupancyGrid((0.0, 0.0, size, size), 0.1, model=model, kernel=k)
                     for k in ("numpy", "numba")}
            times = {k: np.empty(args.reps) for k in grids}
            for i in range(args.reps):
                for k, grid in grids.items():
                    t0 = time.process_time_ns()
                    grid.update(path[i], scans[i], sonar)
                    times[k][i] = (time.process_time_ns() - t0) / 1e3
            same = np.array_equal(grids["numpy"].log_odds.view(np.int64), grids["numba"].log_odds.view(np.int64))
            med = {k: float(np.median(t[50:])) for k, t in times.items()}
            print(f"  {walk:6s} {model:5s} numpy median {med['numpy']:6.1f} us  numba median "
                  f"{med['numba']:6.1f} us  ratio {med['numba'] / med['numpy']:.2f}  maps bit-equal: {same}")
            ax = axes[row, col]
            for k, t in times.items():
                ax.hist(t[50:], bins=np.linspace(0, 300, 121), histtype="step", label=f"{k} (median {med[k]:.0f} us)")
            ax.set_title(f"{model}, {walk} poses")
            ax.legend()
    for ax in axes[1]:
        ax.set_xlabel("CPU per update, us")
    fig.suptitle("OccupancyGrid.update on 400 x 400 cells, 6 sonars: NumPy vs compiled (Numba)")
    fig.tight_layout()
    fig.savefig(HERE / "update_cpu.png", dpi=90)
    print(f"  load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
