# ruff: noqa  (measurement scripts: patch before import, terse)
"""Micro-benchmark of one SeeThroughCarving.update (auto) on a 400 x 400 grid, and its cProfile."""
import time, math, numpy as np
from nav_bench.planners import carving as C
from nav_bench.mapping.grid import GridFrame
from nav_bench.interface import Observation
from nav_bench.testing.harness import default_robot
frame = GridFrame(0.0, 0.0, 0.1, 400, 400)
car = C.SeeThroughCarving(frame, np.zeros(3))
robot = default_robot()
occ = np.zeros((400, 400), bool); occ[195:205, 210] = True
box = (180, 221, 180, 221)
rr, cc = np.nonzero(occ[180:221, 180:221])
obs = Observation(t=1.0, pose=np.array([20.0, 20.0, 0.0]), goal=np.zeros(2), ranges=np.full(6, 1.2), robot=robot, bounds=(0,0,40,40), dt=0.1)
K = C.load_kernels()
for label, fn in [("update", lambda: car.update(obs, rr + 180, cc + 180, box, occ[180:221, 180:221])),
                  ("empty", lambda: car.update(obs, rr[:0], cc[:0], (0, 0, 0, 0), occ[180:221, 180:221]))]:
    for _ in range(100): fn()
    t0 = time.perf_counter(); n = 3000
    for _ in range(n): fn()
    print(label, (time.perf_counter() - t0) / n * 1e6, "us", len(rr))
import cProfile, pstats
cProfile.run("for _ in range(3000): car.update(obs, rr + 180, cc + 180, box, occ[180:221, 180:221])", "/tmp/s15carve/prof")
pstats.Stats("/tmp/s15carve/prof").sort_stats("tottime").print_stats(12)
