"""Grid shortest paths (MovingAI semantics) and the disc robot's optimal path."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import world_from_data
from nav_bench.world.optimal import (
    grid_distances,
    grid_path,
    grid_path_length,
    optimal_path,
    polyline_length,
    string_pull,
    tighten,
)
from nav_bench.world.raster import rasterize

SQ2 = math.sqrt(2.0)


def grid(text: str) -> np.ndarray:
    """'#' blocked, '.' free; first text line is row 0."""
    return np.array([[ch == "#" for ch in line] for line in text.split()])


# --------------------------------------------------------------------------- grid search
def test_empty_grid_octile_distance():
    blocked = np.zeros((5, 7), bool)
    assert grid_path_length(blocked, (0, 0), (4, 6)) == pytest.approx(4 * SQ2 + 2)
    assert grid_path_length(blocked, (0, 0), (4, 6), diagonal=False) == pytest.approx(10)
    assert grid_path_length(blocked, (2, 3), (2, 3)) == 0.0


def test_no_corner_cutting_needs_both_orthogonal_neighbours():
    blocked = grid("""
        .#
        ..
    """)
    assert grid_path_length(blocked, (0, 0), (1, 1)) == pytest.approx(2.0)
    assert grid_path_length(blocked, (0, 0), (1, 1), corner_cutting=True) == pytest.approx(SQ2)
    squeeze = grid("""
        .#
        #.
    """)
    assert grid_path_length(squeeze, (0, 0), (1, 1)) is None
    assert grid_path_length(squeeze, (0, 0), (1, 1), corner_cutting=True) == pytest.approx(SQ2)


def test_detour_around_a_wall():
    blocked = grid("""
        .......
        ...#...
        ...#...
        ...#...
        .......
    """)
    # (2,0) -> (2,6): diagonal to (4,2)? no: up around the wall top at row 0 or bottom at row 4
    # (2,0) -> (1,1) -> (0,2) -> (0,3) -> (0,4) -> (1,5) -> (2,6): 4 diagonals + 2 straight
    assert grid_path_length(blocked, (2, 0), (2, 6)) == pytest.approx(4 * SQ2 + 2)
    length, cells = grid_path(blocked, (2, 0), (2, 6))
    assert length == pytest.approx(4 * SQ2 + 2)
    steps = np.diff(cells, axis=0)
    assert np.abs(steps).max() == 1 and not blocked[cells[:, 0], cells[:, 1]].any()
    assert np.hypot(*steps.T).sum() == pytest.approx(length)
    assert cells[0].tolist() == [2, 0] and cells[-1].tolist() == [2, 6]


def test_unreachable_and_blocked_endpoints():
    blocked = grid("""
        ..#..
        ..#..
        ..#..
    """)
    assert grid_path_length(blocked, (0, 0), (0, 4)) is None
    assert grid_path(blocked, (0, 0), (0, 4)) is None
    assert grid_path_length(blocked, (0, 2), (0, 0)) is None
    dist = grid_distances(blocked, (1, 0))
    assert np.isinf(dist[:, 2:]).all() and dist[0, 1] == pytest.approx(SQ2)
    with pytest.raises(ValueError, match="outside"):
        grid_path_length(blocked, (0, 0), (3, 0))


# --------------------------------------------------------------------------- robot paths
def world(obstacles=(), start=(1.0, 5.0), goal=(9.0, 5.0), size=(10.0, 10.0)):
    return world_from_data({"size": list(size), "start": list(start), "goal": list(goal),
                            "obstacles": list(obstacles)})


def path_is_clear(w, points, radius, tol):
    """Every point of the polyline keeps ``radius - tol`` from the true geometry."""
    samples = np.vstack([np.linspace(a, b, 200) for a, b in itertools.pairwise(points)])
    return clearance(static_geometry(w), samples).min() >= radius - tol


def test_empty_world_is_the_straight_line():
    w = world(start=(1.0, 2.0), goal=(8.5, 7.3))
    p = optimal_path(w, 0.18)
    assert p.length_m == pytest.approx(math.hypot(7.5, 5.3), rel=0.01)
    assert p.points[0].tolist() == [1.0, 2.0] and p.points[-1].tolist() == [8.5, 7.3]


def test_detour_around_a_wall_end():
    r = 0.2
    # wall x in [4.9, 5.1], y in [2.9, 10.1] (ends extended by half the thickness)
    w = world([{"wall": {"from": [5.0, 3.0], "to": [5.0, 10.0], "thickness": 0.2}}],
              start=(2.0, 5.0), goal=(8.0, 5.0))
    # hand computation: start -> tangent to the radius-r circle round corner (4.9, 2.9) ->
    # arc to its bottom point -> 0.2 m straight under the wall -> mirror image
    d = math.hypot(2.9, 2.1)
    tangent = math.sqrt(d * d - r * r)
    phi = math.atan2(2.1, -2.9)  # direction corner -> start
    tangent_angle = phi + math.acos(r / d)  # lower-left tangent point, about 231 deg
    arc = r * (1.5 * math.pi - tangent_angle)
    expected = 2 * (tangent + arc) + 0.2
    assert expected == pytest.approx(7.623, abs=1e-3)
    p = optimal_path(w, r)
    assert p.length_m == pytest.approx(expected, rel=0.01)
    assert p.length_m >= expected * 0.999  # the free raster is conservative
    assert p.grid_length_m >= p.length_m
    assert path_is_clear(w, p.points, r, tol=0.05)


def test_detour_around_a_cylinder():
    r, radius = 0.2, 1.0
    w = world([{"cylinder": {"center": [5.0, 5.0], "radius": radius}}])
    rho, d = radius + r, 4.0
    expected = 2 * math.sqrt(d * d - rho * rho) + rho * (math.pi - 2 * math.acos(rho / d))
    p = optimal_path(w, r)
    assert p.length_m == pytest.approx(expected, rel=0.01)
    assert path_is_clear(w, p.points, r, tol=0.05)


def test_enclosed_goal_is_unreachable():
    box = {"polyline": {"points": [[7, 4], [9, 4], [9, 6], [7, 6]], "closed": True}}
    p = optimal_path(world([box], goal=(8.0, 5.0)), 0.18)
    assert p.length_m is None and p.points.shape == (0, 2)


def test_gap_narrower_than_the_robot_is_closed():
    # two walls leave a 0.3 m gap at y in [4.85, 5.15]; a 0.2 m radius robot must go round
    # (wall ends extend by half the 0.15 m thickness)
    walls = [{"wall": {"from": [5.0, 0.0], "to": [5.0, 4.775]}},
             {"wall": {"from": [5.0, 5.225], "to": [5.0, 10.0]}}]
    assert optimal_path(world(walls), 0.1).length_m == pytest.approx(8.0, rel=0.01)
    assert optimal_path(world(walls), 0.2).length_m is None


def test_start_near_a_wall_snaps_to_the_nearest_free_cell():
    r = 0.18
    w = world([{"wall": {"from": [0.0, 5.0], "to": [10.0, 5.0], "thickness": 0.1}}],
              start=(2.0, 5.1), goal=(8.0, 5.3))
    p = optimal_path(w, r)
    assert p.points[0].tolist() == [2.0, 5.1]
    # start is 0.05 m from the wall: the first leg climbs ~0.18 m, then runs parallel
    assert p.length_m == pytest.approx(6.0 + 0.18, abs=0.12)


def test_string_pull_keeps_endpoints_and_never_crosses_obstacles():
    w = world([{"box": {"center": [5.0, 5.0], "size": [2.0, 2.0]}}])
    raster = rasterize(static_geometry(w), 0.05, inflate=0.2)
    zigzag = np.array([[1.0, 5.0], [2.0, 7.0], [3.0, 6.5], [5.0, 6.5], [7.0, 6.4], [9.0, 5.0]])
    out = string_pull(raster, zigzag)
    assert out[0].tolist() == [1.0, 5.0] and out[-1].tolist() == [9.0, 5.0]
    assert len(out) < len(zigzag)
    assert path_is_clear(w, out, 0.2, tol=0.05)


def test_tighten_pulls_a_wide_detour_onto_the_corners():
    w = world([{"box": {"center": [5.0, 5.0], "size": [2.0, 2.0]}}])
    raster = rasterize(static_geometry(w), 0.02)
    wide = np.array([[1.0, 5.0], [1.0, 8.0], [9.0, 8.0], [9.0, 5.0]])  # over the top, far off
    out = tighten(raster, wide)
    # taut path over the box: (1, 5) -> (4, 6) -> (6, 6) -> (9, 5)
    assert polyline_length(out) == pytest.approx(2 * math.sqrt(10) + 2, rel=0.01)
    assert out[0].tolist() == [1.0, 5.0] and out[-1].tolist() == [9.0, 5.0]
    assert path_is_clear(w, out, 0.0, tol=0.02)
