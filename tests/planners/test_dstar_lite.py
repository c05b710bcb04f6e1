"""D* Lite: incremental repair == A* from scratch, inflation, and driving a maze.

Runtime: ~4 s (the maze episode is ~2 s).
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from nav_bench.episode.loop import run_episode
from nav_bench.interface import Command, Observation, StuckReason
from nav_bench.planners.dstar_lite import (
    CLEARANCE_POWER,
    DStarLite,
    DStarLiteSearch,
    PathRepair,
    _queue_key,
    astar,
    cell_costs,
    clearance_costs,
    disk,
    load_kernels,
    make_search,
    obstacle_distance,
    uniform_costs_to_go,
)
from nav_bench.planners.footprint import GuardSettings, echo_blocks, guard, rollout
from nav_bench.specs import PlannerSetSpec
from nav_bench.testing.harness import BoxWorld, default_robot, run, wall_world
from nav_bench.world.load import load_world

ROOT = Path(__file__).resolve().parents[2]

INF = math.inf


@pytest.fixture(params=["python", pytest.param("numba", marks=pytest.mark.skipif(
    load_kernels() is None, reason="numba is not installed (the 'fast' extra)"))])
def kernel(request: pytest.FixtureRequest) -> str:
    """The search's loops (DStarLite's search_kernel): every search test runs on both."""
    return request.param


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
def test_incremental_repair_matches_a_star_from_scratch(seed: int, kernel: str) -> None:
    rng = np.random.default_rng(seed)
    h, w = (int(v) for v in rng.integers(15, 45, 2))
    occ = rng.random((h, w)) < 0.2
    occ[:3, :3] = occ[-3:, -3:] = False  # start and goal not walled in from the outset
    cost = cell_costs(occ, 1.0, 4.0)
    start, goal = (0, 0), (h - 1, w - 1)
    cost[start] = cost[goal] = 1.0
    search = make_search(cost, start, goal, kernel=kernel)
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


def test_a_star_on_a_hand_made_grid(kernel: str) -> None:
    cost = np.ones((3, 5))
    cost[0:2, 2] = INF  # a wall with a gap at the top row
    c, path = astar(cost, (0, 0), (0, 4))
    # e.g. (0,0) -diag- (1,1) - (2,1) - (2,2) - (2,3) -diag- (1,4) - (0,4): the diagonals into
    # and out of the gap row would cut past the lethal (1,2), so the gap costs 3 straight steps
    assert c == pytest.approx(2 * math.sqrt(2) + 4.0)
    assert path[0] == (0, 0) and path[-1] == (0, 4) and (2, 2) in path
    assert path_cost(cost, path) == pytest.approx(c)
    search = make_search(cost, (0, 0), (0, 4), kernel=kernel)
    search.compute()
    assert search.path_cost == pytest.approx(c)
    assert astar(np.full((2, 2), INF), (0, 0), (1, 1))[0] == INF


def test_repair_expands_far_fewer_cells_than_planning_again(kernel: str) -> None:
    # a comb of walls with alternating gaps: a long winding route, expensive to plan anew
    n = 60
    occ = np.zeros((n, n), dtype=bool)
    for c in range(10, n - 5, 10):
        occ[:, c] = True
        gap = slice(n - 8, n) if (c // 10) % 2 else slice(0, 8)
        occ[gap, c] = False
    cost = cell_costs(occ, 1.0, 5.0)
    goal = (n // 2, n - 3)
    search = make_search(cost, (n // 2, 2), goal, kernel=kernel)
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
        fresh = make_search(cost, path[4], goal, kernel=kernel)
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
    result = run(DStarLite(inflation_margin=0.3, cell=0.1, passage_margin=0.05, clearance_cost=5.0),
                 world, start, goal, time_s=3.0)
    planner = result.planner
    # the harness robot's radius 0.2 m plus passage_margin: inscribed where no point of the cell
    # keeps that much from the occupied cells
    assert planner.inscribed == pytest.approx((0.2 + 0.05) / 0.1)
    occ = planner.occupied
    assert occ.any()  # the wall is in the map after a few seconds of sonar
    dist = obstacle_distance(occ, planner.cap)
    np.testing.assert_allclose(planner.dist, dist)
    expected = clearance_costs(dist, 2.5, 3.0, 1000.0, 5.0)
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
    # the goal inside a closed ring: each loss of the path is met by a recovery (rotate to
    # re-sense, clear the map when still no path) until the no-path recoveries are used up
    ring = [(5.0, 2.0, 6.6, 2.15), (5.0, 3.45, 6.6, 3.6), (5.0, 2.0, 5.15, 3.6), (6.45, 2.0, 6.6, 3.6)]
    world = BoxWorld.room((9.0, 6.0), ring)
    result = run(DStarLite(no_path_recoveries=1), world, (1.0, 2.8, 0.0), (5.8, 2.8), time_s=90.0)
    assert not result.reached and result.collisions == 0
    assert result.kinds("unreachable") >= 2  # lost, recovered (the map cleared), lost for good
    phases = [e[2]["phase"] for e in result.events if e[0] == "recovery"]
    assert phases[:3] == ["rotate", "clear_map", "replan"]  # the one no-path recovery allowed
    assert phases.count("clear_map") == 1
    assert np.all(result.commands[-10:] == 0.0)
    assert result.planner.stuck_reason() is StuckReason.NO_PATH


# --------------------------------------------------------------------------- clearance cost
def test_clearance_cost_puts_the_path_down_the_middle_of_a_corridor() -> None:
    # a 0.9 m corridor (rows 1..9 free between walls in rows 0 and 10), 0.1 m cells, robot
    # radius 0.2 m (2 cells), margin 0.35 m: row 5 is 5 cells from both walls, the cheapest
    occ = np.zeros((11, 40), dtype=bool)
    occ[0, :] = occ[10, :] = True
    dist = obstacle_distance(occ, 6.5)
    np.testing.assert_allclose(dist[:, 20], [0, 1, 2, 3, 4, 5, 4, 3, 2, 1, 0])
    cost = clearance_costs(dist, 2.0, 3.5, 1000.0, 5.0)
    assert cost[0, 0] == INF and cost[2, 0] == 1000.0  # occupied; inscribed (2 cells)
    assert cost[5, 0] == pytest.approx(1.0 + 4.0 * (0.5 / 3.5) ** CLEARANCE_POWER, abs=1 / 128)
    assert cost[3, 0] > cost[4, 0] > cost[5, 0] >= 1.0
    _c, path = astar(cost, (3, 1), (7, 38))  # from off-centre to off-centre
    middle = [rc for rc in path if 6 <= rc[1] <= 33]
    assert middle == [(5, c) for c in range(6, 34)]
    # the binary band it replaces leaves the path anywhere inside rows 4..6
    band = cell_costs(occ, 3.5, 1000.0)
    assert np.all(band[4:7, 0] == 1.0)


# --------------------------------------------------------------------------- time slicing
@pytest.mark.parametrize("seed", range(8))
def test_time_sliced_repair_ends_with_the_cost_of_a_star_from_scratch(seed: int, kernel: str) -> None:
    rng = np.random.default_rng(100 + seed)
    h, w = (int(v) for v in rng.integers(20, 50, 2))
    occ = rng.random((h, w)) < 0.15
    occ[:4, :4] = occ[-4:, -4:] = False
    start, goal = (1, 1), (h - 2, w - 2)

    def costs(o: np.ndarray) -> np.ndarray:
        c = clearance_costs(obstacle_distance(o, 5.0), 1.5, 2.5, 50.0, 4.0)
        c[start] = c[goal] = 1.0
        return c

    cost = costs(occ)
    repair = PathRepair(cost, start, goal, budget=7, lethal=50.0, kernel=kernel)
    checked = 0
    for _ in range(12):
        cells = repair.cells
        if repair.complete and len(cells) > 3:
            start = cells[2]
        new_occ = occ.copy()
        k = int(rng.integers(1, 6))
        new_occ[rng.integers(0, h, k), rng.integers(0, w, k)] ^= True
        new_occ[start] = new_occ[goal] = False
        new = costs(new_occ)
        rr, cc = np.nonzero(new != cost)
        occ, cost = new_occ, new
        repair.cycle(start, rr, cc, cost[rr, cc])
        cycles = 1
        while not repair.complete:  # the budget spreads the repair over several cycles
            for rc in repair.cells[1:]:
                assert cost[rc] < 50.0, "an unfinished repair never offers a lethal/inscribed cell"
            repair.cycle(start)
            cycles += 1
        expected, _ = astar(cost, start, goal)
        if expected == INF:
            assert repair.cells == []
            continue
        assert repair.search.path_cost == pytest.approx(expected, abs=1e-6)
        assert path_cost(cost, repair.cells) == pytest.approx(expected, abs=1e-6)
        checked += cycles > 1
    assert checked >= 3


def test_a_robot_moving_along_its_path_only_advances_an_offset(kernel: str) -> None:
    cost = np.ones((10, 30))
    repair = PathRepair(cost, (5, 0), (5, 29), kernel=kernel)
    first = repair.full_path
    version = repair.version
    repair.cycle((5, 3))
    assert repair.version == version and repair.full_path is first  # no new extraction
    assert repair.cells == [(5, c) for c in range(3, 30)]
    repair.cycle((6, 5))  # off the path: the descent rejoins it
    assert repair.cells[0] == (6, 5) and repair.cells[-1] == (5, 29)
    assert path_cost(cost, repair.cells) == pytest.approx(astar(cost, (6, 5), (5, 29))[0])


def test_the_points_followed_are_the_cells_ahead_in_world_coordinates() -> None:
    """Each cycle the follower's points (a slice of the full path's, PathRepair.span) are the
    cells ahead converted anew, bit for bit, also while a small budget leaves repairs
    unfinished (the safe prefix of the old path)."""

    class Checked(DStarLite):
        cycles = stale = 0

        def update_path(self, obs: Observation) -> bool:
            out = super().update_path(obs)
            expected = self._to_world(self.repair.cells)
            assert self.path_xy.shape == expected.shape and np.array_equal(self.path_xy, expected)
            Checked.cycles += 1
            Checked.stale += self.repair.stale
            return out

    world, start, goal = wall_world()
    result = run(Checked(expansions_per_cycle=20), world, start, goal, time_s=40.0, noise_std=0.01)
    assert result.reached
    assert Checked.cycles > 100 and Checked.stale > 5


# --------------------------------------------------------------------------- planning at once, splicing
def consistent(search: DStarLiteSearch) -> bool:
    """Is every inner cell's rhs, recomputed from its successors, bit for bit its g?"""
    graph = search.graph
    return all(search._recompute_rhs(s) == search.g[s] for s in range(len(graph.cost))
               if graph.inner[s] and s != search.goal)


def test_uniform_costs_to_go_adds_the_steps_as_the_search_does(kernel: str) -> None:
    field = uniform_costs_to_go(5, 6, (0, 0))
    s2 = math.sqrt(2)
    assert field[0, 0] == 0.0 and field[0, 4] == 4.0 and field[2, 2] == s2 + s2
    # (row 3, col 2): a straight step then two diagonals, or a diagonal first: the smaller sum
    assert field[3, 2] == min(1.0 + (s2 + s2), s2 + (1.0 + s2))
    assert field[4, 5] == pytest.approx(1.0 + 4 * s2, abs=1e-12)
    search = make_search(np.full((7, 9), 2.5), (6, 8), (2, 3), kernel=kernel)
    search.plan_from_scratch()
    assert search.queued() == [] and search.settled
    assert consistent(search)  # one ulp off would queue cells at the first change
    assert search.path_cost == pytest.approx(2.5 * (4 * s2 + 1), abs=1e-12)
    assert search.compute() == 0


@pytest.mark.parametrize("seed", range(4))
def test_planning_at_once_equals_the_search_from_scratch(seed: int, kernel: str) -> None:
    rng = np.random.default_rng(200 + seed)
    h, w = (int(v) for v in rng.integers(15, 40, 2))
    cost = np.round(1.0 + 3.0 * rng.random((h, w)), 2)
    cost[rng.random((h, w)) < 0.2] = INF  # lethal cells: diagonals may not cut past them
    start, goal = (1, 1), (h - 2, w - 2)
    cost[start] = cost[goal] = 1.0
    at_once = make_search(cost, start, goal, kernel=kernel)
    at_once.plan_from_scratch()
    expanded = make_search(cost, start, goal, kernel=kernel)
    expanded.compute()
    assert at_once.path_cost == expanded.path_cost  # the same sums: equal, not just close
    assert at_once.path() == expanded.path()
    assert at_once.path_cost == astar(cost, start, goal)[0] or at_once.path_cost == pytest.approx(
        astar(cost, start, goal)[0], abs=1e-9)
    assert consistent(at_once)
    # and it repairs like any other state
    rows, cols = rng.integers(0, h, 6), rng.integers(0, w, 6)
    cost[rows, cols] = np.where(rng.random(6) < 0.5, INF, 1.0)
    cost[start] = cost[goal] = 1.0
    at_once.set_costs(rows, cols, cost[rows, cols])
    at_once.compute()
    expected = astar(cost, start, goal)[0]
    assert at_once.path_cost == pytest.approx(expected, abs=1e-9) or expected == INF == at_once.path_cost


def test_set_costs_counts_real_changes_and_keeps_the_last_of_a_repeated_cell(kernel: str) -> None:
    search = make_search(np.ones((6, 6)), (0, 0), (5, 5), kernel=kernel)
    search.plan_from_scratch()
    changed = search.set_costs([2, 2, 3, 4], [2, 2, 3, 4], [INF, 4.0, 1.0, 1.5])
    assert changed == 3  # (2, 2) twice, (3, 3) unchanged
    graph = search.graph
    assert graph.cost[graph.index((2, 2))] == 4.0 and graph.cost[graph.index((4, 4))] == 1.5
    np.testing.assert_array_equal(graph.cost_array, graph.cost)
    search.compute()
    cost = np.ones((6, 6))
    cost[2, 2], cost[4, 4] = 4.0, 1.5
    assert search.path_cost == pytest.approx(astar(cost, (0, 0), (5, 5))[0], abs=1e-12)
    assert search.set_costs([1], [1], [1.0]) == 0


def test_set_costs_queues_with_the_keys_of_the_reference_formula(kernel: str) -> None:
    """set_costs writes the key out inline: every live queue entry is the reference key of
    its vertex (min(g, rhs), octile distance from the start, km), and a finished search has
    rhs equal to the minimum over each vertex's edges."""
    rng = np.random.default_rng(7)
    cost = rng.choice([1.0, 1.0, 2.0, 5.0, INF], size=(20, 20))
    cost[19, 19] = 1.0
    search = make_search(cost, (0, 0), (19, 19), kernel=kernel)
    search.plan_from_scratch()
    search.move_start((3, 2))
    rows, cols = rng.integers(0, 19, 40), rng.integers(0, 19, 40)
    search.set_costs(rows, cols, rng.choice([1.0, 3.0, 1000.0, INF], size=40))
    graph, live = search.graph, search.queued()
    assert len(live) > 10
    sr, sc = graph.cell(search.start)
    for k1, k2, u in live:
        r, c = graph.cell(u)
        m = min(search.g[u], search.rhs[u])
        assert (k1, k2) == _queue_key(m, r - sr, c - sc, search.km)
    search.compute()
    for u in range(len(search.g)):
        if graph.inner[u] and u != search.goal:
            assert search.rhs[u] == search._recompute_rhs(u)


def test_the_planner_finds_its_cell_as_the_grid_does() -> None:
    planner = DStarLite()
    obs = Observation(t=0.0, pose=np.array([1.0, 1.0, 0.0]), goal=np.array([3.5, 1.0]), ranges=np.full(6, 3.0),
                      robot=default_robot(), bounds=(0.0, 0.0, 4.0, 2.0), dt=0.1)
    planner.reset(obs, np.random.default_rng(0))
    rng = np.random.default_rng(2)
    for xy in rng.uniform(-0.5, 4.5, (2000, 2)).tolist() + [[0.1 * k, 0.3] for k in range(40)]:
        assert planner._cell_of(np.array(xy)) == tuple(int(v) for v in planner.grid.world_to_cell(np.array(xy)))


@pytest.mark.parametrize("seed", range(4))
def test_a_spliced_path_is_the_path_extracted_anew(seed: int, kernel: str) -> None:
    rng = np.random.default_rng(300 + seed)
    h, w = 40, 60
    occ = rng.random((h, w)) < 0.08
    start, goal = (2, 2), (h - 3, w - 3)

    def costs(o: np.ndarray) -> np.ndarray:
        c = clearance_costs(obstacle_distance(o, 5.0), 1.5, 2.5, 50.0, 4.0)
        c[start] = c[goal] = 1.0
        return c

    cost = costs(occ)
    repair = PathRepair(cost, start, goal, kernel=kernel)
    descents: list[int] = []
    descend = repair.search.descend

    def spy(*args: Any, **kwargs: Any) -> list[int]:
        out = descend(*args, **kwargs)
        descents.append(len(out))
        return out

    repair.search.descend = spy  # type: ignore[method-assign]
    checked = spliced = 0
    for _ in range(40):
        cells = repair.cells
        if len(cells) > 2:  # along the path, or beside it
            start = cells[2] if rng.random() < 0.8 else (min(cells[2][0] + 1, h - 1), cells[2][1])
        new_occ = occ.copy()
        r, c = start
        for _ in range(int(rng.integers(0, 4))):  # cells near the robot flip, as sonars make them
            new_occ[int(np.clip(r + rng.integers(-8, 9), 0, h - 1)),
                    int(np.clip(c + rng.integers(-8, 9), 0, w - 1))] ^= True
        new_occ[start] = new_occ[goal] = False
        new = costs(new_occ)
        rr, cc = np.nonzero(new != cost)
        occ, cost = new_occ, new
        version, descents[:] = repair.version, []
        repair.cycle(start, rr, cc, cost[rr, cc])
        if repair.version == version:
            continue
        descended = descents[-1]
        assert repair.full_path == repair.search.path()  # the whole path, cell for cell
        checked += 1
        spliced += descended < len(repair.full_path)
    assert checked >= 10 and spliced >= 5


def test_map_changes_patch_distances_equal_a_distance_transform() -> None:
    robot = default_robot()
    planner = DStarLite()
    obs = Observation(t=0.0, pose=np.array([3.0, 3.0, 0.0]), goal=np.array([5.0, 3.0]),
                      ranges=np.full(6, 3.0), robot=robot, bounds=(0.0, 0.0, 6.0, 6.0), dt=0.1)
    planner.reset(obs, np.random.default_rng(0))

    class Frame:
        values_now = np.full(planner.shape, 50, dtype=np.uint8)

        def values(self, copy: bool = True) -> np.ndarray:
            return self.values_now

    frame = Frame()
    planner.grid = frame
    rng = np.random.default_rng(5)
    robot_rc = (30, 30)
    before = planner.cost.copy()
    for step in range(60):
        cells = rng.integers(0, 60, (int(rng.integers(1, 8)), 2))
        frame.values_now = frame.values_now.copy()
        # freed, new, or both in one cycle (a freed cell's neighbours get their distances back)
        values = (0 if step % 4 == 3 else 100) if step < 12 else rng.choice([0, 100], len(cells))
        frame.values_now[cells[:, 0], cells[:, 1]] = values
        rows, cols, vals = planner._map_changes(robot_rc)
        flat = rows * planner.shape[1] + cols
        assert np.all(np.diff(flat) > 0)  # row-major, as D* Lite's queue receives them
        expected = obstacle_distance(planner.occupied, planner.cap)
        np.testing.assert_array_equal(planner.dist, expected)  # exactly, patch or transform
        cost = clearance_costs(expected, planner.inscribed, planner.margin_cells, 1000.0, 5.0)
        np.testing.assert_array_equal(planner.cost, cost)
        rr, cc = np.nonzero(cost != before)
        assert sorted(zip(rows.tolist(), cols.tolist(), strict=True)) == sorted(zip(rr.tolist(), cc.tolist(), strict=True))
        np.testing.assert_array_equal(vals, cost[rows, cols])
        before = cost
    assert not planner.occupied[planner.goal_rc]


# --------------------------------------------------------------------------- follower
def test_the_guarded_follower_never_drives_into_an_occupied_cell() -> None:
    # a wall corner: occupied cells along x = 1.0 m (y < 1 m) and y = 1.0 m (x < 1 m)
    cell = 0.1
    occ = np.zeros((30, 30), dtype=bool)
    occ[:10, 10] = True
    occ[10, :11] = True
    dist = obstacle_distance(occ, 10.0)

    def clearance(xy: np.ndarray) -> np.ndarray:
        rc = np.floor(np.asarray(xy) / cell).astype(int)[:, ::-1]
        inside = np.all((rc >= 0) & (rc < 30), axis=1)
        rc = np.clip(rc, 0, 29)
        return np.where(inside, dist[rc[:, 0], rc[:, 1]] * cell, 0.0)

    robot = default_robot()
    settings = GuardSettings(required=robot.radius + cell / 2, horizon=1.0)
    rng = np.random.default_rng(3)
    turned = 0
    for _ in range(300):
        pose = np.array([rng.uniform(0.3, 0.75), rng.uniform(0.3, 0.75), rng.uniform(-math.pi, math.pi)])
        obs = Observation(t=0.0, pose=pose, goal=np.array([2.0, 2.0]), ranges=np.full(6, 3.0),
                          robot=robot, bounds=(0.0, 0.0, 3.0, 3.0), dt=0.1)
        wanted = Command(float(rng.uniform(0.05, 0.5)), float(rng.uniform(-2.0, 2.0)))
        out = guard(obs, wanted, 0.0, clearance, settings).command
        now = float(clearance(pose[None, :2])[0])
        along = clearance(rollout(pose, out.v, out.omega, 1.0, 20))
        floor = min(settings.required, now) - 0.01
        assert np.all(along >= floor), (pose, wanted, out)
        changed = out.v == 0.0 or out.v < wanted.v - 1e-9 or abs(out.omega / out.v - wanted.omega / wanted.v) > 1e-6
        turned += changed  # stopped, slowed, or slid along the corner on another arc
    assert turned > 30  # many wanted commands drove at the corner and were changed


def test_an_echo_in_the_footprint_corridor_stops_forward_motion() -> None:
    robot = default_robot()
    ranges = np.full(6, 3.0)
    ranges[2] = ranges[3] = 0.15  # the +-15 deg sonars echo 0.15 m ahead of the rim
    obs = Observation(t=0.0, pose=np.zeros(3), goal=np.array([5.0, 0.0]), ranges=ranges,
                      robot=robot, bounds=(-5.0, -5.0, 5.0, 5.0), dt=0.1)
    out = guard(obs, Command(0.4, 0.0), 0.0, lambda xy: np.full(len(xy), 5.0),
                GuardSettings(required=0.25)).command
    # no straight motion at any speed; at most a slow slide turning away from the echoes
    assert out.v == 0.0 or (out.v <= 0.1 and abs(out.omega) >= 0.5)
    assert not echo_blocks(obs, out.v, out.omega, 1.5)


# --------------------------------------------------------------------------- recovery
def test_a_pinned_robot_starts_its_recovery_within_the_configured_time() -> None:
    # odometry drives on at 0.3 m/s while the front sonars keep reading the same 0.1 m: the
    # wheels spin on a corner. No progress counts, so the recovery starts at recovery_after_s.
    robot = default_robot()
    planner = DStarLite(recovery_after_s=4.0)
    ranges = np.full(6, 3.0)
    ranges[2] = ranges[3] = 0.1

    def obs(t: float) -> Observation:
        return Observation(t=t, pose=np.array([1.0 + 0.3 * t, 2.0, 0.0]), goal=np.array([9.0, 2.0]),
                           ranges=ranges, robot=robot, bounds=(0.0, 0.0, 10.0, 4.0), dt=0.1)

    planner.reset(obs(0.0), np.random.default_rng(0))
    started = None
    for i in range(1, 80):
        t = round(0.1 * i, 1)
        cmd = planner.act(obs(t))
        events = [e for e in planner.pop_events() if e.kind == "recovery"]
        if events:
            started = t
            assert events[0].data == {"phase": "backup", "count": 1, "reason": "pinned"}
            assert cmd.v < 0.0 and cmd.omega == 0.0  # backing up
            break
    assert started is not None and started <= 4.0 + 0.1
    assert planner.stuck_reason() is StuckReason.PINNED


def test_the_recovery_backs_up_rotates_and_re_plans() -> None:
    world, start, goal = wall_world()
    planner = DStarLite(recovery_after_s=1.0, backup_m=0.2, rotate_deg=180.0)
    # hold the robot still so that no progress is made; the recovery then runs its phases
    result = run(_Frozen(planner), world, start, goal, time_s=12.0)
    phases = [e[2]["phase"] for e in result.events if e[0] == "recovery"]
    assert phases[:3] == ["backup", "rotate", "replan"]
    assert planner.recovery.count >= 1


class _Frozen(DStarLite):
    """A D* Lite whose follower never moves the robot (for the recovery test)."""

    def __init__(self, inner: DStarLite) -> None:
        self.__dict__ = inner.__dict__

    def _follow(self, obs: Observation) -> Any:
        from nav_bench.planners.footprint import Guarded

        return Guarded(Command(0.0, 0.0), True)


# --------------------------------------------------------------------------- the paper's labyrinth
@pytest.mark.slow
def test_reaches_the_goal_through_the_papers_labyrinth_in_the_simulator() -> None:
    world = load_world(ROOT / "worlds" / "paper" / "labyrinth.yaml")
    result = run_episode(world, PlannerSetSpec(planner="dstar_lite"), seed=0)
    assert result.row.outcome == "reached", result.row
