"""Replay one bug-planner episode with the follower's internals recorded per cycle.

usage: instr.py WORLD PLANNER SEED TLIMIT OUTPREFIX
Prints the row's outcome and statistics over the last 30 s / 90 s; writes OUTPREFIX.npz
(per-cycle record) and OUTPREFIX_zoom.png (the last 90 s, coloured by mode).
"""
import json
import math
import sys

import numpy as np

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.follow import FOLLOW, GO
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world

world_path, pname, seed, tlim, out = sys.argv[1:6]
world = load_world(world_path)
spec = parse_planner_arg(pname)
agent = make_planner(spec)
rec = []
orig_act = agent.act


def act(obs):
    cmd = orig_act(obs)
    mode = agent.mode
    f = getattr(agent, "follower", None)
    side = getattr(agent, "side", 0)
    near = other = ahead = math.nan
    if f is not None and mode == FOLLOW:
        n = f.nearest(obs)
        near = n[0] if n else math.inf
        other = f.other_side_clearance(obs)
        ahead = f._ahead(obs, other)
    rec.append((obs.t, obs.pose[0], obs.pose[1], obs.pose[2], {GO: 0, FOLLOW: 1}.get(mode, 2), side,
                near, other, ahead, cmd.v, cmd.omega))
    return cmd


agent.act = act
settings = EpisodeSettings(time_s=float(tlim))
res = run_episode(world, spec, seed=int(seed), settings=settings, planner_instance=agent)
row = res.row.to_json()
R = np.array(rec)
np.savez(out + ".npz", rec=R)
tr = res.trace
t = R[:, 0]
T = t[-1]
geo = static_geometry(world)


def stats(win):
    m = t >= T - win
    r = R[m]
    modes = r[:, 4]
    switches = int(np.sum(modes[1:] != modes[:-1]))
    spin = np.mean((np.abs(r[:, 9]) < 1e-6) & (np.abs(r[:, 10]) > 0.3))
    stop = np.mean((np.abs(r[:, 9]) < 1e-6) & (np.abs(r[:, 10]) < 0.3))
    width = r[:, 6] + r[:, 7]
    narrow = np.isfinite(width) & (width < 0.8)
    fol = modes == 1
    ahead_fire = np.mean(np.isfinite(r[:, 8]) & (r[:, 8] < 0.45))
    xy = r[:, 1:3]
    db, dc = signed_distances(geo, xy)
    d = np.sort(np.concatenate([db, dc], axis=1), axis=1)
    local = d[:, 0] + d[:, 1]
    span = np.ptp(xy, axis=0)
    sides = set(r[fol, 5].astype(int).tolist())
    return (f"last {win:>3.0f}s: GO {np.mean(modes==0):.2f} FOLLOW {np.mean(fol):.2f} switches {switches} "
            f"sides {sides} spin {spin:.2f} stop {stop:.2f} ahead<0.45 {ahead_fire:.2f} narrow(width<0.8) {np.mean(narrow):.2f} "
            f"width med {np.nanmedian(np.where(np.isfinite(width), width, np.nan)) if np.isfinite(width).any() else float('nan'):.2f} "
            f"clear min {d[:,0].min():.2f} localgap min {local.min():.2f} med {np.median(local):.2f} "
            f"span {span[0]:.2f}x{span[1]:.2f} centre ({xy[:,0].mean():.2f},{xy[:,1].mean():.2f})")


print(f"{row['world']} {row['planner']} s{row['seed']}: {row['outcome']} {row.get('stuck_reason')} "
      f"t={row['time_s']} contacts={row['collisions']} replans={row['replans']}")
print(stats(30.0))
print(stats(90.0))
if tr.movers.size:
    mv = tr.movers
    m = tr.t >= T - 30
    dm = np.hypot(mv[m, :, 0] - tr.true_pose[m, None, 0], mv[m, :, 1] - tr.true_pose[m, None, 1])
    print(f"movers: min centre distance last 30 s {dm.min():.2f} m; share of cycles with a mover within 1.0 m "
          f"{np.mean(dm.min(axis=1) < 1.0):.2f}")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from nav_bench.reporting.episode_plot import draw_outlines  # noqa: E402

fig, ax = plt.subplots(figsize=(6, 6))
draw_outlines(ax, world)
m90 = t >= T - 90
ax.plot(R[:, 1], R[:, 2], color="0.8", lw=0.6)
for code, col, lab in ((0, "tab:green", "motion to goal"), (1, "tab:blue", "follow boundary")):
    k = m90 & (R[:, 4] == code)
    ax.scatter(R[k, 1], R[k, 2], s=3, color=col, label=lab, zorder=3)
spin = m90 & (np.abs(R[:, 9]) < 1e-6) & (np.abs(R[:, 10]) > 0.3)
ax.scatter(R[spin, 1], R[spin, 2], s=14, marker="x", color="tab:red", label="turn on the spot", zorder=4)
if tr.movers.size:
    m = tr.t >= T - 90
    for j in range(tr.movers.shape[1]):
        ax.plot(tr.movers[m, j, 0], tr.movers[m, j, 1], color="tab:orange", lw=0.8, alpha=0.7)
ax.plot(*world.goal, "r*", ms=12) if hasattr(world, "goal") else None
cx, cy = R[m90, 1].mean(), R[m90, 2].mean()
ax.set_xlim(cx - 1.75, cx + 1.75)
ax.set_ylim(cy - 1.75, cy + 1.75)
ax.set_aspect("equal")
ax.grid(alpha=0.3)
ax.legend(loc="upper right", fontsize=7)
ax.set_title(f"{row['world']} {row['planner']} s{row['seed']}: last 90 s of {row['time_s']:.0f} s", fontsize=9)
fig.savefig(out + "_zoom.png", dpi=110)
with open(out + ".row.json", "w") as fh:
    json.dump(row, fh, default=str)
