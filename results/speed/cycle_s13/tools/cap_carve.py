# ruff: noqa: E402, SIM115  (measurement scripts: patch before import, terse)
"""Capture SeeThroughCarving.update calls: python cap_carve.py PLANNER TIME_S OUT [WORLD]"""
import copy
import pickle
import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import bench_planning as bp

from nav_bench.planners import carving

planner, time_s, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
calls = {"init": [], "upd": []}
i0 = carving.SeeThroughCarving.__init__
def ii(self, frame, pose):
    calls["init"].append((frame, copy.deepcopy(pose)))
    return i0(self, frame, pose)
carving.SeeThroughCarving.__init__ = ii
u = carving.SeeThroughCarving.update
def uu(self, obs, rows, cols, box, occ):
    calls["upd"].append(copy.deepcopy((obs, rows, cols, box, occ)))
    return u(self, obs, rows, cols, box, occ)
carving.SeeThroughCarving.update = uu
from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.specs import PlannerSetSpec
from nav_bench.world.load import load_world

world = bp.big_world() if len(sys.argv) < 5 else load_world(Path("worlds/paper") / f"{sys.argv[4]}.yaml")
spec = PlannerSetSpec(planner=planner)
res = run_episode(world, spec, seed=0, settings=EpisodeSettings(time_s=time_s))
pickle.dump(calls, open(out, "wb"))
print(res.row.outcome, len(calls["upd"]))
