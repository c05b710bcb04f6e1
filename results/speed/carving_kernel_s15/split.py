# ruff: noqa  (measurement scripts: patch before import, terse)
"""Split of D* Lite's or VFH+'s carving and clearance (median us per cycle) on clutter_40m.

    PYTHONPATH=TREE python split.py TREE [dstar_lite|vfh_plus]
"""
import sys, time
import numpy as np
sys.path.insert(0, sys.argv[1]); sys.path.insert(0, sys.argv[1] + "/benchmarks")
import bench_planning as bp
from nav_bench.planners import carving as C, footprint as F, dstar_lite as D, vfh_plus as V
from nav_bench import compiled
planner = sys.argv[2] if len(sys.argv) > 2 else "dstar_lite"
cycles, cur = [], {}
def wrap(owner, name, label):
    f = getattr(owner, name)
    def w(*a, **k):
        t0 = time.process_time()
        try: return f(*a, **k)
        finally: cur[label] = cur.get(label, 0) + time.process_time() - t0
    setattr(owner, name, w)
try:
    K = compiled.load("nav_bench.planners.carving_kernels")
except ImportError:
    K = None
if K is not None:
    wrap(K, "carve_cells", "k_carve")
wrap(C.SeeThroughCarving, "update", "update")
wrap(C.CarvedCells, "kept_parts", "kept_parts")
wrap(F.PointObstacles, "__init__", "points_init")
wrap(F.PointObstacles, "__call__", "points_call")
if planner == "dstar_lite":
    wrap(D.DStarLite, "_local_clearance", "local_clearance")
    wrap(D.DStarLite, "_follow", "follow")
    top = D.DStarLite
else:
    wrap(V.VFHPlus if hasattr(V, "VFHPlus") else V.VfhPlus, "_carved_window", "carved_window")
    wrap(V, "read_window", "read_window"); wrap(V.ActiveWindow, "carved", "window_carved")
    top = V.VFHPlus if hasattr(V, "VFHPlus") else V.VfhPlus
orig = top.act
def act(self, obs):
    cur.clear(); t0 = time.process_time()
    cmd = orig(self, obs); cur["total"] = time.process_time() - t0
    cycles.append(dict(cur)); return cmd
top.act = act
world = bp.big_world()
bp.plan_ms(world, planner, 40.0, 0)
keys = sorted({k for c in cycles for k in c})
for k in keys:
    v = np.array([c.get(k, 0.0) for c in cycles]) * 1e6
    print(f"{k:16s} median {np.median(v):7.1f} mean {v.mean():7.1f} us")
print(len(cycles), "cycles")
