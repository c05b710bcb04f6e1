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
        angles, ranges = obs.robot.sonar.angles, obs.ranges
        front = min(r for a, r in zip(angles, ranges) if abs(a) < 0.5)
        if front < self.p["stop_m"]:  # blocked: turn in place toward the freer side
            left = sum(r for a, r in zip(angles, ranges) if a > 0)
            right = sum(r for a, r in zip(angles, ranges) if a < 0)
            return Command(0.0, 0.8 if left >= right else -0.8)
        error = math.atan2(gy - y, gx - x) - yaw
        error = math.atan2(math.sin(error), math.cos(error))
        omega = max(-1.0, min(1.0, self.p["k_turn"] * error))
        return Command(self.p["v_max"] * max(0.0, math.cos(error)), omega)
