"""Replay one TangentBug episode, log every contact with what the planner did before it.

usage: PYTHONPATH=<tree> python tbinstr.py WORLD.yaml OUTPREFIX [SECONDS_BEFORE=2]

Per control cycle it records the mode: 0 motion to goal with the goal direction free, 1 motion
to goal toward an endpoint, 2 the approach to the blocking point (FOLLOW, not yet acquired),
3 boundary following, 4 the strict lap, 5 unreachable; for mode 1 whether the chosen
endpoint's edge is a rho *jump* (the new rule's discontinuity: the bin past the run is still
blocked) or a free bin. A contact begins when the simulator's contact-episode counter rises
(`ContactEpisodes.update`); it is stamped with the last cycle's time. For each contact it prints
the modes of the SECONDS before, the true pose, and the nearest static primitive (its
obstacle index, kind and shape) with the robot's centre clearance to it. Writes OUTPREFIX.npz
(``rec``: t, x, y, yaw, mode, jump flag, side, v, omega, blocking x, y, endpoint heading per
cycle; ``contacts``: cycle time and count of each contact that began).
"""
import json
import math
import sys

import numpy as np

import nav_bench.planners.tangent_bug as tb
from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.sim import contacts as contacts_mod
from nav_bench.world.geometry import signed_distances, static_geometry
from nav_bench.world.load import load_world

NAMES = {0: "goal-free", 1: "to-endpoint", 2: "approach", 3: "follow", 4: "strict-lap", 5: "unreach"}


def main() -> None:
    world_path, out = sys.argv[1], sys.argv[2]
    before = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
    world = load_world(world_path)
    spec = parse_planner_arg("tangent_bug")
    agent = make_planner(spec)
    rec: list[tuple] = []
    contact_log: list[tuple[float, int]] = []
    last_edges: dict = {}
    # main's rule, or before it (374f213) blocked_interval_edges(blocked, k): both spied on
    edges_name = "obstacle_interval_edges" if hasattr(tb, "obstacle_interval_edges") else "blocked_interval_edges"
    orig_edges = getattr(tb, edges_name)

    def edges_spy(*args):
        e = orig_edges(*args)
        blocked = args[1] if edges_name == "obstacle_interval_edges" else args[0]
        last_edges.clear()
        if e is not None:
            n = len(blocked)
            # an edge bin is a jump when the bin past the run is still blocked
            last_edges.update(left_jump=bool(blocked[e[0]]), right_jump=bool(blocked[e[1]]),
                              left_bin=e[0], right_bin=e[1], n=n)
        return e

    setattr(tb, edges_name, edges_spy)
    orig_update = contacts_mod.ContactEpisodes.update

    def update_spy(self, touching):
        new = orig_update(self, touching)
        if new:
            contact_log.append((rec[-1][0] if rec else 0.0, new))
        return new

    contacts_mod.ContactEpisodes.update = update_spy
    orig_act = agent.act

    def act(obs):
        last_edges.clear()
        cmd = orig_act(obs)
        mode = agent.mode
        jump = -1
        if mode == tb.GO:
            code = 1 if agent._endpoint is not None else 0
            if code == 1 and last_edges:
                heading = agent._endpoint[0]
                kl = float(agent.bins[last_edges["left_bin"]])
                jump = int(last_edges["left_jump"] if abs(heading - kl) < 1e-9 else last_edges["right_jump"])
        elif mode == tb.FOLLOW:
            code = 4 if getattr(agent, "strict_lap", False) else (3 if agent.acquired else 2)
        else:
            code = 5
        bl = agent._blocking if (mode == tb.FOLLOW and agent._blocking is not None) else (math.nan, math.nan)
        rec.append((obs.t, obs.pose[0], obs.pose[1], obs.pose[2], code, jump, agent.side,
                    cmd.v, cmd.omega, bl[0], bl[1],
                    agent._endpoint[0] if (mode == tb.GO and agent._endpoint is not None) else math.nan))
        return cmd

    agent.act = act
    res = run_episode(world, spec, seed=0, settings=EpisodeSettings(), planner_instance=agent)
    row = res.row.to_json()
    R = np.array(rec)
    tr = res.trace
    np.savez(out + ".npz", rec=R, contacts=np.array(contact_log))
    print(f"{row['world']}: {row['outcome']} t={row['time_s']} L={row['path_length_m']:.2f} "
          f"contacts={row['collisions']} replans={row['replans']}")
    geo = static_geometry(world)
    for t_c, _ in contact_log:
        i = int(np.searchsorted(tr.t, t_c + 0.1))
        i = min(i, len(tr.t) - 1)
        xy = tr.true_pose[max(0, i - 3):i + 4, :2].astype(float)
        db, dc = signed_distances(geo, xy)
        d = np.concatenate([db, dc], axis=1)
        j, k = np.unravel_index(np.argmin(d), d.shape)
        nb = db.shape[1]
        src = (int(geo.box_source[k]) if k < nb else int(geo.cylinder_source[k - nb]))
        ob = world.obstacles[src] if src >= 0 else None
        what = f"obstacle {src} {ob.kind} {ob.shape}" if ob is not None else f"primitive {k} (boundary?)"
        w = (R[:, 0] >= t_c - before) & (R[:, 0] <= t_c)
        modes = [NAMES[int(c)] + ("/jump" if (c == 1 and jmp == 1) else "/free-edge" if (c == 1 and jmp == 0) else "")
                 for c, jmp in zip(R[w, 4], R[w, 5], strict=True)]
        runs: list[list] = []
        for m in modes:
            if runs and runs[-1][0] == m:
                runs[-1][1] += 1
            else:
                runs.append([m, 1])
        p = tr.true_pose[i]
        print(f"  contact at t~{t_c:.1f}s true pose ({p[0]:.2f},{p[1]:.2f},{math.degrees(p[2]):.0f}deg) "
              f"centre clearance {d[j, k]:.3f} m to {what}")
        print("    before: " + " ".join(f"{m}x{c}" for m, c in runs) + f"  v,omega last {R[w][-1, 7]:.2f},{R[w][-1, 8]:.2f}"
              + (f" blocking ({R[w][-1, 9]:.2f},{R[w][-1, 10]:.2f})" if np.isfinite(R[w][-1, 9]) else ""))
    with open(out + ".row.json", "w") as fh:
        json.dump(row, fh, default=str)


if __name__ == "__main__":
    main()
