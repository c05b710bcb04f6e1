"""Where are an episode's contacts, and did the gap-centring steer (WallFollower._centring_heading)
fire in the 3 s before them?

    PYTHONPATH=TREE python contact_probe17.py WORLD.yaml PLANNER TLIMIT [SEED]

Replays the episode, logs each cycle where ``_centring_heading`` returned a heading, finds the
contacts from the stored trace (body clearance < 0.002 m, nav_bench.episode.metrics.clearances)
and prints, per contact, its time and place and the centring cycles of the 3 s before it.
"""
import sys

import numpy as np

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.episode.metrics import clearances
from nav_bench.planners import follow
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.world.load import load_world


def main() -> None:
    world_path, name, limit = sys.argv[1:4]
    seed = int(sys.argv[4]) if len(sys.argv) > 4 else 0
    fired: list[float] = []
    centring = follow.WallFollower._centring_heading

    def logged(self, obs, near):
        heading = centring(self, obs, near)
        if heading is not None:
            fired.append(float(obs.t))
        return heading

    follow.WallFollower._centring_heading = logged
    spec = parse_planner_arg(name)
    world = load_world(world_path)
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=float(limit)),
                         planner_instance=make_planner(spec))
    row = result.row.to_json()
    print(row["outcome"], row.get("stuck_reason"), row["time_s"], "contacts", row["collisions"],
          "centring cycles", len(fired))
    tr = result.trace
    gaps = clearances(world, tr.true_pose[:, :2], 0.18)
    touching = gaps < 0.002
    starts = np.flatnonzero(touching & ~np.r_[False, touching[:-1]])
    fired_t = np.array(fired)
    for i in starts:
        t = float(tr.t[i])
        near = fired_t[(fired_t > t - 3.0) & (fired_t <= t)]
        print(f"contact t {t:.1f} at ({tr.true_pose[i, 0]:.2f}, {tr.true_pose[i, 1]:.2f}) gap {gaps[i]:+.4f}; "
              f"centring cycles in the 3 s before: {len(near)} {np.round(near, 1).tolist()[-8:]}")


if __name__ == "__main__":
    main()
