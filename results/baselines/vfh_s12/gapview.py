"""Replay office_11's trace through a fresh planner; each cycle the robot is within 1.3 m of a
gap's midpoint, the histogram in the direction of the midpoint (H^p, masked free?).
PYTHONPATH=$PWD python results/baselines/vfh_s12/gapview.py office_11_TRACE.npz
"""
import math
import sys

sys.path.insert(0, "results/baselines/vfh_s12")
from trace_replay import load

replay = load(sys.argv[1])
gaps = {"SE": (10.33, 4.99), "NE": (10.155, 5.924)}
t, odom, p, obs = replay.t, replay.odom, replay.planner, replay.obs
stats = {g: [0, 0, 1e9] for g in gaps}
for i in range(len(t)):
    p.act(obs(i))
    xy = odom[i, :2]
    for g, m in gaps.items():
        d = math.hypot(m[0] - xy[0], m[1] - xy[1])
        if d < 1.3:
            k = round((math.atan2(m[1] - xy[1], m[0] - xy[0]) % (2 * math.pi)) / p.alpha) % p.n
            free = not p.masked[k]
            stats[g][0] += 1
            stats[g][1] += free
            stats[g][2] = min(stats[g][2], p.primary[k])
            if i % 50 == 0:
                print(f"t={t[i]:.1f} at ({xy[0]:.2f},{xy[1]:.2f}) gap {g} d={d:.2f} dir {k*5} H^p {p.primary[k]:.0f}"
                      f" (+-1: {p.primary[(k-1)%p.n]:.0f},{p.primary[(k+1)%p.n]:.0f}) free {free} chosen {p.k_prev*5:.0f}")
print({g: f"cycles within 1.3 m {s[0]}, free toward midpoint {s[1]}, least H^p {s[2]:.0f}" for g, s in stats.items()})
