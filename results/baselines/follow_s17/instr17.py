"""Replay one episode and print, per follower cycle of its last SECONDS s, the true pose, the
exit of WallFollower.act, the followed point (distance, bearing relative to the heading), the
other side's clearance, the echo ahead and the command; plus the sonar ranges. No change to
the planner: its methods are wrapped.

    PYTHONPATH=TREE python instr17.py WORLD.yaml PLANNER TIME_LIMIT [SECONDS]
"""
import math
import sys

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.interface import wrap_angle
from nav_bench.planners.follow import WallFollower
from nav_bench.planners.registry import make_planner, parse_planner_arg
from nav_bench.world.load import load_world


def main() -> None:
    world_path, name, limit = sys.argv[1:4]
    seconds = float(sys.argv[4]) if len(sys.argv) > 4 else 10.0
    rows: list[str] = []
    times: list[float] = []
    act, band, ahead_of = WallFollower.act, WallFollower._band_turn, WallFollower._ahead
    state: dict = {}

    def wrapped_act(self, obs):
        state.clear()
        cmd = act(self, obs)
        near = self.nearest(obs)
        kind = state.get("exit")
        if kind is None:
            if cmd.v == 0.0 and abs(abs(cmd.omega) - self.turn_rate(obs.robot)) < 1e-9:
                kind = "AWAY"
            elif near is None:
                kind = "arc"
            else:
                kind = "steer"
        x, y, yaw = (float(q) for q in obs.pose)
        nd = f"{near[0]:.2f}@{math.degrees(wrap_angle(near[1] - yaw)):+4.0f}" if near else "none"
        r = " ".join(f"{v:.2f}" if math.isfinite(v) else " inf" for v in obs.ranges)
        rows.append(f"{obs.t:6.1f} ({x:5.2f},{y:5.2f},{math.degrees(yaw):+5.0f}) {kind:5s} near {nd:10s} "
                    f"other {state.get('other', math.nan):5.2f} ahead {state.get('ahead', math.nan):5.2f} "
                    f"cmd ({cmd.v:.2f},{cmd.omega:+.2f}) r [{r}]")
        times.append(obs.t)
        return cmd

    def wrapped_band(self, *args):
        state["exit"] = "band"  # the dead band's turn (follow_s16)
        return band(self, *args)

    def wrapped_ahead(self, obs, other):
        a = ahead_of(self, obs, other)
        state["other"], state["ahead"] = other, a
        return a

    WallFollower.act, WallFollower._band_turn, WallFollower._ahead = wrapped_act, wrapped_band, wrapped_ahead
    spec = parse_planner_arg(name)
    world = load_world(world_path)
    result = run_episode(world, spec, seed=0, settings=EpisodeSettings(time_s=float(limit)),
                         planner_instance=make_planner(spec))
    row = result.row.to_json()
    print(row["outcome"], row.get("stuck_reason"), row["time_s"], "contacts", row["collisions"])
    for t, line in zip(times, rows, strict=True):
        if t > times[-1] - seconds:
            print(line)


if __name__ == "__main__":
    main()
