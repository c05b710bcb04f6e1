"""The Elfes sonar model of OccupancyGrid (issue 12): doors stay open, phantoms are carved away,
real walls stay occupied. Readings come from a small ray caster over boxes (tests/helpers/sonar_scene.py),
the same nearest-hit-over-the-cone rule as the simulator. Values are PMO 0..100; the planners
read a cell as an obstacle above 65 (EO/PC and D* Lite ``occupied_above``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.errors import InputError
from nav_bench.interface import SonarInfo
from nav_bench.mapping import OccupancyGrid, log_odds_to_values
from tests.helpers.sonar_scene import brute_force, diffbot_sonar, readings

pytestmark = pytest.mark.usefixtures("grid_kernel")  # both update paths (conftest.py)

OBSTACLE_ABOVE = 65
ONE_SONAR = SonarInfo(angles=np.array([0.0]), offsets=np.zeros((1, 2)), cone=math.radians(25.0),
                      min_range=0.05, max_range=3.0)
# two 0.1 m walls along y = 4.0..4.1 with a 1 m door between x = 2.5 and x = 3.5
DOOR = np.array([[0.0, 4.0, 2.5, 4.1], [3.5, 4.0, 6.0, 4.1]])
DOOR_POSES = [(3.0, 2.0, math.pi / 2), (2.2, 2.3, 1.2), (3.8, 2.3, math.pi - 1.2)]
DOOR_ROW = 40  # y 4.0..4.1, the walls' row
GAP = slice(26, 34)  # x 2.6..3.4: the door's cells, each at least 0.1 m from a jamb


def look(grid: OccupancyGrid, pose: tuple[float, float, float], boxes: np.ndarray,
         sonar: SonarInfo, times: int = 1) -> None:
    for _ in range(times):
        grid.update(np.array(pose), readings(pose, boxes, sonar), sonar)


def door_map(model: str) -> np.ndarray:
    """The door's row after the six-sonar ring looked 5 cycles from each of three poses."""
    grid = OccupancyGrid((0.0, 0.0, 6.0, 6.0), model=model)
    for pose in DOOR_POSES:
        look(grid, pose, DOOR, diffbot_sonar(), times=5)
    return grid.values()[DOOR_ROW]


def test_a_door_seen_from_three_poses_stays_open() -> None:
    row = door_map("elfes")
    assert row[GAP].tolist() == [32, 29, 27, 32, 32, 27, 29, 32]
    assert (row[GAP] < 35).all()  # free even by EO/PC's free_below
    assert row[24] > OBSTACLE_ABOVE and row[35] > OBSTACLE_ABOVE  # the jambs' cells
    # the three-band model (before issue 12) closes the same door: every arc cell of the
    # jambs' echoes got the full l_occ every cycle, and its seen-through readings cannot undo it
    band = door_map("band")
    assert band[GAP].tolist() == [82, 82, 82, 12, 12, 82, 82, 82]


def test_a_phantom_arc_seen_once_is_carved_away_by_a_reading_through_it() -> None:
    # a wall ending at x = 2.5 (a door's jamb); the sonar at A faces the jamb's edge, so the
    # echo arc 0.81 m out spans the free cells x 2.5..2.7 beyond it (a phantom);
    # from B, closer and facing through the opening, the cone reads no echo and frees them
    jamb = np.array([[0.0, 4.0, 2.5, 4.1]])
    a, b = (2.6, 3.2, math.pi / 2), (2.65, 3.6, math.pi / 2)
    phantom = (DOOR_ROW, slice(25, 27))  # x 2.55, 2.65
    values = {}
    for model in ("elfes", "band"):
        grid = OccupancyGrid((0.0, 0.0, 6.0, 6.0), model=model)
        look(grid, a, jamb, ONE_SONAR)
        seen = grid.values()[phantom].tolist()
        look(grid, b, jamb, ONE_SONAR, times=2)
        values[model] = (seen, grid.values()[phantom].tolist())
    assert values["elfes"] == ([63, 63], [48, 43])  # cleared: more likely free than occupied
    assert values["band"] == ([70, 70], [51, 51])  # band: an obstacle, then still not free


def test_a_carved_door_stays_open_while_the_jambs_echo_goes_on() -> None:
    # the jambs are known occupied and the door's cells known free: five more cycles of the
    # same jamb echoes from the first pose are explained by the jambs (the echo is shared by
    # w_i p_i), the door's cells take a few points each and stay free
    grid = OccupancyGrid((0.0, 0.0, 6.0, 6.0))
    for pose in DOOR_POSES:
        look(grid, pose, DOOR, diffbot_sonar(), times=5)
    look(grid, DOOR_POSES[0], DOOR, diffbot_sonar(), times=5)
    assert grid.values()[DOOR_ROW, GAP].tolist() == [47, 38, 30, 32, 32, 31, 38, 48]


@pytest.mark.parametrize(("distance", "values"), [
    (0.5, [66, 79, 88, 94, 97, 97]),
    (1.0, [61, 70, 79, 85, 90, 94]),
    (2.0, [56, 62, 68, 74, 78, 82]),
    (2.9, [55, 59, 63, 68, 72, 75]),
])
def test_a_wall_seen_a_few_times_from_one_pose_becomes_an_obstacle(distance: float,
                                                                   values: list[int]) -> None:
    # a wall facing the sonar: its axis cell after 1..6 readings. The echo is shared over the
    # arc, so a wide (far) arc needs more readings: 1 at 0.5 m, 2 at 1 m, 3 at 2 m, 4 at 2.9 m
    grid = OccupancyGrid((0.0, 0.0, 6.0, 6.0))
    r, c = grid.world_to_cell((1.05 + distance, 3.05))
    got = []
    for _ in range(6):
        grid.update(np.array([1.05, 3.05, 0.0]), np.array([distance]), ONE_SONAR)
        got.append(int(grid.values()[r, c]))
    assert got == values


def test_a_real_wall_seen_while_driving_past_stays_occupied() -> None:
    # the robot drives along a wall 1 m to its left, 10 cm per cycle, with all six sonars:
    # every wall cell it passed is an obstacle, no cell of the free corridor is
    wall = np.array([[0.0, 4.0, 6.0, 4.1]])
    grid = OccupancyGrid((0.0, 0.0, 6.0, 6.0))
    for x in np.arange(1.0, 5.0, 0.1):
        look(grid, (float(x), 3.0, 0.0), wall, diffbot_sonar())
    values = grid.values()
    face = values[39, 15:46]  # y 3.9..4.0: the cells holding the wall's face (x 1.5..4.5)
    assert (face > OBSTACLE_ABOVE).all(), face.tolist()
    corridor = values[31:38, 10:50]  # y 3.1..3.8 in front of it
    assert (corridor <= OBSTACLE_ABOVE).all()


def test_free_evidence_falls_off_with_the_angle_from_the_axis() -> None:
    # Elfes' angular weight 1 - (theta / 12.5 deg)^2 on the half-cell-widened cone: a no-echo
    # reading, cells 2 m out and 0, 0.1 .. 0.5 m off the axis (the last outside the cone)
    grid = OccupancyGrid((0.0, 0.0, 6.0, 6.0))
    grid.update(np.array([1.05, 3.05, 0.0]), np.array([3.0]), ONE_SONAR)
    assert grid.log_odds[30:36, 30] == pytest.approx([-0.4, -0.395, -0.353, -0.27, -0.148, 0.0],
                                                     abs=1e-3)


@pytest.mark.parametrize("model", ["elfes", "band"])
def test_vectorised_update_equals_the_cell_by_cell_model(model: str) -> None:
    rng = np.random.default_rng(3)
    sonar = diffbot_sonar()
    grid = OccupancyGrid((0.0, 0.0, 6.0, 5.0), model=model)
    for _ in range(15):
        pose = np.array([rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5), rng.uniform(-np.pi, np.pi)])
        ranges = np.where(rng.random(6) < 0.3, 3.0, rng.uniform(0.1, 2.9, 6))
        expected = brute_force(grid, pose, ranges, sonar)
        grid.update(pose, ranges, sonar)
        np.testing.assert_allclose(grid.log_odds, expected, atol=1e-12)
    np.testing.assert_array_equal(grid.values(), log_odds_to_values(grid.log_odds))


RING16 = np.radians(22.5 * np.arange(16))


@pytest.mark.parametrize("model", ["elfes", "band"])
@pytest.mark.parametrize(("ring", "sonar"), [
    # 16 sonars with 30 deg cones 22.5 deg apart: neighbouring cones share cells every cycle
    ("ring16", SonarInfo(angles=RING16, offsets=0.2 * np.stack([np.cos(RING16), np.sin(RING16)], 1),
                         cone=math.radians(30.0), min_range=0.05, max_range=3.0)),
    # two sonars in the same place, 3 deg apart, and a third like the first: most cells twice
    ("stacked", SonarInfo(angles=np.radians([0.0, 3.0, 0.0]), offsets=np.zeros((3, 2)),
                          cone=math.radians(25.0), min_range=0.05, max_range=2.0)),
])
def test_overlapping_cones_are_fused_one_sonar_after_the_other(model: str, ring: str,
                                                               sonar: SonarInfo) -> None:
    # the update fuses all sonars at once unless cones share cells; then it must still equal
    # the sonars fused in order (the later echo's share sees the earlier update), here with
    # the robot also near and beyond the grid's edges
    rng = np.random.default_rng(5)
    grid = OccupancyGrid((0.0, 0.0, 6.0, 5.0), model=model)
    k = len(sonar.angles)
    for i in range(12):
        pose = np.array([rng.uniform(-0.5, 6.5), rng.uniform(-0.5, 5.5), rng.uniform(-np.pi, np.pi)])
        if i % 2:
            pose[:2] = rng.uniform(2.0, 3.0, 2)  # back to the middle: cells seen again
        ranges = np.where(rng.random(k) < 0.3, sonar.max_range, rng.uniform(0.1, 0.97 * sonar.max_range, k))
        expected = brute_force(grid, pose, ranges, sonar)
        grid.update(pose, ranges, sonar)
        if model == "band":  # sums of the same two constants in the same order: exact
            np.testing.assert_array_equal(grid.log_odds, expected)
        else:
            np.testing.assert_allclose(grid.log_odds, expected, atol=1e-12)
    np.testing.assert_array_equal(grid.values(), log_odds_to_values(grid.log_odds))


def test_a_grid_updated_with_another_sonar_ring_uses_that_rings_cones() -> None:
    # the cone tables and mount positions are per ring: a second ring (another cone and range)
    # on the same grid is not read through the first one's tables
    grid = OccupancyGrid((0.0, 0.0, 6.0, 5.0))
    pose, ranges = np.array([3.0, 2.5, 0.4]), np.array([1.5, 3.0, 0.8, 3.0, 2.0, 3.0])
    wide = SonarInfo(angles=np.array([0.0, 2.0]), offsets=np.zeros((2, 2)), cone=math.radians(40.0),
                     min_range=0.05, max_range=4.0)
    for sonar, reading in ((diffbot_sonar(), ranges), (wide, np.array([2.5, 4.0])),
                           (diffbot_sonar(), ranges[::-1].copy())):
        expected = brute_force(grid, pose, reading, sonar)
        grid.update(pose, reading, sonar)
        np.testing.assert_allclose(grid.log_odds, expected, atol=1e-12)


def test_unknown_sonar_model_is_refused_with_the_choices() -> None:
    with pytest.raises(InputError, match=r"sonar model 'muriel'.*\['elfes', 'band'\]"):
        OccupancyGrid((0, 0, 1, 1), model="muriel")
    with pytest.raises(InputError, match="echo_share"):
        OccupancyGrid((0, 0, 1, 1), echo_share=0.0)


@pytest.mark.parametrize("bins", [720, 45])
def test_the_cone_tables_bin_width_does_not_change_the_map(bins: int, monkeypatch) -> None:
    # the per-direction tables only pick candidate cells (a superset of each cone's, in the
    # disc's order): 0.5 deg or 8 deg bins give the default 2 deg bins' map bit for bit
    import nav_bench.mapping.occupancy as occupancy

    rng = np.random.default_rng(9)
    sonar = diffbot_sonar()
    steps = [(np.array([rng.uniform(0.5, 5.5), rng.uniform(0.5, 4.5), rng.uniform(-np.pi, np.pi)]),
              np.where(rng.random(6) < 0.3, 3.0, rng.uniform(0.1, 2.9, 6))) for _ in range(20)]
    default = OccupancyGrid((0.0, 0.0, 6.0, 5.0))
    for pose, ranges in steps:
        default.update(pose, ranges, sonar)
    monkeypatch.setattr(occupancy, "_AXIS_BINS", bins)
    monkeypatch.setattr(occupancy, "_AXIS_BIN", 2 * math.pi / bins)
    other = OccupancyGrid((0.0, 0.0, 6.0, 5.0))
    for pose, ranges in steps:
        other.update(pose, ranges, sonar)
    np.testing.assert_array_equal(other.log_odds, default.log_odds)
    np.testing.assert_array_equal(other.values(), default.values())
