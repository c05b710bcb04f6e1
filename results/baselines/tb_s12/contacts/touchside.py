"""Where on the robot each contact was: bearing of the touched surface from the heading, and
whether it lies on the side of the boundary being followed.

usage: PYTHONPATH=<tree> python touchside.py WORLD.yaml TRACE.npz REC.npz [...triples]

TRACE from ``nav-bench episode --trace``, REC from tbinstr.py (same episode). For each contact
the true pose at the next control cycle, 72 points 0.2 m round the centre (the body radius
0.18 m plus 2 cm), and the bearings of those within 2 cm of an obstacle: the touch bearing is
their circular mean (deg, + = left of the heading). Followed side: + = left (LEFT = 1).
"""
import math
import sys

import numpy as np

from nav_bench.episode.trace import Trace
from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world


def touch_bearing(geo, pose) -> float:
    a = np.linspace(-math.pi, math.pi, 72, endpoint=False)
    pts = np.c_[pose[0] + 0.2 * np.cos(pose[2] + a), pose[1] + 0.2 * np.sin(pose[2] + a)]
    db, dc = signed_distances(geo, pts)
    d = np.concatenate([db, dc], axis=1).min(axis=1)
    near = a[d < 0.02]
    if not len(near):
        near = a[[int(np.argmin(d))]]
    return math.degrees(math.atan2(np.sin(near).mean(), np.cos(near).mean()))


def main() -> None:
    args = sys.argv[1:]
    for wpath, tpath, rpath in zip(args[::3], args[1::3], args[2::3], strict=True):
        geo = static_geometry(load_world(wpath))
        tr = Trace.load(tpath)
        z = np.load(rpath)
        R = z["rec"]
        for tc, _ in z["contacts"]:
            i = min(int(np.searchsorted(tr.t, tc + 0.1)), len(tr.t) - 1)
            b = touch_bearing(geo, tr.true_pose[i].astype(float))
            r = R[min(int(np.searchsorted(R[:, 0], tc)), len(R) - 1)]
            side = int(r[6])
            where = "ahead" if abs(b) < 30 else ("followed side" if b * side > 0 else "other side")
            print(f"{tr.row['world']} t={tc:.1f}s touch bearing {b:+.0f} deg, followed side "
                  f"{'left' if side == 1 else 'right'}: {where}; v {r[7]:.2f} omega {r[8]:+.2f}")


if __name__ == "__main__":
    main()
