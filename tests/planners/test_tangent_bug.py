"""TangentBug: its local range function, and the harness worlds (wall, U); recorded episodes
of TangentBug, Bug2 and DWA replayed against the commands of the code before issue 16.

Runtime: ~8 s (the replays: 3,690 cycles).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nav_bench.interface import Observation, RobotInfo, SonarInfo, StuckReason
from nav_bench.planners.base import Planner
from nav_bench.planners.bug2 import Bug2
from nav_bench.planners.dwa import DWA
from nav_bench.planners.follow import FOLLOW, GO, RIGHT, UNREACHABLE, EchoMemory
from nav_bench.planners.tangent_bug import (
    TangentBug,
    binned_range_function,
    blocked_interval_edges,
    range_bins,
    range_function,
)
from nav_bench.testing.harness import BoxWorld, default_robot, observe, run, u_world, wall_world


def test_range_function_grows_each_echo_by_the_clearance_radius() -> None:
    directions = np.radians(np.arange(-180.0, 180.0, 5.0))
    rho = range_function(np.array([[2.0, 0.0]]), np.zeros(2), 0.5, directions)
    half = math.degrees(math.asin(0.5 / 2.0))  # 14.48 deg
    blocked = np.degrees(directions[np.isfinite(rho)])
    assert blocked.min() == pytest.approx(-10.0) and blocked.max() == pytest.approx(10.0)
    assert half == pytest.approx(14.48, abs=0.01)
    assert np.all(rho[np.isfinite(rho)] == pytest.approx(2.0))
    # the nearer of two echoes on the same bearing defines rho
    rho2 = range_function(np.array([[2.0, 0.0], [1.0, 0.0]]), np.zeros(2), 0.5, np.array([0.0]))
    assert rho2[0] == pytest.approx(1.0)


def test_blocked_interval_edges_wrap_around() -> None:
    blocked = np.zeros(12, dtype=bool)
    blocked[[10, 11, 0, 1, 2]] = True
    assert blocked_interval_edges(blocked, 0) == (9, 3)  # first free clockwise, counter-clockwise
    assert blocked_interval_edges(np.ones(5, dtype=bool), 2) is None


@pytest.mark.parametrize("seed", [0, 1])
def test_gets_around_a_single_wall(seed: int) -> None:
    world, start, goal = wall_world()
    result = run(TangentBug(), world, start, goal, time_s=60.0, seed=seed, noise_std=0.01)
    assert result.reached and result.collisions == 0
    xy = result.poses[:, :2]
    assert xy[:, 1].min() < 1.5 - 0.2 or xy[:, 1].max() > 4.5 + 0.2  # round an end of the wall
    assert result.path_length < 11.0


def test_escapes_a_u_and_takes_a_shorter_way_than_bug2() -> None:
    world, start, goal = u_world()
    tangent = run(TangentBug(), world, start, goal, time_s=120.0, seed=3, noise_std=0.01)
    bug2 = run(Bug2(), world, start, goal, time_s=120.0, seed=3, noise_std=0.01)
    assert tangent.reached and tangent.collisions == 0 and bug2.reached
    assert tangent.kinds("replan") >= 1  # boundary following happened
    # leaves the boundary as soon as the goal is visibly reachable (d_reach < d_followed)
    assert tangent.path_length < bug2.path_length - 1.5


def test_stops_following_when_the_goal_is_reachable() -> None:
    world, start, goal = wall_world()
    result = run(TangentBug(), world, start, goal, time_s=60.0)
    planner = result.planner
    assert planner.mode == "motion_to_goal"
    # after the wall end it heads straight for the goal: the last 2 m are a straight segment
    tail = result.poses[np.hypot(*(result.poses[:, :2] - goal).T) < 2.0, :2]
    direction = (goal - tail[0]) / np.linalg.norm(goal - tail[0])
    rel = tail - tail[0]
    lateral = np.abs(rel[:, 0] * direction[1] - rel[:, 1] * direction[0])
    assert lateral.max() < 0.1


def _following(world, pose: tuple[float, float, float], goal: tuple[float, float],
               d_followed: float) -> tuple[TangentBug, Observation]:
    """A TangentBug put in boundary following (acquired, right side) with ``d_followed``."""
    robot = default_robot()
    obs = observe(world, np.array(pose), np.array(goal), robot, 0.0, 0.1)
    planner = TangentBug()
    planner.reset(obs, np.random.default_rng(0))
    planner._start_following(obs, np.array(pose[:2]), RIGHT)
    planner.acquired, planner.d_followed = True, d_followed
    return planner, observe(world, np.array(pose), np.array(goal), robot, 0.1, 0.1)


def test_leave_condition_d_reach_below_d_followed_by_hand() -> None:
    """The robot 3 m from the goal, facing it. Open room: the front sonars see 3 m of free
    space toward the goal, d_reach < 1 m < d_followed = 2 m -> it leaves the boundary.
    A wall 0.8 m ahead: the visible free space ends 0.35 m (robot radius + clearance) before
    it, d_reach > 2 m = d_followed -> it keeps following."""
    open_room_ = BoxWorld.room((8.0, 6.0))
    planner, obs = _following(open_room_, (4.0, 3.0, 0.0), (7.0, 3.0), d_followed=2.0)
    assert planner._d_reach(obs, np.array([4.0, 3.0]), np.array([7.0, 3.0])) < 1.0
    planner.act(obs)
    assert planner.mode == GO
    walled = BoxWorld.room((8.0, 6.0), [(4.8, 1.0, 5.0, 5.0)])
    planner, obs = _following(walled, (4.0, 3.0, 0.0), (7.0, 3.0), d_followed=2.0)
    d_reach = planner._d_reach(obs, np.array([4.0, 3.0]), np.array([7.0, 3.0]))
    assert 2.0 < d_reach < 3.0
    planner.act(obs)
    assert planner.mode == FOLLOW


def test_echo_memory_keeps_a_wall_until_a_reading_sees_through_it() -> None:
    """The wall behind the robot is remembered however long ago it was seen (the 8 s horizon
    forgot it); a point a later reading sees through is dropped."""
    robot = default_robot()
    world = BoxWorld.room((8.0, 6.0), [(4.8, 1.0, 5.0, 5.0)])
    memory = EchoMemory(math.inf, carve=True, spacing=0.05)
    memory.add(observe(world, np.array([4.0, 3.0, 0.0]), np.array([7.0, 3.0]), robot, 0.0, 0.1))
    wall_points = len(memory)
    assert wall_points > 0
    memory.add(observe(world, np.array([4.0, 3.0, math.pi]), np.array([7.0, 3.0]), robot, 100.0, 0.1))
    assert np.any(np.abs(memory.points()[:, 0] - 4.8) < 0.1)  # still there after 100 s
    phantom = Observation(t=101.0, pose=np.array([4.0, 3.0, 0.0]), goal=np.array([7.0, 3.0]),
                          ranges=np.full(6, robot.sonar.max_range), robot=robot,
                          bounds=world.bounds, dt=0.1)
    memory.add(phantom)  # nothing ahead now (as if the wall had been a misplaced echo)
    assert not np.any(np.abs(memory.points()[:, 0] - 4.8) < 0.1)


def test_says_no_path_once_the_goal_is_unreachable() -> None:
    world, start, goal = u_world()
    planner, _ = _following(world, start, goal, d_followed=math.inf)
    assert planner.stuck_reason() is None
    planner.mode = UNREACHABLE
    assert planner.stuck_reason() is StuckReason.NO_PATH


def _door_world(width: float) -> BoxWorld:
    """10 x 6 m room split at x = 5 by a 0.1 m wall with a door of ``width`` m centred on y = 3."""
    return BoxWorld.room((10.0, 6.0), [(4.95, 0.0, 5.05, 3.0 - width / 2),
                                       (4.95, 3.0 + width / 2, 5.05, 6.0)])


def test_echo_growth_leaves_a_door_wider_than_the_grown_robot_open() -> None:
    """Jamb echoes 0.8 m apart, seen from 1 m in front: grown by radius + clearance
    (0.2 + 0.1 m) they leave +-5 deg round the door's axis free; grown by the former 0.35 m
    only +-2 deg, which a cone echo placed a few cm into the doorway closes."""
    jambs = np.array([[5.0, 2.6], [5.0, 3.4]])
    xy, ahead = np.array([4.0, 3.0]), np.radians(np.arange(-5.0, 6.0, 1.0))
    grow = default_robot().radius + TangentBug().settings.clearance
    assert grow == pytest.approx(0.30)
    assert np.isinf(range_function(jambs, xy, grow, ahead)).all()  # -5..5 deg free
    rho = range_function(jambs, xy, 0.35, ahead)
    assert np.degrees(ahead[np.isinf(rho)]) == pytest.approx([-2.0, -1.0, 0.0, 1.0, 2.0])


@pytest.mark.parametrize("width", [0.8, 0.9])
def test_drives_through_a_door_wider_than_the_grown_robot(width: float) -> None:
    """Head-on through a 0.8 m and a 0.9 m door (the only way): with 0.15 m clearance
    (0.35 m growth) the 0.8 m door closed and the robot gave up at the wall (x = 4.77 m)."""
    result = run(TangentBug(), _door_world(width), (1.0, 3.0, 0.0), (9.0, 3.0), time_s=90.0,
                 seed=1, noise_std=0.01)
    assert result.reached and result.collisions == 0
    assert result.path_length < 8.5  # straight through (7.8 m to the goal's tolerance)


# ----------------------------------------------------------------------------- fast paths = reference
REPLAY = Path(__file__).resolve().parents[1] / "data" / "planner_replay"


def test_binned_range_function_equals_the_full_one_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    bins = range_bins(120)
    for n_pts in (0, 1, 7, 300):
        # points from 1 mm (blocks half the circle) to 3 m away, bearings across the -pi cut
        pts = rng.uniform(-3.0, 3.0, size=(n_pts, 2))
        pts[: n_pts // 4] *= 1e-3
        xy = rng.uniform(-1.0, 1.0, size=2)
        for grow in (0.0, 0.28, 0.5):
            full = range_function(pts + xy, xy, grow, bins)
            np.testing.assert_array_equal(binned_range_function(pts + xy, xy, grow, bins), full)
    # a point exactly on a bin's edge of blocking, at the wrap-around bearing
    pts = np.array([[-2.0, 0.0], [-2.0, -1e-12], [0.5, 0.28]])
    np.testing.assert_array_equal(binned_range_function(pts, np.zeros(2), 0.28, bins),
                                  range_function(pts, np.zeros(2), 0.28, bins))


def replay_commands(name: str, planner: Planner) -> tuple[np.ndarray, np.ndarray]:
    """Feed the observations recorded in ``tests/data/planner_replay/<name>.npz`` to
    ``planner``; its commands (N, 2) and the recorded ones. The files are real PyBullet
    episodes (seed 0) played with main's code at cd00640, before issue 16's speed-ups, in the
    format ``benchmarks/bench_tangent_bug.py --record`` writes."""
    with np.load(REPLAY / f"{name}.npz") as stored:
        rec = {key: stored[key] for key in stored.files}  # read once: an NpzFile inflates per access
    sonar = SonarInfo(angles=rec["sonar_angles"], offsets=rec["sonar_offsets"], cone=float(rec["sonar_cone"]),
                      min_range=float(rec["sonar_min_range"]), max_range=float(rec["sonar_max_range"]))
    robot = RobotInfo(radius=float(rec["robot_radius"]), wheel_base=float(rec["wheel_base"]),
                      v_max=float(rec["v_max"]), omega_max=float(rec["omega_max"]), sonar=sonar)
    bounds = tuple(float(b) for b in rec["bounds"])
    cmds = []
    for i in range(len(rec["t"])):
        obs = Observation(t=float(rec["t"][i]), pose=rec["pose"][i].copy(), goal=rec["goal"][i].copy(),
                          ranges=rec["ranges"][i].copy(), robot=robot, bounds=bounds, dt=float(rec["dt"]))
        if i == 0:
            planner.reset(obs, np.random.default_rng(0))
        cmd = planner.act(obs)
        cmds.append([cmd.v, cmd.omega])
    return np.asarray(cmds), rec["cmd"]


@pytest.mark.parametrize("name", ["tangent_bug_congested_120s", "tangent_bug_clutter40_60s",
                                  "bug2_congested_60s", "bug2_clutter40_60s", "dwa_congested_30s"])
def test_replayed_episode_gives_the_reference_commands_bit_for_bit(name: str) -> None:
    """The incremental echo memory, the binned range function and the per-cycle sharing change
    no command of a recorded episode (1200 cycles of congested: memories of up to ~1100
    echoes, boundary following and motion to goal); DWA shares the echo memory."""
    planner = {"tangent_bug": TangentBug, "bug2": Bug2, "dwa": DWA}[name.rsplit("_", 2)[0]]()
    got, want = replay_commands(name, planner)
    assert got.shape == want.shape
    np.testing.assert_array_equal(got, want)
