"""How far the body's centre rolls on when a moving robot is told to turn on the spot (v = 0),
with the default robot (robots/diffbot.yaml): cruise at v0 for 2 s, then (0, omega) for 2 s."""
import math
import sys

sys.path.insert(0, "tests/sim")
from sim_helpers import make_sim, make_world

from nav_bench.interface import Command
from nav_bench.sim import SimSession
from nav_bench.specs import load_robot

robot = load_robot()
with SimSession() as s:
    for v0, w in [(0.0, 9.0), (0.1, 9.0), (0.2, 9.0), (0.3, 9.0), (0.4, 9.0), (0.3, 2.0), (0.3, 0.0), (0.2, 0.0)]:
        sim = make_sim(s, make_world(), robot)
        info = sim.robot_info
        steps = round(0.1 / sim.dt)
        for _ in range(20):
            sim.apply(Command(v0, 0.0))
            sim.step(steps)
        p0 = sim.true_pose().copy()
        far, t_stop = 0.0, None
        for i in range(20):
            sim.apply(Command(0.0, max(-info.omega_max, min(info.omega_max, w))))
            for j in range(steps):
                sim.step(1)
                d = math.hypot(*(sim.true_pose()[:2] - p0[:2]))
                if d > far + 1e-4:
                    far, t_stop = d, (i * steps + j + 1) * sim.dt
        print(f"v0 {v0:.1f} m/s, then v 0 omega {min(w, info.omega_max):.2f} rad/s (omega_max {info.omega_max:.2f}): "
              f"centre rolls on {far * 1000:.0f} mm, for {t_stop or 0:.2f} s")
