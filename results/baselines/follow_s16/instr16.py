"""Replay one episode and count, per follower cycle of its last SECONDS s, which exit of
WallFollower.act gave the command: the turn away from a wall ahead, the arc toward a lost
boundary, the dead band's turn (_band_turn) or the drive on the heading; and how often the gap
check put the heading on a corner gap's axis. No change to the planner: its methods are wrapped.

    PYTHONPATH=TREE python instr16.py WORLD.yaml PLANNER TIME_LIMIT [SECONDS]
"""
import sys
from collections import Counter

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.planners.follow import WallFollower
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.world.load import load_world


def main() -> None:
    world_path, name, limit = sys.argv[1:4]
    seconds = float(sys.argv[4]) if len(sys.argv) > 4 else 30.0
    cycles: list[tuple[float, str, bool, float, float, float, float]] = []
    state: dict = {}
    act, band = WallFollower.act, getattr(WallFollower, "_band_turn", None)
    axis_clear = getattr(WallFollower, "_axis_clear", None)

    def wrapped_act(self, obs):
        state.clear()
        cmd = act(self, obs)
        if "exit" in state:
            kind = state["exit"]
        elif cmd.v == 0.0 and abs(abs(cmd.omega) - self.turn_rate(obs.robot)) < 1e-9:
            kind = "turn away"
        elif cmd.v > 0.0 and abs(cmd.omega - self.side * cmd.v / max(self.distance, 1e-3)) < 1e-9:
            kind = "arc"
        else:
            kind = "steer"
        cycles.append((obs.t, kind, state.get("axis", False), *obs.pose, cmd.omega))
        return cmd

    def wrapped_band(self, obs, heading, correction):
        state["exit"] = "band"
        return band(self, obs, heading, correction)

    def wrapped_clear(self, obs, heading):
        ok = axis_clear(self, obs, heading)
        state["axis"] = state.get("axis", False) or ok
        return ok

    WallFollower.act = wrapped_act
    if band is not None:
        WallFollower._band_turn = wrapped_band
    if axis_clear is not None:
        WallFollower._axis_clear = wrapped_clear
    spec = parse_planner_arg(name)
    result = run_episode(load_world(world_path), spec, seed=0, settings=EpisodeSettings(time_s=float(limit)),
                         planner_instance=make_planner(spec))
    row = result.row.to_json()
    print(row["outcome"], row.get("stuck_reason"), row["time_s"], "contacts", row["collisions"])
    last = [c for c in cycles if c[0] > cycles[-1][0] - seconds] if cycles else []
    print(f"follower cycles in the last {seconds:.0f} s: {len(last)};", dict(Counter(c[1] for c in last)),
          "axis steered:", sum(c[2] for c in last))
    print("all follower cycles:", len(cycles), dict(Counter(c[1] for c in cycles)), "axis steered:", sum(c[2] for c in cycles))


if __name__ == "__main__":
    main()
