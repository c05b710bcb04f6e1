# ruff: noqa: E402  (measurement scripts: patch before import, terse)
"""Per-part CPU medians (us) of one planner's act() on the big world: python parts.py PLANNER TIME_S"""
import functools
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import bench_planning as bp

from nav_bench.mapping import occupancy
from nav_bench.planners import carving, dstar_lite, dwa, recovery, vfh_plus

planner, time_s = sys.argv[1], float(sys.argv[2])
acc = {}
cyc = {}
def wrap(owner, name, label):
    f = getattr(owner, name)
    @functools.wraps(f)
    def g(*a, **k):
        t0 = time.process_time_ns()
        try:
            return f(*a, **k)
        finally:
            cyc[label] = cyc.get(label, 0) + time.process_time_ns() - t0
    setattr(owner, name, g)
targets = [(occupancy.OccupancyGrid, "update", "grid.update"),
           (dstar_lite.DStarLite, "_map_changes", "_map_changes"),
           (dstar_lite.PathRepair, "cycle", "repair.cycle"),
           (dstar_lite.DStarLite, "_local_clearance", "_local_clearance"),
           (carving.SeeThroughCarving, "_note", " carving._note"),
           (carving, "seen_through_cells", "  seen_through_cells"),
           (carving, "cell_parts", " cell_parts"),
           (carving.SeeThroughCarving, "_forget", " carving._forget"),
           (dstar_lite.DStarLite, "_follow", "_follow"),
           (recovery.ProgressWatch, "update", "watch.update"),
           (vfh_plus, "read_window", "vfh read_window"),
           (vfh_plus.ActiveWindow, "carved", "vfh window.carved"),
           (vfh_plus.VFHPlus, "_carved_window", "vfh _carved_window"),
           (vfh_plus, "window_histogram", "vfh window_histogram"),
           (vfh_plus, "window_turning_limits", "vfh turning_limits"),
           (vfh_plus, "select_direction", "vfh select_direction"),
           (dwa, "choose_velocity", "dwa choose_velocity"),
           (dwa.DWA, "obstacle_points", "dwa obstacle_points"),
           ]
for t in targets:
    if hasattr(t[0], t[1]):
        wrap(*t)
from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.registry import make_planner
from nav_bench.specs import PlannerSetSpec

spec = PlannerSetSpec(planner=planner)
agent = make_planner(spec)
act = agent.act
tot = []
def timed(obs):
    cyc.clear()
    t0 = time.process_time_ns()
    out = act(obs)
    tot.append(time.process_time_ns() - t0)
    for k, v in cyc.items():
        acc.setdefault(k, []).append(v)
    return out
agent.act = timed
res = run_episode(bp.big_world(), spec, seed=0, settings=EpisodeSettings(time_s=time_s), planner_instance=agent)
print(planner, res.row.outcome, len(tot), "cycles; act median %.3f ms" % (np.median(tot) / 1e6))
for k, v in acc.items():
    print(f"  {k:28s} median {np.median(v)/1e3:8.1f} us  mean {np.mean(v)/1e3:8.1f} us  n={len(v)}")
