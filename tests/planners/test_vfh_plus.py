"""VFH+: hand-computed histograms, the turning mask, valley choice, and driving.

Runtime: ~1 s.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from nav_bench.interface import GridState, StuckReason
from nav_bench.mapping.grid import GridFrame
from nav_bench.planners.vfh_plus import (
    AREA_SHARE_BEYOND_M,
    ActiveWindow,
    VFHPlus,
    active_cells,
    binary_histogram,
    candidate_directions,
    certainty_from_occupancy,
    choose_direction,
    masked_histogram,
    near_sectors,
    polar_histogram,
    relax_factors,
    roll_arc,
    select_direction,
    turning_limits,
    window_histogram,
)
from nav_bench.testing.harness import (
    BoxWorld,
    default_robot,
    observe,
    open_room,
    run,
    u_world,
    wall_world,
)

N = 72  # 5 deg sectors


def test_polar_histogram_of_two_cells_by_hand() -> None:
    cells = np.array([[1.0, 0.0], [0.0, 0.5]])  # 1 m ahead (c = 15), 0.5 m to the left (c = 3)
    hist = polar_histogram(cells, np.array([15.0, 3.0]), np.zeros(2), N, r_rs=0.3, d_max=1.6, b=4.0)
    # cell 1: m = 15^2 (1 + 4 (1.6^2 - 1^2)) = 225 * 7.24; gamma = asin(0.3) = 17.46 deg -> sectors -3..3
    m1 = 225.0 * (1.0 + 4.0 * (1.6 ** 2 - 1.0))
    # cell 2: m = 3^2 (1 + 4 (1.6^2 - 0.5^2)) = 9 * 10.24; gamma = asin(0.6) = 36.87 deg
    # around 90 deg -> sectors 55..125 deg = 11..25
    m2 = 9.0 * (1.0 + 4.0 * (1.6 ** 2 - 0.5 ** 2))
    expected = np.zeros(N)
    expected[[69, 70, 71, 0, 1, 2, 3]] = m1
    expected[11:26] = m2
    np.testing.assert_allclose(hist, expected)
    assert m1 == pytest.approx(1629.0) and m2 == pytest.approx(92.16)


def dense_polar_histogram(cells_xy: np.ndarray, certainty: np.ndarray, xy: np.ndarray, n: int,
                          r_rs: float, d_max: float, b: float) -> np.ndarray:
    """H^p testing every cell against every sector (the formulation before issue 16)."""
    d = cells_xy - xy
    dist = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-6)
    beta = np.arctan2(d[:, 1], d[:, 0])
    mag = certainty.astype(float) ** 2 * (1.0 + b * (d_max ** 2 - dist ** 2))
    gamma = np.arcsin(np.minimum(1.0, r_rs / dist))
    centres = np.arange(n) * (2 * math.pi / n)
    diff = np.abs(np.remainder(centres[:, None] - beta[None, :] + math.pi, 2 * math.pi) - math.pi)
    return np.where(diff <= gamma[None, :], mag[None, :], 0.0).sum(axis=1)


@pytest.mark.parametrize("n", [4, 36, 72, 360])
def test_polar_histogram_equals_every_sector_tested_bit_for_bit(n: int) -> None:
    # cells at every bearing (also on sector centres and at +-pi), from inside r_rs to the window's
    # edge: only the sectors near each cell are tested, with the same arithmetic and sums
    rng = np.random.default_rng(7)
    xy = np.array([2.03, 1.97])
    for size in (1, 7, 8, 9, 150, 400):
        angle = rng.uniform(-math.pi, math.pi, size)
        angle[: size // 3] = rng.integers(0, n, size // 3) * (2 * math.pi / n)
        dist = rng.uniform(0.05, 1.6, size)
        cells = xy + dist[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)
        cert = rng.uniform(0.0, 15.0, size)
        np.testing.assert_array_equal(polar_histogram(cells, cert, xy, n, 0.23, 1.6, 4.0),
                                      dense_polar_histogram(cells, cert, xy, n, 0.23, 1.6, 4.0))


def test_binary_histogram_hysteresis() -> None:
    prev = np.array([False, True, False, True])
    h = binary_histogram(np.array([50.0, 50.0, 300.0, 5.0]), prev, low=20.0, high=100.0)
    assert h.tolist() == [False, True, True, False]  # between thresholds: keep the old value


def test_turning_circle_masks_directions_beyond_a_blocking_cell() -> None:
    # moving at v with omega_max such that r = 0.5 m; a cell 0.3 m ahead, 0.6 m to the right:
    # 0.32 m from the right circle's centre (0, -0.5) < r + r_rs = 0.8 -> blocks the right side
    cells, cert = np.array([[0.3, -0.6]]), np.array([10.0])
    phi_r, phi_l = turning_limits(cells, cert, np.zeros(3), 0.5, 0.3, mask_certainty=3.0)
    assert phi_r == pytest.approx(math.atan2(-0.6, 0.3)) and phi_l == pytest.approx(math.pi)
    masked = masked_histogram(np.zeros(N, dtype=bool), 0.0, phi_r, phi_l)
    angles = np.remainder(np.arange(N) * 5.0 + 180.0, 360.0) - 180.0  # sector centres, deg
    assert not masked[(angles > -63.0) & (angles < 180.0)].any()
    assert masked[(angles < -63.5)].all()
    # standing still (r = 0) nothing is masked
    assert turning_limits(cells, cert, np.zeros(3), 0.0, 0.3, 3.0) == (-math.pi, math.pi)


def _turning_limits_of_every_cell(cells, cert, pose, radius_turn, r_rs, mask_certainty):
    """The turning limits with every strong cell's relative bearing worked out (the formula
    before only the cells within a circle were)."""
    if radius_turn <= 0:
        return -math.pi, math.pi
    x, y, th = pose
    s, c = math.sin(th), math.cos(th)
    strong = cert > mask_certainty
    px, py = cells[strong, 0], cells[strong, 1]
    rel = np.remainder(np.arctan2(py - y, px - x) - th + math.pi, 2 * math.pi) - math.pi
    reach2 = (radius_turn + r_rs) ** 2
    block_r = (rel < 0) & ((px - (x + radius_turn * s)) ** 2 + (py - (y - radius_turn * c)) ** 2 < reach2)
    block_l = (rel > 0) & ((px - (x - radius_turn * s)) ** 2 + (py - (y + radius_turn * c)) ** 2 < reach2)
    return (float(rel[block_r].max()) if block_r.any() else -math.pi,
            float(rel[block_l].min()) if block_l.any() else math.pi)


def test_turning_limits_equal_the_formula_over_every_cell_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    blocked = 0
    for _ in range(300):
        pose = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-math.pi, math.pi)])
        cells = pose[:2] + rng.uniform(-1.6, 1.6, (int(rng.integers(0, 40)), 2))
        cert = rng.uniform(0.0, 15.0, len(cells))
        radius_turn = float(rng.choice([0.0, 0.2, 0.4]))
        got = turning_limits(cells, cert, pose, radius_turn, 0.25, 3.0)
        assert got == _turning_limits_of_every_cell(cells, cert, pose, radius_turn, 0.25, 3.0)
        blocked += got != (-math.pi, math.pi)
    assert blocked > 50  # the draws do block the circles, not only leave them free


def test_valley_nearest_the_goal_direction_wins() -> None:
    masked = np.ones(N, dtype=bool)
    masked[10:41] = False   # a wide valley (31 sectors), 50..200 deg
    masked[50:56] = False   # a narrow valley (6 sectors), 250..275 deg
    cands = candidate_directions(masked, k_target=60.0, s_max=16)
    assert sorted(cands) == pytest.approx([18.0, 32.0, 52.5])  # wide: borders + s_max/2; narrow: centre
    # goal at 300 deg: the narrow valley (262.5 deg) is nearest to it
    assert choose_direction(cands, 60.0, 20.0, 20.0, N, (5.0, 0.0, 0.0)) == pytest.approx(52.5)
    assert choose_direction(cands, 60.0, 52.0, 52.0, N, (5.0, 2.0, 2.0)) == pytest.approx(52.5)
    # ...unless heading and previous choice (both at 100 deg) outweigh it:
    # cost(18) = 5*30 + 2*2 + 2*2 = 158 < cost(52.5) = 5*7.5 + 2*32.5 + 2*32.5 = 167.5
    assert choose_direction(cands, 60.0, 20.0, 20.0, N, (5.0, 2.0, 2.0)) == pytest.approx(18.0)
    # goal at 135 deg inside the wide valley: the goal direction itself is a candidate and wins
    cands = candidate_directions(masked, k_target=27.0, s_max=16)
    assert 27.0 in cands
    assert choose_direction(cands, 27.0, 50.0, 50.0, N, (5.0, 2.0, 2.0)) == pytest.approx(27.0)
    assert candidate_directions(np.ones(N, dtype=bool), 0.0, 16) == []
    assert candidate_directions(np.zeros(N, dtype=bool), 7.0, 16) == [7.0]


def walked_valleys(masked: np.ndarray, k_target: float, s_max: int) -> list[float]:
    """candidate_directions sector by sector (the formulation before issue 16)."""
    n = len(masked)
    if masked.all():
        return []
    if not masked.any():
        return [float(k_target) % n]
    start = int(np.flatnonzero(masked)[0])
    out: list[float] = []
    k = 0
    while k < n:
        if masked[(start + k) % n]:
            k += 1
            continue
        run_start = k
        while k < n and not masked[(start + k) % n]:
            k += 1
        k_r, width = start + run_start, k - run_start
        if width <= s_max:
            out.append((k_r + (width - 1) / 2) % n)
        else:
            c_r, c_l = k_r + s_max / 2, k_r + width - 1 - s_max / 2
            out += [c_r % n, c_l % n]
            t = (k_target - k_r) % n + k_r
            if c_r <= t <= c_l:
                out.append(t % n)
    return out


def test_valleys_equal_a_sector_by_sector_walk() -> None:
    rng = np.random.default_rng(11)
    for _ in range(300):
        masked = rng.random(N) < rng.uniform(0.0, 1.0)
        k_target = float(rng.uniform(0.0, N))
        assert candidate_directions(masked, k_target, 16) == walked_valleys(masked, k_target, 16)


def test_certainty_reads_only_evidence_of_occupancy() -> None:
    values = np.array([[0, 50, 75, 100]], dtype=np.uint8)
    np.testing.assert_allclose(certainty_from_occupancy(values, 15.0), [[0.0, 0.0, 7.5, 15.0]])


def test_active_window_is_the_whole_maps_cells_within_the_radius() -> None:
    # the window's square only, cells above 50 only: the same cells, order and numbers as
    # reading every cell of the map, also where the window leaves the grid
    rng = np.random.default_rng(3)
    frame = GridFrame.from_bounds((0.0, 0.0, 6.0, 5.0), 0.1)
    values = rng.integers(0, 101, frame.shape).astype(np.uint8)
    rows, cols = np.mgrid[0:frame.rows, 0:frame.cols]
    centres = frame.cell_center(rows, cols).reshape(-1, 2)
    cert = certainty_from_occupancy(values, 15.0).reshape(-1)
    for xy in ([3.02, 2.51], [0.04, 4.97], [5.9, 0.3], [-0.5, 2.0]):
        xy = np.array(xy)
        near = (np.hypot(*(centres - xy).T) <= 1.6) & (cert > 0)
        cells, got = active_cells(values, frame, xy, 1.6, 15.0)
        np.testing.assert_array_equal(cells, centres[near])
        np.testing.assert_array_equal(got, cert[near])


def test_histogram_from_a_hand_built_shared_grid() -> None:
    frame = GridFrame.from_bounds((0.0, 0.0, 4.0, 4.0), 0.1)
    values = np.full(frame.shape, 50, dtype=np.uint8)  # all unknown: certainty 0
    values[:, :20] = 0  # free
    values[20, 30] = 100  # cell centre (3.05, 2.05): 1 m along +x from the robot, c = 15
    values[25, 20] = 60  # cell centre (2.05, 2.55): 0.5 m to the left, c = 3
    values[20, 39] = 100  # (3.95, 2.05): outside the 1.6 m window
    xy = np.array([2.05, 2.05])
    cells, cert = active_cells(values, frame, xy, 1.6, 15.0)
    np.testing.assert_allclose(cells, [[3.05, 2.05], [2.05, 2.55]])
    np.testing.assert_allclose(cert, [15.0, 3.0])
    hist = polar_histogram(cells, cert, xy, N, r_rs=0.3, d_max=1.6, b=4.0)
    expected = np.zeros(N)  # as in the two-cell case by hand above
    expected[[69, 70, 71, 0, 1, 2, 3]] = 225.0 * (1.0 + 4.0 * (1.6 ** 2 - 1.0))
    expected[11:26] = 9.0 * (1.0 + 4.0 * (1.6 ** 2 - 0.5 ** 2))
    np.testing.assert_allclose(hist, expected)


def test_debug_state_is_the_shared_grid_and_no_valley_means_no_path() -> None:
    world, _start, goal = wall_world()
    planner = VFHPlus()
    robot = default_robot()
    obs = observe(world, np.array([3.0, 3.0, 0.0]), np.array(goal), robot, 0.0, 0.1)
    planner.reset(obs, np.random.default_rng(0))
    planner.act(obs)
    grids = GridState.from_state(planner.debug_state())
    assert grids is not None and grids.pmo.dtype == np.uint8 and grids.cell == pytest.approx(0.1)
    assert grids.pmo.max() > 50 and grids.pmo.min() < 50  # the wall ahead and the free cones
    assert planner.stuck_reason() is None
    planner.blocked = True  # what act() sets when every sector is blocked
    assert planner.stuck_reason() is StuckReason.NO_PATH


def test_first_observation_of_a_wall_peaks_straight_ahead() -> None:
    world, _start, goal = wall_world()
    planner = VFHPlus()
    robot = default_robot()
    obs = observe(world, np.array([3.0, 3.0, 0.0]), np.array(goal), robot, 0.0, 0.1)
    planner.reset(obs, np.random.default_rng(0))
    for _ in range(3):
        planner.act(obs)
    hist = planner.primary
    assert hist.argmax() in (0, 1, 71)
    assert hist[18] == 0.0 and hist[36] == 0.0  # nothing to the left or behind


def corridor_corner_grid() -> tuple[GridFrame, np.ndarray]:
    """A 3 x 3 m map (0.1 m cells) of a maze's dead-end corner as the sonar map draws it, walls
    two cells thick (a 1 m corridor narrowed to 0.8 m): the corridor y 0.2..1.0 runs from the
    left wall (x 0..0.2) to its dead end (x 2.0..2.2) under a ceiling (y 1.0..1.2, x 1.0..2.2)
    and opens upward at x 0.2..1.0. Every other cell is free."""
    frame = GridFrame.from_bounds((0.0, 0.0, 3.0, 3.0), 0.1)
    values = np.zeros(frame.shape, dtype=np.uint8)
    values[0:2, :22] = 100    # floor, y 0..0.2
    values[:, 0:2] = 100      # left wall, x 0..0.2
    values[10:12, 10:22] = 100  # the corridor's ceiling, y 1.0..1.2, x 1.0..2.2
    values[:12, 20:22] = 100  # its dead end, x 2.0..2.2
    return frame, values


def test_no_valley_at_the_thresholds_relaxes_them_toward_the_way_out() -> None:
    """Under the ceiling's corner (robot 0.15 m below it) every sector sums wall cells above
    threshold_high = 2500 although the corridor opens to the upper left: threshold_high x 2
    opens 100..110 deg and the robot takes its centre, 105 deg."""
    frame, values = corridor_corner_grid()
    p = VFHPlus().settings
    k_goal = math.degrees(math.atan2(3.0 - 0.85, 3.0 - 0.95)) / 5.0  # goal at (3, 3): 46.4 deg
    xy = np.array([0.95, 0.85])
    cells, cert = active_cells(values, frame, xy, 1.6, 15.0)
    hist = polar_histogram(cells, cert, xy, N, r_rs=0.23, d_max=1.6, b=4.0)
    masked = masked_histogram(binary_histogram(hist, np.zeros(N, bool), 1500.0, 2500.0), 0.0, -math.pi, math.pi)
    assert masked.all()
    k, relaxed, factor = select_direction(hist, masked, -math.pi, math.pi, 0.0, (k_goal, 0.0, 0.0), p)
    assert factor == 2.0 and np.flatnonzero(~relaxed).tolist() == [20, 21, 22]
    assert k == pytest.approx(21.0)
    # 0.2 m lower, in the open corridor, the configured thresholds find 100..115 deg themselves
    xy = np.array([0.95, 0.65])
    cells, cert = active_cells(values, frame, xy, 1.6, 15.0)
    hist = polar_histogram(cells, cert, xy, N, r_rs=0.23, d_max=1.6, b=4.0)
    masked = masked_histogram(binary_histogram(hist, np.zeros(N, bool), 1500.0, 2500.0), 0.0, -math.pi, math.pi)
    k, _relaxed, factor = select_direction(hist, masked, -math.pi, math.pi, 0.0, (k_goal, 0.0, 0.0), p)
    assert factor == 1.0 and np.flatnonzero(~masked).tolist() == [22, 23] and k == pytest.approx(22.5)
    assert relax_factors(4.0) == [2.0, 4.0] and relax_factors(1.0) == []


def test_relaxed_thresholds_never_open_a_sector_toward_a_cell_within_reach() -> None:
    """A cell 0.3 m ahead (< r_rs + cell = 0.33 m) closes asin(0.23 / 0.3) = 50.1 deg each
    side, sectors -10..10, whatever H^p says; a cell 0.5 m away does not count."""
    cells, cert = np.array([[0.3, 0.0], [0.0, 0.5]]), np.array([15.0, 15.0])
    near = near_sectors(cells, cert, np.zeros(2), N, 0.23, 0.33, 3.0)
    assert np.flatnonzero(near).tolist() == [*range(0, 11), *range(62, 72)]
    assert not near_sectors(cells, np.array([2.0, 15.0]), np.zeros(2), N, 0.23, 0.33, 3.0).any()
    p = VFHPlus().settings
    primary = np.full(N, 3000.0)  # every sector over threshold_high, all under 2 x threshold_high
    k, relaxed, factor = select_direction(primary, np.ones(N, bool), -math.pi, math.pi, 0.0,
                                          (1.0, 1.0, 1.0), p, near)
    assert factor == 2.0 and relaxed[near].all() and not relaxed[~near].any()
    assert k == pytest.approx(19.0)  # wide valley 11..61: 11 + s_max/2, nearer to sector 1 than 61 - 8


def end_wall_histogram(ahead: float, radius: float, b: float) -> np.ndarray:
    """H^p (72 sectors, r_rs = 0.25 m) of a certain wall across a 4 m wide map, ``ahead`` m in
    front (+y) of the robot at (2.05, 2.05), read with window ``radius`` m and weight ``b``."""
    frame = GridFrame.from_bounds((0.0, 0.0, 4.0, 5.0), 0.1)
    values = np.zeros(frame.shape, dtype=np.uint8)
    values[20 + round(ahead / 0.1), 10:31] = 100  # cells x 1.05..3.05, c = 15
    xy = np.array([2.05, 2.05])
    cells, cert = active_cells(values, frame, xy, radius, 15.0)
    return polar_histogram(cells, cert, xy, N, r_rs=0.25, d_max=radius, b=b)


SHORT_WINDOW = {"window_radius": 1.2, "distance_weight": 7.11, "slow_density": 3000.0}  # vfh_s8


def test_a_corridors_end_wall_closes_the_way_on_from_1_48_m() -> None:
    """The maze shuttle (issue 12, results/baselines/vfh_s8): with the 1.6 m window and b = 4 a
    certain wall 1.4 m ahead sums 3735 straight ahead (over threshold_high = 2500), so in a 1 m
    corridor the way on closes before the turn at its end comes into view. The 1.2 m window
    with b = 7.11 (a = 1 + b 1.2^2 = 11.24, the same near weight) leaves it free and closes it
    from 1.1 m: the five cells within r_rs of the ray sum
    225 (5 (1 + 7.11 (1.44 - 1.21)) - 7.11 (2 x 0.04 + 2 x 0.01)) = 2804.74."""
    p = VFHPlus().settings  # the 1.2 m window is the default since the eleventh session
    assert (p.window_radius, p.distance_weight, p.threshold_high) == (1.2, 7.11, 2500.0)
    assert end_wall_histogram(1.4, 1.6, 4.0)[18] == pytest.approx(3735.0)
    assert not end_wall_histogram(1.4, 1.2, 7.11).any()
    at_1_1 = end_wall_histogram(1.1, 1.2, 7.11)
    assert at_1_1[18] == pytest.approx(2804.737, abs=1e-3)
    assert np.flatnonzero(at_1_1 > p.threshold_high).tolist() == [17, 18, 19]
    assert end_wall_histogram(0.7, 1.2, 7.11)[18] == pytest.approx(8563.837, abs=1e-3)


def l_turn_world() -> BoxWorld:
    """A 1 m corridor x 0..1 north to an end wall at y 4.3 that turns east at y 3.3..4.3 (the
    layout of generated maze_0's first corner)."""
    return BoxWorld.room((6.0, 4.4), [(1.0, 0.0, 1.1, 3.3),   # the corridor's east wall
                                      (1.0, 3.2, 5.0, 3.3),   # the east corridor's south wall
                                      (0.0, 4.3, 6.0, 4.4)])  # the end wall


L_TURN_START, L_TURN_GOAL = (0.5, 0.5, math.pi / 2), (5.5, 3.8)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_old_1_6_m_window_shuttles_before_the_turn_at_the_end_of_a_1_m_corridor(seed: int) -> None:
    """Issue 12, the maze shuttle (results/baselines/vfh_s8): with the 1.6 m window and b = 4
    the robot turns back 1-1.2 m short of the end wall and never takes the turn (whole cells,
    as then: the carving of the thirteenth session lets this window take the turn too)."""
    old = VFHPlus(window_radius=1.6, distance_weight=4.0, slow_density=5000.0, carve_seen_through=False)
    result = run(old, l_turn_world(), L_TURN_START, L_TURN_GOAL, time_s=120.0, noise_std=0.01, seed=seed)
    assert not result.reached


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_short_window_takes_the_turn_at_the_end_of_a_1_m_corridor(seed: int) -> None:
    """The goal beyond an L-turn at the corridor's end: the 1.2 m window takes the turn in
    under 30 s without contact."""
    result = run(VFHPlus(**SHORT_WINDOW), l_turn_world(), L_TURN_START, L_TURN_GOAL,
                 time_s=120.0, noise_std=0.01, seed=seed)
    assert result.reached and result.collisions == 0 and result.time < 30.0


def test_does_not_stand_still_in_a_1_2_m_corridor() -> None:
    """An 8 m corridor 1.2 m wide: the robot drives through at speed, never blocked."""
    world = BoxWorld.room((12.0, 4.0), [(2.0, 0.0, 10.0, 1.4), (2.0, 2.6, 10.0, 4.0)])
    result = run(VFHPlus(), world, (1.0, 2.0, 0.0), (11.0, 2.0), time_s=60.0, noise_std=0.01,
                 robot=default_robot(radius=0.18))
    assert result.reached and result.collisions == 0
    assert not [e for e in result.events if e[0] == "blocked"]
    x = result.poses[:, 0]
    assert np.all(x[50::50] - x[:-50:50][: len(x[50::50])] > 1.0)  # > 1 m every 5 s
    assert result.time < 30.0


@pytest.mark.parametrize("offset", [0.0, 1.0, 1.5])
def test_passes_a_one_metre_door_off_the_straight_line(offset: float) -> None:
    """A wall across a 10 x 6 m room with a 1 m door whose centre is ``offset`` m off the
    start-goal line (kinematic harness, sonar noise)."""
    c = 3.0 + offset
    world = BoxWorld.room((10.0, 6.0), [(4.925, 0.0, 5.075, c - 0.5), (4.925, c + 0.5, 5.075, 6.0)])
    result = run(VFHPlus(), world, (2.0, 2.5, 0.0), (8.0, 2.5), time_s=60.0, noise_std=0.01,
                 robot=default_robot(radius=0.18))
    assert result.reached and result.collisions == 0
    xy = result.poses[:, :2]
    crossing = xy[np.argmax(xy[:, 0] > 5.0)]
    assert c - 0.5 < crossing[1] < c + 0.5


@pytest.mark.parametrize("world_fn", [open_room, wall_world])
def test_reaches_the_goal(world_fn) -> None:
    world, start, goal = world_fn()
    result = run(VFHPlus(), world, start, goal, time_s=60.0, noise_std=0.01)
    assert result.reached and result.collisions == 0


def test_trapped_by_the_u_like_other_local_methods() -> None:
    world, start, goal = u_world()  # documented: VFH+ has no memory of where it has been
    result = run(VFHPlus(), world, start, goal, time_s=60.0)
    assert not result.reached and result.collisions == 0
    assert result.poses[-1, 0] < 5.0  # never got past the bottom of the U


@pytest.mark.slow
def test_passes_a_one_metre_door_in_the_simulator() -> None:
    """PyBullet: a wall across a 10 x 6 m room with a 1 m door off the straight line."""
    from nav_bench.episode import EpisodeSettings
    from nav_bench.episode.loop import run_episode
    from nav_bench.specs import PlannerSetSpec
    from nav_bench.world.load import world_from_data

    world = world_from_data({
        "name": "door_1m", "size": [10.0, 6.0], "start": [2.0, 2.5], "goal": [8.0, 2.5],
        "obstacles": [{"wall": {"from": [5.0, 0.0], "to": [5.0, 3.5], "thickness": 0.15}},
                      {"wall": {"from": [5.0, 4.5], "to": [5.0, 6.0], "thickness": 0.15}}]})
    result = run_episode(world, PlannerSetSpec(planner="vfh_plus"), seed=0,
                         settings=EpisodeSettings(time_s=120.0))
    assert result.row.outcome == "reached", result.row
    xy = result.trace.true_pose[:, :2]
    crossing = xy[np.argmax(xy[:, 0] > 5.0)]
    assert 3.5 < crossing[1] < 4.5  # through the door



# --------------------------------------------------------------------------- cells seen through
GAP_WORLD = BoxWorld.room((4.0, 3.0), [(2.0, 0.5, 2.3, 1.225), (2.0, 1.775, 2.3, 2.5)])  # 0.55 m gap at y 1.5
GAP_ROBOT = default_robot(radius=0.18)  # the body 0.36 m, the enlarged robot 2 r_rs = 0.46 m


def read_gap(planner: VFHPlus, yaws: list[float], t0: float = 0.0, x: float = 1.2) -> None:
    """Let ``planner`` read the gap world from (``x``, 1.5), 0.8 m before the gap, at each heading."""
    for i, yaw in enumerate(yaws):
        planner.act(observe(GAP_WORLD, np.array([x, 1.5, yaw]), np.array([3.5, 1.5]), GAP_ROBOT,
                            t0 + 0.1 * i, 0.1))


def whole_cell_histogram(planner: VFHPlus, xy: np.ndarray) -> np.ndarray:
    """H^p of the planner's grid read as whole cells (the histogram before the carving)."""
    p = planner.settings
    cells, cert = active_cells(planner.grid.values(), planner.frame, xy, p.window_radius, p.c_max)
    return polar_histogram(cells, cert, xy, planner.n, GAP_ROBOT.radius + p.safety_distance,
                           p.window_radius, p.distance_weight)


@pytest.mark.parametrize("carve", [True, False])
def test_cells_seen_through_from_two_views_no_longer_close_a_055_m_gap(carve: bool) -> None:
    """Two boxes 0.55 m apart, the robot 0.8 m before the gap. Facing it, the front sonars' arcs
    are blamed across the gap: the grid closes it (H^p straight ahead over threshold_high).
    Turned 6-24 deg either way, the front cones look through the gap: the grid alone still
    holds the three sectors toward it over threshold_high, while the parts seen through from
    two views leave them below threshold_low, free (sector 0 = the gap's direction, world +x)."""
    planner = VFHPlus(carve_seen_through=carve)
    xy = np.array([1.2, 1.5])
    planner.reset(observe(GAP_WORLD, np.array([1.2, 1.5, 0.0]), np.array([3.5, 1.5]), GAP_ROBOT, 0.0, 0.1),
                  np.random.default_rng(0))
    read_gap(planner, [0.0] * 6)
    assert planner.binary[0] and planner.primary[0] > planner.settings.threshold_high
    np.testing.assert_array_equal(planner.primary, whole_cell_histogram(planner, xy))  # nothing seen through
    turns = [-0.1, -0.18, -0.26, -0.34, -0.42, 0.1, 0.18, 0.26, 0.34, 0.42]  # 6-24 deg each way
    read_gap(planner, turns, t0=0.6)
    toward_gap = [71, 0, 1]
    grid_only = whole_cell_histogram(planner, xy)
    assert np.all(grid_only[toward_gap] > planner.settings.threshold_high)
    if carve:
        assert np.all(planner.primary[toward_gap] < planner.settings.threshold_low)
        assert not planner.binary[toward_gap].any()
    else:
        np.testing.assert_array_equal(planner.primary, grid_only)
        assert planner.binary[toward_gap].all()


def test_a_part_seen_through_from_one_view_only_is_kept() -> None:
    """Readings from one pose (turned 17 deg, a front cone through the gap) see through parts
    but carve nothing: a box corner can poke between a cone's rays, and a ray grazing past it
    reads long, but not from two views. A reading from a second view (4 cm on) carves them."""
    planner = VFHPlus()
    xy = np.array([1.2, 1.5])
    planner.reset(observe(GAP_WORLD, np.array([1.2, 1.5, 0.3]), np.array([3.5, 1.5]), GAP_ROBOT, 0.0, 0.1),
                  np.random.default_rng(0))
    read_gap(planner, [0.3] * 6)
    assert np.isfinite(planner.carving.seen_t).any() and not np.isfinite(planner.carving.carved_t).any()
    np.testing.assert_array_equal(planner.primary, whole_cell_histogram(planner, xy))
    read_gap(planner, [0.3], t0=0.6, x=1.24)  # moved 4 cm: a second view
    assert np.isfinite(planner.carving.carved_t).any()
    assert planner.primary.sum() < whole_cell_histogram(planner, np.array([1.24, 1.5])).sum()


def test_a_cell_with_parts_seen_through_stands_as_its_kept_parts() -> None:
    """ActiveWindow.carved: a cell with every part kept stays its centre (weight 1); one with
    some parts dropped becomes its k kept parts, in its place in window order, each with the
    cell's certainty and 1/k of its magnitude; one with every part dropped is gone."""
    from nav_bench.planners.carving import PARTS
    from nav_bench.planners.footprint import cell_parts

    centres = np.array([[1.05, 0.05], [1.05, 0.15], [1.05, 0.25]])
    window = ActiveWindow.of_cells(centres, np.array([15.0, 6.0, 3.0]), np.zeros(2))
    parts = cell_parts(centres, 0.1)
    kept = np.ones((3, PARTS), dtype=bool)
    assert window.carved(kept, parts, np.zeros(2)) is window  # nothing seen through
    kept[1, 5:] = False  # the middle cell keeps its lowest row of parts (y 0.11)
    kept[2] = False
    out = window.carved(kept, parts, np.zeros(2))
    assert len(out) == 1 + 5
    np.testing.assert_array_equal(out.x[:1], [1.05])
    np.testing.assert_allclose(out.x[1:], [1.01, 1.03, 1.05, 1.07, 1.09])
    np.testing.assert_allclose(out.y[1:], 0.11)
    np.testing.assert_array_equal(out.certainty, [15.0] + [6.0] * 5)
    np.testing.assert_allclose(out.weight, [1.0] + [1.0 / 5] * 5)
    np.testing.assert_allclose(out.area, [1.0] + [1.0 / PARTS] * 5)
    np.testing.assert_allclose(out.dist, np.hypot(out.x, out.y))
    # 1.05 m off, beyond AREA_SHARE_BEYOND_M: each of the 5 parts' magnitude is its area's share
    # of its cell's, 1/25: that of certainty 6 / 5
    hist = window_histogram(out, out.bearings(), N, r_rs=0.23, d_max=1.2, b=7.11)
    expected = (polar_histogram(centres[:1], np.array([15.0]), np.zeros(2), N, 0.23, 1.2, 7.11)
                + polar_histogram(np.stack([out.x[1:], out.y[1:]], axis=1), np.full(5, 6.0 / 5),
                                  np.zeros(2), N, 0.23, 1.2, 7.11))
    np.testing.assert_allclose(hist, expected, rtol=1e-12)


def test_a_kept_part_weighs_its_cells_magnitude_share_near_and_its_area_share_far() -> None:
    # one kept part (k = 1: the cell's whole magnitude as its share; area 1/25), certainty 14,
    # straight ahead: at 0.45 m, inside AREA_SHARE_BEYOND_M (0.5 m), the whole cell's magnitude
    # 14^2 (1 + 7.11 (1.44 - 0.2025)) = 1920.5; at 0.55 m 1/25 of 14^2 (1 + 7.11 (1.44 - 0.3025))
    # = 1/25 x 1781.2 = 71.2; a whole cell there keeps its whole magnitude
    xy = np.zeros(2)
    for dist, area, expected in ((0.45, 1.0 / 25, 1920.5), (0.55, 1.0 / 25, 71.2), (0.55, 1.0, 1781.2)):
        cell = ActiveWindow.of_cells(np.array([[dist, 0.0]]), np.array([14.0]), xy)
        point = dataclasses.replace(cell, weight=np.array([1.0]), area=np.array([area]))
        h = window_histogram(point, point.bearings(), N, 0.23, 1.2, 7.11)
        assert h[0] == pytest.approx(expected, abs=0.1)
    assert AREA_SHARE_BEYOND_M == 0.5


@pytest.mark.parametrize("memory_s", [3.0, 10.0])
def test_the_gap_seen_through_closes_again_when_the_carving_memory_runs_out(memory_s: float) -> None:
    """The 0.55 m gap opened by the carving (as above), then the robot faces away from it for
    5 s (no cone looks toward it, the same view throughout, so nothing is seen through again),
    as VFH+ turns on the spot in front of a gap when the goal term picks the other valley. The
    carving of the jambs expires ``CARVE_MEMORY_S`` (3 s) after the last view that saw through
    it, and the grid closes the gap's three sectors again over threshold_high: in office_11 and
    clutter_0 the expired parts carry 37-42 % of the parts that close the way on while it is
    closed (``results/baselines/vfh_s14/``). VFH+'s ``carve_memory_s`` 10 (``../vfh_s16``, with
    ``carve_undo`` unexplained: an echo nothing kept explains takes a wrong carving back) keeps
    the gap open at t = 6.5 s; 3 s is main's former and D* Lite's memory."""
    planner = VFHPlus(carve_memory_s=memory_s)
    xy = np.array([1.2, 1.5])
    planner.reset(observe(GAP_WORLD, np.array([1.2, 1.5, 0.0]), np.array([3.5, 1.5]), GAP_ROBOT, 0.0, 0.1),
                  np.random.default_rng(0))
    read_gap(planner, [0.0] * 6)
    read_gap(planner, [-0.1, -0.18, -0.26, -0.34, -0.42, 0.1, 0.18, 0.26, 0.34, 0.42], t0=0.6)
    toward_gap = [71, 0, 1]
    p = planner.settings
    assert np.all(planner.primary[toward_gap] < p.threshold_low)  # open at t = 1.5 s
    read_gap(planner, [math.pi] * 20, t0=1.6)  # facing away till t = 3.5 s: still open
    assert np.all(planner.primary[toward_gap] < p.threshold_low)
    assert not planner.binary[toward_gap].any()
    read_gap(planner, [math.pi] * 30, t0=3.6)  # till t = 6.5 s: closed again after 3 s, as the grid has it
    if memory_s > 6.5:
        assert np.all(planner.primary[toward_gap] < p.threshold_low)
        read_gap(planner, [math.pi] * 60, t0=6.6)  # till t = 12.5 s: closed again after 10 s
    grid_only = whole_cell_histogram(planner, xy)
    assert np.all(grid_only[toward_gap] > p.threshold_high)
    np.testing.assert_allclose(planner.primary[toward_gap], grid_only[toward_gap], rtol=1e-12)
    assert planner.binary[toward_gap].all()


def test_a_turn_on_the_spot_at_speed_with_nothing_near_turns_at_once() -> None:
    # goal behind the robot, 0.3 m/s (odometry), the room's walls beyond the roll: no brake
    world, _start, _goal = open_room()
    robot, goal = default_robot(), np.array([1.0, 2.5])
    planner = VFHPlus()
    planner.reset(observe(world, np.array([3.0, 2.5, 0.0]), goal, robot, 0.0, 0.1), np.random.default_rng(0))
    for t, x in ((0.1, 3.03), (0.2, 3.031)):
        cmd = planner.act(observe(world, np.array([x, 2.5, 0.0]), goal, robot, t, 0.1))
        assert cmd.v == 0.0
        assert abs(cmd.omega) == pytest.approx(robot.omega_max)


def test_the_roll_on_bends_toward_the_turn() -> None:
    # 0.18 m of roll (0.3 m/s x 0.6 s), the heading swinging 75 deg left: it ends 0.152 m on and
    # 0.069 m to the left (a 24 deg chord: the swing grows with the square of the travel)
    arc = roll_arc(0.18, math.radians(75.0))
    assert arc.shape == (8, 2)
    np.testing.assert_allclose(arc[-1], [0.1518, 0.0694], atol=1e-4)
    np.testing.assert_allclose(roll_arc(0.18, math.radians(-75.0))[-1], [0.1518, -0.0694], atol=1e-4)
    np.testing.assert_allclose(roll_arc(0.18, 0.0)[-1], [0.18, 0.0], atol=1e-12)


def test_the_brake_tests_the_arc_toward_the_turn_and_only_before_the_turn_begins() -> None:
    # a sure point 0.30 m off at +45 deg (0.212 m to the side: a straight roll of 0.18 m along
    # the heading passes it at 0.215 m). Turning left from 0.3 m/s, the arc comes within 0.155 m
    # (under the 0.18 m body): brake. Turning right it stays 0.253 m off: turn. Below brake_speed,
    # once a left turn on the spot has begun (not a right one), or with the point not above
    # mask_certainty: turn.
    world, _start, _goal = open_room()
    robot = default_robot()
    planner = VFHPlus()
    planner.reset(observe(world, np.array([3.0, 2.5, 0.0]), np.array([5.0, 4.0]), robot, 0.0, 0.1),
                  np.random.default_rng(0))
    xy = np.array([3.0, 2.5])
    point = xy + 0.30 * np.array([math.cos(math.radians(45.0)), math.sin(math.radians(45.0))])
    sure = ActiveWindow.of_cells(point[None], np.array([15.0]), xy)
    faint = ActiveWindow.of_cells(point[None], np.array([planner.settings.mask_certainty]), xy)
    assert planner._spot_turn(2.0, 0.3, sure, 0.0, robot.radius) == 0.0
    assert planner._spot_turn(-2.0, 0.3, sure, 0.0, robot.radius) == -2.0
    assert planner._spot_turn(2.0, 0.01, sure, 0.0, robot.radius) == 2.0
    assert planner._spot_turn(2.0, 0.3, faint, 0.0, robot.radius) == 2.0
    planner.spinning = 1.0  # a left turn on the spot under way goes on; a right one is a new turn
    assert planner._spot_turn(2.0, 0.3, sure, 0.0, robot.radius) == 2.0
    planner.spinning = -1.0
    assert planner._spot_turn(2.0, 0.3, sure, 0.0, robot.radius) == 0.0


def test_a_kept_part_within_r_rs_carries_its_whole_cell() -> None:
    # one kept part of a carved cell (its share 1/4, certainty 14) at +65 deg, as a convex
    # corner beside the body. At 0.20 m, within r_rs (0.23 m), it covers +-90 deg with the whole
    # cell's magnitude, 14^2 (1 + 7.11 (1.2^2 - 0.2^2)) = 2147.0, in the heading sector (0 deg)
    # too, not its share 536.7; -30 deg is beyond its +-90. At 0.25 m it keeps its share,
    # 0.25 x 14^2 (1 + 7.11 (1.44 - 0.0625)) = 528.9, over +-66.9 deg: the heading, not -5 deg.
    xy = np.zeros(2)
    for dist, heading, minus5, expected in ((0.20, 2147.0, 2147.0, 2147.0), (0.25, 528.9, 0.0, 528.9)):
        point = dist * np.array([[math.cos(math.radians(65.0)), math.sin(math.radians(65.0))]])
        cell = ActiveWindow.of_cells(point, np.array([14.0]), xy)
        part = ActiveWindow(cell.x, cell.y, cell.certainty, cell.dx, cell.dy, cell.dist, weight=np.array([0.25]))
        h = window_histogram(part, part.bearings(), N, 0.23, 1.2, 7.11)
        assert h[0] == pytest.approx(heading, abs=0.1)
        assert h[71] == pytest.approx(minus5, abs=0.1)
        assert h[66] == 0.0
        assert h.max() == pytest.approx(expected, abs=0.1)


def test_a_turn_on_the_spot_at_speed_is_capped_only_where_its_roll_would_meet_a_point() -> None:
    # 0.25 m/s, a 5.77 rad/s turn to the left, default_robot (radius 0.2 m, wheel base from it):
    # a faint point (certainty 1, under mask_certainty) 0.3 m off at +45 deg lies on the roll
    # (H3's arc comes within 0.155 m): capped at 2 x 0.25 / b; the same point at -45 deg (off
    # the roll, 0.253 m) or the robot below brake_speed: the turn as asked
    robot = default_robot()
    planner = VFHPlus()
    world, _start, _goal = open_room()
    planner.reset(observe(world, np.array([3.0, 2.5, 0.0]), np.array([5.0, 4.0]), robot, 0.0, 0.1),
                  np.random.default_rng(0))
    xy = np.array([3.0, 2.5])
    cap = 2 * 0.25 / robot.wheel_base
    for bearing, speed, expected in ((45.0, 0.25, cap), (-45.0, 0.25, 5.77), (45.0, 0.01, 5.77)):
        point = xy + 0.30 * np.array([math.cos(math.radians(bearing)), math.sin(math.radians(bearing))])
        faint = ActiveWindow.of_cells(point[None], np.array([1.0]), xy)
        assert planner._capped(5.77, speed, faint, 0.0, robot) == pytest.approx(expected)
