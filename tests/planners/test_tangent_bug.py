"""TangentBug: its local range function, and the harness worlds (wall, U); the binned range
function and the echo memory against their plain forms, and recorded episodes of TangentBug,
Bug2 and DWA replayed against the commands of the code before issue 16's speed-ups.

Runtime: ~3 s (the replays: 2,763 cycles).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nav_bench.interface import Observation, RobotInfo, SonarInfo
from nav_bench.planners.base import Planner
from nav_bench.planners.bug2 import Bug2
from nav_bench.planners.dwa import DWA
from nav_bench.planners.follow import LEFT, RIGHT, EchoMemory, world_echoes
from nav_bench.planners.tangent_bug import (
    OtherBoundaryLap,
    TangentBug,
    binned_range_function,
    obstacle_interval_edges,
    range_bins,
    range_function,
)
from nav_bench.testing.harness import BoxWorld, default_robot, run, u_world, wall_world

REPLAY = Path(__file__).resolve().parents[1] / "data" / "planner_replay"


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
    rho = np.where(blocked, 1.0, np.inf)
    # first bin past the interval clockwise, counter-clockwise
    assert obstacle_interval_edges(rho, blocked, 0, math.inf) == (9, 3)
    assert obstacle_interval_edges(np.ones(5), np.ones(5, dtype=bool), 2, math.inf) is None


def test_the_blocking_obstacle_ends_where_the_range_function_jumps() -> None:
    """A wall 1.4 m away across the goal direction (bins 3-8) and a box 0.6 m away beside it
    (bins 9-11, 0): every bin but 1-2 is blocked, but the wall's interval ends where rho jumps
    to the box's (by more than the grown radius, 0.35 m); a wall seen obliquely (rho growing
    0.2 m a bin) stays one obstacle. A bin forced blocked with rho inf (the goal's) joins it."""
    rho = np.array([0.6, np.inf, np.inf, 1.4, 1.4, 1.4, 1.4, 1.4, 1.4, 0.6, 0.6, 0.6])
    blocked = np.isfinite(rho)
    assert obstacle_interval_edges(rho, blocked, 5, 0.35) == (2, 9)
    assert obstacle_interval_edges(rho, blocked, 5, math.inf) == (2, 1)  # every blocked bin: box too
    oblique = np.array([np.inf, 1.0, 1.2, 1.4, 1.6, 1.8, np.inf, np.inf])
    assert obstacle_interval_edges(oblique, np.isfinite(oblique), 3, 0.35) == (0, 6)
    forced = np.array([np.inf, 1.0, np.inf, 1.1, np.inf, np.inf])
    assert obstacle_interval_edges(forced, np.isfinite(forced) | (np.arange(6) == 2), 2, 0.35) == (0, 4)


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


def box_and_wall() -> BoxWorld:
    """Issue 12's harness (very_complex): a 12 x 8 m room, a 1 m box and a long wall 1 m beyond
    it, closed at its left end by the room's wall."""
    return BoxWorld.room((12.0, 8.0), [(4.0, 3.0, 5.0, 4.0),   # the box beside the start
                                       (0.0, 5.0, 8.0, 5.2)])  # the wall, 1 m beyond it


@pytest.mark.parametrize(("start", "time_s", "length"), [
    ((3.4, 3.2, 0.3), 23.8, 9.02),             # before the box: round its top, then along the wall
    ((4.5, 2.4, math.pi / 2), 96.4, 36.09),    # behind the box, facing it
])
def test_follows_the_wall_that_blocks_the_way_not_the_box_beside_it(
        start: tuple[float, float, float], time_s: float, length: float) -> None:
    """Issue 12 (very_complex): the goal (6.5, 6.5) lies beyond a wall across the way, with a
    box beside the robot. The blocked interval of every blocked direction took the box and the
    wall for one obstacle, so the robot followed the box: main reports ``unreachable`` after a
    lap from both starts; with only the strict second lap (tb_s11) the first start cycles
    between the box and the wall until its time is up, and the second laps the box before it
    leaves (107.0 s, 3 re-plans).
    The blocking obstacle's interval now ends where the range function jumps (to the box):
    the robot follows the wall once, without a lap, and reaches the goal."""
    result = run(TangentBug(), box_and_wall(), start, (6.5, 6.5), time_s=150.0, seed=0)
    reasons = [d.get("reason") for kind, _, d in result.events if kind == "replan"]
    assert result.kinds("unreachable") == 0
    assert reasons == ["follow_boundary"]
    assert result.reached and result.collisions == 0
    assert result.time == pytest.approx(time_s, abs=0.05)
    assert result.path_length == pytest.approx(length, abs=0.01)


def test_a_box_lapped_in_the_passage_before_the_wall_is_lapped_strictly_once_more() -> None:
    """The strict lap (tb_s11) is still what lets the robot off a box it has lapped. Started
    at the mouth of the 1 m passage between the box and the wall, the robot stalls; the blocking
    point lies in the passage, and the approach takes the box's echo beside the robot (the
    nearest on the followed side) for the boundary reached, so the follower keeps the box. ``d_followed`` from every near echo ahead and on the followed side
    takes the wall's echoes across the passage, so leaving the box never pays until the lap
    closes; the strict lap (``d_followed`` from the followed boundary only) lets it leave, and
    it reaches the goal. (Main reaches this one in 23.7 s: its interval of every blocked
    direction sent it round the box's top into the passage and along the wall.)"""
    result = run(TangentBug(), box_and_wall(), (3.0, 3.8, 0.0), (6.5, 6.5), time_s=150.0, seed=0)
    reasons = [d.get("reason") for kind, _, d in result.events if kind == "replan"]
    assert result.kinds("unreachable") == 0
    assert reasons == ["follow_boundary", "strict_lap", "follow_boundary", "follow_boundary"]
    assert result.reached and result.collisions == 0
    assert result.time == pytest.approx(129.5, abs=0.05)
    assert result.path_length == pytest.approx(46.97, abs=0.01)


def circle(centre: tuple[float, float], radius: float, start: float, turn: float,
           n: int) -> tuple[np.ndarray, np.ndarray]:
    """(n, 2) positions and (n,) headings round a circle from angle ``start`` by ``turn`` rad
    (> 0 CCW), heading along the tangent."""
    s = start + np.linspace(0.0, turn, n)
    xy = np.asarray(centre) + radius * np.stack([np.cos(s), np.sin(s)], axis=1)
    return xy, s + math.copysign(math.pi / 2, turn)


def first_fire(lap: OtherBoundaryLap, xy: np.ndarray, yaw: np.ndarray) -> int | None:
    for i in range(len(xy)):
        if lap.update(xy[i], yaw[i]):
            return i
    return None


def test_a_lap_round_another_boundary_fires_where_the_loop_closes() -> None:
    """Following began at (0, 0) with the boundary on the right; the robot drives 2 m east,
    then goes clockwise round a box centred 1 m south of (2, 0) (the boundary on its right):
    back within 0.4 m of (2, 0) after turning 2 pi, it has lapped another boundary."""
    lap = OtherBoundaryLap(radius=0.4, min_length=1.6)
    lap.arm(np.zeros(2), 0.0, RIGHT)
    lead = np.stack([np.linspace(0.0, 2.0, 41), np.zeros(41)], axis=1)
    ring, ring_yaw = circle((2.0, -1.0), 1.0, math.pi / 2, -2.2 * math.pi, 441)
    xy, yaw = np.concatenate([lead, ring]), np.concatenate([np.zeros(41), ring_yaw])
    fired = first_fire(lap, xy, yaw)
    assert fired is not None
    # the lead's samples (every 0.05 m, those beyond 0.8 m of the origin) lie on y = 0, and the
    # ring point a rad short of its top is 1 - cos(a) below that line: within 0.4 m of a sample
    # once cos(a) > 0.6 (to half a sample spacing), after 2 pi - acos(0.6) of turn
    turned = (fired - 41) / 440 * 2.2 * math.pi
    assert turned == pytest.approx(2 * math.pi - math.acos(0.6), abs=0.04)


def test_a_lap_back_to_where_following_began_is_left_to_the_loop_detector() -> None:
    lap = OtherBoundaryLap(radius=0.4, min_length=1.6)
    xy, yaw = circle((0.0, -1.0), 1.0, math.pi / 2, -2.5 * math.pi, 501)
    lap.arm(xy[0], yaw[0], RIGHT)
    # every sample within 0.8 m of the origin is skipped: the first samples the ring comes
    # back to lie beyond them, reached only after 2 pi + 2 asin(0.4) - 2 asin(0.2) of turn
    fired = first_fire(lap, xy[1:], yaw[1:])
    assert fired is not None
    assert (fired + 1) / 500 * 2.5 * math.pi > 2 * math.pi + 0.4


@pytest.mark.parametrize("side", [LEFT, RIGHT])
def test_no_lap_of_another_boundary_without_a_net_turn_toward_the_followed_side(side: int) -> None:
    """Clockwise round a circle is a lap round an obstacle kept on the right (RIGHT), and round
    free space for a follower keeping its boundary on the left; going out and back is neither."""
    lap = OtherBoundaryLap(radius=0.4, min_length=1.6)
    lap.arm(np.zeros(2), 0.0, side)
    lead = np.stack([np.linspace(0.0, 2.0, 41), np.zeros(41)], axis=1)
    ring, ring_yaw = circle((2.0, -1.0), 1.0, math.pi / 2, -2.2 * math.pi, 441)
    fired = first_fire(lap, np.concatenate([lead, ring]), np.concatenate([np.zeros(41), ring_yaw]))
    assert (fired is not None) == (side == RIGHT)
    lap.arm(np.zeros(2), 0.0, side)
    out = np.stack([np.linspace(0.0, 3.0, 61), np.zeros(61)], axis=1)
    back = out[::-1]
    assert first_fire(lap, np.concatenate([out, back]),
                      np.concatenate([np.zeros(61), np.full(61, math.pi)])) is None


@pytest.mark.slow
def test_leaves_the_box_it_drifted_onto_in_the_congested_world() -> None:
    """Issue 12 (``congested``, seed 0): the follower began on a long box, came down into the
    0.6 m gap beside a smaller box and lapped that one with ``d_followed`` left over from the
    long box (6.4 m: the small box never offers it), so it never left and timed out at 300 s
    (main, 2 re-plans). A lap of another boundary now restarts following there, and the robot
    leaves that box and reaches the goal."""
    from nav_bench.episode.loop import run_episode
    from nav_bench.specs import PlannerSetSpec
    from nav_bench.world.load import load_world

    world = load_world(Path(__file__).resolve().parents[2] / "worlds" / "paper" / "congested.yaml")
    result = run_episode(world, PlannerSetSpec(planner="tangent_bug"), seed=0)
    assert result.row.outcome == "reached", result.row
    assert result.row.collisions == 0
    assert result.row.time_s < 150.0


# ----------------------------------------------------------------------------- issue 16: cost
def test_binned_range_function_equals_the_full_one_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    for n in (8, 13, 120, 360):
        bins = range_bins(n)
        for n_pts in (0, 1, 7, 300):
            xy = rng.uniform(-20.0, 20.0, size=2)
            pts = rng.uniform(-3.0, 3.0, size=(n_pts, 2))
            pts[: n_pts // 4] *= 1e-3  # 1 mm to 4 mm away: each blocks half the circle
            # bearings on the bins and across the -pi/pi cut, where the remainder wraps
            b = np.concatenate([bins[rng.integers(0, n, n_pts // 4)],
                                math.pi + rng.normal(0, 1e-3, n_pts // 4)])
            pts[n_pts // 4: n_pts // 4 + len(b)] = rng.uniform(0.1, 3.0, (len(b), 1)) * np.stack(
                [np.cos(b), np.sin(b)], axis=1)
            for grow in (0.0, 0.28, 0.33, 0.5):
                full = range_function(pts + xy, xy, grow, bins)
                np.testing.assert_array_equal(binned_range_function(pts + xy, xy, grow, bins), full)
    # a point exactly behind (bearing pi), one just past the cut, one whose disc ends on a bin
    bins = range_bins(120)
    pts = np.array([[-2.0, 0.0], [-2.0, -1e-12], [0.5, 0.28], [1.0, 0.0]])
    for grow in (0.28, math.sin(2 * math.pi / 120)):
        np.testing.assert_array_equal(binned_range_function(pts, np.zeros(2), grow, bins),
                                      range_function(pts, np.zeros(2), grow, bins))


class PlainEchoMemory:
    """EchoMemory as it was before issue 16: concatenate, mask by time, keep the last capacity."""

    def __init__(self, horizon: float, capacity: int = 4000) -> None:
        self.horizon, self.capacity = horizon, capacity
        self.xy, self.t = np.zeros((0, 2)), np.zeros(0)

    def add(self, obs: Observation) -> None:
        pts = world_echoes(obs)
        xy = np.concatenate([self.xy, pts])
        t = np.concatenate([self.t, np.full(len(pts), obs.t)])
        keep = t >= obs.t - self.horizon
        self.xy, self.t = xy[keep][-self.capacity:], t[keep][-self.capacity:]


@pytest.mark.parametrize(("horizon", "capacity"), [(8.0, 4000), (1.0, 4000), (0.0, 4000), (math.inf, 4000),
                                                   (2.0, 7), (2.0, 3), (2.0, 0), (-1.0, 4000)])
def test_echo_memory_keeps_the_points_the_plain_one_keeps(horizon: float, capacity: int) -> None:
    """Same points in the same order after every cycle, also when time stands still, goes back
    (the memory is rebuilt) or the capacity is below a cycle's echoes."""
    robot = default_robot()
    rng = np.random.default_rng(7)
    memory, plain = EchoMemory(horizon, capacity), PlainEchoMemory(horizon, capacity)
    t = 0.0
    for i in range(400):
        t = t - 1.5 if i % 97 == 50 else (t if i % 31 == 0 else t + 0.1)
        ranges = np.where(rng.random(6) < 0.3, robot.sonar.max_range, rng.uniform(0.05, 3.0, 6))
        obs = Observation(t=t, pose=rng.uniform(-3.0, 3.0, 3), goal=np.zeros(2), ranges=ranges, robot=robot,
                          bounds=(-5.0, -5.0, 5.0, 5.0), dt=0.1)
        memory.add(obs)
        plain.add(obs)
        assert len(memory) == len(plain.xy)
        np.testing.assert_array_equal(memory.points(), plain.xy)
        c = rng.uniform(-3.0, 3.0, 2)
        near = np.hypot(plain.xy[:, 0] - c[0], plain.xy[:, 1] - c[1]) <= 2.0
        np.testing.assert_array_equal(memory.points(c, 2.0), plain.xy[near])


def replay_commands(name: str, planner: Planner) -> tuple[np.ndarray, np.ndarray]:
    """Feed the observations recorded in ``tests/data/planner_replay/<name>.npz`` to
    ``planner``; its commands (N, 2) and the recorded ones. The files are real PyBullet
    episodes (seed 0) written by ``benchmarks/bench_tangent_bug.py --record``; the DWA one with
    main's code at f4bd289, before issue 16's speed-ups; the TangentBug and Bug2 ones again
    whenever issue 12's wall follower changed their commands (s6follow, then the seventh
    session's narrow-passage mode, which changed the TangentBug labyrinth and 40 m clutter
    ones), and the four TangentBug ones when the blocking obstacle's interval came to end where
    the range function jumps (s12tb: the very_complex one no longer ends unreachable), and the
    TangentBug concave_trap and labyrinth ones and the Bug2 one when the follower's dead band
    came to turn at least at ``band_turn_rate`` (follow_s16: one command each): ``--record DIR
    --planners tangent_bug --worlds clutter_40m,concave_trap,labyrinth,very_complex --time-s
    60`` and ``--planners bug2 --worlds very_complex --time-s 40``)."""
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


@pytest.mark.parametrize("name", ["tangent_bug_clutter_40m_60s", "tangent_bug_concave_trap_60s",
                                  "tangent_bug_labyrinth_60s", "tangent_bug_very_complex_60s",
                                  "bug2_very_complex_40s", "dwa_clutter_40m_20s"])
def test_replayed_episode_gives_the_recorded_commands(name: str) -> None:
    """The per-cycle polar view, the binned range function, no endpoints while following and
    the buffered echo memory change no command of a recorded episode: TangentBug's cover
    motion to goal with the goal blocked (185 cycles of the binned range function), boundary
    following (8 switches to it) and back, with memories of 400-460 echoes at the end; Bug2 and
    DWA share the echo memory."""
    kind = next(k for k in ("tangent_bug", "bug2", "dwa") if name.startswith(k))
    planner = {"tangent_bug": TangentBug, "bug2": Bug2, "dwa": DWA}[kind]()
    got, want = replay_commands(name, planner)
    assert got.shape == want.shape
    # equal on the machine that recorded them; NumPy picks its SIMD kernels by CPU (AVX-512 or
    # not), and their results differ in the last bit (1e-15 here), while a changed decision
    # moves a command by far more than 1e-9
    np.testing.assert_allclose(got, want, rtol=0.0, atol=1e-9)
