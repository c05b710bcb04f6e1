"""same_as_main.py KERNEL OUT: a 300-step random sequence of readings, poses and occupied cells
through SeeThroughCarving with its defaults (main's carving, D* Lite's), KERNEL numpy or numba;
saves the kept masks (OUT.npy) and the final carved records (OUT_c.npy). Run it with
PYTHONPATH=/work/main and with PYTHONPATH=<the patched tree>, then compare the files with
np.array_equal: the patch leaves the default carving bit for bit as main's."""
import sys

import numpy as np

from nav_bench.interface import Observation
from nav_bench.mapping.grid import GridFrame
from nav_bench.planners.carving import SeeThroughCarving
from nav_bench.testing.harness import default_robot

rng = np.random.default_rng(1501)
robot = default_robot(radius=0.18)
cell = 0.1
frame = GridFrame(-1.0, -1.0, cell, 50, 60)
pose = np.array([frame.xmin + 30 * cell, frame.ymin + 25 * cell, 0.0])
ref = SeeThroughCarving(frame, pose, sys.argv[1])
occupied = rng.random(frame.shape) < 0.2
t = 0.0
out = []
for _step in range(300):
    pose = pose + np.array([*rng.normal(0.0, 0.02, 2), rng.normal(0.0, 0.06)])
    t = t + 0.1
    r0, c0 = frame.cell_of(float(pose[0]), float(pose[1]))
    n = 10
    a0, a1, b0, b1 = max(r0-n,0), min(r0+n+1,frame.rows), max(c0-n,0), min(c0+n+1,frame.cols)
    box = occupied[a0:a1, b0:b1].copy()
    rr, cc = np.nonzero(box)
    ranges = rng.uniform(0.05, 3.0, 6)
    obs = Observation(t=t, pose=pose.copy(), goal=np.zeros(2), ranges=ranges, robot=robot, bounds=(0.0,0.0,1.0,1.0), dt=0.1)
    o = ref.update(obs, rr + a0, cc + b0, (a0, a1, b0, b1), box)
    out.append(o.kept.copy())
np.save(sys.argv[2], np.concatenate([k.ravel() for k in out]))
np.save(sys.argv[2]+"_c", ref.carved_t)
