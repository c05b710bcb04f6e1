"""part.py A.npz B.npz: where two traces part (first cycle the commands differ, first the true
positions differ by 1 cm / 10 cm), brake cycles (commanded exactly (0, 0)) per trace, and where each ends."""

import sys

import numpy as np

a, b = (np.load(p, allow_pickle=True) for p in sys.argv[1:3])
n = min(len(a["t"]), len(b["t"]))
dc = np.flatnonzero(np.any(np.abs(a["cmd"][:n] - b["cmd"][:n]) > 1e-6, axis=1))
dp = np.linalg.norm(a["true_pose"][:n, :2].astype(float) - b["true_pose"][:n, :2], axis=1)
i = dc[0] if len(dc) else None
print("first cmd differs: cycle", i, "t", a["t"][i] if i is not None else None)
if i is not None:
    for k in range(max(0, i - 2), i + 4):
        print(
            f"  t {a['t'][k]:6.1f} A pose {np.round(a['true_pose'][k], 3)} cmd {np.round(a['cmd'][k], 3)} | B pose {np.round(b['true_pose'][k], 3)} cmd {np.round(b['cmd'][k], 3)}"
        )
for thr in (0.01, 0.1, 0.5):
    j = np.flatnonzero(dp > thr)
    print(f"positions apart > {thr} m from t", a["t"][j[0]] if len(j) else None)
for name, tr in (("A", a), ("B", b)):
    c = tr["cmd"]
    t = tr["t"]
    stop = (np.abs(c[:, 0]) < 1e-9) & (np.abs(c[:, 1]) < 1e-9)
    spot = (np.abs(c[:, 0]) < 1e-9) & ~stop
    print(
        name,
        f"cycles {len(t)}, (0,0) cycles {stop.sum()}, spot-turn cycles {spot.sum()}, end {np.round(tr['true_pose'][-1], 2)} t {t[-1]:.1f}",
    )
