"""DWA and DWA under a D* Lite path: roll-outs, admissible velocities, the dynamic window, and
driving (stops before a wall, passes a 1 m door, goes round a wall with the global path); the
issue-16 decision (anchor bounds, exact distances where they cannot decide) against the
straightforward one it replaced, to the bit.

Runtime: ~15 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nav_bench.planners.dwa as dwa_module
from nav_bench.planners.dstar_lite import DStarLite
from nav_bench.planners.dwa import (
    DWA,
    Choice,
    DWAGlobal,
    anchor_columns,
    arc_clearances,
    choose_velocity,
    edge_clearance,
    linspace,
    nearest_distances,
    rollout,
)
from nav_bench.testing.harness import BoxWorld, default_robot, observe, run, wall_world

P = DWA().settings  # the defaults, as the planner reads them


def test_rollout_follows_straight_lines_and_circles() -> None:
    arcs = rollout(np.array([1.0, 2.0, 0.0]), np.array([0.5, 1.0]), np.array([0.0, 1.0]), 10,
                   math.pi / 10)
    assert arcs.shape == (2, 10, 3)
    np.testing.assert_allclose(arcs[0, -1], [1.0 + 0.5 * math.pi, 2.0, 0.0], atol=1e-12)
    # v = 1, omega = 1: a unit circle to the left; after pi s the robot is 2 m up, facing back
    np.testing.assert_allclose(arcs[1, -1], [1.0, 4.0, math.pi], atol=1e-12)
    np.testing.assert_allclose(np.hypot(arcs[1, :, 0] - 1.0, arcs[1, :, 1] - 3.0), 1.0, atol=1e-12)


def test_clearance_is_measured_from_the_robot_edge() -> None:
    arcs = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]])
    clear = arc_clearances(arcs, np.array([[2.0, 0.0], [0.0, 3.0]]), radius=0.2)
    np.testing.assert_allclose(clear, [[1.8, 0.8]])
    assert np.isinf(arc_clearances(arcs, np.zeros((0, 2)), 0.2)).all()


def test_the_clearance_of_one_pose_is_the_roll_out_clearance_of_that_pose() -> None:
    # choose_velocity's "already this close" clearance: the same value, to the last bit, as
    # arc_clearances' k-d tree query would give for the pose
    rng = np.random.default_rng(2)
    for _ in range(50):
        pose = rng.uniform(-5.0, 5.0, 3)
        points = pose[:2] + rng.uniform(-1.7, 1.7, (int(rng.integers(1, 150)), 2))
        expected = arc_clearances(pose[None, None, :], points, 0.2)[0, 0]
        assert edge_clearance(pose[:2], points, 0.2) == expected
    assert edge_clearance(np.zeros(2), np.zeros((0, 2)), 0.2) == math.inf


def test_the_window_limits_acceleration_and_free_space_takes_its_top() -> None:
    pose, goal = np.zeros(3), np.array([5.0, 0.0])
    c = choose_velocity(pose, goal, 0.2, 0.0, np.zeros((0, 2)), 0.2, 0.1, P, 0.5, 1.0)
    assert c.v == pytest.approx(0.2 + P.acc_v * 0.1) and c.omega == 0.0  # straight at the goal
    c = choose_velocity(pose, goal, 0.5, 0.0, np.zeros((0, 2)), 0.2, 0.1, P, 0.5, 1.0)
    assert c.v == pytest.approx(0.5)  # never above v_max
    c = choose_velocity(pose, np.array([0.0, 5.0]), 0.0, 0.0, np.zeros((0, 2)), 0.2, 0.1, P, 0.5, 1.0)
    assert c.omega == pytest.approx(P.acc_omega * 0.1)  # turns toward a goal on the left, as fast as allowed


def test_only_velocities_that_can_stop_in_time_are_admissible() -> None:
    # a wall of points 0.45 m ahead of a robot of radius 0.2 moving at 0.4 m/s: 0.25 m of edge
    # clearance, 0.20 m to the 0.05 m collision line; stopping from v needs 0.1 v + v^2 / 1.0
    wall = np.stack([np.full(41, 0.45), np.linspace(-2.0, 2.0, 41)], axis=1)
    c = choose_velocity(np.zeros(3), np.array([5.0, 0.0]), 0.4, 0.0, wall, 0.2, 0.1, P, 0.5, 1.0)
    assert c.v < 0.4  # it slows down
    assert 0.1 * c.v + c.v ** 2 / (2 * P.acc_v) <= 0.20 + 0.02  # and can still stop before the line
    far = wall + np.array([2.0, 0.0])
    c = choose_velocity(np.zeros(3), np.array([5.0, 0.0]), 0.4, 0.0, far, 0.2, 0.1, P, 0.5, 1.0)
    assert c.v == pytest.approx(0.45)


@pytest.mark.parametrize("seed", [0, 1])
def test_stops_before_a_wall(seed: int) -> None:
    # a 1.2 m wide dead-end corridor; the goal lies beyond its end wall (x = 4)
    world = BoxWorld.room((6.0, 1.2), [(4.0, 0.0, 6.0, 1.2)])
    result = run(DWA(), world, (1.0, 0.6, 0.0), (5.0, 0.6), time_s=20.0, seed=seed, noise_std=0.01)
    assert not result.reached and result.collisions == 0
    x = result.poses[:, 0]
    assert x.max() < 4.0 - 0.2 - 0.02  # the body's front never reached the wall
    first_stop = int(np.argmax((result.commands[:, 0] == 0.0) & (np.arange(len(result.commands)) > 5)))
    assert first_stop > 0 and 3.3 < x[first_stop] < 3.8  # it drove up, then stopped in front of the wall
    assert result.commands[:, 0].max() == pytest.approx(0.5)  # at full speed on the way
    assert result.kinds("blocked") >= 1


@pytest.mark.parametrize("cls", [DWA, DWAGlobal], ids=["dwa", "dwa_global"])
def test_passes_a_1m_door(cls: type) -> None:
    # a wall across an 8 x 6 m room with a 1.0 m door (y 2.5..3.5); start and goal on either side
    world = BoxWorld.room((8.0, 6.0), [(3.9, 0.0, 4.1, 2.5), (3.9, 3.5, 4.1, 6.0)])
    result = run(cls(), world, (1.0, 2.0, 0.0), (7.0, 4.0), time_s=60.0, noise_std=0.01)
    assert result.reached and result.collisions == 0
    crossing = result.poses[np.argmax(result.poses[:, 0] > 4.0)]
    assert 2.5 + 0.2 < crossing[1] < 3.5 - 0.2  # through the door, body inside its frame
    assert result.time < 30.0 and result.path_length < 9.0  # straight line 6.3 m


def test_global_path_leads_round_a_wall_that_traps_plain_dwa() -> None:
    world, start, goal = wall_world()
    result = run(DWAGlobal(), world, start, goal, time_s=60.0, noise_std=0.01)
    assert result.reached and result.collisions == 0
    assert result.kinds("replan") >= 1  # D* Lite repaired its path as the wall came into view
    state = result.planner.debug_state()
    assert state["path"].shape[1] == 2 and state["pmo"].shape == (60, 80)


@pytest.mark.parametrize("width", [1.05, 1.2])
def test_dwa_global_turns_round_a_wall_end_between_two_corridors(width: float) -> None:
    # a wall 2.2 m long splits a 4 m room into two corridors ``width`` wide, open at its far end;
    # the goal is in the other corridor, just above the start: a U-turn round the wall's end.
    # With its local goal 1 m along the path, DWA's straight line to it cut the corner, every
    # arc came out blocked and the robot looped in the corridor until the time ran out
    world = BoxWorld.room((4.0, 2 * width + 0.1), [(0.0, width, 2.2, width + 0.1)])
    robot = default_robot(radius=0.18)
    result = run(DWAGlobal(), world, (0.55, width / 2, 0.0), (0.55, 1.5 * width + 0.1),
                 time_s=90.0, noise_std=0.01, robot=robot)
    assert result.reached and result.collisions == 0
    assert result.time < 25.0 and result.path_length < 5.5  # along the corridors: 4.2-4.4 m
    assert result.poses[:, 0].max() > 2.2  # round the wall's end, not through it


def test_use_grid_adds_the_occupied_cells_as_obstacles() -> None:
    world = BoxWorld.room((6.0, 1.2), [(4.0, 0.0, 6.0, 1.2)])
    plain = run(DWA(), world, (1.0, 0.6, 0.0), (5.0, 0.6), time_s=6.0)
    gridded = run(DWA(use_grid=True), world, (1.0, 0.6, 0.0), (5.0, 0.6), time_s=6.0)
    assert "pmo" not in plain.planner.debug_state()
    pmo = gridded.planner.debug_state()["pmo"]
    assert (pmo[:, 39:41] > 65).any()  # the end wall at x = 4 m is in the grid
    obs_pts = len(gridded.planner.memory)
    assert obs_pts > 0 and gridded.collisions == plain.collisions == 0


# ----------------------------------------------------------------------------- issue 16
def reference_choose_velocity(pose, goal, v_now, omega_now, points, radius, dt, p, v_max, omega_max,
                              v_cap=math.inf) -> Choice:
    """choose_velocity before issue 16, verbatim: every sample rolled out (rollout) and every
    pose's clearance from the k-d tree (arc_clearances). The reference of the fast one."""
    v_lo, v_hi = max(0.0, v_now - p.acc_v * dt), min(v_max, v_now + p.acc_v * dt)
    if v_lo > v_hi:
        v_lo = v_hi = max(0.0, min(v_max, v_now - p.acc_v * dt))
    w_lo = max(-omega_max, omega_now - p.acc_omega * dt)
    w_hi = min(omega_max, omega_now + p.acc_omega * dt)
    if w_lo > w_hi:
        w_lo = w_hi = min(omega_max, max(-omega_max, omega_now))
    vs = np.linspace(v_lo, v_hi, p.v_samples)
    ws = np.linspace(w_lo, w_hi, p.omega_samples)
    if w_lo < 0.0 < w_hi:
        ws = np.unique(np.append(ws, 0.0))
    vv, ww = (a.ravel() for a in np.meshgrid(vs, ws, indexing="ij"))
    steps = max(1, round(p.sim_time / p.sim_step))
    arcs = rollout(pose, vv, ww, steps, p.sim_step)
    clear = arc_clearances(arcs, points, radius)
    now = edge_clearance(np.asarray(pose[:2], dtype=float), points, radius)
    hit = clear < min(p.min_clearance, now - 1e-6)
    first = np.where(hit.any(axis=1), hit.argmax(axis=1), steps)
    dist = np.where(first < steps, vv * p.sim_step * first, math.inf)
    admissible = (vv * dt + vv * vv / (2.0 * p.acc_v) <= dist + 1e-12) | (vv <= 1e-9)
    admissible &= vv <= v_cap + 1e-9
    end = arcs[:, -1, :]
    bearing = np.arctan2(goal[1] - end[:, 1], goal[0] - end[:, 0])
    err = np.abs(np.remainder(bearing - end[:, 2] + math.pi, 2 * math.pi) - math.pi)
    heading = 1.0 - err / math.pi
    cap = p.clearance_cap
    clearance = np.clip(clear.min(axis=1), 0.0, cap) / cap
    velocity = vv / max(v_max, 1e-9)
    score = p.k_heading * heading + p.k_clearance * clearance + p.k_velocity * velocity
    moving = admissible & (vv > 1e-9)
    if not admissible.any():
        score = np.where(vv <= vv.min() + 1e-12, clear.min(axis=1), -math.inf)
    else:
        score = np.where(moving if moving.any() else admissible, score, -math.inf)
    best = int(np.argmax(score))
    return Choice(float(vv[best]), float(ww[best]), float(score[best]), int(np.count_nonzero(moving)))


def test_linspace_is_numpys_to_the_bit() -> None:
    rng = np.random.default_rng(0)
    cases = [(0.0, 0.1, 7), (0.45, 0.5, 7), (-1.0, -0.4, 15), (0.3, 0.3, 7), (-0.3, 0.3, 15),
             (1e-17, 0.1, 7), (0.0, 0.0, 2)]
    cases += [(float(a), float(a + b), int(k)) for a, b, k in
              zip(rng.uniform(-2, 2, 200), rng.uniform(0, 1, 200), rng.integers(2, 30, 200), strict=True)]
    for start, stop, num in cases:
        assert linspace(start, stop, num) == np.linspace(start, stop, num).tolist()


def test_nearest_distances_are_the_k_d_trees_to_the_bit() -> None:
    rng = np.random.default_rng(1)
    for _ in range(30):
        q = rng.uniform(-20.0, 20.0, (int(rng.integers(1, 300)), 2))
        points = q[0] + rng.uniform(-2.0, 2.0, (int(rng.integers(1, 200)), 2))
        expected = arc_clearances(np.c_[q, np.zeros(len(q))][:, None, :], points, 0.0)[:, 0]
        np.testing.assert_array_equal(nearest_distances(q, points), expected)
    # what it computes: the distance to the nearest point, e.g. 5 (3-4-5) and 1
    np.testing.assert_array_equal(nearest_distances(np.array([[0.0, 0.0], [3.0, 5.0]]),
                                                    np.array([[3.0, 4.0], [6.0, 8.0]])), [5.0, 1.0])


def test_the_anchor_margin_bounds_how_far_a_pose_moves_with_v_and_omega() -> None:
    # the pose after t of (v, omega) is within |v - v_a| t + v_a |omega - omega_a| t^2 / 2 of the
    # pose of (v_a, omega_a): v = 0.5 straight ends at (0.5, 0); with omega = 1 at
    # 0.5 (sin 1, 1 - cos 1) = (0.42074, 0.22985), 0.24313 m away, within 0.5 * 1 * 1 / 2 = 0.25
    arcs = rollout(np.zeros(3), np.array([0.5, 0.5]), np.array([0.0, 1.0]), 1, 1.0)
    np.testing.assert_allclose(arcs[1, 0, :2], [0.5 * math.sin(1.0), 0.5 * (1 - math.cos(1.0))], atol=1e-15)
    gap = float(np.hypot(*(arcs[0, 0, :2] - arcs[1, 0, :2])))
    assert gap == pytest.approx(0.24313, abs=1e-5) and gap <= 0.25
    rng = np.random.default_rng(3)
    pose = np.array([3.0, -2.0, 0.7])
    v, w = rng.uniform(0.0, 0.6, 2000), rng.uniform(-1.2, 1.2, 2000)
    va, wa = rng.uniform(0.0, 0.6, 2000), rng.uniform(-1.2, 1.2, 2000)
    t = np.arange(1, 11) * 0.1
    gap = np.hypot(*(rollout(pose, v, w, 10, 0.1) - rollout(pose, va, wa, 10, 0.1))[:, :, :2].transpose(2, 0, 1))
    bound = np.abs(v - va)[:, None] * t + (va * np.abs(w - wa))[:, None] * t * t / 2
    assert (gap <= bound + 1e-12).all() and (gap / bound).max() > 0.95  # tight at times


def test_anchor_columns_every_third_turn_rate_and_the_last() -> None:
    cols, of = anchor_columns(16)  # 15 samples and the inserted omega = 0
    assert cols.tolist() == [0, 3, 6, 9, 12, 15]
    assert cols[of].tolist() == [0, 0, 3, 3, 3, 6, 6, 6, 9, 9, 9, 12, 12, 12, 15, 15]
    assert anchor_columns(15)[0].tolist() == [0, 3, 6, 9, 12, 14]


def scene(rng: np.random.Generator, kind: str) -> tuple:
    """A random DWA decision: pose, goal, v_now, omega_now, points, v_cap."""
    pose = np.array([*rng.uniform(-20.0, 20.0, 2), rng.uniform(-math.pi, math.pi)])
    goal = pose[:2] + rng.uniform(-5.0, 5.0, 2)
    v_now, omega_now = float(rng.choice([0.0, rng.uniform(0, 0.5), 0.5])), float(rng.uniform(-1, 1))
    c, s = math.cos(pose[2]), math.sin(pose[2])
    if kind == "none":
        points = np.zeros((0, 2))
    elif kind == "wall":  # a wall across the heading 0.3..1.5 m ahead, echo points along it
        d, k = rng.uniform(0.3, 1.5), int(rng.integers(5, 120))
        lat = rng.uniform(-2.0, 2.0, k)
        points = pose[:2] + np.c_[d * c - lat * s, d * s + lat * c] + rng.normal(0, 0.01, (k, 2))
    elif kind == "close":  # the robot (radius 0.2) already within min_clearance, or overlapping
        k = int(rng.integers(1, 60))
        ang, rad = rng.uniform(-math.pi, math.pi, k), rng.uniform(0.15, 1.7, k)
        points = pose[:2] + np.c_[rad * np.cos(ang), rad * np.sin(ang)]
    else:  # clutter: points all round within 1.7 m
        k = int(rng.integers(1, 250))
        ang, rad = rng.uniform(-math.pi, math.pi, k), rng.uniform(0.22, 1.7, k)
        points = pose[:2] + np.c_[rad * np.cos(ang), rad * np.sin(ang)]
    v_cap = float(rng.choice([math.inf, rng.uniform(0.05, 0.5)]))
    return pose, goal, v_now, omega_now, points, v_cap


@pytest.mark.parametrize("kind", ["clutter", "wall", "close", "none"])
def test_the_decision_is_the_reference_decision_to_the_bit(kind: str) -> None:
    rng = np.random.default_rng(["clutter", "wall", "close", "none"].index(kind))
    settings = [P, DWA(omega_samples=4, v_samples=3).settings, DWA(sim_time=2.0, acc_omega=0.5).settings,
                DWA(k_clearance=0.0).settings, DWA(min_clearance=0.0).settings]
    braking = 0
    for i in range(400):
        pose, goal, v_now, omega_now, points, v_cap = scene(rng, kind)
        p = settings[i % len(settings)]
        v_max = 0.3 if i % 7 == 0 else 0.5  # below v_now: the brake window
        args = (pose, goal, v_now, omega_now, points, 0.2, 0.1, p, v_max, 1.0)
        got, want = choose_velocity(*args, v_cap=v_cap), reference_choose_velocity(*args, v_cap=v_cap)
        assert got == want, (i, got, want)
        braking += want.admissible == 0 and want.v > 0
    if kind in ("wall", "close"):
        assert braking > 0  # the no-admissible branch was met


def test_the_decision_computes_few_exact_distances() -> None:
    # a wall 1 m ahead at full speed: 7 x 16 samples x 10 poses = 1,120 poses, 41 points (45,920
    # pairs before issue 16); exact distances for the 6 anchor turn rates of the middle speed
    # (60 poses x 41 points), no collision the bounds leave open (none is possible), and the
    # 7 arcs that can win (70 poses) against the 7 points that can be nearest to them: 2,950
    wall = np.stack([np.full(41, 1.0), np.linspace(-2.0, 2.0, 41)], axis=1)
    pairs: list[tuple[int, int]] = []

    def counting(q: np.ndarray, points: np.ndarray) -> np.ndarray:
        pairs.append((len(q), len(points)))
        return nearest_distances(q, points)

    args = (np.zeros(3), np.array([5.0, 0.3]), 0.5, 0.0, wall, 0.2, 0.1, P, 0.5, 1.0)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(dwa_module, "nearest_distances", counting)
        got = choose_velocity(*args)
    assert got == reference_choose_velocity(*args)
    assert (got.v, got.admissible) == (0.5, 105) and got.omega == pytest.approx(0.6 / 14)
    assert pairs == [(60, 41), (70, 7)]


def test_dwa_global_inscribes_within_half_a_cell_and_dstar_lite_within_its_passage_margin() -> None:
    # the two planners share D* Lite's search but not its follower: dwa_global's inscribed
    # band is the robot radius plus half a cell (DWA keeps its own clearance on the
    # roll-outs), D* Lite's the radius plus passage_margin
    world = BoxWorld.room((4.0, 4.0), [])
    robot = default_robot(radius=0.2)
    obs = observe(world, np.array([1.0, 1.0, 0.0]), np.array([3.0, 3.0]), robot, 0.0, 0.1)
    assert DWAGlobal(cell=0.1).required_clearance(obs) == pytest.approx(0.25)
    assert DStarLite(passage_margin=0.03).required_clearance(obs) == pytest.approx(0.23)


def test_dwa_global_drives_on_to_a_tenth_of_a_metre_of_the_odometric_goal_and_dwa_stops_at_a_fifth() -> None:
    # the robot stops on its odometry; the episode accepts 0.3 m of the true goal, so
    # dwa_global's 0.1 m leaves 0.2 m for the odometry's drift (results/baselines/dwa_global_s16/)
    world = BoxWorld.room((4.0, 4.0), [])
    robot = default_robot()
    goal = np.array([2.15, 2.0])
    obs = observe(world, np.array([2.0, 2.0, 0.0]), goal, robot, 0.0, 0.1)  # 0.15 m short
    planner = DWAGlobal()
    planner.reset(obs, np.random.default_rng(0))
    assert planner.act(obs).v > 0.0
    plain = DWA()
    plain.reset(obs, np.random.default_rng(0))
    cmd = plain.act(obs)
    assert (cmd.v, cmd.omega) == (0.0, 0.0)
    near = observe(world, np.array([2.08, 2.0, 0.0]), goal, robot, 0.1, 0.1)  # 0.07 m short
    cmd = planner.act(near)
    assert (cmd.v, cmd.omega) == (0.0, 0.0)


def test_dwa_global_keeps_dstar_lites_inflation_margin() -> None:
    # one fact, one home: a path down the middle of passages (results/baselines/dwa_global_s16/)
    assert DWAGlobal().settings.inflation_margin == DStarLite().settings.inflation_margin == pytest.approx(0.35)
