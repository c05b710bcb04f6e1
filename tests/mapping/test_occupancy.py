"""PMO: the log-odds sonar occupancy grid (nav_bench.mapping.occupancy)."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from nav_bench.errors import InputError
from nav_bench.interface import SonarInfo
from nav_bench.mapping import GridFrame, OccupancyGrid, log_odds_to_values

pytestmark = pytest.mark.usefixtures("grid_kernel")  # both update paths (conftest.py)

# these tests pin the three-band model (its numbers are exact and simple); the default Elfes
# model is tested in test_sonar_model.py
BandGrid = functools.partial(OccupancyGrid, model="band")
FREE_ONCE = 40  # round(100 / (1 + e^0.4)): one l_free = -0.4 on an unknown cell
OCC_ONCE = 70  # round(100 / (1 + e^-0.85)): one l_occ = 0.85


def one_sonar(offset: tuple[float, float] = (0.0, 0.0), angle: float = 0.0,
              cone_deg: float = 25.0, max_range: float = 3.0) -> SonarInfo:
    return SonarInfo(angles=np.array([angle]), offsets=np.array([offset], dtype=float),
                     cone=math.radians(cone_deg), min_range=0.05, max_range=max_range)


def value_at(grid: OccupancyGrid, x: float, y: float) -> int:
    r, c = grid.world_to_cell((x, y))
    return int(grid.values()[r, c])


def test_frame_shape_cells_and_outside_points() -> None:
    frame = GridFrame.from_bounds((0.0, 0.0, 10.0, 10.0), 0.1)
    assert frame.shape == (100, 100)
    assert frame.world_to_cell((0.05, 9.95)).tolist() == [99, 0]  # row 0 at y = ymin
    assert frame.cell_center(99, 0) == pytest.approx([0.05, 9.95])
    assert frame.world_to_cell((-0.01, 10.0)).tolist() == [100, -1]
    assert not frame.contains(100, -1) and frame.contains(0, 0)
    pts = np.array([[1.23, 4.56], [9.99, 0.0]])
    assert frame.world_to_cell(pts).tolist() == [[45, 12], [0, 99]]
    assert GridFrame.from_bounds((0, 0, 40, 40), 0.1).shape == (400, 400)
    with pytest.raises(InputError):
        GridFrame.from_bounds((0, 0, 0, 5), 0.1)


def test_new_grid_is_unknown_and_values_are_ros_uint8() -> None:
    grid = BandGrid((0.0, 0.0, 4.0, 3.0))
    v = grid.values()
    assert v.dtype == np.uint8 and v.shape == (30, 40) and np.all(v == 50)
    assert not grid.values(copy=False).flags.writeable
    assert log_odds_to_values(np.array([0.0, -0.4, 0.85, -2.0, 3.5])).tolist() == [50, 40, 70, 12, 97]


def test_one_cone_against_a_wall_free_before_occupied_at_unknown_behind() -> None:
    # robot at a cell centre facing +x, the echo 2.0 m ahead: the wall face at x = 3.05
    grid = BandGrid((0.0, 0.0, 6.0, 6.0))
    grid.update(np.array([1.05, 3.05, 0.0]), np.array([2.0]), one_sonar())
    for x in (1.25, 2.05, 2.85, 2.95):  # along the axis, short of the arc
        assert value_at(grid, x, 3.05) == FREE_ONCE, x
    assert value_at(grid, 3.05, 3.05) == OCC_ONCE  # the echo arc, one cell thick
    assert value_at(grid, 3.05, 3.35) == OCC_ONCE  # the arc spans the cone's width (12.5 deg: 0.44 m)
    for x in (3.15, 3.35, 4.05):  # behind the echo: nothing known
        assert value_at(grid, x, 3.05) == 50, x
    assert value_at(grid, 2.05, 4.05) == 50  # 45 deg off the axis: outside the 25 deg cone
    assert value_at(grid, 0.85, 3.05) == 50  # behind the sonar


def test_mount_offset_and_yaw_place_the_cone() -> None:
    # sonar 0.2 m ahead of the centre, facing the robot's left; robot faces +x
    grid = BandGrid((0.0, 0.0, 6.0, 6.0))
    grid.update(np.array([3.05, 1.05, 0.0]), np.array([1.0]), one_sonar((0.0, 0.2), math.pi / 2))
    assert value_at(grid, 3.05, 2.25) == OCC_ONCE  # 1.05 + 0.2 + 1.0
    assert value_at(grid, 3.05, 1.75) == FREE_ONCE
    assert value_at(grid, 3.05, 2.45) == 50


def test_max_range_reading_frees_up_to_max_range_and_marks_nothing() -> None:
    grid = BandGrid((0.0, 0.0, 6.0, 6.0))
    grid.update(np.array([1.05, 3.05, 0.0]), np.array([3.0]), one_sonar())
    v = grid.values()
    assert v.max() == 50  # no occupied evidence anywhere
    assert value_at(grid, 3.95, 3.05) == FREE_ONCE  # 2.9 m out
    assert value_at(grid, 4.25, 3.05) == 50  # 3.2 m: beyond max range
    grid.update(np.array([1.05, 3.05, 0.0]), np.array([np.inf]), one_sonar())  # no echo, as inf
    assert value_at(grid, 3.95, 3.05) == 31  # two free sightings: log-odds -0.8


def test_log_odds_accumulate_and_clamp() -> None:
    grid = BandGrid((0.0, 0.0, 6.0, 6.0))
    for _ in range(20):
        grid.update(np.array([1.05, 3.05, 0.0]), np.array([2.0]), one_sonar())
    assert value_at(grid, 3.05, 3.05) == 97  # l_max 3.5
    assert value_at(grid, 2.05, 3.05) == 12  # l_min -2.0
    assert grid.log_odds.max() == pytest.approx(3.5) and grid.log_odds.min() == pytest.approx(-2.0)


def test_cells_outside_the_grid_are_ignored() -> None:
    grid = BandGrid((0.0, 0.0, 2.0, 2.0))
    grid.update(np.array([1.95, 1.05, 0.0]), np.array([1.0]), one_sonar())  # facing out of the grid
    assert value_at(grid, 1.95, 1.05) == FREE_ONCE  # the part inside is updated
    grid.update(np.array([-5.0, -5.0, 0.0]), np.array([1.0]), one_sonar())  # robot far outside
    assert np.count_nonzero(grid.values() != 50) == 1


def test_bad_sensor_model_parameters_are_refused() -> None:
    with pytest.raises(InputError, match="l_occ"):
        BandGrid((0, 0, 1, 1), l_occ=-0.1)
    with pytest.raises(InputError, match="l_min"):
        BandGrid((0, 0, 1, 1), l_min=0.5)
