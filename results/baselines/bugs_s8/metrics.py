"""Figures of the last 30 s of stored bug-planner traces (classification.md, metrics_base.txt).

    python results/baselines/bugs_s8/metrics.py TRACE_DIR

Per trace: the true positions' box (m), net turns of the true heading (+ = CCW), the share of
cycles turning on the spot (v = 0, |omega| > 0.3 rad/s), the switches from a 3.46 rad/s turn on
the spot to driving, the true yaw rate in the cycle after such a switch and how far the body
turns on in the next 0.3 s, and the final odometry error (m).
"""

import glob
import math
import sys

import numpy as np

from nav_bench.episode.trace import Trace


def describe(tr: Trace) -> str:
    row, t = tr.row, tr.t
    last = t >= t[-1] - 30
    yaw = np.unwrap(tr.true_pose[:, 2])
    net = (yaw[last][-1] - yaw[last][0]) / (2 * math.pi)
    span = np.ptp(tr.true_pose[last, :2], axis=0)
    cmd = tr.cmd[last]
    spin = np.mean((np.abs(cmd[:, 0]) < 1e-6) & (np.abs(cmd[:, 1]) > 0.3))
    rate = np.diff(yaw) / np.diff(t)
    cycles = np.nonzero(last[:-1])[0][1:]
    switches = [i for i in cycles if abs(tr.cmd[i - 1, 0]) < 1e-6 and abs(tr.cmd[i - 1, 1]) > 3.0
                and tr.cmd[i, 0] > 0.1]
    after = [abs(rate[i]) for i in switches]
    carry = [abs(yaw[min(i + 3, len(yaw) - 1)] - yaw[i]) for i in switches]
    odo = np.hypot(*(tr.true_pose[-1, :2] - tr.odom_pose[-1, :2]))
    return (f"{row['planner']:11s} {row['world']:10s} s{row['seed']} {row['outcome']} {row.get('stuck_reason')} "
            f"t={row['time_s']} contacts={row['collisions']} | last 30 s: span {span[0]:.2f}x{span[1]:.2f} m, "
            f"net turn {net:+.1f} circles, spin share {spin:.2f}, spin->drive switches {len(switches)}, "
            f"yaw rate after {np.mean(after) if after else math.nan:.2f} rad/s, "
            f"carry-on 0.3 s {math.degrees(np.mean(carry)) if carry else math.nan:.0f} deg | "
            f"odo err {odo:.2f} m, goal dist {row['goal_distance_m']:.2f}")


if __name__ == "__main__":
    for path in sorted(glob.glob(sys.argv[1] + "/*.npz")):
        print(describe(Trace.load(path)))
