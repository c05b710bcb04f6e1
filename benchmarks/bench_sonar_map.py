"""The sonar map's update, per control cycle: the Elfes model against the three-band model,
the NumPy path against the compiled one, and optionally this tree's update against another git
revision's, side by side.

    python benchmarks/bench_sonar_map.py [--reps 3000] [--seed 0] [--size 40] [--against REV]

One ``OccupancyGrid.update`` per control cycle (6 sonars of the default robot, 25 deg cones,
3 m range, 30% no-echo readings, random poses) on a ``size`` m world (40 m: 400 x 400 cells of
0.1 m). Every variant sees the same poses and readings and the variants are timed alternately,
call by call, so they share the machine's load; prints median and 99th percentile
(microseconds) of the wall clock and of the process's CPU time (less sensitive to other jobs on
a shared machine), the ratios elfes / band and, with Numba installed (the ``fast`` extra),
the ratios numba / numpy (``OccupancyGrid(kernel=...)``; both must build the same maps: the
largest log-odds difference is printed). Target (issue 12): under 0.5 ms per update on 400 x 400.

``--against REV`` also times ``nav_bench/mapping/occupancy.py`` as it is at git revision
``REV`` (e.g. ``main``), prints the ratios this tree / REV per model, and checks that both
built the same maps: the largest log-odds difference per model (0 when bit-for-bit).
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import ModuleType

import numpy as np

from nav_bench.interface import SonarInfo
from nav_bench.mapping import OccupancyGrid
from nav_bench.mapping.occupancy import SONAR_MODELS, _kernels

TARGET_US = 500.0
ROOT = Path(__file__).resolve().parents[1]


def diffbot_sonar() -> SonarInfo:
    """The default robot's sonar ring: -90..90 deg on the body edge (0.18 m)."""
    angles = np.radians([-90.0, -45.0, -15.0, 15.0, 45.0, 90.0])
    return SonarInfo(angles=angles, offsets=0.18 * np.stack([np.cos(angles), np.sin(angles)], 1),
                     cone=math.radians(25.0), min_range=0.05, max_range=3.0)


def occupancy_at(rev: str) -> ModuleType:
    """``nav_bench/mapping/occupancy.py`` as it is at git revision ``rev``, imported as a module."""
    try:
        source = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:nav_bench/mapping/occupancy.py"],
                                check=True, capture_output=True, text=True).stdout
    except subprocess.CalledProcessError as err:
        sys.exit(f"error: --against {rev!r}: {err.stderr.strip()}")
    path = Path(tempfile.mkdtemp()) / "occupancy_against.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("occupancy_against", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=3000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--size", type=float, default=40.0, help="world side, m (cells of 0.1 m)")
    parser.add_argument("--against", metavar="REV", help="also time occupancy.py at this git revision")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    sonar, size, n = diffbot_sonar(), args.size, args.reps + 50
    poses = np.column_stack([rng.uniform(1.0, size - 1.0, n), rng.uniform(1.0, size - 1.0, n),
                             rng.uniform(-math.pi, math.pi, n)])
    scans = np.where(rng.random((n, 6)) < 0.3, 3.0, rng.uniform(0.2, 2.9, (n, 6)))
    bounds = (0.0, 0.0, size, size)
    kernels = ("numpy", "numba") if _kernels() is not None else ("numpy",)
    grids = {(k, m): OccupancyGrid(bounds, 0.1, model=m, kernel=k) for k in kernels for m in SONAR_MODELS}
    if args.against:
        other = occupancy_at(args.against).OccupancyGrid
        grids.update({(args.against, m): other(bounds, 0.1, model=m) for m in SONAR_MODELS})
    clocks = {"wall": time.perf_counter_ns, "cpu": time.process_time_ns}
    times = {(c, key): np.empty(args.reps) for c in clocks for key in grids}
    for i in range(n):
        for key, grid in grids.items():  # alternate: every variant under the same load
            w0, c0 = time.perf_counter_ns(), time.process_time_ns()
            grid.update(poses[i], scans[i], sonar)
            w1, c1 = time.perf_counter_ns(), time.process_time_ns()
            if i >= 50:  # the first 50 warm up (the disc of offsets is built on the first call)
                times["wall", key][i - 50] = w1 - w0
                times["cpu", key][i - 50] = c1 - c0
    shape = next(iter(grids.values())).shape
    print(f"OccupancyGrid.update, {shape[1]} x {shape[0]} grid, 6 sonars, {args.reps} updates "
          f"per variant, load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    stats = {key: (float(np.median(t)) / 1e3, float(np.percentile(t, 99)) / 1e3)
             for key, t in times.items()}
    for clock in clocks:
        for (tree, model) in grids:
            median, p99 = stats[clock, (tree, model)]
            verdict = "under" if median < TARGET_US else "OVER"
            print(f"  {clock:4s} {tree:8s} {model:6s} median {median:7.1f} us   p99 {p99:8.1f} us   "
                  f"({verdict} the {TARGET_US:.0f} us target)")
        for kernel in kernels:
            (m_new, p_new), (m_old, p_old) = stats[clock, (kernel, "elfes")], stats[clock, (kernel, "band")]
            print(f"  {clock:4s} ratio elfes / band ({kernel}): median {m_new / m_old:.2f}, "
                  f"p99 {p_new / p_old:.2f}")
        pairs = [(("numba", m), ("numpy", m)) for m in SONAR_MODELS if len(kernels) > 1]
        pairs += [((kernels[-1], m), (args.against, m)) for m in SONAR_MODELS if args.against]
        for new, old in pairs:
            (m_new, p_new), (m_old, p_old) = stats[clock, new], stats[clock, old]
            print(f"  {clock:4s} ratio {new[0]} / {old[0]} ({new[1]}): median "
                  f"{m_new / m_old:.2f}, p99 {p_new / p_old:.2f}")
    for new, old in pairs:
        diff = np.abs(grids[new].log_odds - grids[old].log_odds).max()
        print(f"  {new[1]}: largest |log-odds difference| {new[0]} vs {old[0]}: {diff:.3g}")


if __name__ == "__main__":
    main()
