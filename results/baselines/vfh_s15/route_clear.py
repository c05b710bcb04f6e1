"""The clearance (m) along the widest route (vfh_s14/gapwhy.widest_route) from a point to the
goal, over its first 2.5 m: where the route hugs one obstacle at r* the clearance stays at r*
over a stretch; a two-sided constriction is where both sides are that close.
PYTHONPATH=$PWD python results/baselines/vfh_s15/route_clear.py WORLD X Y
"""
import sys

import numpy as np
import yaml

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s14")
from gapwhy import widest_route

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

name, x, y = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
with open(f"results/baselines/bugs_s6/worlds/{name}.yaml") as f:
    world = world_from_data(yaml.safe_load(f))
g = static_geometry(world)
(length, way), r_star = widest_route(g, (x, y), tuple(world.goal))
print(f"route {length:.2f} m, r* {r_star:.2f} m")
run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(way, axis=0).T))])
for s, p, c in zip(run, way, clearance(g, way), strict=True):
    if s <= 2.5:
        print(f"{s:5.2f} ({p[0]:.2f}, {p[1]:.2f}) clearance {c:.3f} gap {2 * c:.3f}")
