"""``nav-bench perf``: how fast simulation and episodes run on this machine.

Figures are ratios measured in one run (machines differ; ratios travel better):
  * bare physics stepping with the robot alone (steps/s);
  * a full ``goal_seek`` episode in a paper world as a real-time factor;
  * the split of that episode's wall time: physics, sensing, planning, the rest;
  * stepping cost with 1,000 static obstacles, and in the imported TurtleBot3 map, relative to
    an empty world of the same size.
Targets (issue 2): real-time factor >= 100 on one core; everything but physics <= 25 %
of the episode; 1,000 obstacles within 1.5x of empty.
"""

from __future__ import annotations

import time

import numpy as np

from nav_bench.episode import EpisodeSettings, run_episode
from nav_bench.planners.base import Command
from nav_bench.specs import PlannerSetSpec, WorldSpec, load_robot, load_world

CURVE = Command(0.3, 0.2)  # m/s, rad/s: a gentle curve, so wheels and contacts do real work


def _stepping_rate(world: WorldSpec, steps: int = 4800, command: Command = CURVE) -> float:
    """Physics steps per wall second with the robot driving a gentle curve in ``world``."""
    from nav_bench.sim.session import SimSession
    from nav_bench.sim.simulation import Simulation

    robot = load_robot()
    with SimSession(physics_hz=240.0) as session:
        sim = Simulation(session, world, robot, np.random.default_rng(0), physics_hz=240.0)
        sim.apply(command)
        sim.step(240)  # warm-up: contacts and caches settle
        t0 = time.perf_counter()
        for _ in range(steps // 24):
            sim.step(24)
        return steps / (time.perf_counter() - t0)


def clutter_world(n: int = 1000, size: float = 40.0) -> WorldSpec:
    """``n`` small boxes on a regular grid, leaving a clear square round the start."""
    side = int(np.ceil(np.sqrt(n + 16)))
    pitch = size / (side + 1)
    obstacles = []
    for i in range(side):
        for j in range(side):
            x, y = (i + 1) * pitch, (j + 1) * pitch
            if len(obstacles) < n and np.hypot(x - 2.0, y - 2.0) > 2.5:
                obstacles.append({"box": {"center": [round(x, 3), round(y, 3)], "size": [0.3, 0.3]}})
    return WorldSpec.model_validate({"name": f"clutter_{n}", "size": [size, size], "start": [2, 2, 0],
                                     "goal": [size - 1, size - 1], "obstacles": obstacles})


STEADY_WORLD = "worlds/paper/very_complex.yaml"
IMPORTED_WORLD = "worlds/imported/turtlebot3_world.yaml"


def _episode_figures(world: WorldSpec, world_file: str, planner: str,
                     seconds: float | None) -> tuple[float, float]:
    """Play one episode, print its real-time factor and wall-time split; returns both."""
    result = run_episode(world, PlannerSetSpec(planner=planner), seed=0,
                         settings=EpisodeSettings(time_s=seconds), world_file=world_file)
    timing, row = result.timing, result.row
    total = timing["total"]
    rtf = row["time_s"] / total
    print(f"{planner} episode in {row['world']}: {row['time_s']:.1f} s simulated in "
          f"{total:.2f} s wall -> real-time factor {rtf:.0f}x ({row['outcome']})")
    for key in ("physics", "sensing", "planning", "other"):
        print(f"  {key:10s} {timing.get(key, 0.0):7.3f} s  {100 * timing.get(key, 0.0) / total:5.1f} %")
    return rtf, 1.0 - timing.get("physics", 0.0) / total


def run_perf(world_file: str = "worlds/paper/open_room.yaml", seconds: float | None = None) -> dict[str, float]:
    """Measure and print the figures; returns them."""
    empty_small = WorldSpec.model_validate({"name": "robot_alone", "size": [10, 10], "boundary": False,
                                            "start": [5, 5, 0], "goal": [9, 9]})
    bare = _stepping_rate(empty_small)
    print(f"bare stepping, robot alone:           {bare:10.0f} physics steps/s "
          f"({bare / 240.0:.0f}x real time at 240 Hz)")

    world = load_world(world_file)
    rtf, not_physics = _episode_figures(world, world_file, "goal_seek", seconds)
    # a longer episode, where the fixed cost of opening a client and building the scene
    # (~30 ms) is spread over more cycles: the steady-state figures
    _episode_figures(load_world(STEADY_WORLD), STEADY_WORLD, "eopc", None)

    empty = WorldSpec.model_validate({"name": "empty_40", "size": [40, 40], "start": [2, 2, 0],
                                      "goal": [39, 39]})
    rate_empty = _stepping_rate(empty)
    rate_clutter = _stepping_rate(clutter_world(1000))
    ratio = rate_empty / rate_clutter
    imported = load_world(IMPORTED_WORLD)
    rate_imported = _stepping_rate(imported)
    rate_imported_empty = _stepping_rate(WorldSpec.model_validate(
        {"name": "empty_like_imported", "size": list(imported.size), "start": imported.start,
         "goal": list(imported.goal)}))
    ratio_imported = rate_imported_empty / rate_imported
    print(f"stepping, imported {imported.name} ({len(imported.obstacles)} boxes): "
          f"{ratio_imported:.2f}x the cost of an empty world of its size")
    print(f"stepping, 40 m world, empty:          {rate_empty:10.0f} steps/s")
    print(f"stepping, 40 m world, 1000 obstacles: {rate_clutter:10.0f} steps/s -> "
          f"{ratio:.2f}x the cost of empty")
    print()
    print(f"targets: real-time factor >= 100 ({'met' if rtf >= 100 else 'MISSED'}), "
          f"non-physics share <= 25 % ({100 * not_physics:.1f} %: "
          f"{'met' if not_physics <= 0.25 else 'MISSED'}), "
          f"1000 obstacles <= 1.5x empty ({'met' if ratio <= 1.5 else 'MISSED'})")
    return {"bare_steps_per_s": bare, "real_time_factor": rtf, "non_physics_share": not_physics,
            "clutter_ratio": ratio, "imported_ratio": ratio_imported}
