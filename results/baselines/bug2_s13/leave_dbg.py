"""Why did Bug2 not leave where a lap crossed (H, goal]? Plays one generated layout with the
default episode settings and episode seed 0 (not the suite's derived seed: the episode is not
the gate's one) and prints, at each crossing of the segment from the current hit point H to
the goal more than 0.3 m from H, the parts of the leave test.

    python leave_dbg.py office 26
"""

from __future__ import annotations

import math
import sys

import numpy as np

from nav_bench.episode.loop import run_episode
from nav_bench.planners import bug2
from nav_bench.specs import PlannerSetSpec
from nav_bench.world.generate import generate_world
from nav_bench.world.load import world_from_data

plain_act = bug2.Bug2.act


def logged_act(self: bug2.Bug2, obs: bug2.Observation) -> bug2.Command:
    xy, goal = np.asarray(obs.pose[:2], float), np.asarray(obs.goal, float)
    if self.mode == bug2.FOLLOW and self.hit is not None:
        p = self.settings
        to_goal = float(np.hypot(*(goal - xy)))
        heading = math.atan2(goal[1] - xy[1], goal[0] - xy[0])
        d = goal - self.hit
        n = np.array([-d[1], d[0]]) / np.hypot(*d)
        now, before = float((xy - self.hit) @ n), float((self._prev_xy - self.hit) @ n)
        if now * before <= 0 and float(np.hypot(*(xy - self.hit))) > 0.3:
            points = self.memory.points(xy, p.leave_clear + 1.0)
            free = bug2.free_along(points, xy, heading, min(p.leave_clear, to_goal),
                                   bug2.corridor_half_width(obs.robot), body=obs.robot.radius)
            print(f"t={obs.t:.1f} xy=({xy[0]:.2f}, {xy[1]:.2f}) on_mline={self._on_mline(xy, goal)} "
                  f"to_goal {to_goal:.2f} < d(H) - margin: {to_goal < self.hit_goal_distance - p.leave_margin} "
                  f"free_along={free} H=({self.hit[0]:.2f}, {self.hit[1]:.2f})")
    return plain_act(self, obs)


bug2.Bug2.act = logged_act
result = run_episode(world_from_data(generate_world(sys.argv[1], int(sys.argv[2]))), PlannerSetSpec(planner="bug2"),
                     seed=0)
print(result.row.outcome, result.row.time_s, result.row.events)
