"""rollon.py CX CY R AXIS_DEG TRACE...: the turns on the spot (runs of cycles commanded v = 0)
begun within R m of (CX, CY): how many, how far the body moved in each (median, max, cm), and
their summed displacement along AXIS_DEG (the passage's direction, m)."""

import sys

import numpy as np

cx, cy, R, axis = map(float, sys.argv[1:5])
u = np.array([np.cos(np.radians(axis)), np.sin(np.radians(axis))])
for path in sys.argv[5:]:
    tr = np.load(path, allow_pickle=True)
    p, c = tr["true_pose"].astype(float), tr["cmd"]
    v0 = np.abs(c[:, 0]) < 1e-9
    runs, k = [], 0
    while k < len(v0):
        if v0[k]:
            j = k
            while j < len(v0) and v0[j]:
                j += 1
            e = min(j, len(p) - 1)
            if np.linalg.norm(p[k, :2] - [cx, cy]) < R:
                runs.append(p[e, :2] - p[k, :2])  # from the first v=0 cycle to the first v>0 one
            k = j
        else:
            k += 1
    d = np.array(runs) if runs else np.zeros((0, 2))
    m = np.linalg.norm(d, axis=1) * 100
    print(
        f"{path.split('/')[-1][:-4]:32s} spot turns {len(d):3d} | moved median {np.median(m):4.1f} cm, max {m.max():4.1f} cm | "
        f"summed along {axis:.0f} deg {(d @ u).sum():+.2f} m, forward parts {np.clip(d @ u, 0, None).sum():.2f} m"
    )
