"""The sonar map's compiled update (nav_bench.mapping.occupancy_kernels, Numba: the optional
``fast`` extra) against the NumPy one: the same cells, log-odds and values, bit for bit, over
long random sequences of poses and readings. Skipped without Numba, except the choice's errors."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

import nav_bench.mapping.occupancy as occupancy
from nav_bench.errors import InputError
from nav_bench.interface import SonarInfo
from nav_bench.mapping import OccupancyGrid
from tests.helpers.sonar_scene import diffbot_sonar
from tests.mapping.conftest import needs_numba

RING16 = np.radians(np.arange(16) * 22.5)
SONARS = {
    "diffbot": diffbot_sonar(),
    # neighbouring 30 deg cones 22.5 deg apart share cells every cycle: several runs
    "ring16": SonarInfo(angles=RING16, offsets=0.2 * np.stack([np.cos(RING16), np.sin(RING16)], 1),
                        cone=math.radians(30.0), min_range=0.05, max_range=3.0),
    # the same place, 3 deg apart, and a third like the first: most cells twice or three times
    "stacked": SonarInfo(angles=np.radians([0.0, 3.0, 0.0]), offsets=np.zeros((3, 2)),
                         cone=math.radians(25.0), min_range=0.05, max_range=2.0),
}


def random_steps(rng: np.random.Generator, sonar: SonarInfo, n: int, size: tuple[float, float]
                 ) -> list[tuple[np.ndarray, np.ndarray]]:
    """``n`` (pose, ranges): the robot anywhere from 1 m outside the grid to its middle, a
    third of the readings without echo (max_range, beyond it or not finite), some very short;
    every other step one of three poses again with its own readings (walls: cells pile up
    evidence to the clamps)."""
    k, w, h = len(sonar.angles), size[0], size[1]
    anchors = [(np.array([rng.uniform(1.0, w - 1.0), rng.uniform(1.0, h - 1.0), rng.uniform(-4.0, 4.0)]),
                rng.uniform(0.3, 0.9 * sonar.max_range, k)) for _ in range(3)]
    steps = []
    for i in range(n):
        if i % 2:
            steps.append(anchors[int(rng.integers(3))])
            continue
        pose = np.array([rng.uniform(-1.0, w + 1.0), rng.uniform(-1.0, h + 1.0), rng.uniform(-7.0, 7.0)])
        ranges = rng.uniform(0.02, 0.99 * sonar.max_range, k)
        no_echo = rng.random(k) < 0.3
        short = rng.random(k) < 0.1  # about half the arc's thickness: the arc at the sonar
        ranges[short] = rng.choice([0.05, 0.05 + 1e-12, 0.0500001, 0.05 - 1e-12], size=int(short.sum()))
        ranges[no_echo] = rng.choice([sonar.max_range, sonar.max_range + 1.0, math.inf, math.nan],
                                     size=int(no_echo.sum()))
        steps.append((pose, ranges))
    return steps


def assert_same_map(reference: OccupancyGrid, compiled: OccupancyGrid, step: int) -> None:
    """Log-odds bit for bit (as int64 words: -0.0 and NaN would show) and values."""
    assert np.array_equal(reference.log_odds.view(np.int64), compiled.log_odds.view(np.int64)), step
    assert np.array_equal(reference.values(copy=False), compiled.values(copy=False)), step


@needs_numba
@pytest.mark.parametrize("model", ["elfes", "band"])
@pytest.mark.parametrize("ring", sorted(SONARS))
def test_the_compiled_update_builds_the_numpy_map_bit_for_bit(model: str, ring: str) -> None:
    sonar, size = SONARS[ring], (8.0, 6.0)
    reference = OccupancyGrid((0.0, 0.0, *size), model=model, kernel="numpy")
    compiled = OccupancyGrid((0.0, 0.0, *size), model=model, kernel="numba")
    assert compiled.compiled and not reference.compiled
    for step, (pose, ranges) in enumerate(random_steps(np.random.default_rng(3), sonar, 400, size)):
        reference.update(pose, ranges, sonar)
        compiled.update(pose, ranges, sonar)
        assert_same_map(reference, compiled, step)
    # the sequence reached both clamps and the values' ends
    assert reference.log_odds.min() == reference.l_min and reference.log_odds.max() == reference.l_max


@needs_numba
@pytest.mark.parametrize("model", ["elfes", "band"])
def test_the_compiled_cells_are_the_numpy_cells(model: str) -> None:
    # the intermediate values, not only the map: the same cells in the same order, sonars, arcs
    # and Elfes weights (a fused multiply-add in the kernel would show in the weights' bits)
    grid = OccupancyGrid((0.0, 0.0, 8.0, 6.0), model=model, kernel="numba")
    kernels, sonar = occupancy._kernels(), SONARS["ring16"]
    for pose, ranges in random_steps(np.random.default_rng(11), sonar, 100, (8.0, 6.0)):
        reading = grid._reading(pose, ranges, sonar)
        cells = grid._cone_cells(reading, sonar)
        n, idx, sonar_of, occ, off_axis, along, _bounds, _runs = grid._compiled_cells(reading, sonar)
        if cells is None:
            assert n == 0
            continue
        assert idx[:n].tolist() == cells.idx.tolist()
        assert sonar_of[:n].tolist() == cells.sonar.tolist()
        assert occ[:n].tolist() == cells.occ.tolist()
        assert (grid._marks == -1).all()  # the scratch is left as found
        if model == "elfes":
            weight = np.arctan2(off_axis[:n], along[:n])
            kernels.elfes_weight(weight, sonar.cone / 2)
            assert np.array_equal(weight.view(np.int64), cells.weight.view(np.int64))


@needs_numba
def test_the_runs_of_sonars_are_the_numpy_runs() -> None:
    # _independent_runs' bounds: a new run where a sonar's cone shares a cell with an earlier one
    grid = OccupancyGrid((0.0, 0.0, 8.0, 6.0), kernel="numba")
    seen = set()
    for ring in ("diffbot", "ring16", "stacked"):
        sonar = SONARS[ring]
        for pose, ranges in random_steps(np.random.default_rng(7), sonar, 60, (8.0, 6.0)):
            reading = grid._reading(pose, ranges, sonar)
            cells = grid._cone_cells(reading, sonar)
            if cells is None:
                continue
            *_, bounds, runs = grid._compiled_cells(reading, sonar)
            expected = [(s.start, s.stop) for s in grid._independent_runs(cells)]
            assert list(zip(bounds[:runs].tolist(), bounds[1:runs + 1].tolist(), strict=True)) == expected
            seen.add(runs)
    assert 1 in seen and max(seen) >= 3


@needs_numba
def test_a_compiled_grid_pickles_and_goes_on_equal() -> None:
    sonar = diffbot_sonar()
    steps = random_steps(np.random.default_rng(5), sonar, 40, (6.0, 5.0))
    reference = OccupancyGrid((0.0, 0.0, 6.0, 5.0), kernel="numpy")
    compiled = OccupancyGrid((0.0, 0.0, 6.0, 5.0), kernel="numba")
    for pose, ranges in steps[:20]:
        reference.update(pose, ranges, sonar)
        compiled.update(pose, ranges, sonar)
    compiled = pickle.loads(pickle.dumps(compiled))
    for step, (pose, ranges) in enumerate(steps[20:]):
        reference.update(pose, ranges, sonar)
        compiled.update(pose, ranges, sonar)
        assert_same_map(reference, compiled, step)


def test_the_kernel_choice_auto_numpy_numba_and_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    assert not OccupancyGrid((0, 0, 1, 1), kernel="numpy").compiled
    assert OccupancyGrid((0, 0, 1, 1), kernel="auto").compiled == (occupancy._kernels() is not None)
    with pytest.raises(InputError, match=r"kernel must be one of \['auto', 'numpy', 'numba'\], got 'c'"):
        OccupancyGrid((0, 0, 1, 1), kernel="c")
    monkeypatch.setattr(occupancy, "_kernels", lambda: None)  # as without Numba
    assert not OccupancyGrid((0, 0, 1, 1)).compiled  # auto falls back to NumPy
    with pytest.raises(InputError, match=r"'numba' needs Numba: pip install 'nav-bench\[fast\]'"):
        OccupancyGrid((0, 0, 1, 1), kernel="numba")


def test_the_grid_kernel_fixture_sets_the_default(grid_kernel: str) -> None:
    assert OccupancyGrid((0, 0, 1, 1)).compiled == (grid_kernel == "numba")
