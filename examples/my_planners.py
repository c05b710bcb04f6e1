"""A complete user planner in about 30 lines (shown in the README).

Run it without installing anything:  nav-bench episode worlds/paper/open_room.yaml \
    --planner examples.my_planners:Cautious
"""

import math

from nav_bench.planners import Command, Observation, Param, Planner


class Cautious(Planner):
    """Drive at the goal; when the front is blocked, turn toward the side with more room."""

    name = "cautious"
    reference = "none: a teaching example"
    params = (
        Param("v_max", 0.4, "m/s", "cruise speed"),
        Param("stop_m", 0.45, "m", "stop and turn when a front echo is closer than this"),
        Param("k_turn", 1.5, "1/s", "heading gain toward the goal"),
    )

    def act(self, obs: Observation) -> Command:
        x, y, yaw = obs.pose
        gx, gy = obs.goal
        if math.hypot(gx - x, gy - y) < 0.2:
            return Command(0.0, 0.0)
        a, r = obs.robot.sonar.angles, obs.ranges  # (K,) mount angles (rad), readings (m)
        if r[abs(a) < 0.5].min() < self.settings.stop_m:  # blocked: turn toward the freer side
            return Command(0.0, 0.8 if r[a > 0].sum() >= r[a < 0].sum() else -0.8)
        error = math.atan2(gy - y, gx - x) - yaw
        error = math.atan2(math.sin(error), math.cos(error))
        omega = max(-1.0, min(1.0, self.settings.k_turn * error))
        return Command(self.settings.v_max * max(0.0, math.cos(error)), omega)
