"""What holds a gap's valley closed on the sonar map (issue 12): replays a VFH+ trace through a
fresh planner (the row's parameters) and, at the cycles the robot is within NEAR m of the gap
(true frame), splits the H^p of the way-on sector (of the three sectors nearest the bearing
of the gap's midpoint or, with ``--oracle``, of the point LOOK m along the true-map robot's
path past its point nearest the robot: the lowest) over the window's points (:meth:`ActiveWindow.carved`: whole cells and
kept parts) that cover it:

* true: a part (or a whole cell's part, 1/25 of its magnitude) within SURFACE_M of a box or
  cylinder surface, or inside one (odometry frame mapped into the world by the cycle's pose);
* proud: farther out, in the open. Each proud part is classed by its records since cycle 0:
  ``a0`` no reading saw through it; ``a1`` readings from one view only (the carving needs
  two); ``b_*`` two or more views saw through it yet it is kept: ``b_expired`` carved more
  than ``carve_memory_s`` ago, ``b_undone`` carved then kept again by an unexplained echo,
  ``b_forgot`` carved then its cell was freed and occupied again, ``b_unpaired`` never
  carved (its views were not within 3 s of each other);

and the same sector's H^p three other ways: the true parts alone (perfect carving of the
sonar map), and the oracle's true map (``/work/studies/s18/oracle/oracle_seed.py``: a 0.1 m
raster of the obstacles, a cell occupied where its centre lies inside one, certainty c_max)
as whole cells and with only its parts inside an obstacle kept.

``--dump T ...`` prints, at those times, the points carrying the most magnitude in the gap's
sector: the part (world, m), its clearance (m), its cell's certainty and how long the cell
has been occupied (s), the views that saw through it, and per sonar the cycles it lay in that
cone within range (in) and of those the cycles whose echo was nearer than it (short).
PYTHONPATH=$PWD python results/baselines/vfh_s18/sonar_gap.py TRACE.npz --mid X Y [--near 1.3]
    [--oracle ORACLE_TRACE.npz] [--look 0.5] [--every 5] [--dump T ...]
"""
import argparse
import math
import sys
from collections import Counter

import numpy as np

sys.path.insert(0, "results/baselines/vfh_s12")
sys.path.insert(0, "results/baselines/vfh_s18")
from replay_common import RADIUS, odom_to_true, true_to_odom
from trace_replay import load

from nav_bench.planners.carving import PARTS
from nav_bench.planners.footprint import CARVE_MARGIN, cell_parts, seen_through_cells
from nav_bench.planners.vfh_plus import ActiveWindow, read_window, window_histogram
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.raster import rasterize

SURFACE_M = 0.03  # m: a part this near an obstacle's surface (or inside) is true obstacle
TRACK_M = 1.8  # m: the parts tracked round the gap (the window's 1.2 m plus the approach)
GAP_ZONE_M = 0.3  # m: the robot within this of the midpoint is in the gap, farther on its approach
ZONES = (f"in the gap (< {GAP_ZONE_M} m)", "approach")
CLASSES = ("true", "a0", "a1", "b_expired", "b_undone", "b_forgot", "b_unpaired")


class PartRecords:
    """Per part of the cells within TRACK_M of the gap (odometry frame of cycle 0): how many
    views saw through it, in which cones it lay and how often an echo came from nearer, when
    the carving last carved it, undid it or forgot it, and since when its cell is occupied."""

    def __init__(self, p, mid):
        f = p.frame
        rr, cc = np.mgrid[0:f.shape[0], 0:f.shape[1]]
        cx, cy = f.xmin + (cc + 0.5) * f.cell, f.ymin + (rr + 0.5) * f.cell
        near = np.hypot(cx - mid[0], cy - mid[1]) <= TRACK_M
        self.rows, self.cols = rr[near], cc[near]
        self.centres = np.stack([cx[near], cy[near]], 1)
        self.parts = cell_parts(self.centres, f.cell)
        self.index = {(int(r), int(c)): j for j, (r, c) in enumerate(zip(self.rows, self.cols, strict=True))}
        m = len(self.rows)
        self.views = np.zeros((m, PARTS), dtype=int)
        self.last_view = np.full((m, PARTS), -1)
        self.cone_in = np.zeros((m, PARTS, 6), dtype=int)
        self.cone_short = np.zeros((m, PARTS, 6), dtype=int)
        self.carve_t = np.full((m, PARTS), -np.inf)
        self.undo_t = np.full((m, PARTS), -np.inf)
        self.forget_t = np.full((m, PARTS), -np.inf)
        self.occ_since = np.full(m, np.nan)

    def before(self, p):
        return p.carving.carved_t[self.rows, self.cols].astype(float)

    def after(self, p, obs, before):
        t = obs.t
        after = p.carving.carved_t[self.rows, self.cols].astype(float)
        occ = p.grid.values(copy=False)[self.rows, self.cols] > 50
        self.occ_since = np.where(occ, np.where(np.isnan(self.occ_since), t, self.occ_since), np.nan)
        dropped = np.isfinite(before) & ~np.isfinite(after)
        self.undo_t[dropped & occ[:, None]] = t
        self.forget_t[dropped & ~occ[:, None]] = t
        self.carve_t[after > before] = after[after > before]
        sonar = obs.robot.sonar
        seen = seen_through_cells(self.centres, p.frame.cell, obs.pose, obs.ranges, sonar, parts=self.parts)
        fresh = seen & (self.last_view != p.carving.view)
        self.views += fresh
        self.last_view[seen] = p.carving.view
        x, y, yaw = (float(v) for v in obs.pose)
        mx, my = sonar.mounts(x, y, math.cos(yaw), math.sin(yaw))
        ranges = np.where(np.isfinite(obs.ranges), np.minimum(obs.ranges, sonar.max_range), sonar.max_range)
        for s in range(len(mx)):
            dx, dy = self.parts[..., 0] - mx[s], self.parts[..., 1] - my[s]
            d = np.hypot(dx, dy)
            off = np.abs((np.arctan2(dy, dx) - yaw - sonar.angles[s] + np.pi) % (2 * np.pi) - np.pi)
            inside = (off <= sonar.cone / 2) & (d <= sonar.max_range)
            self.cone_in[..., s] += inside
            self.cone_short[..., s] += inside & (ranges[s] < d + CARVE_MARGIN)

    def klass(self, j, q, t, memory_s):
        """The class of part ``q`` of tracked cell ``j`` at time ``t`` (s), proud."""
        if self.views[j, q] == 0:
            return "a0"
        if self.views[j, q] == 1:
            return "a1"
        c = self.carve_t[j, q]
        if not np.isfinite(c):
            return "b_unpaired"
        if self.undo_t[j, q] >= c:
            return "b_undone"
        if self.forget_t[j, q] >= c:
            return "b_forgot"
        return "b_expired"


def window_points(p, obs):
    """The carved window as VFH+ builds it this cycle, point by point: (window, cell index of
    each point (M,), part index (-1: whole cell), rows, cols)."""
    s = p.settings
    xy = np.asarray(obs.pose[:2], float)
    radius = min(s.window_radius, float(np.hypot(*(np.asarray(obs.goal) - xy))))
    w = read_window(p.grid.values(copy=False), p.frame, xy, radius, s.c_max)
    centres = np.stack([w.x, w.y], 1)
    parts = cell_parts(centres, p.frame.cell)
    kept = p.carving.carved_t[w.rows, w.cols] < np.float32(obs.t - p.carving.memory_s)
    whole = kept.all(axis=1)
    cell_i, part_i = np.nonzero(kept & ~whole[:, None])
    cells = np.flatnonzero(whole)
    ci = np.concatenate([cells, cell_i])
    qi = np.concatenate([np.full(len(cells), -1), part_i])
    x = np.concatenate([w.x[cells], parts[cell_i, part_i, 0]])
    y = np.concatenate([w.y[cells], parts[cell_i, part_i, 1]])
    share = 1.0 / np.maximum(kept.sum(axis=1), 1)
    weight = np.concatenate([np.ones(len(cells)), share[cell_i]])
    dx, dy = x - xy[0], y - xy[1]
    win = ActiveWindow(x, y, w.certainty[ci], dx, dy, np.hypot(dx, dy), weight=weight)
    return win, ci, qi, w.rows, w.cols, parts


def point_magnitudes(win, k, p):
    """(M,) each point's magnitude in sector ``k`` (0 where it does not cover it)."""
    s = p.settings
    r_rs = RADIUS + s.safety_distance
    dist = np.maximum(win.dist, 1e-6)
    mag = win.certainty ** 2 * (1.0 + s.distance_weight * (s.window_radius ** 2 - dist ** 2))
    mag = mag * np.where(dist < r_rs, 1.0, win.weight)
    gamma = np.arcsin(np.minimum(1.0, r_rs / dist))
    off = np.abs((k * p.alpha - win.bearings() + np.pi) % (2 * np.pi) - np.pi)
    return np.where(off <= gamma, mag, 0.0)


def oracle_histogram(raster, g, p, obs, true_pose, k, perfect):
    """H^p of sector ``k`` from the oracle's true map at the cycle's true pose: whole raster
    cells at certainty c_max, or (``perfect``) only their parts inside an obstacle."""
    s = p.settings
    xy = true_pose[:2]
    radius = min(s.window_radius, float(np.hypot(*(np.asarray(obs.goal) - obs.pose[:2]))))
    values = np.where(raster.occupied, 100.0, 50.0)
    w = read_window(values, p.frame, xy, radius, s.c_max)
    if perfect and len(w):
        parts = cell_parts(np.stack([w.x, w.y], 1), p.frame.cell)
        kept = (clearance(g, parts.reshape(-1, 2)) <= 0).reshape(parts.shape[:2])
        w = w.carved(kept, parts, xy)
    h = window_histogram(w, w.bearings(), p.n, RADIUS + s.safety_distance, s.window_radius, s.distance_weight)
    return float(h[k])


def way_on(path, xy, look):
    """The point ``look`` m along ``path`` (N, 2) past its point nearest ``xy``, m."""
    run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))])
    j = int(np.argmin(np.hypot(*(path - xy).T)))
    return path[min(int(np.searchsorted(run, run[j] + look)), len(path) - 1)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trace")
    ap.add_argument("--mid", type=float, nargs=2, required=True, help="the gap's midpoint, world m")
    ap.add_argument("--near", type=float, default=1.3)
    ap.add_argument("--oracle", help="the true-map robot's trace: the way on is where it went (else: the midpoint)")
    ap.add_argument("--look", type=float, default=0.5, help="m along the true-map robot's path past its nearest point")
    ap.add_argument("--every", type=int, default=5, help="print every Nth near cycle (0: summary only)")
    ap.add_argument("--dump", type=float, nargs="*", default=[])
    ap.add_argument("--top", type=int, default=10)
    ap.add_argument("--picture", nargs=2, metavar=("T", "PNG"), action="append", default=[],
                    help="draw the window at T s into PNG (may be repeated)")
    a = ap.parse_args()
    rp = load(a.trace)
    p = rp.planner
    s = p.settings
    world = world_from_data(rp.meta["world"])
    g = static_geometry(world)
    obs0 = rp.obs(0)
    raster = rasterize(g, p.frame.cell, bounds=tuple(obs0.bounds))
    mid = np.array(a.mid)
    way = None if a.oracle is None else np.load(a.oracle)["true_pose"][:, :2].astype(float)
    rec = PartRecords(p, true_to_odom(mid, rp.odom[0].astype(float), rp.true[0].astype(float)))
    row = rp.meta["row"]
    print(f"{row['world']} seed {row.get('seed')}: {row['outcome']} {row['time_s']} s; gap midpoint {mid.tolist()}, "
          f"half-width {float(clearance(g, mid[None])[0]):.3f} m")
    print("t | true x y yaw | d gap | way-on sector deg | H^p | closed | true | a0 a1 | b: exp undone forgot unpaired | "
          "true only | oracle whole / perfect")
    zones = {z: (Counter(), Counter(), [0]) for z in ZONES}  # magnitude by class, openings, closed cycles
    n_near = n_closed = 0
    for i in range(len(rp.t)):
        obs = rp.obs(i)
        before = rec.before(p)
        p.act(obs)
        rec.after(p, obs, before)
        od, tr = rp.odom[i].astype(float), rp.true[i].astype(float)
        d_gap = float(np.hypot(*(tr[:2] - mid)))
        if d_gap > a.near:
            continue
        n_near += 1
        mo = true_to_odom(mid if way is None else way_on(way, tr[:2], a.look), od, tr)
        k0 = round((math.atan2(mo[1] - od[1], mo[0] - od[0]) % (2 * math.pi)) / p.alpha)
        k = min(((k0 + j) % p.n for j in (-1, 0, 1)), key=lambda m: p.primary[m])
        win, ci, qi, rows, cols, parts = window_points(p, obs)
        mag = point_magnitudes(win, k, p)
        assert abs(mag.sum() - p.primary[k]) <= 1e-6 * max(1.0, p.primary[k]), (mag.sum(), p.primary[k])
        split = Counter()
        detail = []
        for m in np.flatnonzero(mag):
            j = rec.index.get((int(rows[ci[m]]), int(cols[ci[m]])))
            qs = range(PARTS) if qi[m] < 0 else [qi[m]]
            cl = clearance(g, odom_to_true(parts[ci[m], list(qs)], od, tr))
            centre_out = float(clearance(g, odom_to_true(parts[ci[m]].mean(axis=0)[None], od, tr))[0]) > 0
            for q, c in zip(qs, cl, strict=True):
                share = mag[m] / len(qs)
                kind = "true" if c <= SURFACE_M else ("?" if j is None else rec.klass(j, q, obs.t, s.carve_memory_s))
                split[kind] += share
                if kind == "true" and centre_out:  # a cell centred in the open, carved down to the surface
                    split["true, cell centre outside"] += share
                detail.append((share, kind, m, q, c, j, qi[m] < 0))
        closed = bool(p.masked[k])
        h_true = split["true"]
        o_whole = oracle_histogram(raster, g, p, obs, tr, k, False)
        o_perf = oracle_histogram(raster, g, p, obs, tr, k, True)
        if closed:
            n_closed += 1
            tot, opens, count = zones[ZONES[0] if d_gap < GAP_ZONE_M else ZONES[1]]
            count[0] += 1
            tot.update(split)
            opens["true only < high"] += h_true < s.threshold_high
            opens["true only < low"] += h_true < s.threshold_low
            opens["true of cells centred inside only < high"] += (
                h_true - split["true, cell centre outside"] < s.threshold_high)
            opens["oracle whole < high"] += o_whole < s.threshold_high
            opens["oracle perfect < high"] += o_perf < s.threshold_high
            a_only = p.primary[k] - split["a0"] - split["a1"]
            b_only = p.primary[k] - sum(split[c] for c in CLASSES if c.startswith("b_"))
            opens["without class a < high"] += a_only < s.threshold_high
            opens["without class b < high"] += b_only < s.threshold_high
        if (a.every and n_near % a.every == 0) or any(abs(obs.t - t) < 0.05 for t in a.dump):
            print(f"{obs.t:6.1f} | {tr[0]:.2f} {tr[1]:.2f} {math.degrees(tr[2]) % 360:3.0f} | {d_gap:.2f} | "
                  f"{k * 5:3d} | {p.primary[k]:6.0f} | {'C' if closed else 'o'} | {split['true']:5.0f} | "
                  f"{split['a0']:5.0f} {split['a1']:5.0f} | {split['b_expired']:5.0f} {split['b_undone']:5.0f} "
                  f"{split['b_forgot']:5.0f} {split['b_unpaired']:5.0f} | {h_true:6.0f} | {o_whole:6.0f} / {o_perf:6.0f}")
        if any(abs(obs.t - t) < 0.05 for t in a.dump):
            dump(detail, win, rec, obs, od, tr, a.top, p)
        for t_pic, png in a.picture:
            if abs(obs.t - float(t_pic)) >= 0.05:
                continue
            title = (f"{row['world']} s{row.get('seed')}, t = {obs.t:.1f} s: way-on sector {k * 5} deg, H^p {p.primary[k]:.0f}"
                     f" (true {split['true']:.0f}, proud {p.primary[k] - split['true']:.0f})")
            picture(png, world, detail, rec, win, p, od, tr, k, rp, i, way, title)
    print(f"cycles within {a.near} m: {n_near}; the gap's sector closed (H^m): {n_closed}")
    for zone, (tot, opens, count) in zones.items():
        if count[0]:
            print(f"  {zone}: {count[0]} closed cycles; mean H^p while closed, by class: "
                  + ", ".join(f"{c} {tot[c] / count[0]:.0f}" for c in CLASSES)
                  + f" (true from cells centred outside the obstacle: {tot['true, cell centre outside'] / count[0]:.0f})")
            print("    of them open (H^p under the threshold) with: "
                  + ", ".join(f"{key} {v}" for key, v in opens.items()))


COLOURS = {"true": "black", "a0": "tab:orange", "a1": "gold", "b_expired": "tab:red", "b_undone": "tab:pink",
           "b_forgot": "tab:purple", "b_unpaired": "tab:brown", "?": "grey"}


def picture(path, world, detail, rec, win, p, od, tr, k, rp, i, way, title):
    """The window's points round the robot at cycle ``i`` (world frame): grey, every kept point;
    coloured by class, the pieces in the way-on sector ``k`` (area ~ magnitude)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    from nav_bench.world.draw import draw_world

    fig, ax = plt.subplots(figsize=(7, 7))
    draw_world(ax, world, faint=True, show_start_goal=False)
    allpts = odom_to_true(np.stack([win.x, win.y], 1), od, tr)
    ax.plot(allpts[:, 0], allpts[:, 1], ".", color="0.6", ms=2)
    seen = set()
    for share, kind, m, q, _, j, whole in detail:
        pt = odom_to_true(rec.parts[j, q][None], od, tr)[0] if j is not None else allpts[m]
        ax.scatter(*pt, s=max(share, 1) / 8, color=COLOURS[kind], label=None if kind in seen else kind,
                   marker="s" if whole else "o", alpha=0.8)
        seen.add(kind)
    lo = max(0, i - 300)
    ax.plot(rp.true[lo:i + 1, 0], rp.true[lo:i + 1, 1], "-", color="tab:blue", lw=0.8, label="sonar-map robot, 30 s")
    if way is not None:
        ax.plot(way[:, 0], way[:, 1], "--", color="tab:green", lw=1, label="true-map robot")
    ax.add_patch(Circle(tr[:2], RADIUS, fill=False, color="tab:blue", lw=1.5))
    ax.add_patch(Circle(tr[:2], RADIUS + p.settings.safety_distance, fill=False, color="tab:blue", lw=0.5, ls=":"))
    ang = k * p.alpha + float(tr[2] - od[2])
    ax.plot([tr[0], tr[0] + 1.2 * math.cos(ang)], [tr[1], tr[1] + 1.2 * math.sin(ang)], "-", color="tab:green", lw=2)
    ax.set_xlim(tr[0] - 1.3, tr[0] + 1.3)
    ax.set_ylim(tr[1] - 1.3, tr[1] + 1.3)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.legend(loc="lower left", fontsize=7)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def dump(detail, win, rec, obs, od, tr, top, p):
    """The ``top`` pieces of magnitude (a part, or a whole cell's 1/25) in the gap's sector."""
    detail.sort(key=lambda d: -d[0])
    print(f"    t {obs.t:.1f}: the {top} largest pieces: mag class | part world x y | clearance | "
          "certainty, cell occupied for, its kept parts | views saw through | per sonar in/short | carved, undone ago")
    for share, kind, m, q, c, j, whole in detail[:top]:
        pt = odom_to_true(rec.parts[j, q][None], od, tr)[0] if j is not None else (np.nan, np.nan)
        extra = ""
        if j is not None:
            cones = " ".join(f"{rec.cone_in[j, q, s]}/{rec.cone_short[j, q, s]}" for s in range(6))
            age = obs.t - rec.occ_since[j]
            extra = (f"{win.certainty[m]:.1f}, {age:.1f} s, kept parts {round(1 / win.weight[m]) if not whole else 25} | {rec.views[j, q]} | {cones} | "
                     f"{obs.t - rec.carve_t[j, q]:.1f} / {obs.t - rec.undo_t[j, q]:.1f}")
        print(f"      {share:6.0f} {kind:<10} | {pt[0]:.3f} {pt[1]:.3f} {'(whole cell)' if whole else ''} | {c:+.3f} | {extra}")


if __name__ == "__main__":
    main()
