"""D* Lite's compiled search (Numba, the optional ``fast`` extra) against the Python one: the
same g, rhs, queue, expansions, touched vertices and paths, bit for bit, over hundreds of
cycles of random cost changes, lethal cells, budgets and start moves. Skipped without Numba."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from nav_bench.errors import InputError
from nav_bench.planners.dstar_lite import (
    CompiledSearch,
    DStarLite,
    DStarLiteSearch,
    PathRepair,
    clearance_costs,
    load_kernels,
    make_search,
    obstacle_distance,
)

INF = math.inf

needs_numba = pytest.mark.skipif(load_kernels() is None, reason="numba is not installed (the 'fast' extra)")


def assert_same_state(py: DStarLiteSearch, nb: DStarLiteSearch) -> None:
    """Bit for bit: g, rhs, costs, queue (keys and vertices), km, counters."""
    assert np.array_equal(np.asarray(py.g), nb.g)
    assert np.array_equal(np.asarray(py.rhs), nb.rhs)
    assert np.array_equal(np.asarray(py.graph.cost), nb.graph.cost_array)
    assert py.queued() == nb.queued()
    assert (py.km, py.last, py.start) == (nb.km, nb.last, nb.start)
    assert (py.expansions, py.steps, py.settled) == (nb.expansions, nb.steps, nb.settled)
    assert py.touched == nb.touched


def random_change(rng: np.random.Generator, h: int, w: int, keep: tuple[tuple[int, int], ...]
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A handful of cells, some repeated, with new costs: free, dear, inscribed or lethal."""
    k = int(rng.integers(1, 25))
    rows, cols = rng.integers(0, h, k), rng.integers(0, w, k)
    vals = rng.choice([1.0, 1.0, 1.5, 2.375, 5.0, 1000.0, INF, INF], size=k)
    for i, (r, c) in enumerate(zip(rows.tolist(), cols.tolist(), strict=True)):
        if (r, c) in keep:
            vals[i] = 1.0
    return rows, cols, vals


def clearance_map(occ: np.ndarray, free: tuple[tuple[int, int], ...]) -> np.ndarray:
    """Step costs of an occupancy grid as D* Lite's planner makes them (inscribed 1.5 cells at
    50, falling from 4 to 1 over 2.5 cells more), the cells ``free`` at 1."""
    cost = clearance_costs(obstacle_distance(occ, 5.0), 1.5, 2.5, 50.0, 4.0)
    for rc in free:
        cost[rc] = 1.0
    return cost


@needs_numba
@pytest.mark.parametrize("seed", range(8))
def test_the_compiled_search_is_the_python_search_bit_for_bit(seed: int) -> None:
    rng = np.random.default_rng(1400 + seed)
    h, w = (int(v) for v in rng.integers(12, 50, 2))
    cost = rng.choice([1.0, 1.0, 1.0, 2.0, 3.5, INF], size=(h, w))
    start, goal = (int(rng.integers(h)), int(rng.integers(w))), (int(rng.integers(h)), int(rng.integers(w)))
    cost[start] = cost[goal] = 1.0
    py, nb = DStarLiteSearch(cost, start, goal), make_search(cost, start, goal, "numba")
    assert isinstance(nb, CompiledSearch)
    if seed % 2:  # half start from the closed-form / Dijkstra plan, half expand from the goal
        py.plan_from_scratch()
        nb.plan_from_scratch()
    py.touched, nb.touched = [], []
    assert_same_state(py, nb)
    budgets = [None, 1, 3, 10, 40, 200]
    cycles = paths = 0
    for _ in range(60):
        if rng.random() < 0.5 and py.settled:  # the robot moves a few cells along its path
            path = py.path()
            assert nb.path() == path
            if len(path) > 2:
                py.move_start(path[2])
                nb.move_start(path[2])
                start = path[2]
        elif rng.random() < 0.2:  # or somewhere else (a recovery, odometry drift)
            start = (int(rng.integers(h)), int(rng.integers(w)))
            py.move_start(start)
            nb.move_start(start)
        rows, cols, vals = random_change(rng, h, w, (start, goal))
        assert py.set_costs(rows, cols, vals) == nb.set_costs(rows, cols, vals)
        assert_same_state(py, nb)
        budget = budgets[int(rng.integers(len(budgets)))]
        for _ in range(int(rng.integers(1, 4))):
            assert py.compute(budget) == nb.compute(budget)
            assert_same_state(py, nb)
            cycles += 1
        if py.settled:
            assert py.path_cost == nb.path_cost
            assert nb.path() == py.path() and nb.descend(7) == py.descend(7)
            flat = py.descend()
            index = np.full(len(py.g), -1, dtype=np.int64)  # where the descent may join this path
            index[flat] = np.arange(len(flat))
            for after in (-1, len(flat) // 2):
                assert nb.descend(None, index, after) == py.descend(None, index, after)
            paths += 1
        py.touched.clear()
        nb.touched.clear()
    assert cycles > 100 and paths > 10


@needs_numba
@pytest.mark.parametrize("seed", range(3))
def test_path_repair_is_the_same_with_either_kernel(seed: int) -> None:
    """PathRepair's cycles (budgets, splicing, safe prefixes) on a clearance-cost map."""
    rng = np.random.default_rng(1500 + seed)
    h, w, start, goal = 40, 60, (2, 2), (37, 57)
    occ = rng.random((h, w)) < 0.06
    cost = clearance_map(occ, (start, goal))
    py = PathRepair(cost, start, goal, budget=150, lethal=50.0, prefix=25)
    nb = PathRepair(cost, start, goal, budget=150, lethal=50.0, prefix=25, kernel="numba")
    assert isinstance(nb.search, CompiledSearch) and not isinstance(py.search, CompiledSearch)
    versions, unfinished = set(), 0
    for _ in range(150):
        versions.add(py.version)
        unfinished += not py.complete
        cells = py.cells
        assert nb.cells == cells and nb.span == py.span and nb.version == py.version
        if len(cells) > 2 and rng.random() < 0.7:
            start = cells[2] if rng.random() < 0.8 else (min(cells[2][0] + 1, h - 1), cells[2][1])
        elif py.complete and len(cells) <= 2:  # arrived (or no path): plan anew from elsewhere
            start = (int(rng.integers(h)), int(rng.integers(w // 2)))
            cost[start] = 1.0
            py.restart(cost, start)
            nb.restart(cost, start)
            assert_same_state(py.search, nb.search)
        new_occ = occ.copy()
        k = int(rng.integers(1, 6)) if rng.random() < 0.2 else 0  # repairs have cycles to finish
        new_occ[rng.integers(0, h, k), rng.integers(0, w, k)] ^= True
        new_occ[start] = new_occ[goal] = False
        new = clearance_map(new_occ, (start, goal))
        rr, cc = np.nonzero(new != cost)
        occ, cost = new_occ, new
        assert py.cycle(start, rr, cc, cost[rr, cc]) == nb.cycle(start, rr, cc, cost[rr, cc])
        assert_same_state(py.search, nb.search)
    assert len(versions) > 8 and unfinished > 5  # new paths, and repairs spread over cycles


@needs_numba
def test_the_planner_chooses_its_kernel_per_instance() -> None:
    assert DStarLite().settings.search_kernel == "auto"
    cost = np.ones((5, 5))
    assert isinstance(make_search(cost, (0, 0), (4, 4), "auto"), CompiledSearch)
    assert type(make_search(cost, (0, 0), (4, 4), "python")) is DStarLiteSearch
    with pytest.raises(InputError):
        make_search(cost, (0, 0), (4, 4), "fortran")


@needs_numba
def test_a_compiled_search_pickles_mid_repair() -> None:
    cost = np.ones((30, 40))
    search = make_search(cost, (2, 2), (27, 37), "numba")
    search.compute()
    search.set_costs(np.arange(5, 25), np.full(20, 20), np.full(20, INF))
    search.compute(15)  # unfinished: the queue is not empty
    copy = pickle.loads(pickle.dumps(search))
    assert_same_state(search, copy)
    assert search.compute() == copy.compute() > 0
    assert_same_state(search, copy)
    assert copy.path() == search.path() != []


def test_without_numba_auto_is_python(monkeypatch: pytest.MonkeyPatch) -> None:
    import nav_bench.planners.dstar_lite as dstar_lite

    monkeypatch.setattr(dstar_lite, "load_kernels", lambda: None)
    cost = np.ones((5, 5))
    assert type(dstar_lite.make_search(cost, (0, 0), (4, 4), "auto")) is DStarLiteSearch
    with pytest.raises(InputError, match="fast"):
        dstar_lite.make_search(cost, (0, 0), (4, 4), "numba")


def test_numba_asked_for_without_numba_is_a_parameter_error_naming_file_key_and_line(
        monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    """Checked when the parameter set is read, before anything is simulated (in the planner's
    reset it would end every episode as an error row)."""
    import nav_bench.planners.dstar_lite as dstar_lite
    from nav_bench.errors import SpecError
    from nav_bench.planners.registry import load_planner_set

    monkeypatch.setattr(dstar_lite, "load_kernels", lambda: None)
    path = tmp_path / "fast.yaml"
    path.write_text("planner: dwa_global\nparams:\n  search_kernel: numba\n")
    with pytest.raises(SpecError) as err:
        load_planner_set(path)
    assert (str(err.value.file), err.value.key_path, err.value.line) == (str(path), "params.search_kernel", 3)
    assert "pip install 'nav-bench[fast]'" in str(err.value)
    path.write_text("planner: dwa_global\nparams:\n  search_kernel: auto\n")
    assert load_planner_set(path).params == {"search_kernel": "auto"}


@pytest.mark.parametrize("asked", ["auto", "python", "numba"])
def test_the_state_says_which_loops_ran(asked: str) -> None:
    """``auto`` resolved: the trace keeps the kernel that ran, on which an episode's CPU depends."""
    from nav_bench.interface import Observation
    from nav_bench.planners.dstar_lite import DStarLite
    from nav_bench.testing.harness import default_robot

    if asked != "python" and load_kernels() is None:
        pytest.skip("numba is not installed (the 'fast' extra)")
    planner = DStarLite(search_kernel=asked)
    obs = Observation(t=0.0, pose=np.array([1.0, 1.0, 0.0]), goal=np.array([3.5, 1.0]),
                      ranges=np.full(6, 3.0), robot=default_robot(), bounds=(0.0, 0.0, 4.0, 2.0), dt=0.1)
    planner.reset(obs, np.random.default_rng(0))
    assert planner.debug_state()["search_kernel"] == ("python" if asked == "python" else "numba")
