"""D* Lite's follower: exact-geometry clearance, the guard through gaps, carving the grid's
phantom cells with the sonar readings, progress while creeping, a back-up that stops at the map.

Runtime: ~3 s.
"""

from __future__ import annotations

import math

import numpy as np

from nav_bench.interface import Command, Observation
from nav_bench.planners.dstar_lite import DStarLite, clearance_costs, obstacle_distance
from nav_bench.planners.footprint import (
    CARVE_SUB,
    GuardSettings,
    PointObstacles,
    SquareClearance,
    carve,
    cell_parts,
    echo_arcs,
    echo_blocks,
    guard,
    is_safe,
    rollout,
    seen_through,
    seen_through_cells,
)
from nav_bench.planners.recovery import ProgressWatch, Recovery, RecoveryPhase, RecoverySettings
from nav_bench.testing.harness import BoxWorld, default_robot, run

NO_ECHO = np.full(6, 3.0)


def observation(pose: tuple[float, float, float], ranges: np.ndarray = NO_ECHO, t: float = 0.0,
                goal: tuple[float, float] = (9.0, 1.0), radius: float = 0.2) -> Observation:
    return Observation(t=t, pose=np.array(pose, dtype=float), goal=np.array(goal), ranges=ranges,
                       robot=default_robot(radius=radius), bounds=(0.0, 0.0, 10.0, 2.0), dt=0.1)


# --------------------------------------------------------------------------- exact geometry
def test_clearance_is_the_distance_to_the_occupied_cells_squares() -> None:
    occ = np.zeros((10, 10), dtype=bool)
    occ[5, 5] = True  # the square [0.5, 0.6] x [0.5, 0.6]
    sq = SquareClearance(occ, 0.0, 0.0, 0.1, 1.0)
    pts = np.array([[0.55, 0.3], [0.3, 0.55], [0.3, 0.3], [0.55, 0.55], [0.6, 0.8], [-0.1, 0.5]])
    expected = [0.2, 0.2, math.hypot(0.2, 0.2), 0.0, 0.2, 0.0]  # inside the square: 0; outside the grid: 0
    np.testing.assert_allclose(sq(pts), expected, atol=1e-12)
    # the same with the small squares a cell is checked as (discs round them: <= 0.6 cm short)
    parts = PointObstacles(cell_parts(np.array([[0.55, 0.55]]), 0.1).reshape(-1, 2), 0.1 / (2 * CARVE_SUB),
                           1.0, (0.0, 0.0, 1.0, 1.0))
    got = parts(pts[:3])
    assert np.all(got <= np.array(expected[:3]) + 1e-12) and np.all(got >= np.array(expected[:3]) - 0.006)


def test_a_gap_of_four_free_cells_is_inscribed_and_one_of_five_is_not() -> None:
    # the search's costs go by distances between cell centres (the planner's map updates lower
    # them by a patch per new obstacle cell): with the default robot (0.18 m) + passage_margin
    # (0.02 m) = 2 cells, the middle of a gap of four free cells (0.4 m on the grid) is inscribed,
    # of five (0.5 m) is not. The grid narrows a true 0.55-0.6 m gap to four or five free
    # cells; the guard, which measures exactly, passes the robot either way once it is there.
    def gap(free: int) -> np.ndarray:
        occ = np.zeros((3, 14), dtype=bool)
        occ[:, [0, free + 1]] = True
        return obstacle_distance(occ, 9.0)

    np.testing.assert_allclose(gap(4)[1, :6], [0, 1, 2, 2, 1, 0])
    np.testing.assert_allclose(gap(5)[1, :7], [0, 1, 2, 3, 2, 1, 0])
    inscribed = (0.18 + 0.02) / 0.1
    assert clearance_costs(gap(4), inscribed, 3.5, 1000.0, 5.0)[1, 2] == 1000.0
    assert clearance_costs(gap(5), inscribed, 3.5, 1000.0, 5.0)[1, 3] < 5.0


# --------------------------------------------------------------------------- the guard in a gap
def gap_map(width: float) -> SquareClearance:
    """A wall across x = 1.00..1.10 m, 1 cm cells, with a gap of ``width`` m centred on y = 1
    (only the wall's 1 cm cells near the gap: the guard never looks farther)."""
    cell = 0.01
    occ = np.zeros((200, 300), dtype=bool)
    ys = (np.arange(200) + 0.5) * cell
    occ[np.abs(ys - 1.0) > width / 2, 100:110] = True
    occ[np.abs(ys - 1.0) > width / 2 + 0.05, 100:110] = False  # the wall's edge is all that counts
    return SquareClearance(occ, 0.0, 0.0, cell, 0.45)


def drive_at_the_gap(width: float, steps: int = 200) -> tuple[np.ndarray, float]:
    """The guard alone, fed straight-ahead commands from (0.5, 1.0) toward x = 2: the final pose
    and the least clearance (m) on the way, checked every 0.5 cm."""
    robot_r = 0.2
    clear = gap_map(width)
    settings = GuardSettings(required=robot_r + 0.02, cruise_extra=0.04, squeeze_speed=0.1, v_max=0.4,
                             slow_distance=0.1, floor=robot_r + 0.01)
    pose = np.array([0.5, 1.0, 0.0])
    least = math.inf
    for _ in range(steps):
        obs = observation(tuple(pose), radius=robot_r)
        out = guard(obs, Command(0.4, 0.0), 0.0, clear, settings, target=np.array([2.0, 1.0])).command
        path = rollout(pose, out.v, out.omega, 0.1, 20)
        least = min(least, float(clear(path).min()))
        pose = np.array([*path[-1], pose[2] + out.omega * 0.1])
    return pose, least


def test_the_guard_passes_a_gap_5_cm_wider_than_the_robot_and_stops_before_one_2_cm_narrower() -> None:
    pose, least = drive_at_the_gap(0.45)  # diameter 0.40 m + 5 cm
    assert pose[0] > 1.4  # through
    assert least >= 0.2 + 0.02 - 0.003  # the squeeze margin kept, to the exact wall
    pose, least = drive_at_the_gap(0.38)  # 2 cm narrower than the robot
    assert pose[0] < 1.0 - 0.2 and least > 0.2  # stopped in front, never touching


def test_a_robot_inside_its_margin_may_arc_away_but_not_ratchet_closer() -> None:
    # is_safe: below the required clearance a rollout may dip toward the floor on the way if it
    # ends no nearer than now; it may never end nearer (commands that each lose a little would
    # walk the robot onto the corner)
    assert is_safe(0.21, np.array([0.215, 0.23]), 0.22, floor=0.205)
    assert is_safe(0.21, np.array([0.206, 0.212]), 0.22, floor=0.205)
    assert not is_safe(0.21, np.array([0.206, 0.205]), 0.22, floor=0.205)  # ends nearer
    assert not is_safe(0.21, np.array([0.20, 0.25]), 0.22, floor=0.205)  # dips below the floor
    assert is_safe(0.19, np.array([0.19, 0.21]), 0.22, floor=0.205)  # below the floor: no nearer
    assert not is_safe(0.19, np.array([0.185, 0.21]), 0.22, floor=0.205)


def test_the_guard_turns_to_a_heading_it_can_leave_a_corner_by() -> None:
    # the robot stands with an occupied cell just ahead-right of its edge and its target straight
    # ahead beyond it: every forward arc from its heading brushes the cell, so it turns on the
    # spot (away, toward the free side) and then drives
    occ = np.zeros((100, 100), dtype=bool)
    occ[45:50, 62:67] = True  # x 0.62..0.67, y 0.45..0.50
    clear = SquareClearance(occ, 0.0, 0.0, 0.01, 0.6)
    settings = GuardSettings(required=0.22, floor=0.21, squeeze_speed=0.1, v_max=0.4)
    obs = observation((0.45, 0.62, 0.0), radius=0.2)
    assert clear(np.array([[0.45, 0.62]]))[0] < 0.22
    out = guard(obs, Command(0.4, 0.0), 0.0, clear, settings, target=np.array([1.2, 0.62]))
    assert out.command.v == 0.0 and out.command.omega > 0.0  # turn left, away from the cell


# --------------------------------------------------------------------------- echoes
def test_an_echo_arc_blocks_only_when_all_of_it_is_in_the_way() -> None:
    robot = default_robot()
    ranges = NO_ECHO.copy()
    ranges[2] = ranges[3] = 0.15  # the +-15 deg sonars echo 0.15 m ahead of the rim: a wall
    obs = observation((0.0, 0.0, 0.0), ranges)
    assert echo_blocks(obs, 0.4, 0.0, 1.0) and echo_blocks(obs, 0.1, 0.0, 1.5)
    ranges = NO_ECHO.copy()
    ranges[5] = 0.05  # the 90 deg sonar: something at its rim, beside the robot's path
    assert not echo_blocks(observation((0.0, 0.0, 0.0), ranges), 0.4, 0.0, 1.0)
    assert echo_arcs(obs).shape == (2, 7, 2)
    assert robot.radius == 0.2



def full_echo_test(obs: Observation, v: float, omega: float, horizon: float, steps: int, yaw: float) -> bool:
    """echo_blocks without its early rejection: every arc point against every rollout point."""
    arcs = echo_arcs(obs)
    if v == 0.0 or len(arcs) == 0:
        return False
    path = rollout(np.array([0.0, 0.0, yaw]), v, omega, horizon, steps)
    pts = arcs.reshape(-1, 2)
    d_now = np.hypot(pts[:, 0], pts[:, 1])
    d_along = np.hypot(pts[:, None, 0] - path[None, :, 0], pts[:, None, 1] - path[None, :, 1]).min(axis=1)
    hit = (d_along < obs.robot.radius + 0.02) & (d_along < d_now - 0.005)
    return bool(np.any(hit.reshape(arcs.shape[:2]).all(axis=1)))


def test_echo_blocks_rejects_far_echoes_early_with_the_full_tests_answers() -> None:
    """The early return (no arc wholly within the rollout's reach) answers as the full test,
    on 3,000 random echoes, speeds, turn rates and initial turns (both answers plentiful)."""
    rng = np.random.default_rng(5)
    answers = []
    for _ in range(3000):
        ranges = rng.uniform(0.0, 1.2, 6)
        ranges[rng.random(6) < 0.3] = 3.0  # no echo
        obs = observation((rng.uniform(0, 5), rng.uniform(0, 2), rng.uniform(-4, 4)), ranges)
        v = float(rng.choice([0.0, 0.05, 0.1, 0.4, -0.1]))
        omega, yaw = float(rng.uniform(-2, 2)), float(rng.choice([0.0, rng.uniform(-2, 2)]))
        horizon, steps = float(rng.uniform(0.5, 1.5)), int(rng.integers(2, 25))
        answer = echo_blocks(obs, v, omega, horizon, steps, yaw=yaw)
        assert answer == full_echo_test(obs, v, omega, horizon, steps, yaw)
        answers.append(answer)
    assert 100 < sum(answers) < 2900


# --------------------------------------------------------------------------- carving
def test_cells_a_reading_saw_through_are_carved_away() -> None:
    robot = default_robot()
    # the 15 deg sonar (mount ~(0.19, 0.05)) reads 1.0 m: a cell on its axis 0.5 m out is free,
    # one at 1.0 m holds the echo, one outside its cone is not seen
    ranges = NO_ECHO.copy()
    ranges[:] = 0.05  # every other sonar: an echo at its rim, sees nothing farther
    ranges[3] = 1.0
    mount = robot.sonar.offsets[3]
    axis = np.array([math.cos(math.radians(15)), math.sin(math.radians(15))])
    cells = np.array([mount + 0.5 * axis, mount + 1.0 * axis, mount + 0.5 * np.array([0.0, 1.0])])
    pose = np.zeros(3)
    kept = carve(cells, 0.1, [(pose, ranges)], robot.sonar)
    owner = np.argmin(np.hypot(kept[:, None, 0] - cells[None, :, 0], kept[:, None, 1] - cells[None, :, 1]), axis=1)
    counts = np.bincount(owner, minlength=3)
    assert counts[0] == 0  # seen through
    assert counts[1] == CARVE_SUB ** 2 or counts[1] > 0  # the echo is in it
    assert counts[2] == CARVE_SUB ** 2  # outside every cone
    # the body: a cell under the robot is free
    under = seen_through(np.array([[0.05, 0.0], [0.5, 0.5]]), 0.02, [(pose, ranges)], robot.sonar, body=0.2)
    assert under.tolist() == [True, False]


def test_the_planner_carves_a_cell_seen_through_from_two_views_and_forgets_it_when_freed() -> None:
    planner = DStarLite()

    def obs_at(x: float, t: float) -> Observation:
        return Observation(t=t, pose=np.array([x, 1.0, 0.0]), goal=np.array([3.5, 1.0]), ranges=NO_ECHO,
                           robot=default_robot(), bounds=(0.0, 0.0, 4.0, 2.0), dt=0.1)

    planner.reset(obs_at(1.0, 0.0), np.random.default_rng(0))
    planner.occupied[11, 15] = True  # a phantom cell (1.55, 1.15) on the 15 deg sonar's axis
    assert len(planner._local_clearance(obs_at(1.0, 0.1)).centres) == CARVE_SUB ** 2  # one view: kept
    assert len(planner._local_clearance(obs_at(1.0, 0.2)).centres) == CARVE_SUB ** 2  # the same view
    assert len(planner._local_clearance(obs_at(1.05, 0.3)).centres) == 0  # a second view: carved
    assert np.isfinite(planner._carving.carved_t[11, 15]).all()
    planner.occupied[11, 15] = False  # the grid frees it: the carving is forgotten
    planner._local_clearance(obs_at(1.05, 0.4))
    assert np.all(planner._carving.carved_t[11, 15] == -np.inf)
    planner.occupied[11, 15] = True
    assert len(planner._local_clearance(obs_at(1.05, 0.5)).centres) == CARVE_SUB ** 2


def test_seen_through_cells_equals_the_test_of_every_part() -> None:
    """The cell-level skip never drops a part the per-part test passes, and testing a cell only
    against the sonars that may see through it gives every part's value bit for bit (2,000
    random readings and cell sets, echoes, no echoes, cells under and behind the robot)."""
    robot = default_robot()
    rng = np.random.default_rng(3)
    seen = 0
    for _ in range(2000):
        pose = np.array([rng.uniform(1.0, 2.0), rng.uniform(1.0, 2.0), rng.uniform(-4.0, 4.0)])
        ranges = rng.uniform(0.05, 3.5, 6)
        ranges[rng.random(6) < 0.2] = np.inf
        cells = np.floor(rng.uniform(0.0, 3.0, (int(rng.integers(1, 60)), 2)) / 0.1) * 0.1 + 0.05
        fast = seen_through_cells(cells, 0.1, pose, ranges, robot.sonar)
        every = seen_through(cell_parts(cells, 0.1).reshape(-1, 2), 0.1 / CARVE_SUB, [(pose, ranges)],
                             robot.sonar).reshape(len(cells), -1)
        assert np.array_equal(fast, every)
        seen += int(every.sum())
    assert seen > 10000  # the test sees plenty of parts seen through


def test_sonar_mounts_are_the_pose_transform_of_the_offsets_bit_for_bit() -> None:
    """_Mounts.of (one (2, S) array) gives x + cos(yaw) ox - sin(yaw) oy and
    y + sin(yaw) ox + cos(yaw) oy exactly as written per sonar, and caps the ranges."""
    from nav_bench.planners.footprint import _Mounts

    sonar = default_robot().sonar
    rng = np.random.default_rng(5)
    for _ in range(500):
        x, y, yaw = rng.uniform(-50.0, 50.0), rng.uniform(-50.0, 50.0), rng.uniform(-9.0, 9.0)
        ranges = rng.uniform(0.0, 4.0, 6)
        ranges[rng.random(6) < 0.3] = np.inf
        mounts = _Mounts.of(np.array([x, y, yaw]), ranges, sonar)
        c, s = math.cos(yaw), math.sin(yaw)
        for k, (ox, oy) in enumerate(sonar.offsets.tolist()):
            assert mounts.mx[k] == x + c * ox - s * oy
            assert mounts.my[k] == y + s * ox + c * oy
            assert mounts.r[k] == min(ranges[k], sonar.max_range)


def test_point_obstacles_match_a_k_d_tree_bit_for_bit() -> None:
    """Distances computed point by point equal a k-d tree's exactly, at the bound too."""
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(1)
    for k in range(1000):
        centres = rng.uniform(0.0, 3.0, (int(rng.integers(1, 700)), 2))
        obstacles = PointObstacles(centres, 0.01, 0.44, (0.0, 0.0, 3.0, 3.0))
        bound = 0.44 + obstacles.radius
        if k % 2:
            q = rng.uniform(-0.2, 3.2, (int(rng.integers(1, 40)), 2))
        else:  # points at the bound from a centre
            a = rng.uniform(0.0, 2 * math.pi, int(rng.integers(1, 40)))
            q = centres[int(rng.integers(0, len(centres)))] + bound * np.stack([np.cos(a), np.sin(a)], axis=1)
        d = cKDTree(centres).query(q, distance_upper_bound=bound)[0]
        inside = (q[:, 0] >= 0.0) & (q[:, 0] < 3.0) & (q[:, 1] >= 0.0) & (q[:, 1] < 3.0)
        expected = np.where(inside, np.minimum(np.maximum(d - obstacles.radius, 0.0), 0.44), 0.0)
        assert np.array_equal(obstacles(q), expected)
    many = rng.uniform(0.0, 3.0, (300, 2))  # a query too large for point by point: the tree
    big = PointObstacles(centres, 0.01, 0.44, (0.0, 0.0, 3.0, 3.0))
    assert np.array_equal(big(many), np.concatenate([big(many[i:i + 20]) for i in range(0, 300, 20)]))
    assert big(np.zeros((0, 2))).shape == (0,)


def test_point_obstacles_answer_one_point_as_part_of_a_batch() -> None:
    """The one-point query (the guard's clearance of the robot) equals the batch's value bit
    for bit: near, at the bound, beyond it, outside the bounds, on a centre."""
    rng = np.random.default_rng(2)
    for _ in range(300):
        centres = rng.uniform(0.0, 3.0, (int(rng.integers(1, 700)), 2))
        obstacles = PointObstacles(centres, 0.01, 0.44, (0.0, 0.0, 3.0, 3.0))
        a = rng.uniform(0.0, 2 * math.pi, 10)
        at_bound = centres[0] + (0.44 + obstacles.radius) * np.stack([np.cos(a), np.sin(a)], axis=1)
        q = np.concatenate([rng.uniform(-0.2, 3.2, (20, 2)), at_bound, centres[:3]])
        batch = obstacles(q)
        one = np.concatenate([obstacles(q[i:i + 1]) for i in range(len(q))])
        assert one.dtype == batch.dtype and np.array_equal(one, batch)
    assert PointObstacles(np.zeros((0, 2)), 0.01, 0.44, (0.0, 0.0, 3.0, 3.0))(np.array([[1.0, 1.0]]))[0] == 0.44


# --------------------------------------------------------------------------- progress and recovery
def test_a_straight_creep_counts_as_progress_but_rocking_does_not() -> None:
    s = RecoverySettings(after_s=6.0, progress_m=0.3)
    for speed, rocking, stalled in ((0.04, False, False), (0.3, True, True)):
        watch = ProgressWatch(s)
        x = 1.0
        for i in range(100):  # 10 s
            t = 0.1 * i
            if rocking:
                x = 1.0 + 0.1 * math.sin(t * 3.0)
            else:
                x += speed * 0.1
            ranges = np.full(6, 3.0)
            watch.update(Observation(t=t, pose=np.array([x, 1.0, 0.0]), goal=np.array([9.0, 9.0]),
                                     ranges=ranges, robot=default_robot(), bounds=(0, 0, 10, 10), dt=0.1))
        assert (watch.stalled_for(9.9) >= 6.0) == stalled, (speed, rocking)


def test_the_watch_measures_travel_and_progress_as_array_arithmetic_does() -> None:
    """The watch's Python-float bookkeeping gives the same numbers as float64 arrays: the travel
    is the sum of np.hypot of the odometry steps, the best goal distance np.hypot of goal - xy."""
    watch = ProgressWatch(RecoverySettings(progress_m=10.0))  # no progress: travel accumulates
    rng = np.random.default_rng(7)
    xy = np.array([1.0, 1.0])
    goal = np.array([9.0, 1.3])
    watch.restart(Observation(t=0.0, pose=np.array([*xy, 0.0]), goal=goal, ranges=NO_ECHO,
                              robot=default_robot(), bounds=(0, 0, 10, 10), dt=0.1))
    travel, best = 0.0, float(np.hypot(*(goal - xy)))
    for i in range(1, 60):
        step = rng.uniform(-0.03, 0.03, 2)
        new = xy + step
        travel += float(np.hypot(*(new - xy)))
        xy = new
        watch.update(Observation(t=0.1 * i, pose=np.array([*xy, 0.3]), goal=goal, ranges=NO_ECHO,
                                 robot=default_robot(), bounds=(0, 0, 10, 10), dt=0.1))
    assert watch.travel == travel
    assert watch.best_goal == best


def test_the_back_up_stops_before_an_occupied_cell_behind_the_robot() -> None:
    occ = np.zeros((100, 100), dtype=bool)
    occ[40:60, 30:32] = True  # a wall at x = 0.30..0.32 m (1 cm cells), behind the robot
    clear = SquareClearance(occ, 0.0, 0.0, 0.01, 0.6)
    rec = Recovery(RecoverySettings(backup_m=0.5))
    pose = np.array([0.65, 0.5, 0.0])
    obs = observation(tuple(pose))
    rec.start(obs)
    for i in range(80):
        obs = observation(tuple(pose), t=0.1 * i)
        cmd = rec.step(obs, clear, 0.22)
        if rec.phase is not RecoveryPhase.BACKUP:
            break
        pose = pose + np.array([cmd.v * 0.1, 0.0, 0.0])
    assert rec.phase is RecoveryPhase.ROTATE
    assert clear(pose[None, :2])[0] >= 0.22 - 0.003  # never backed into the wall's margin


# --------------------------------------------------------------------------- in the harness
def test_squeezes_through_a_door_in_the_harness() -> None:
    # a wall across the room with one 0.62 m door (the 0.4 m robot + 0.22 m): the grid's cells
    # stand proud of the jambs and narrow it; the carved guard takes the robot through
    wall = [(2.0, 0.0, 2.1, 1.19), (2.0, 1.81, 2.1, 3.0)]
    world = BoxWorld.room((4.0, 3.0), wall)
    result = run(DStarLite(), world, (0.8, 1.5, 0.0), (3.3, 1.5), time_s=60.0, noise_std=0.01)
    assert result.reached and result.collisions == 0
