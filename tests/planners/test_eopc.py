"""EO/PC (nav_bench.planners.eopc): cost terms, Table 1, the selection tiers, EO, the loop.

Hand-built grids: a 4 m x 4 m frame of 0.1 m cells, the breakpoint at the centre of cell
(20, 20) = (2.05, 2.05) m, heading +x. The neighbours at theta = 0, 90, 180, -90 deg
(indices 0, 4, 8, 12) then sit exactly on cell centres, so region A (radius 0.25 m) holds
the 21 cells with i^2 + j^2 <= 6.25.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from nav_bench.errors import InputError
from nav_bench.interface import Command, Observation
from nav_bench.mapping import GridFrame
from nav_bench.planners.eopc import (
    EOPC,
    FrontSonars,
    choose_neighbour,
    collision_risk,
    crossed_cells,
    eo_speed,
    front_distance,
    front_sonars,
    goal_path_blocked,
    heuristic_cost,
    intensity_of_obstacles,
    intensity_of_trajectory,
    iteration_risk,
    neighbour_points,
    old_path_heading,
    region_cells,
    region_radius,
    risk_index,
    select_neighbour,
    square_offsets,
    steer,
    term_scales,
    travel_cost,
)
from nav_bench.planners.goal_seek import GoalSeek
from nav_bench.testing.harness import BoxWorld, default_robot, run, u_world, wall_world

DATA = Path(__file__).resolve().parents[1] / "data" / "eopc"

FRAME = GridFrame.from_bounds((0.0, 0.0, 4.0, 4.0), 0.1)
BP = np.array([2.05, 2.05])
GOAL_AHEAD = np.array([3.55, 2.05])  # 1.5 m straight ahead of the breakpoint
A_CELLS = 21


def grids(pmo: int = 0, pmt: int = 0) -> tuple[np.ndarray, np.ndarray]:
    return np.full(FRAME.shape, pmo, dtype=np.uint8), np.full(FRAME.shape, pmt, dtype=np.int64)


def decide(pmo: np.ndarray, pmt: np.ndarray, goal: np.ndarray = GOAL_AHEAD, **kw: object):
    force = bool(kw.pop("force", False))
    tried = kw.pop("tried", ())
    return choose_neighbour(pmo, pmt, FRAME, BP, 0.0, goal, EOPC.Settings(**kw), tried=tried, force=force)


# ------------------------------------------------------------------ Table 1, quantisation
TABLE_1 = {  # (RI, RC) -> r, as printed in the paper
    (100, 100): 100, (100, 50): 100, (100, 0): 100,
    (50, 100): 100, (50, 50): 50, (50, 0): 50,
    (0, 100): 100, (0, 50): 50, (0, 0): 0,
}


@pytest.mark.parametrize(("ri", "rc"), sorted(TABLE_1))
def test_risk_index_is_table_1(ri: int, rc: int) -> None:
    assert int(risk_index(np.array([rc]), np.array([ri]))[0]) == TABLE_1[(ri, rc)]


def test_rc_and_ri_quantisation_thresholds() -> None:
    assert collision_risk(np.array([0, 34, 35, 50, 65, 66, 100]), 35, 65).tolist() == \
        [0, 0, 50, 50, 50, 100, 100]
    assert iteration_risk(np.array([0, 1, 19, 20, 500]), 20).tolist() == [0, 50, 50, 100, 100]


# ------------------------------------------------------------------ cost terms
def test_neighbours_on_the_circle_with_theta_from_the_heading() -> None:
    pts, theta = neighbour_points(BP, 0.0, 0.5, 16)
    assert np.degrees(theta[[0, 1, 4, 8, 9, 15]]) == pytest.approx([0, 22.5, 90, 180, -157.5, -22.5])
    assert np.all(theta > -math.pi) and np.all(theta <= math.pi)
    assert np.hypot(*(pts - BP).T) == pytest.approx(np.full(16, 0.5))
    assert pts[[0, 4, 8, 12]] == pytest.approx(np.array([[2.55, 2.05], [2.05, 2.55], [1.55, 2.05],
                                                         [2.05, 1.55]]))
    rotated, _ = neighbour_points(BP, math.pi / 2, 0.5, 16)  # theta = 0 follows the heading
    assert rotated[0] == pytest.approx([2.05, 2.55])


def test_travel_and_heuristic_costs() -> None:
    pts, theta = neighbour_points(BP, 0.0, 0.5, 16)
    g = travel_cost(theta, 0.5)
    assert g[[0, 4, 8, 12, 15]] == pytest.approx([0.0, math.pi / 4, math.pi / 2, math.pi / 4, math.pi / 16])
    h = heuristic_cost(pts, GOAL_AHEAD)
    assert h[[0, 4, 8]] == pytest.approx([1.0, math.hypot(1.5, 0.5), 2.0])


def test_region_a_is_the_disc_of_cells_around_each_point() -> None:
    pts, _ = neighbour_points(BP, 0.0, 0.5, 16)
    rows, cols, member = region_cells(FRAME, pts, 0.25)
    assert member.sum(axis=1)[[0, 4, 8, 12]].tolist() == [A_CELLS] * 4
    _, pmt = grids()
    pmt[20, 25] = 7  # P0's own cell
    pmt[22, 25] = 3  # 0.2 m from P0: inside A
    pmt[23, 25] = 100  # 0.3 m from P0: outside A
    ipt = intensity_of_trajectory(pmt, FRAME, rows, cols, member)
    assert ipt[0] == pytest.approx(10.0)
    assert ipt[8] == pytest.approx(0.0)


def test_ipo_sums_obstacle_evidence_or_raw_pmo() -> None:
    pts, _ = neighbour_points(BP, 0.0, 0.5, 16)
    rows, cols, member = region_cells(FRAME, pts, 0.25)
    pmo, _ = grids(pmo=50)
    pmo[20, 26] = 100  # evidence 100
    pmo[21, 25] = 75  # evidence 50
    pmo[19, 25] = 20  # free: evidence 0
    evidence = intensity_of_obstacles(pmo, FRAME, rows, cols, member, "evidence")
    raw = intensity_of_obstacles(pmo, FRAME, rows, cols, member, "raw")
    assert evidence[0] == pytest.approx(150.0)
    assert raw[0] == pytest.approx(18 * 50 + 100 + 75 + 20)
    assert evidence[8] == pytest.approx(0.0) and raw[8] == pytest.approx(A_CELLS * 50)


def test_region_cells_outside_the_grid_count_as_unknown_and_unvisited() -> None:
    frame = GridFrame.from_bounds((0.0, 0.0, 1.0, 1.0), 0.1)
    pts = np.array([[0.05, 0.05]])  # a corner cell: most of A lies outside
    rows, cols, member = region_cells(frame, pts, 0.25)
    pmo = np.zeros(frame.shape, dtype=np.uint8)
    inside = 8  # cells (i, j) >= 0 with i^2 + j^2 <= 6.25
    assert intensity_of_obstacles(pmo, frame, rows, cols, member, "raw")[0] == \
        pytest.approx((A_CELLS - inside) * 50)
    assert intensity_of_obstacles(pmo, frame, rows, cols, member, "evidence")[0] == 0
    assert intensity_of_trajectory(np.ones(frame.shape), frame, rows, cols, member)[0] == inside


def test_f_adds_the_raw_terms_with_unit_weights() -> None:
    pmo, pmt = grids(pmo=50)
    pmo[20, 26] = 100
    pmt[20, 25] = 7
    pmt[22, 25] = 3
    d = decide(pmo, pmt, exclude_blocked_segments=False)
    assert (d.G[0], d.H[0], d.IPO[0], d.IPT[0]) == pytest.approx((0.0, 1.0, 100.0, 10.0))
    assert (d.RC[0], d.RI[0], d.r[0]) == (50, 50, 50)
    assert d.F[0] == pytest.approx(0.0 + 1.0 + 100.0 + 10.0 + 50.0)
    weighted = decide(pmo, pmt, exclude_blocked_segments=False, w_g=2, w_h=3, w_ipo=0.5, w_ipt=0.1, w_r=0)
    assert weighted.F[4] == pytest.approx(2 * math.pi / 4 + 3 * math.hypot(1.5, 0.5))


def test_normalize_divides_each_term_by_its_largest_value() -> None:
    pmo, pmt = grids(pmo=50)
    pmo[20, 26] = 100
    pmt[20, 25] = 7
    pmt[22, 25] = 3
    d = decide(pmo, pmt, exclude_blocked_segments=False, normalize=True)
    expected = 0.0 + 1.0 / (1.5 + 0.5) + 100.0 / (A_CELLS * 100) + 10.0 / (A_CELLS * 20) + 50 / 100
    assert d.F[0] == pytest.approx(expected)
    scales = term_scales(EOPC.Settings(), BP, GOAL_AHEAD, np.array([A_CELLS]))
    assert scales["G"] == pytest.approx(0.5 * math.pi) and scales["r"] == 100


# ------------------------------------------------------------------ selection tiers
def test_tier_1_all_free_takes_the_straight_line() -> None:
    d = decide(*grids())
    assert (d.tier, d.chosen) == (1, 0) and d.turn == 0.0
    assert np.all(d.r == 0) and np.all(d.candidate)


def test_tier_1_takes_smallest_f_among_safe_points() -> None:
    pmo, pmt = grids()
    pmt[:, 23:29] = 100  # the way ahead is worn out: RI 100 and a large IPT
    d = decide(pmo, pmt)
    assert d.r[0] == 100 and d.r[4] == 0 and d.IPT[4] == 0
    assert (d.tier, d.chosen) == (1, 4)  # +90 deg: ties with -90 go to the lower index (left)
    assert d.F[4] == pytest.approx(math.pi / 4 + math.hypot(1.5, 0.5))


def test_tier_2_takes_smallest_ri_then_smallest_f() -> None:
    pmo, pmt = grids()
    pmt[:] = 25  # RI 100 everywhere ...
    pmt[20, 15] = 3  # ... but behind (theta 180) only a little visited: RI 50
    d = decide(pmo, pmt)
    assert not np.any(d.r == 0)
    assert (d.tier, d.chosen) == (2, 8)  # higher F than straight ahead, but lower RI
    pmt[25, 20] = 3  # +90 deg also RI 50, and its F is lower than behind
    d = decide(pmo, pmt)
    assert (d.tier, d.chosen) == (2, 4) and d.F[4] < d.F[8]


def test_tier_2_accepts_a_high_iteration_risk_in_extreme_cases() -> None:
    # every neighbour visited too often, all free; IPT off so F is G + H + r
    d = decide(*grids(pmt=25), w_ipt=0)
    assert np.all(d.RI == 100)
    assert (d.tier, d.chosen) == (2, 0)


def test_tier_2_needs_rc_below_beta() -> None:
    pmo, pmt = grids(pmo=50, pmt=25)  # all unknown (RC 50) and worn (RI 100)
    assert decide(pmo, pmt, exclude_blocked_segments=False).tier == 2
    d = decide(pmo, pmt, exclude_blocked_segments=False, beta_I=50)
    assert (d.tier, d.chosen) == (3, None)


def test_tier_3_blocked_keeps_heading_until_forced() -> None:
    pmo, pmt = grids(pmo=100)
    pmo[20, 20] = 0  # the robot's own cell
    d = decide(pmo, pmt)
    assert np.all(d.r == 100) and not d.candidate.any()
    assert (d.tier, d.chosen, d.turn, d.forced) == (3, None, 0.0, False)
    forced = decide(pmo, pmt, force=True, w_ipo=0)
    assert (forced.tier, forced.chosen, forced.forced) == (3, 0, True)


def test_select_neighbour_forced_prefers_candidates_then_untried() -> None:
    r = np.array([100, 100, 100])
    rc = np.array([100, 100, 100])
    ri = np.zeros(3, dtype=int)
    F = np.array([1.0, 2.0, 3.0])
    cand = np.array([False, False, True])
    assert select_neighbour(r, rc, ri, F, cand, 100, np.ones(3, bool), force=True) == (2, 3)
    none = np.zeros(3, bool)
    assert select_neighbour(r, rc, ri, F, none, 100, np.array([False, True, True]), True) == (1, 3)
    assert select_neighbour(r, rc, ri, F, none, 100, none, True) == (0, 3)
    assert select_neighbour(r, rc, ri, F, none, 100, none, False) == (None, 3)


def test_a_neighbour_behind_an_occupied_cell_is_never_chosen() -> None:
    pmo, pmt = grids()
    pmo[18:23, 23] = 100  # a short wall 0.3 m ahead, across the three forward segments
    d = decide(pmo, pmt, w_ipo=0)  # IPO off: only the segment rule keeps the robot off it
    assert d.RC[[0, 1, 15]].tolist() == [0, 0, 0]  # the points themselves look free ...
    assert not d.candidate[[0, 1, 15]].any()  # ... but the robot cannot get there
    assert d.candidate[[2, 14]].all()
    assert d.chosen in (2, 14)
    for goal in ([3.55, 2.05], [3.0, 2.4], [3.0, 1.7], [2.6, 2.1]):
        assert decide(pmo, pmt, goal=np.array(goal), w_ipo=0).chosen not in (0, 1, 15), goal
    assert decide(pmo, pmt, w_ipo=0, exclude_blocked_segments=False).chosen == 0


def test_neighbours_beyond_the_map_are_not_candidates() -> None:
    pmo, pmt = grids()
    d = choose_neighbour(pmo, pmt, FRAME, np.array([3.75, 2.05]), 0.0, np.array([5.0, 2.05]),
                         EOPC.Settings())
    assert d.RC[0] == 100 and not d.candidate[0]  # (4.25, 2.05) is outside the 4 m grid
    assert d.chosen not in (0, 1, 15)


def test_points_already_tried_are_not_candidates() -> None:
    pmo, pmt = grids()
    first = decide(pmo, pmt)
    again = decide(pmo, pmt, tried=[first.points[first.chosen]])
    assert not again.candidate[first.chosen] and again.tried.sum() == 1
    assert again.chosen != first.chosen


def test_the_replan_event_is_plain_json() -> None:
    d = decide(*grids())
    data = json.loads(json.dumps(d.replan_event(0.0, "eo_stop", "heading").data()))
    assert len(data["neighbours"]) == 16 and len(data["risk"]) == 16
    assert data["chosen"] == 0 and data["tier"] == 1 and data["candidate"] == [True] * 16


def test_the_replan_event_holds_the_decision_rounded_to_1e_6() -> None:
    d = decide(*grids())
    data = d.replan_event(0.0, "eo_stop", "heading").data()
    assert data["neighbours"] == [[round(float(x), 6), round(float(y), 6)] for x, y in d.points]
    assert data["risk"] == [int(v) for v in d.r] and data["rc"] == [int(v) for v in d.RC]
    assert data["F"] == [round(float(v), 6) for v in d.F]
    assert all(type(v) is int for v in data["risk"] + data["ri"])


def test_square_offsets_are_the_raveled_mgrid() -> None:
    dr, dc = square_offsets(2)
    mr, mc = np.mgrid[-2:3, -2:3]
    assert dr.tolist() == mr.ravel().tolist() and dc.tolist() == mc.ravel().tolist()
    assert not dr.flags.writeable


# ------------------------------------------------------------------ EO
def test_eo_speed_ramp_at_and_between_the_thresholds() -> None:
    v = lambda d, v_min=0.0: eo_speed(d, 0.5, 0.8, 0.35, v_min)  # noqa: E731
    assert v(2.0) == 0.5 and v(0.8) == 0.5
    assert v(0.575) == pytest.approx(0.25)  # half way: half speed
    assert v(0.44) == pytest.approx(0.1)
    assert v(0.35) == 0.0 and v(0.349) == 0.0
    assert v(0.36, v_min=0.05) == pytest.approx(0.05)  # the floor that lets the robot reach lambda2
    assert v(0.349, v_min=0.05) == 0.0


def test_front_distance_is_measured_from_the_robot_centre() -> None:
    robot = default_robot()  # sonars on the body edge, 0.2 m from the centre
    front = front_sonars(robot.sonar, math.radians(100))
    assert front.tolist() == [False, True, True, True, True, False]
    ranges = np.array([0.1, 1.0, 0.5, 0.6, 3.0, 0.05])
    assert front_distance(ranges, robot.sonar, front) == pytest.approx(0.7)
    assert front_sonars(robot.sonar, math.radians(20)).tolist() == [False] * 6


def _echo_points_distance(ranges: np.ndarray, sonar, front: np.ndarray) -> float:
    """The front distance written out as the docstring states it: each echo placed at
    ``offset + range * axis`` in the robot frame, no echo as max_range, the nearest taken."""
    if not front.any():
        return math.inf
    r = np.where(np.isfinite(ranges), np.minimum(ranges, sonar.max_range), sonar.max_range)[front]
    a, off = sonar.angles[front], sonar.offsets[front]
    return float(np.min(np.hypot(off[:, 0] + r * np.cos(a), off[:, 1] + r * np.sin(a))))


def test_front_distance_is_the_nearest_echo_point_bit_for_bit() -> None:
    # EO/PC and goal_seek keep the front sonars' geometry (FrontSonars) and ask it every
    # cycle: exactly the echo-point formula, no-echo, infinite and NaN readings included
    robot = default_robot()
    rng = np.random.default_rng(4)
    for fov in (100.0, 40.0, 360.0, 10.0):
        front = front_sonars(robot.sonar, math.radians(fov))
        geometry = FrontSonars.of(robot.sonar, front)
        for _ in range(200):
            ranges = rng.uniform(0.0, 3.5, 6)
            ranges[rng.random(6) < 0.2] = robot.sonar.max_range
            ranges[rng.random(6) < 0.05] = rng.choice([np.inf, np.nan])
            expected = _echo_points_distance(ranges, robot.sonar, front)
            for got in (geometry.distance(ranges), front_distance(ranges, robot.sonar, front)):
                assert got == expected or (math.isnan(expected) and math.isnan(got))
    assert FrontSonars.of(robot.sonar, front_sonars(robot.sonar, 0.0)).distance(np.ones(6)) == math.inf


def test_steer_is_np_clip_of_the_proportional_rate() -> None:
    for error in (0.0, -0.0, 0.3, -0.3, 2.0, -2.0, 1e300, -math.inf, math.inf):
        for gain, limit in ((1.5, 1.0), (0.5, 0.2), (2.0, 0.0)):
            got = steer(error, gain, limit)
            assert got == float(np.clip(gain * error, -limit, limit))
            assert math.copysign(1.0, got) == math.copysign(1.0, float(np.clip(gain * error, -limit, limit)))
    assert math.isnan(steer(math.nan, 1.0, 1.0))


# ------------------------------------------------------------------ the planner loop
def observation(pose, ranges, goal=(8.0, 2.0), t=0.0) -> Observation:
    return Observation(t=t, pose=np.asarray(pose, dtype=float), goal=np.asarray(goal, dtype=float),
                       ranges=np.asarray(ranges, dtype=float), robot=default_robot(),
                       bounds=(0.0, 0.0, 10.0, 4.0), dt=0.1)


def test_grids_are_updated_before_the_goal_check() -> None:
    planner = EOPC()
    obs = observation((8.05, 2.05, 0.0), [3.0] * 6)
    planner.reset(obs, np.random.default_rng(0))
    assert planner.act(obs) == Command(0.0, 0.0)  # at the goal: stop ...
    state = planner.debug_state()
    r, c = planner.pmt.world_to_cell((8.05, 2.05))
    assert state["pmt"][r, c] == 1 and (state["pmo"] < 50).any()  # ... after mapping the cycle
    assert state["mode"] == "goal" and state["target"] == [8.0, 2.0]
    assert state["pmo"].dtype == np.uint8 and state["cell"] == 0.1
    assert state["bounds"] == pytest.approx([-0.2, -0.2, 10.2, 4.2])  # world + map_margin


def test_stop_before_a_wall_replans_and_turns_in_place_toward_pi() -> None:
    world = BoxWorld.room((8.0, 6.0), [(4.0, 1.0, 4.15, 5.0)])
    planner = EOPC()
    result = run(planner, world, (1.0, 3.0, 0.0), (7.0, 3.0), time_s=14.0)
    replans = [(t, d) for k, t, d in result.events if k == "replan"]
    assert replans and planner.replans == len(replans)
    t0, first = replans[0]
    bx, by = first["breakpoint"]
    assert 4.0 - bx == pytest.approx(0.35, abs=0.03)  # stopped at lambda2 from the wall face
    assert by == pytest.approx(3.0, abs=0.01)
    assert first["tier"] in (1, 2) and first["candidate"][first["chosen"]]
    assert not first["candidate"][0]  # straight on is through the wall
    json.dumps(first)
    k = round(t0 / 0.1)  # commands right after the re-plan: turning on the spot
    turn = result.commands[k:k + 5]
    assert np.all(turn[:, 0] == 0.0)
    assert np.all(np.sign(turn[:, 1]) == np.sign(first["theta"][first["chosen"]]))
    assert result.collisions == 0


def test_a_boxed_in_robot_tries_each_direction_once_then_waits_blocked() -> None:
    """Every sonar reads 0.1 m whatever the heading: each re-plan on the spot must pick a new
    point (no zero-motion loop on one choice), and blocked cycles are counted in between."""
    planner = EOPC(max_blocked_cycles=2)
    pose = np.array([5.05, 2.05, 0.0])
    planner.reset(observation(pose, [0.1] * 6), np.random.default_rng(0))
    for k in range(600):  # the robot can only turn: integrate yaw, keep x, y
        cmd = planner.act(observation(pose, [0.1] * 6, t=k * 0.1))
        assert cmd.v == 0.0
        pose[2] = math.remainder(pose[2] + cmd.omega * 0.1, 2 * math.pi)
    events = planner.pop_events()
    chosen = [tuple(np.round(e.data["neighbours"][e.data["chosen"]], 2)) for e in events
              if e.kind == "replan"]
    assert len(chosen) >= 16
    assert len(set(chosen[:16])) == 16  # all 16 directions, none twice
    assert sum(e.kind == "blocked" for e in events) >= 2 * 16


def test_parameters_and_settings() -> None:
    assert region_radius(EOPC().settings) == pytest.approx(0.25)  # 0 means RR/2
    assert region_radius(EOPC(RR=0.6, region_radius=0.4).settings) == 0.4
    assert EOPC(RR=0.6).settings.RR == 0.6 and EOPC(RR=0.6).p["RR"] == 0.6  # p: read-only view
    with pytest.raises(TypeError):
        EOPC().p["RR"] = 0.7
    with pytest.raises(InputError, match="lambda"):
        EOPC(lambda_1=0.9)
    with pytest.raises(InputError):
        EOPC(ipo_mode="sum")
    with pytest.raises(InputError, match="lambda1 > lambda2"):  # at construction, not in reset
        EOPC(lambda1=0.3)
    assert all(p.unit is not None and p.doc for p in EOPC.params)


# ------------------------------------------------------------------ escaping a dead end
def u_pocket() -> BoxWorld:
    """A U open toward the start: 1.0 m wide inside, arms 0.7 m long, the goal behind its
    bottom. Driving at the goal puts the whole robot inside the U."""
    return BoxWorld.room((8.0, 8.0), [(5.0, 3.35, 5.15, 4.65),   # bottom
                                      (4.3, 3.35, 5.15, 3.5),    # lower arm
                                      (4.3, 4.5, 5.15, 4.65)])   # upper arm


def test_eopc_escapes_a_u_shaped_dead_end() -> None:
    result = run(EOPC(), u_pocket(), (2.0, 4.0, 0.0), (7.0, 4.0), time_s=300.0)
    inside = (result.poses[:, 0] > 4.4) & (np.abs(result.poses[:, 1] - 4.0) < 0.5)
    assert inside.any()  # it went into the U ...
    assert result.reached  # ... and out again, round it to the goal
    assert result.kinds("replan") >= 3 and result.collisions == 0


def test_goal_seek_stays_trapped_in_the_same_u() -> None:
    result = run(GoalSeek(), u_pocket(), (2.0, 4.0, 0.0), (7.0, 4.0), time_s=60.0)
    assert not result.reached
    assert result.poses[-1, 0] == pytest.approx(5.0 - 0.35 - 0.0, abs=0.05)


# ------------------------------------------------------------------ when PC runs: blocked path
def line_grid(value: int = 0) -> np.ndarray:
    """FRAME-sized PMO, all ``value``; the tests draw on row 20 (y = 2.05), the line BP -> goal."""
    return np.full(FRAME.shape, value, dtype=np.uint8)


def test_crossed_cells_are_the_cells_the_segment_passes_through_in_order() -> None:
    # slope 1/3 from the centre of cell (0, 0); through the corner at (0.2, 0.1), whose two
    # corner-touched cells (0, 2) and (1, 1) the segment does not enter
    cells = crossed_cells(FRAME, np.array([0.05, 0.05]), np.array([0.35, 0.15]))
    assert cells.tolist() == [[0, 0], [0, 1], [1, 2], [1, 3]]
    assert crossed_cells(FRAME, np.array([1.05, 2.05]), np.array([1.05, 2.05])).tolist() == [[20, 10]]
    assert crossed_cells(FRAME, np.array([0.35, 0.05]), np.array([0.05, 0.05])).tolist() == [
        [0, 3], [0, 2], [0, 1], [0, 0]]


def test_goal_path_is_blocked_only_by_occupied_cells_on_the_segment() -> None:
    goal = np.array([3.55, 2.05])
    pmo = line_grid(0)
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0) is False
    pmo[20, 30] = 66  # just above occupied_above, on the line (x = 3.05)
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0) is True
    pmo[20, 30] = 65  # at the threshold: RC = 50, not occupied
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0) is False
    pmo[20, 36] = 100  # beyond the goal (x = 3.65): not on the segment
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0) is False


def test_unknown_cells_and_the_world_beyond_the_grid_never_block() -> None:
    pmo = line_grid(50)  # nothing seen yet
    assert goal_path_blocked(pmo, FRAME, BP, np.array([3.55, 2.05]), 65.0) is False
    assert goal_path_blocked(line_grid(0), FRAME, BP, np.array([9.0, 2.05]), 65.0) is False  # leaves the grid


def test_the_robots_own_cell_does_not_block() -> None:
    pmo = line_grid(0)
    pmo[20, 20] = 100  # the breakpoint's cell: sonar noise under the robot
    assert goal_path_blocked(pmo, FRAME, BP, np.array([3.55, 2.05]), 65.0) is False


def test_corridor_mode_sees_an_obstacle_beside_the_line_that_the_segment_misses() -> None:
    pmo = line_grid(0)
    pmo[22, 28] = 100  # centre (2.85, 2.25): 0.2 m beside the line, cells 0.15..0.25 m off it
    goal = np.array([3.55, 2.05])
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0, half_width=0.0) is False
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0, half_width=0.18) is True
    assert goal_path_blocked(pmo, FRAME, BP, goal, 65.0, half_width=0.1) is False


def test_old_path_heading_is_the_direction_of_the_segment_just_driven() -> None:
    assert old_path_heading(np.array([1.0, 1.0]), np.array([1.5, 1.5]), 0.3) == pytest.approx(math.pi / 4)
    assert old_path_heading(np.array([1.0, 1.0]), np.array([0.5, 1.0]), 0.3) == pytest.approx(math.pi)
    assert old_path_heading(None, np.array([0.5, 1.0]), 0.3) == 0.3  # no old path: the heading
    assert old_path_heading(np.array([0.5, 1.0]), np.array([0.5, 1.0]), 0.3) == 0.3


def arrived_at_pi(wall_x: float | None, replan_on: str = "blocked_path") -> tuple[EOPC, Command]:
    """An EOPC that chose Pi = (3.05, 2.05) at the breakpoint (2.55, 1.55) and now stands on Pi
    facing 45 deg, with no echo in range; ``wall_x``: PMO cells certainly occupied across the
    line to the goal (8.05, 2.05) at that x, 3.5 m away: beyond the 3 m sonars, so this
    cycle's free readings cannot clear them."""
    planner = EOPC(replan_on=replan_on)
    pose = np.array([3.05, 2.05, math.pi / 4])
    obs = observation(pose, [3.0] * 6, goal=(8.05, 2.05))
    planner.reset(obs, np.random.default_rng(0))
    if wall_x is not None:
        r0, c = planner.pmo.frame.world_to_cell((wall_x, 1.0))
        r1, _ = planner.pmo.frame.world_to_cell((wall_x, 3.0))
        planner.pmo._log_odds[r0:r1 + 1, c] = planner.pmo.l_max
        planner.pmo._values[r0:r1 + 1, c] = 97
    planner.mode, planner._target = "to_point", np.array([3.05, 2.05])
    planner._chain_from = np.array([2.55, 1.55])
    return planner, planner.act(obs)


def test_arriving_at_pi_with_the_goal_path_blocked_is_a_breakpoint_measured_from_the_old_path() -> None:
    planner, cmd = arrived_at_pi(wall_x=6.55)
    (event,) = planner.pop_events()
    assert event.kind == "replan" and planner.replans == 1
    assert event.data["trigger"] == "blocked_path" and event.data["theta_from"] == "old_path"
    assert event.data["breakpoint"] == pytest.approx([3.05, 2.05])
    assert event.data["heading"] == pytest.approx(math.pi / 4, abs=1e-6)  # (2.55, 1.55) -> Pi
    theta0 = np.asarray(event.data["neighbours"][0])  # theta = 0 continues the old path
    assert theta0 == pytest.approx([3.05 + 0.5 * math.cos(math.pi / 4), 2.05 + 0.5 * math.sin(math.pi / 4)],
                                   abs=1e-6)
    chosen = event.data["chosen"]
    # a candidate chosen by the rules (no wall within 3 m); Y turns from the robot's own yaw
    assert event.data["tier"] in (1, 2) and event.data["candidate"][chosen]
    assert planner.mode in ("turn", "to_point")
    aim = math.atan2(*(np.asarray(event.data["neighbours"][chosen]) - [3.05, 2.05])[::-1])
    assert planner._turn_goal == pytest.approx(math.remainder(aim - math.pi / 4, 2 * math.pi), abs=1e-6)
    assert cmd.v == 0.0


def test_arriving_at_pi_with_a_clear_line_hands_back_to_the_goal() -> None:
    planner, cmd = arrived_at_pi(wall_x=None)
    assert planner.pop_events() == [] and planner.mode == "goal"
    assert planner.debug_state()["target"] == [8.05, 2.05]
    # the goal lies 45 deg to the right, within align_deg: drive on at v_max*cos(45 deg), turning right
    assert cmd == Command(pytest.approx(0.5 * math.cos(math.pi / 4)), -1.0)


def test_the_stop_reading_heads_for_the_goal_even_when_pmo_blocks_the_line() -> None:
    planner, _ = arrived_at_pi(wall_x=6.55, replan_on="stop")
    assert planner.pop_events() == [] and planner.mode == "goal"


@pytest.mark.parametrize("case", ["wall", "u", "u_noisy"])
def test_replan_on_stop_retraces_the_first_readings_trajectory(case: str) -> None:
    """``replan_on: stop`` is the project's first reading, kept exactly: the reference poses and
    commands were recorded with the code before ``replan_on`` existed (same generator, seed 3),
    and before issue 12's Elfes sonar model: the three-band model they were recorded with is pinned."""
    world, start, goal = {"wall": wall_world, "u": u_world, "u_noisy": u_world}[case]()
    time_s = {"wall": 120.0, "u": 200.0, "u_noisy": 200.0}[case]
    result = run(EOPC(replan_on="stop", sonar_model="band"), world, start, goal, time_s=time_s, seed=3,
                 noise_std=0.01 if case == "u_noisy" else 0.0)
    reference = np.load(DATA / "stop_reading_reference.npz")
    np.testing.assert_allclose(result.poses, reference[f"{case}_poses"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(result.commands, reference[f"{case}_commands"], rtol=0, atol=1e-9)


def test_blocked_path_leaves_the_u_that_the_stop_reading_cannot() -> None:
    world, start, goal = u_world()
    chained = run(EOPC(), world, start, goal, time_s=300.0, seed=3)
    assert chained.reached and chained.collisions == 0
    triggers = [d["trigger"] for k, _, d in chained.events if k == "replan"]
    assert triggers.count("blocked_path") > triggers.count("eo_stop") >= 1
    stop_only = run(EOPC(replan_on="stop"), world, start, goal, time_s=300.0, seed=3)
    assert not stop_only.reached


def test_unknown_replan_on_is_refused_with_the_allowed_values() -> None:
    with pytest.raises(InputError, match=r"replan_on.*\['blocked_path', 'stop'\]"):
        EOPC(replan_on="sometimes")
