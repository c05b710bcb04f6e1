"""Per-cycle CPU cost of D* Lite and dwa_global on clutter_40m (400 x 400 cells), 40 s, seed 0.

    PYTHONPATH=TREE python cycle_cost.py TREE

Prints, per planner, the cycles' median, mean, p99 and total (ms) of ``act()`` as
``benchmarks/bench_planning.py`` of TREE measures them (process CPU clock).
"""

import sys

import numpy as np

sys.path.insert(0, sys.argv[1] + "/benchmarks")
import bench_planning as bp

world = bp.big_world()
for planner in ("dstar_lite", "dwa_global"):
    _wall, cpu, outcome = bp.plan_ms(world, planner, 40.0, 0)
    print(f"{planner:11s} {outcome:8s} n={len(cpu)} median {np.median(cpu):.3f} mean {cpu.mean():.3f} "
          f"p99 {np.percentile(cpu, 99):.3f} total {cpu.sum():.0f} ms")
