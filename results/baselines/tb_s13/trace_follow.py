"""TangentBug's boundary-following state every few simulated seconds of one episode.

    PYTHONPATH=. python results/baselines/tb_s13/trace_follow.py WORLD.yaml SEED [EVERY_S]

Prints the pose, the mode and side, ``d_followed`` and ``d_followed_side`` (m), the follower's
nearest side echo (m, deg) and, on cycles where it was worked out, the free length toward the
goal (m). The planner is the tree's own (PYTHONPATH), wrapped, not changed.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners import tangent_bug as tb
from nav_bench.planners.registry import make_planner
from nav_bench.specs import PlannerSetSpec
from nav_bench.world.load import load_world


def main() -> None:
    world = load_world(Path(sys.argv[1]))
    seed = int(sys.argv[2])
    every = float(sys.argv[3]) if len(sys.argv) > 3 else 5.0
    spec = PlannerSetSpec(planner="tangent_bug")
    agent = make_planner(spec)
    free: dict[str, tuple[float, tuple[float, float]]] = {}
    next_t = [0.0]
    plain_free, plain_follow = tb.TangentBug._free_length, tb.TangentBug._follow

    def free_length(self, obs, xy, d_goal, theta_g):
        out = plain_free(self, obs, xy, d_goal, theta_g)
        free["last"] = (obs.t, out)
        return out

    def follow(self, obs, xy, goal, d_goal, theta_g, v):
        cmd = plain_follow(self, obs, xy, goal, d_goal, theta_g, v)
        if obs.t >= next_t[0]:
            next_t[0] = obs.t + every
            near = self.follower.nearest(obs)
            last = free.get("last")
            fl = round(last[1][1], 2) if last is not None and last[0] == obs.t else None
            print(f"t={obs.t:6.1f} xy=({xy[0]:.2f}, {xy[1]:.2f}) yaw={math.degrees(obs.pose[2]):5.0f} "
                  f"mode={self.mode} side={self.side} d_followed={self.d_followed:.2f} "
                  f"d_followed_side={self.d_followed_side:.2f} strict={self.strict_lap} "
                  f"d_goal={d_goal:.2f} nearest={None if near is None else (round(near[0], 2), round(math.degrees(near[1])))} "
                  f"free={fl}")
        return cmd

    tb.TangentBug._free_length, tb.TangentBug._follow = free_length, follow
    result = run_episode(world, spec, seed=seed, settings=EpisodeSettings(time_s=300),
                         planner_instance=agent)
    print(result.row.outcome, result.row.time_s, "re-plans:", result.row.replans)


if __name__ == "__main__":
    main()
