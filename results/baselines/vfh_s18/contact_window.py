"""What VFH+'s window held for the obstacle point a contact touches, cycle by cycle before the
contact start. Replays a trace through a fresh planner (the row's parameters) and, at
LOOKS s before each contact start (true clearance <= 2 mm), prints for the touching point
(true, mapped into the odometry frame of that cycle):

* the body: odometry speed along the heading (m/s), the command, the touching side (deg from
  the heading, CCW +) and the point's bearing from the heading at that cycle;
* the grid: the highest certainty of a cell within 0.1 m of the point (0: not in the grid);
* the carving: that cell's parts within 0.1 m of the point, kept / carved, and of the carved
  ones the age (s), the source (body: within the radius of the pose that carved it; view: seen
  through from two views) and the pose that carved it (distance from the pose, bearing from
  that pose's heading, deg);
* the histogram: H^p in the sector of the point, as the planner had it (memory_s) and as
  main's 3 s memory would have it from the same records (parts carved more than 3 s ago kept),
  and whether H^b blocks it.

PYTHONPATH=$PWD python results/baselines/vfh_s18/contact_window.py TRACE.npz [--looks 2,1,0.5,0.1]
"""
import argparse
import math
import sys

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s18")
from replay_common import RADIUS, CarveLog, touch_point, true_to_odom
from trace_replay import load

from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import read_window, window_box, window_histogram
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data

MAIN_MEMORY_S = 3.0  # s, main's carving memory
NEAR_M = 0.10  # m: parts and cells this near the touching point


def histogram_with(p, obs, kept_before):
    """H^p of the planner's window at ``obs`` with the parts carved before ``kept_before`` (s)
    kept (the carving's records as they are)."""
    xy = np.asarray(obs.pose[:2], dtype=float)
    radius = min(p.settings.window_radius, float(np.hypot(*(np.asarray(obs.goal) - xy))))
    values = p.grid.values(copy=False)
    box = window_box(p.frame, xy, radius)
    window = read_window(values, p.frame, xy, radius, p.settings.c_max, box, False)
    f = p.frame
    centres = np.stack([f.xmin + (window.cols + 0.5) * f.cell, f.ymin + (window.rows + 0.5) * f.cell], 1)
    parts = cell_parts(centres, f.cell)
    kept = p.carving.carved_t[window.rows, window.cols] < np.float32(kept_before)
    w = window.carved(kept, parts, xy, False)
    r_rs = RADIUS + p.settings.safety_distance
    return window_histogram(w, w.bearings(), p.n, r_rs, p.settings.window_radius, p.settings.distance_weight)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--looks", default="2,1,0.5,0.1", help="s before each contact start")
    ap.add_argument("--first", type=int, default=99, help="only the first N contact starts")
    a = ap.parse_args()
    looks_s = [float(x) for x in a.looks.split(",")]
    rp = load(a.trace)
    p = rp.planner
    g = static_geometry(world_from_data(rp.meta["world"]))
    gap = clearance(g, rp.true[:, :2].astype(float)) - RADIUS
    touch = gap <= 0.002
    starts = [i for i in range(1, len(rp.t)) if touch[i] and not touch[i - 1]][:a.first]
    looks = {}
    for j in starts:
        for s in looks_s:
            looks.setdefault(max(0, j - round(s / 0.1)), j)
    f = p.frame
    shape = p.carving.carved_t.shape
    log = CarveLog(p)
    row = rp.meta["row"]
    print(f"{row['world']} seed {row.get('seed')} {row['outcome']} contacts {row['collisions']}")
    for i in range(len(rp.t)):
        if i > max(looks, default=-1):
            break
        obs = rp.obs(i)
        cmd = p.act(obs)
        log.note(i, obs)
        if i not in looks:
            continue
        j = looks[i]
        tp, side = touch_point(g, rp.true[j, :2].astype(float), float(rp.true[j, 2]))
        tpo = true_to_odom(tp, rp.odom[i].astype(float), rp.true[i].astype(float))
        od = rp.odom[i].astype(float)
        yaw = float(od[2])
        bearing = math.degrees(math.atan2(tpo[1] - od[1], tpo[0] - od[0]) - yaw)
        bearing = (bearing + 180) % 360 - 180
        dist = float(np.hypot(*(tpo - od[:2])))
        speed = 0.0
        if i > 0:
            mv = rp.odom[i, :2] - rp.odom[i - 1, :2]
            speed = float((mv[0] * math.cos(yaw) + mv[1] * math.sin(yaw)) / (rp.t[i] - rp.t[i - 1]))
        values = p.grid.values(copy=False)
        rr, cc = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
        cx, cy = f.xmin + (cc + 0.5) * f.cell, f.ymin + (rr + 0.5) * f.cell
        near_cells = np.argwhere(np.hypot(cx - tpo[0], cy - tpo[1]) < NEAR_M + f.cell * 0.71)
        occ = [(r, c, float(values[r, c])) for r, c in near_cells if values[r, c] > 50]
        kept_n, carved = 0, []
        for r, c, _ in occ:
            parts = cell_parts(np.array([[cx[r, c], cy[r, c]]]), f.cell)[0]
            close = np.hypot(parts[:, 0] - tpo[0], parts[:, 1] - tpo[1]) < NEAR_M
            ct = p.carving.carved_t[r, c]
            for q in np.flatnonzero(close):
                if ct[q] >= obs.t - p.carving.memory_s:
                    ci = int(log.cycle[r, c, q])
                    pose_c = rp.odom[ci].astype(float) if ci >= 0 else od
                    d_c = float(np.hypot(*(parts[q] - pose_c[:2])))
                    b_c = (math.degrees(math.atan2(parts[q, 1] - pose_c[1], parts[q, 0] - pose_c[0]) - pose_c[2])
                           + 180) % 360 - 180
                    carved.append((obs.t - float(ct[q]), "body" if log.body[r, c, q] else "view", d_c, b_c,
                                   float(rp.t[ci]) if ci >= 0 else float("nan")))
                else:
                    kept_n += 1
        k = round(((math.radians(bearing) + yaw) % (2 * math.pi)) / p.alpha) % p.n
        h_main_all = histogram_with(p, obs, obs.t - MAIN_MEMORY_S)
        h_now, h_main = float(p.primary[k]), float(h_main_all[k])
        kh = round((yaw % (2 * math.pi)) / p.alpha) % p.n
        kc = round(p.k_prev) % p.n
        rel_c = (kc - kh + p.n // 2) % p.n - p.n // 2
        cert = max((v for _, _, v in occ), default=50.0)
        print(f"  contact t={rp.t[j]:.1f} true ({rp.true[j, 0]:.2f},{rp.true[j, 1]:.2f}) side {side:+.0f}"
              f" | t={obs.t:.1f} ({obs.t - rp.t[j]:+.1f}s) v_odom {speed:+.2f} cmd ({cmd.v:.2f},{cmd.omega:+.2f})"
              f" point {dist:.2f} m at {bearing:+.0f} deg; gap {gap[i]:+.3f}")
        print(f"    grid: {len(occ)} occupied cells within {NEAR_M:.2f} m (+cell), top value {cert:.0f};"
              f" parts near: kept {kept_n}, carved {len(carved)}"
              f" | H^p sector {k}: {h_now:.0f} (main 3 s memory: {h_main:.0f}) H^b {bool(p.binary[k])}"
              f" H^m {bool(p.masked[k])}")
        print(f"    heading sector H^p {p.primary[kh]:.0f} (main {h_main_all[kh]:.0f}); chosen {rel_c * 5:+d} deg"
              f" H^p {p.primary[kc]:.0f} (main {h_main_all[kc]:.0f}); blocked {p.blocked}")
        if carved:
            ages = np.array([c[0] for c in carved])
            src = {s: sum(1 for c in carved if c[1] == s) for s in ("body", "view")}
            over3 = int((ages > MAIN_MEMORY_S).sum())
            c0 = min(carved, key=lambda c: c[4] if math.isfinite(c[4]) else 1e9)
            print(f"    carved: ages {ages.min():.1f}-{ages.max():.1f} s (> 3 s: {over3}); {src};"
                  f" e.g. carved at t={c0[4]:.1f} from {c0[2]:.2f} m at {c0[3]:+.0f} deg off that heading ({c0[1]})")


main()
