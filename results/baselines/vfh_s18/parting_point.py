"""parting_point.py SONAR.npz ORACLE.npz: the gap a sonar-map VFH+ robot rocks at and the
true-map robot passes, as a midpoint for sonar_gap.py: of the true-map robot's path points
within 1.0 m of where the sonar-map robot spent its last 60 s (mean true position), the one
with the least clearance from the obstacles (m). Prints "x y clearance"."""
import sys

import numpy as np

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

sonar = load(sys.argv[1])
g = static_geometry(world_from_data(sonar.meta["world"]))
late = sonar.true[sonar.t >= sonar.t[-1] - 60.0, :2].astype(float).mean(axis=0)
path = np.load(sys.argv[2])["true_pose"][:, :2].astype(float)
near = np.hypot(*(path - late).T) <= 1.0
if not near.any():
    near = np.hypot(*(path - late).T) <= np.hypot(*(path - late).T).min() + 0.2
cand = path[near]
c = clearance(g, cand)
j = int(np.argmin(c))
print(f"{cand[j, 0]:.3f} {cand[j, 1]:.3f} {c[j]:.3f}")
