# ruff: noqa  (measurement scripts: terse)
"""Do the warm-ups cover every type the planners call the kernels with? Counts each kernel's
compiled signatures after the warm-ups and after a D* Lite and a VFH+ episode on clutter_40m:
    PYTHONPATH=TREE python signatures.py TREE"""
import sys
sys.path.insert(0, sys.argv[1] + "/benchmarks")
import bench_planning as bp
from nav_bench.planners import carving, vfh_plus
carving._load_compiled_code(); vfh_plus._load_compiled_code()
mods = [carving.load_kernels(), vfh_plus.load_kernels()]
def count():
    return {f"{m.__name__.split('.')[-1]}.{n}": len(getattr(m, n).signatures)
            for m in mods for n in dir(m) if hasattr(getattr(m, n), "signatures")}
before = count()
for planner in ("dstar_lite", "vfh_plus"):
    bp.plan_ms(bp.big_world(), planner, 20.0, 0)
after = count()
for k in sorted(before):
    print(f"{k:36s} after warm-up {before[k]}  after the episodes {after[k]}")
print("new signatures in the episodes:", {k: after[k] - before[k] for k in after if after[k] != before[k]} or "none")
