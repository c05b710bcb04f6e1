"""Gaps (m) between pairs of static obstacles within 1 m of where the robot spent its last 30 s."""
import sys
import numpy as np
from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world

world = load_world(sys.argv[1]); R = np.load(sys.argv[2])['rec']
tp = None
if len(sys.argv) > 3:  # true positions from a trace
    from nav_bench.episode.trace import Trace
    tr = Trace.load(sys.argv[3]); xy = tr.true_pose[tr.t >= tr.t[-1] - 30, :2]
else:
    xy = R[R[:, 0] >= R[-1, 0] - 30, 1:3]
c = xy.mean(axis=0)
geo = static_geometry(world)
g = np.mgrid[c[0]-1.5:c[0]+1.5:0.01, c[1]-1.5:c[1]+1.5:0.01].reshape(2, -1).T
db, dc = signed_distances(geo, g)
D = np.concatenate([db, dc], axis=1)
dpos, _ = signed_distances(geo, xy)
near = np.nonzero(np.min(np.concatenate(signed_distances(geo, xy), axis=1), axis=0) < 1.0)[0]
out = []
for a in range(len(near)):
    for b in range(a + 1, len(near)):
        i, j = near[a], near[b]
        ok = (D[:, i] >= 0) & (D[:, j] >= 0)
        s = D[ok, i] + D[ok, j]
        if len(s):
            k = np.argmin(s); out.append((s[k], g[ok][k]))
gaps = sorted(x for x in out if 0.3 < x[0] < 0.9)
print(f"centre ({c[0]:.2f},{c[1]:.2f}); gaps 0.3-0.9 m between obstacles within 1 m of the last 30 s: " +
      ", ".join(f"{s:.2f} at ({p[0]:.2f},{p[1]:.2f})" for s, p in gaps))
