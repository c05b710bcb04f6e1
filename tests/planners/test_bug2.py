"""Bug2 on the kinematic harness: around a wall, out of a U, and a goal it cannot reach.

Runtime: ~0.5 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.interface import StuckReason
from nav_bench.planners.base import Planner
from nav_bench.planners.bug2 import FOLLOW, GO, UNREACHABLE, Bug2
from nav_bench.planners.follow import (
    LEFT,
    RIGHT,
    LoopDetector,
    WallFollower,
    estimate_wall,
    obstacle_ahead,
    points_ahead,
)
from nav_bench.testing.harness import BoxWorld, default_robot, observe, run, u_world, wall_world


@pytest.mark.parametrize("seed", [0, 1])
def test_gets_around_a_single_wall_and_leaves_on_the_m_line(seed: int) -> None:
    world, start, goal = wall_world()  # wall x = 3.9..4.1, y = 1.5..4.5; m-line y = 3
    result = run(Bug2(), world, start, goal, time_s=60.0, seed=seed, noise_std=0.01)
    assert result.reached and result.collisions == 0
    assert result.kinds("replan") == 1  # one hit point
    (_, t_hit, hit), = [e for e in result.events if e[0] == "replan"]
    assert hit["y"] == pytest.approx(3.0, abs=0.05)  # the hit point is on the m-line...
    assert 3.9 - hit["x"] == pytest.approx(0.55, abs=0.1)  # ...hit_distance before the wall
    xy = result.poses[:, :2]
    before = xy[: round(t_hit / 0.1)]
    assert np.abs(before[:, 1] - 3.0).max() < 0.02  # motion to goal follows the m-line
    # it went round one end of the wall: with the wall on its right, turning left = over the top
    assert xy[:, 1].max() > 4.5 + 0.3 and xy[:, 1].min() > 2.5
    # and left the wall where it crossed the m-line beyond it, then drove along the m-line
    after = xy[xy[:, 0] > 4.8]
    assert np.abs(after[:, 1] - 3.0).max() < 0.15
    assert result.path_length < 11.0


def test_wall_side_left_goes_round_the_other_end() -> None:
    world, start, goal = wall_world()
    result = run(Bug2(wall_side="left"), world, start, goal, time_s=60.0)
    assert result.reached and result.collisions == 0
    assert result.poses[:, 1].min() < 1.5 - 0.3 and result.poses[:, 1].max() < 3.5


def test_escapes_a_u_shaped_obstacle_with_the_goal_behind_it() -> None:
    world, start, goal = u_world()  # U open toward the start, goal behind its bottom
    result = run(Bug2(), world, start, goal, time_s=120.0, seed=2, noise_std=0.01)
    assert result.reached and result.collisions == 0
    xy = result.poses[:, :2]
    assert xy[:, 0].max() > 7.5 and (xy[:, 0] > 4.0).any()
    assert np.any((xy[:, 0] > 3.0) & (xy[:, 0] < 5.0) & (np.abs(xy[:, 1] - 4.0) < 0.3))  # went in
    assert result.kinds("replan") == 1  # one hit at the bottom, then one boundary walk out
    assert result.path_length < 20.0


def test_a_full_lap_around_an_enclosed_goal_means_unreachable() -> None:
    ring = [(5.0, 2.0, 6.6, 2.15), (5.0, 3.45, 6.6, 3.6), (5.0, 2.0, 5.15, 3.6), (6.45, 2.0, 6.6, 3.6)]
    world = BoxWorld.room((9.0, 6.0), ring)
    result = run(Bug2(), world, (1.0, 2.8, 0.0), (5.8, 2.8), time_s=80.0)
    assert not result.reached and result.collisions == 0
    assert result.kinds("unreachable") == 1
    planner = result.planner
    assert planner.mode == UNREACHABLE
    (_, t_stop, where), = [e for e in result.events if e[0] == "unreachable"]
    assert math.dist((where["x"], where["y"]), planner.hit) < 0.4  # back at the hit point
    stopped = result.commands[round(t_stop / 0.1) + 1:]
    assert len(stopped) > 0 and np.all(stopped == 0.0)


def test_mode_switches_at_the_hit_distance() -> None:
    robot = default_robot()
    world = BoxWorld.room((6.0, 4.0), [(3.0, 0.0, 3.2, 4.0)])
    bug = Bug2()
    far = observe(world, np.array([2.0, 2.0, 0.0]), np.array([5.0, 2.0]), robot, 0.0, 0.1)
    bug.reset(far, np.random.default_rng(0))
    cmd = bug.act(far)  # wall 1 m ahead: keep going
    assert bug.mode == GO and cmd.v > 0
    near = observe(world, np.array([2.5, 2.0, 0.0]), np.array([5.0, 2.0]), robot, 0.1, 0.1)
    cmd = bug.act(near)  # 0.5 m < hit_distance 0.55: follow the wall, turning left first
    assert bug.mode == FOLLOW and cmd.v == 0.0 and cmd.omega > 0


@pytest.mark.parametrize("yaw_deg", [0.0, 10.0, -10.0, 25.0])
def test_wall_fit_accounts_for_the_cone_width(yaw_deg: float) -> None:
    """A cone sonar reports the nearest point in its cone, not the one on its axis; the fit
    recovers the true distance (0.5 m) and the angle (negative = converging on the left)."""
    world = BoxWorld.room((6.0, 4.0), [(0.0, 2.5, 6.0, 2.7)])  # wall face 0.5 m left of (3, 2)
    obs = observe(world, np.array([3.0, 2.0, math.radians(yaw_deg)]), np.array([5.0, 2.0]),
                  default_robot(), 0.0, 0.1, rays=7)
    wall = estimate_wall(obs, LEFT, lost=1.1)
    assert wall is not None
    assert wall.distance == pytest.approx(0.5, abs=0.01)
    assert math.degrees(wall.angle) == pytest.approx(-yaw_deg, abs=1.0)
    assert estimate_wall(obs, RIGHT, lost=1.1) is None  # nothing within reach on the right


# -- the shared wall follower and loop detector (Bug2 and TangentBug both use them) -----------
class _FollowOnly(Planner):
    """A planner that only follows the wall on its right (the bug planners' follow mode)."""

    name = "follow_only"

    def reset(self, obs, rng) -> None:
        super().reset(obs, rng)
        self.follower = WallFollower(RIGHT, 0.5, 0.4, 0.5)

    def act(self, obs):
        return self.follower.act(obs)


def _box_distance(xy: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
    """(N,) distance (m) of points (N, 2) to an axis-aligned box."""
    dx = np.maximum(np.maximum(box[0] - xy[:, 0], xy[:, 0] - box[2]), 0.0)
    dy = np.maximum(np.maximum(box[1] - xy[:, 1], xy[:, 1] - box[3]), 0.0)
    return np.hypot(dx, dy)


def test_wall_follower_rounds_four_convex_corners_without_losing_the_box() -> None:
    box = (4.0, 4.0, 6.0, 6.0)
    world = BoxWorld.room((10.0, 10.0), [box])
    result = run(_FollowOnly(), world, (3.5, 4.5, math.pi / 2), (9.5, 0.5), time_s=60.0,
                 noise_std=0.01)
    xy = result.poses[:, :2]
    assert result.collisions == 0
    d = _box_distance(xy, box)
    assert d.max() < 1.0 and d.min() > 0.25  # the box stays beside the robot all the way round
    bearing = np.unwrap(np.arctan2(xy[:, 1] - 5.0, xy[:, 0] - 5.0))
    assert bearing[0] - bearing[-1] > 2 * math.pi  # clockwise (box on the right), a full lap


def test_wall_follower_turns_round_a_door_frame() -> None:
    """A 0.1 m thick wall end (a door frame): the robot turns by 180 deg round it and comes
    back down the other face, never farther than 1 m from it."""
    frame = (4.95, 0.0, 5.05, 4.0)
    world = BoxWorld.room((10.0, 7.0), [frame])
    result = run(_FollowOnly(), world, (4.45, 1.5, math.pi / 2), (9.5, 0.5), time_s=25.0,
                 noise_std=0.01)
    xy = result.poses[:, :2]
    assert result.collisions == 0
    assert _box_distance(xy, frame).max() < 1.0
    other_face = (xy[:, 0] > 5.3) & (xy[:, 1] < 3.0)
    assert other_face.any()  # came round the end and down the far side


def test_loop_detector_tells_a_lap_from_a_u_turn() -> None:
    lap = LoopDetector(radius=0.4, min_length=1.6)
    lap.arm(np.array([0.0, 0.0]))
    angles = np.linspace(0.0, 2 * math.pi + 0.3, 200)  # round a circle of 1 m radius and on
    fired = [lap.update(np.array([math.sin(a), 1.0 - math.cos(a)])) for a in angles]
    assert any(fired)
    u_turn = LoopDetector(radius=0.4, min_length=1.6)
    u_turn.arm(np.array([0.0, 0.0]))
    out = [np.array([0.0, y]) for y in np.linspace(0.0, 3.0, 60)]  # up a corridor,
    back = [np.array([0.3, y]) for y in np.linspace(3.0, -0.5, 70)]  # down its other side
    assert not any(u_turn.update(p) for p in out + back)


def test_bug2_says_no_path_once_the_goal_is_unreachable() -> None:
    planner = Bug2()
    world, start, goal = u_world()
    obs = observe(world, np.array(start), np.array(goal), default_robot(), 0.0, 0.1)
    planner.reset(obs, np.random.default_rng(0))
    assert planner.stuck_reason() is None
    planner.mode = UNREACHABLE
    assert planner.stuck_reason() is StuckReason.NO_PATH


def test_wall_follower_turns_into_a_corridor_round_a_corner_on_its_wall_side() -> None:
    """An L-shaped 1 m corridor turning right (maze generator geometry): going round the
    corner the robot faces the corridor's far wall; it must turn toward its wall side, into
    the corridor, not away from it (which sent it back the way it came, round the pocket,
    and made the loop detector call a reachable goal unreachable)."""
    walls = [(1.0, 0.0, 1.1, 3.3),   # right wall of the vertical leg, ends at y = 3.3
             (1.0, 3.25, 6.0, 3.35),  # bottom wall of the horizontal leg
             (0.0, 4.35, 6.0, 4.45)]  # top wall of the horizontal leg (ahead of the vertical one)
    world = BoxWorld.room((6.0, 5.0), walls)
    result = run(_FollowOnly(), world, (0.5, 1.0, math.pi / 2), (5.9, 0.1), time_s=30.0,
                 noise_std=0.01)
    xy = result.poses[:, :2]
    assert result.collisions == 0
    assert xy[:, 0].max() > 3.0  # along the horizontal leg
    assert xy[np.argmax(xy[:, 0] > 1.5):, 1].min() > 3.35  # and stayed in it


def test_wall_follower_circles_a_thin_post_that_falls_between_the_beams() -> None:
    """A 0.15 m square post: beside the robot it is seen by one beam at most, and behind it by
    none (no sonar between -90 deg and the back). The follower keeps it on its right by the
    remembered echoes: two laps round it, never farther than 0.9 m, no contact."""
    post = (4.925, 4.925, 5.075, 5.075)
    world = BoxWorld.room((10.0, 10.0), [post])
    result = run(_FollowOnly(), world, (4.45, 5.0, math.pi / 2), (9.5, 0.5), time_s=60.0,
                 noise_std=0.01)
    xy = result.poses[:, :2]
    assert result.collisions == 0
    d = _box_distance(xy, post)
    assert d.max() < 0.9 and d.min() > 0.2
    bearing = np.unwrap(np.arctan2(xy[:, 1] - 5.0, xy[:, 0] - 5.0))
    assert bearing[0] - bearing[-1] > 4 * math.pi  # clockwise (post on the right), two laps


def test_wall_follower_turns_away_from_a_wall_hit_at_an_angle() -> None:
    """Hit at 45 deg, 0.5 m below a long wall (paper/labyrinth's first hit): the follower must
    turn away from its wall side to put the wall on its right and go west along it. The
    previous rule saw the open space on the right diagonal, turned right, left the wall on
    its left and circled in the open (a lap: 'unreachable')."""
    wall = (0.0, 2.45, 8.0, 2.55)
    world = BoxWorld.room((10.0, 10.0), [wall])
    result = run(_FollowOnly(), world, (5.0, 1.95 - 0.05, math.pi / 4), (9.5, 9.5), time_s=20.0,
                 noise_std=0.01)
    xy = result.poses[:, :2]
    assert result.collisions == 0
    assert _box_distance(xy, wall).max() < 0.9
    assert xy[-1, 0] < 2.5  # 2.5 m west along the wall (0.4 m/s, turning first)


def test_a_remembered_post_between_the_front_beams_is_ahead() -> None:
    """A 4 cm post 0.33 m ahead on the axis: seen from their mounts on the body edge it lies
    18 deg off each front sonar's axis, outside both 25 deg cones, so this cycle's echoes
    miss it; its echo remembered from farther back finds it."""
    robot = default_robot()
    world = BoxWorld.room((10.0, 10.0), [(5.33, 4.98, 5.37, 5.02)])
    obs = observe(world, np.array([5.0, 5.0, 0.0]), np.array([9.0, 5.0]), robot, 0.0, 0.1)
    assert obstacle_ahead(obs, 0.5, robot.radius) == math.inf
    remembered = np.array([[5.33, 5.0], [5.2, 5.6]])  # the post's face, and a wall 0.6 m aside
    assert points_ahead(remembered, obs, 0.5, robot.radius) == pytest.approx(0.33)
