"""D* Lite: incremental repair == A* from scratch, inflation, and driving a maze.

Runtime: ~4 s (the maze episode is ~2 s).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from nav_bench.planners.dstar_lite import (
    DStarLite,
    DStarLiteSearch,
    PathRepair,
    astar,
    cell_costs,
    clearance_costs,
    disk,
    obstacle_distance,
)
from nav_bench.testing.harness import BoxWorld, run, wall_world

INF = math.inf


def path_cost(cost: np.ndarray, path: list[tuple[int, int]]) -> float:
    """Cost of a cell path under the planner's rules (asserting each step is legal)."""
    total = 0.0
    for (r0, c0), (r1, c1) in itertools.pairwise(path):
        dr, dc = r1 - r0, c1 - c0
        assert max(abs(dr), abs(dc)) == 1, "steps go to one of the 8 neighbours"
        assert cost[r1, c1] < INF, "never into a lethal cell"
        if dr and dc:
            assert cost[r0 + dr, c0] < INF and cost[r0, c0 + dc] < INF, "no corner cutting"
        total += (math.sqrt(2) if dr and dc else 1.0) * cost[r1, c1]
    return total


@pytest.mark.parametrize("seed", range(6))
def test_incremental_repair_matches_a_star_from_scratch(seed: int) -> None:
    rng = np.random.default_rng(seed)
    h, w = (int(v) for v in rng.integers(15, 45, 2))
    occ = rng.random((h, w)) < 0.2
    occ[:3, :3] = occ[-3:, -3:] = False  # start and goal not walled in from the outset
    cost = cell_costs(occ, 1.0, 4.0)
    start, goal = (0, 0), (h - 1, w - 1)
    cost[start] = cost[goal] = 1.0
    search = DStarLiteSearch(cost, start, goal)
    search.compute()
    checked = 0
    for _ in range(15):
        path = search.path()
        if len(path) > 3:  # the robot advances two cells along its path
            start = path[2]
            search.move_start(start)
        k = int(rng.integers(1, 12))  # a handful of cells change: new walls, freed cells, costs
        rows, cols = rng.integers(0, h, k), rng.integers(0, w, k)
        for r, c in zip(rows, cols, strict=True):
            cost[r, c] = 1.0 if (r, c) in (start, goal) else rng.choice([1.0, 4.0, INF], p=[.5, .3, .2])
        search.set_costs(rows, cols, cost[rows, cols])
        search.compute()
        expected, _ = astar(cost, start, goal)
        if expected == INF:
            assert search.path_cost == INF and search.path() == []
            continue
        assert search.path_cost == pytest.approx(expected, abs=1e-9)
        repaired = search.path()
        assert repaired[0] == start and repaired[-1] == goal
        assert path_cost(cost, repaired) == pytest.approx(expected, abs=1e-9)
        checked += 1
    assert checked >= 3


def test_a_star_on_a_hand_made_grid() -> None:
    cost = np.ones((3, 5))
    cost[0:2, 2] = INF  # a wall with a gap at the top row
    c, path = astar(cost, (0, 0), (0, 4))
    # e.g. (0,0) -diag- (1,1) - (2,1) - (2,2) - (2,3) -diag- (1,4) - (0,4): the diagonals into
    # and out of the gap row would cut past the lethal (1,2), so the gap costs 3 straight steps
    assert c == pytest.approx(2 * math.sqrt(2) + 4.0)
    assert path[0] == (0, 0) and path[-1] == (0, 4) and (2, 2) in path
    assert path_cost(cost, path) == pytest.approx(c)
    search = DStarLiteSearch(cost, (0, 0), (0, 4))
    search.compute()
    assert search.path_cost == pytest.approx(c)
    assert astar(np.full((2, 2), INF), (0, 0), (1, 1))[0] == INF


def test_repair_expands_far_fewer_cells_than_planning_again() -> None:
    # a comb of walls with alternating gaps: a long winding route, expensive to plan anew
    n = 60
    occ = np.zeros((n, n), dtype=bool)
    for c in range(10, n - 5, 10):
        occ[:, c] = True
        gap = slice(n - 8, n) if (c // 10) % 2 else slice(0, 8)
        occ[gap, c] = False
    cost = cell_costs(occ, 1.0, 5.0)
    goal = (n // 2, n - 3)
    search = DStarLiteSearch(cost, (n // 2, 2), goal)
    search.compute()
    repaired, from_scratch = [], []
    for _ in range(6):  # walk 4 cells, then a 5-cell wall appears 8 cells ahead on the path
        path = search.path()
        search.move_start(path[4])
        r, c = path[12]
        rows, cols = np.arange(r - 2, r + 3), np.full(5, c)
        cost[rows, cols] = INF
        search.set_costs(rows, cols, cost[rows, cols])
        repaired.append(search.compute())
        fresh = DStarLiteSearch(cost, path[4], goal)
        from_scratch.append(fresh.compute())
        assert search.path_cost == pytest.approx(fresh.path_cost, abs=1e-9)
    assert max(repaired) < 100 < 2000 < min(from_scratch)


def test_inflation_costs_cells_within_radius_plus_margin() -> None:
    occ = np.zeros((9, 9), dtype=bool)
    occ[4, 4] = True
    cost = cell_costs(occ, 2.0, 10.0)
    assert cost[4, 4] == INF
    assert int(disk(2.0).sum()) == 13  # offsets with |(dr, dc)| <= 2
    assert int((cost == 10.0).sum()) == 12
    assert cost[4, 6] == 10.0 and cost[5, 6] == 1.0  # distance 2 inflated, sqrt(5) not
    # a path past an obstacle keeps out of the inflated band when there is room
    occ = np.zeros((30, 30), dtype=bool)
    occ[5:25, 15] = True
    cost = cell_costs(occ, 3.0, 25.0)
    _c, path = astar(cost, (15, 2), (15, 28))
    cells = np.array(path)
    assert np.all(cost[cells[:, 0], cells[:, 1]] == 1.0)
    occupied = np.argwhere(occ)
    gap = np.hypot(*(cells[:, None, :] - occupied[None, :, :]).transpose(2, 0, 1)).min()
    assert gap > 3.0


def test_planner_costs_match_a_distance_transform_of_the_whole_map() -> None:
    # the planner recomputes distances and costs only in windows around flipped cells
    world, start, goal = wall_world()
    result = run(DStarLite(inflation_margin=0.3, cell=0.1), world, start, goal, time_s=3.0)
    planner = result.planner
    assert planner.inscribed == pytest.approx(0.2 / 0.1)  # the harness robot: radius 0.2 m
    occ = planner.occupied
    assert occ.any()  # the wall is in the map after a few seconds of sonar
    dist = obstacle_distance(occ, planner.cap)
    np.testing.assert_allclose(planner.dist, dist)
    expected = clearance_costs(dist, 2.0, 3.0, 1000.0, 5.0)
    np.testing.assert_array_equal(planner.cost, expected)


@pytest.mark.parametrize("seed", [0, 1])
def test_around_a_wall_with_replans_and_clearance(seed: int) -> None:
    world, start, goal = wall_world()
    result = run(DStarLite(), world, start, goal, time_s=60.0, seed=seed, noise_std=0.01)
    assert result.reached and result.collisions == 0
    assert result.kinds("replan") >= 1
    edge = min(world.clearance(p[:2]) for p in result.poses) - 0.2
    assert edge > 0.05
    assert result.path_length < 9.0  # straight line 6 m; round the wall end ~7.5 m


MAZE = ["#########",
        "#...#...#",
        "###.#.#.#",
        "#...#.#.#",
        "#.###.#.#",
        "#.....#.#",
        "#########"]


def test_reaches_the_goal_of_a_maze() -> None:
    occ = np.array([[ch == "#" for ch in row] for row in MAZE[::-1]])  # row 0 at the bottom
    world = BoxWorld.from_grid(occ, 1.0)  # 1 m corridors
    result = run(DStarLite(), world, (1.5, 5.5, 0.0), (7.5, 1.5), time_s=150.0, noise_std=0.01)
    assert result.reached and result.collisions == 0
    xy = result.poses[:, :2]
    assert (xy[:, 1] < 2.0).any() and (xy[:, 0] > 5.0).any()  # through the bottom corridor
    assert result.kinds("replan") > 10  # each new piece of wall that blocks the route


def test_unreachable_goal_stops_and_says_so() -> None:
    ring = [(5.0, 2.0, 6.6, 2.15), (5.0, 3.45, 6.6, 3.6), (5.0, 2.0, 5.15, 3.6), (6.45, 2.0, 6.6, 3.6)]
    world = BoxWorld.room((9.0, 6.0), ring)
    result = run(DStarLite(), world, (1.0, 2.8, 0.0), (5.8, 2.8), time_s=60.0)
    assert not result.reached and result.collisions == 0
    assert result.kinds("unreachable") >= 1
    assert np.all(result.commands[-10:] == 0.0)
