"""The see-through carving's settings VFH+ can choose (issue 12, results/baselines/vfh_s16/):
an echo keeping wrong carvings again (``undo``: on the echo's axis, or on an arc nothing kept
explains) and the body's carving only while no echo is near (``body_clear``). Both kernels."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from nav_bench.errors import InputError
from nav_bench.mapping.grid import GridFrame
from nav_bench.planners import carving as carving_mod
from nav_bench.planners.carving import PARTS, SeeThroughCarving, load_kernels
from nav_bench.planners.footprint import cell_parts
from nav_bench.planners.vfh_plus import VFHPlus
from nav_bench.testing.harness import BoxWorld, default_robot, observe
from tests.planners.test_vfh_plus import GAP_ROBOT, GAP_WORLD, read_gap

KERNELS = ["numpy", pytest.param("numba", marks=pytest.mark.skipif(load_kernels() is None, reason="no numba"))]
TOWARD_GAP = [71, 0, 1]  # VFH+'s sectors toward the 0.55 m gap (sector 0 = world +x)


def open_the_gap_then_face_it(undo: str, kernel: str) -> tuple[VFHPlus, np.ndarray, np.ndarray]:
    """VFH+ with a 10 s carving memory before the 0.55 m gap (test_vfh_plus): six readings
    facing it, ten turned 6-24 deg either way (the carving opens it), ten facing it again.
    Returns the planner and its H^p toward the gap after the turns and at the end."""
    planner = VFHPlus(carve_memory_s=10.0, carve_undo=undo)
    start = observe(GAP_WORLD, np.array([1.2, 1.5, 0.0]), np.array([3.5, 1.5]), GAP_ROBOT, 0.0, 0.1)
    planner.reset(start, np.random.default_rng(0))
    planner.carving = SeeThroughCarving(planner.frame, start.pose, kernel, memory_s=10.0, undo=undo)
    read_gap(planner, [0.0] * 6)
    read_gap(planner, [-0.1, -0.18, -0.26, -0.34, -0.42, 0.1, 0.18, 0.26, 0.34, 0.42], t0=0.6)
    opened = planner.primary[TOWARD_GAP].copy()
    read_gap(planner, [0.0] * 10, t0=1.6)
    return planner, opened, planner.primary[TOWARD_GAP].copy()


def arc_parts(parts: np.ndarray, pose: np.ndarray, ranges: np.ndarray, sonar, cell: float) -> np.ndarray:
    """The fourteenth session's candidate 5: every part on an echo's arc (inside the cone, at
    the range read within the axis tolerance), whatever else lies on it."""
    mounts = carving_mod._Mounts.of(pose, ranges, sonar)
    _, along_tol = carving_mod._axis_tolerances(cell)
    angle = mounts.yaw + sonar.angles
    q = parts.reshape(-1, 2)
    dx, dy = q[None, :, 0] - mounts.mx[:, None], q[None, :, 1] - mounts.my[:, None]
    d = np.hypot(dx, dy)
    inside = dx * np.cos(angle)[:, None] + dy * np.sin(angle)[:, None] >= d * math.cos(sonar.cone / 2)
    hit = inside & (np.abs(d - mounts.r[:, None]) <= along_tol) & (mounts.r < sonar.max_range)[:, None]
    return np.logical_or.reduce(hit, axis=0).reshape(parts.shape[:2])


@pytest.mark.parametrize("kernel", KERNELS)
def test_an_unexplained_echo_keeps_the_gap_open_that_the_axis_and_the_arc_undo_close(kernel: str) -> None:
    """Facing the opened gap, the front cones' echoes come from the jambs' corners and the
    wall 1.7 m on. Undoing on every arc (the fourteenth session's candidate 5) or on the axis
    points keeps proud parts again (the axis points of grazing echoes lie in the open gap, on
    cells the grid blamed from other arcs): the arc undo closes the gap's sectors over
    threshold_high; the axis undo raises each of them by about 270 (opened) and 320-370 (faced),
    under threshold_low since kept parts beyond 0.5 m weigh their area's share
    (``AREA_SHARE_BEYOND_M``, results/baselines/vfh_s20/; before it, over threshold_low).
    Undoing only where no kept part explains the echo leaves the gap exactly as no undo."""
    p = VFHPlus().settings
    _, opened_off, faced_off = open_the_gap_then_face_it("off", kernel)
    assert np.all(opened_off < p.threshold_low) and np.all(faced_off < p.threshold_low)
    _, opened, faced = open_the_gap_then_face_it("unexplained", kernel)
    np.testing.assert_array_equal(opened, opened_off)
    np.testing.assert_array_equal(faced, faced_off)
    _, opened_axis, faced_axis = open_the_gap_then_face_it("axis", kernel)
    assert np.all(opened_axis - opened_off > 250.0) and np.all(faced_axis - faced_off > 300.0)
    if kernel == "numpy":  # the arc variant is a NumPy stand-in
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(carving_mod, "echo_axis_parts", arc_parts)
            _, _, faced_arc = open_the_gap_then_face_it("axis", kernel)
        assert np.all(faced_arc > p.threshold_high)


WALL = BoxWorld.room((4.0, 3.0), [(2.05, 0.5, 2.35, 2.5)])  # a box face at x 2.05, inside its cells
FRAME = GridFrame(0.0, 0.0, 0.1, 30, 40)


def wrongly_carved_face(undo: str, kernel: str) -> tuple[SeeThroughCarving, np.ndarray, np.ndarray]:
    """The cells x 2.0-2.2, y 1.0-2.0 (the face at x 2.05 in their middle) all carved at t 0, as
    the body carves an obstacle odometry has drifted into, then one reading from (1.4, 1.5)
    facing the face at t 0.1. Returns the carving, the parts (M, PARTS, 2) and which are kept."""
    robot = default_robot(radius=0.18)
    carving = SeeThroughCarving(FRAME, np.array([1.4, 1.5, 0.0]), kernel, memory_s=10.0, undo=undo)
    rows, cols = np.meshgrid(np.arange(10, 20), np.arange(20, 22), indexing="ij")
    rows, cols = rows.ravel(), cols.ravel()
    carving.carved_t[rows, cols] = 0.0
    carving.noted[rows, cols] = True
    occupied = np.zeros(FRAME.shape, dtype=bool)
    occupied[rows, cols] = True
    obs = observe(WALL, np.array([1.4, 1.5, 0.0]), np.array([3.5, 1.5]), robot, 0.1, 0.1)
    out = carving.update(obs, rows, cols, (0, FRAME.rows, 0, FRAME.cols), occupied)
    return carving, out.parts, out.kept


@pytest.mark.parametrize("kernel", KERNELS)
def test_a_face_carved_wrongly_comes_back_where_an_echo_lands_on_it(kernel: str) -> None:
    """Nothing kept explains the echoes from the face (the +-15 deg sonars' at 0.48 m, the
    +-45 deg sonars' at their cone's edge), so the parts on their arcs (within 3.4 cm of the
    range read, inside the cone) are kept again: the face's parts in the front cones (y
    1.35-1.43 and 1.57-1.65) among them. Without undo they stay carved. Parts beyond the arcs
    (x 2.09 and on, inside the box: the echo says nothing of them) stay carved, and so do the
    parts between the two front cones (y 1.45-1.55: no cone looks there)."""
    _, parts, kept_off = wrongly_carved_face("off", kernel)
    assert not kept_off.any()
    _, parts, kept = wrongly_carved_face("unexplained", kernel)
    x, y = parts[..., 0], parts[..., 1]
    on_face = np.abs(x - 2.05) < 0.015
    assert kept[on_face & (np.abs(y - 1.39) < 0.045)].all() and kept[on_face & (np.abs(y - 1.61) < 0.045)].all()
    assert not kept[x > 2.08].any()
    assert not kept[np.abs(y - 1.5) < 0.05].any()
    assert 60 < kept.sum() < 100


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("clear, near, carves", [(0.0, 0.05, True), (0.07, 0.05, False), (0.07, 0.1, True)])
def test_the_body_carves_only_while_no_echo_is_nearer_than_body_clear(kernel: str, clear: float, near: float,
                                                                      carves: bool) -> None:
    """An occupied cell under the robot: its parts within the radius are carved at once, unless
    a sonar reads an echo nearer than ``body_clear`` (pressed on an obstacle, the wheels slip
    and odometry drives on into it). ``body_clear`` 0 (D* Lite's, main's) always carves."""
    robot = default_robot(radius=0.18)
    frame = GridFrame(0.0, 0.0, 0.1, 10, 10)
    carving = SeeThroughCarving(frame, np.array([0.5, 0.5, 0.0]), kernel, body_clear=clear)
    occupied = np.zeros(frame.shape, dtype=bool)
    occupied[5, 5] = True  # the cell (0.5-0.6, 0.5-0.6), under the body
    ranges = np.full(len(robot.sonar.angles), robot.sonar.max_range)
    ranges[2] = near
    obs = observe(BoxWorld.room((1.0, 1.0)), np.array([0.5, 0.5, 0.0]), np.ones(2), robot, 1.0, 0.1)
    obs = dataclasses.replace(obs, ranges=ranges)
    out = carving.update(obs, np.array([5]), np.array([5]), (0, 10, 0, 10), occupied)
    under = np.hypot(out.parts[0, :, 0] - 0.5, out.parts[0, :, 1] - 0.5) <= robot.radius
    assert under.all() and len(under) == PARTS
    assert (~out.kept[0]).all() == carves and out.kept[0].all() == (not carves)


def test_the_undo_mode_is_checked() -> None:
    with pytest.raises(InputError, match="undo"):
        SeeThroughCarving(FRAME, np.zeros(3), "numpy", undo="always")
    parts = cell_parts(np.array([[2.05, 1.55]]), 0.1)
    assert parts.shape == (1, PARTS, 2)


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("body_memory_s, kept_at_4_2", [(None, False), (3.0, True)])
def test_the_body_carving_expires_after_body_memory_s(kernel: str, body_memory_s: float | None,
                                                      kept_at_4_2: bool) -> None:
    """With a 10 s memory, a part the body carved at t 1 s is still carved at t 4.2 s unless
    ``body_memory_s`` is 3 s (recorded 7 s early, it expires at t 4 s). Readings at the
    minimum range see through nothing, so only the body carves."""
    robot = default_robot(radius=0.18)
    frame = GridFrame(0.0, 0.0, 0.1, 10, 10)
    carving = SeeThroughCarving(frame, np.array([0.55, 0.55, 0.0]), kernel, memory_s=10.0,
                                body_memory_s=body_memory_s)
    occupied = np.zeros(frame.shape, dtype=bool)
    occupied[5, 5] = True
    near = np.full(len(robot.sonar.angles), robot.sonar.min_range)
    base = observe(BoxWorld.room((1.0, 1.0)), np.array([0.55, 0.55, 0.0]), np.ones(2), robot, 1.0, 0.1)
    at_1 = dataclasses.replace(base, ranges=near)
    assert not carving.update(at_1, np.array([5]), np.array([5]), (0, 10, 0, 10), occupied).kept.any()
    away = dataclasses.replace(base, t=4.2, pose=np.array([0.1, 0.1, 0.0]), ranges=near)
    kept = carving.update(away, np.array([5]), np.array([5]), (0, 10, 0, 10), occupied).kept
    assert kept.all() == kept_at_4_2 and kept.any() == kept_at_4_2
