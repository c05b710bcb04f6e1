import sys
import numpy as np
sys.path.insert(0, sys.argv[1] + "/benchmarks")
import bench_planning as bp
w = bp.big_world()
for planner in ("dstar_lite", "dwa_global"):
    wall, cpu, outcome = bp.plan_ms(w, planner, 40.0, 0)
    print(f"{planner:11s} {outcome:8s} n={len(cpu)} median {np.median(cpu):.3f} mean {cpu.mean():.3f} p99 {np.percentile(cpu, 99):.3f} total {cpu.sum():.0f} ms")
