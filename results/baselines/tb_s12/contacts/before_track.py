"""How near the other revision's run came to each contact pose: the smallest distance (m) from its
whole true track, and the smallest among its poses within 45 deg of the contact's heading.

usage: PYTHONPATH=<tree> python before_track.py TRACE.npz REC.npz OTHER_TRACE.npz ...(triples)
"""
import math
import sys

import numpy as np

from nav_bench.episode.trace import Trace


def main() -> None:
    a = sys.argv[1:]
    for tpath, rpath, opath in zip(a[::3], a[1::3], a[2::3], strict=True):
        tr, other = Trace.load(tpath), Trace.load(opath)
        for tc, _ in np.load(rpath)["contacts"].reshape(-1, 2):
            i = min(int(np.searchsorted(tr.t, tc + 0.1)), len(tr.t) - 1)
            p = tr.true_pose[i].astype(float)
            d = np.hypot(other.true_pose[:, 0] - p[0], other.true_pose[:, 1] - p[1])
            dh = np.abs((other.true_pose[:, 2] - p[2] + np.pi) % (2 * np.pi) - np.pi)
            same = np.where(dh < math.radians(45), d, np.inf)
            j = int(np.argmin(same))
            print(f"{tr.row['world']} {tc:.1f}s: other track nearest {d.min():.2f} m; same heading (+-45 deg) "
                  f"nearest {d[j]:.2f} m at {other.t[j]:.1f}s")


if __name__ == "__main__":
    main()
