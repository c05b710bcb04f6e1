"""Replay one episode and print the follower cycles where its circling detector says circling:
time, true pose, whether the centring steered (CENTRE) or not (and why: no far corner, gap too
narrow, axis not clear), and a summary of the circling spells. No change to the planner: its
methods are wrapped.

    PYTHONPATH=TREE python probe18.py WORLD.yaml PLANNER TIME_LIMIT
"""
import math
import sys

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.follow import WallFollower, corridor_half_width
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.world.load import load_world


def main() -> None:
    world_path, name, limit = sys.argv[1:4]
    act, centring = WallFollower._act, WallFollower._centring_heading
    state: dict = {}

    def wrapped_centring(self, obs, near):
        h = centring(self, obs, near)
        if near is None:
            state["why"] = "no-near"
        else:
            corner = self._far_corner_clearance(obs)
            width = near[0] + corner
            if not math.isfinite(corner):
                state["why"] = "no-corner"
            elif not (2.0 * corridor_half_width(obs.robot) <= width and corner < near[0]):
                state["why"] = f"width {near[0]:.2f}+{corner:.2f}"
            else:
                state["why"] = "CENTRE" if h is not None else "axis-blocked"
        return h

    def wrapped_act(self, obs):
        state.clear()
        cmd = act(self, obs)
        if self.circling.fired:
            x, y, yaw = (float(q) for q in obs.pose)
            print(f"{obs.t:6.1f} ({x:5.2f},{y:5.2f},{math.degrees(yaw):+5.0f}) {state.get('why', 'n/a'):14s} "
                  f"cmd ({cmd.v:.2f},{cmd.omega:+.2f})")
        return cmd

    WallFollower._act, WallFollower._centring_heading = wrapped_act, wrapped_centring
    spec = parse_planner_arg(name)
    result = run_episode(load_world(world_path), spec, seed=0, settings=EpisodeSettings(time_s=float(limit)),
                         planner_instance=make_planner(spec))
    row = result.row.to_json()
    print(row["outcome"], row.get("stuck_reason"), row["time_s"], "contacts", row["collisions"])


if __name__ == "__main__":
    main()
