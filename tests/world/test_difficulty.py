"""BARN difficulty measures on hand-built worlds with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.world.difficulty import cast_rays, difficulty, sample_polyline
from nav_bench.world.geometry import static_geometry
from nav_bench.world.load import world_from_data

SQ2 = math.sqrt(2.0)


def world(size, start, goal, obstacles=()):
    return world_from_data({"size": list(size), "start": list(start), "goal": list(goal),
                            "obstacles": list(obstacles)})


def test_rays_hit_boxes_cylinders_and_the_world_edge():
    w = world((10, 10), (1, 1), (9, 9), [{"box": {"center": [5, 5], "size": [2, 2], "yaw_deg": 45}},
                                         {"cylinder": {"center": [2, 8], "radius": 0.5}}])
    g = static_geometry(w)
    rays = cast_rays(g, np.array([[1.0, 5.0], [2.0, 5.0], [5.0, 5.0]]),
                     np.radians([0, 90, 180, 270]))
    # from (1, 5): east to the diamond's left corner at x = 5 - sqrt 2; north to y = 10
    assert rays[0] == pytest.approx([4 - SQ2, 5, 1, 5])
    # from (2, 5) north: the cylinder's bottom at y = 7.5
    assert rays[1, 1] == pytest.approx(2.5)
    assert rays[2] == pytest.approx([0, 0, 0, 0])  # inside the box
    diag = cast_rays(g, np.array([[1.0, 1.0]]), np.radians([45]))
    # along the diagonal to the diamond's edge: the diamond |x-5|+|y-5| <= sqrt 2
    assert diag[0, 0] == pytest.approx(SQ2 * (4 - SQ2 / 2))


def test_sample_polyline_even_spacing():
    pts = sample_polyline(np.array([[0, 0], [3, 0], [3, 4]]), 0.5)
    assert len(pts) == 15 and pts[0].tolist() == [0, 0] and pts[-1].tolist() == [3, 4]
    assert np.hypot(*np.diff(pts, axis=0).T) == pytest.approx(np.full(14, 0.5))


def test_empty_room():
    d = difficulty(world((10, 10), (2, 5), (8, 5)))
    assert d["tortuosity"] == pytest.approx(1.0)
    assert d["optimal_length_m"] == pytest.approx(6.0)
    assert d["free_area_m2"] == pytest.approx(100.0)
    # along y = 5 from x = 2 to 8 the nearest wall is at min(x, 10 - x): mean 3.5 m
    assert d["closest_obstacle_m"] == pytest.approx(3.5, rel=0.005)
    # rays at (x, 5): E 10-x, W x, N 5, S 5, NE/SE sqrt2 min(10-x, 5), NW/SW sqrt2 min(x, 5)
    x = np.linspace(2, 8, 100001)
    vis = (10 + 10 + 2 * SQ2 * np.minimum(10 - x, 5) + 2 * SQ2 * np.minimum(x, 5)) / 8
    assert d["average_visibility_m"] == pytest.approx(vis.mean(), rel=0.002)
    assert d["dispersion"] == 0.0  # nothing within 0.63 m of the path
    # narrowest chord: horizontal and vertical 10 m; a diagonal one is shorter only near
    # x = 2, where it runs from the left wall to the top: sqrt 2 (x + 5)
    chord = np.minimum(10, SQ2 * (np.minimum(10 - x, 5) + np.minimum(x, 5)))
    assert d["characteristic_dimension_m"] == pytest.approx(chord.mean(), rel=1e-3)


def test_straight_corridor():
    width = 1.0
    d = difficulty(world((10, width), (1, 0.5), (9, 0.5)))
    assert d["closest_obstacle_m"] == pytest.approx(width / 2)
    assert d["characteristic_dimension_m"] == pytest.approx(width)
    assert d["tortuosity"] == pytest.approx(1.0)
    # E + W = 10, N = S = 0.5, four diagonals 0.5 sqrt 2
    assert d["average_visibility_m"] == pytest.approx((10 + 1 + 4 * 0.5 * SQ2) / 8)
    # of 16 rays, those within 22.5 deg of N or S hit the walls within 0.63 m
    # (0.5 / sin 67.5 = 0.54), the others do not (0.5 / sin 45 = 0.71): 2 blocked arcs
    assert d["dispersion"] == pytest.approx(4.0)
    assert d["free_area_m2"] == pytest.approx(10.0)


def test_wall_detour_tortuosity():
    r = 0.2
    w = world((10, 10), (2, 5), (8, 5), [{"wall": {"from": [5, 3], "to": [5, 10], "thickness": 0.2}}])
    d = difficulty(w, robot_radius=r)
    # the hand-computed detour of test_optimal: 7.623 m over a 6 m chord
    assert d["tortuosity"] == pytest.approx(7.623 / 6.0, rel=0.01)
    assert d["free_area_m2"] == pytest.approx(100 - 0.2 * 7.0, abs=0.05)
    assert d["closest_obstacle_m"] < 2.0 and d["dispersion"] > 0


def test_unreachable_goal_has_no_path_measures():
    box = {"polyline": {"points": [[7, 4], [9, 4], [9, 6], [7, 6]], "closed": True}}
    d = difficulty(world((10, 10), (1, 5), (8, 5), [box]))
    assert d["optimal_length_m"] is None and d["tortuosity"] is None
    assert d["closest_obstacle_m"] is None
    assert d["free_area_m2"] == pytest.approx(100 - 4 * 2.15 * 0.15, abs=0.1)
