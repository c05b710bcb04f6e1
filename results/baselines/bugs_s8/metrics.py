import glob, json, math, sys
import numpy as np
from nav_bench.episode.trace import Trace
for f in sorted(glob.glob(sys.argv[1] + "/*.npz")):
    tr = Trace.load(f); row = tr.row
    t = tr.t; m = t >= t[-1] - 30
    yaw = np.unwrap(tr.true_pose[:, 2]); net = (yaw[m][-1] - yaw[m][0]) / (2 * math.pi)
    xy = tr.true_pose[m, :2]; span = np.ptp(xy, axis=0)
    cmd = tr.cmd[m]; spin = np.mean((np.abs(cmd[:, 0]) < 1e-6) & (np.abs(cmd[:, 1]) > 0.3))
    # turn on the spot -> drive transitions: true yaw rate in the cycle after the command changed
    rate = np.diff(yaw) / np.diff(t)
    tt = np.nonzero(m[:-1])[0]
    tr_i = [i for i in tt[1:] if abs(tr.cmd[i - 1, 0]) < 1e-6 and abs(tr.cmd[i - 1, 1]) > 3.0 and tr.cmd[i, 0] > 0.1]
    over = [abs(rate[i]) for i in tr_i if i < len(rate)]
    # how far it turns on after the command stopped turning (sum of yaw over the next 3 cycles after a spin->drive switch)
    carry = [abs(yaw[min(i + 3, len(yaw) - 1)] - yaw[i]) for i in tr_i]
    odo = np.hypot(*(tr.true_pose[-1, :2] - tr.odom_pose[-1, :2]))
    print(f"{row['planner']:11s} {row['world']:10s} s{row['seed']} {row['outcome']} {row.get('stuck_reason')} t={row['time_s']} contacts={row['collisions']} "
          f"| last 30 s: span {span[0]:.2f}x{span[1]:.2f} m, net turn {net:+.1f} circles, spin share {spin:.2f}, "
          f"spin->drive switches {len(tr_i)}, yaw rate after {np.mean(over) if over else float('nan'):.2f} rad/s, "
          f"carry-on 0.3 s {math.degrees(np.mean(carry)) if carry else float('nan'):.0f} deg | odo err {odo:.2f} m, goal dist {row['goal_distance_m']:.2f}")
