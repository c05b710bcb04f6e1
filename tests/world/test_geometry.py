"""The true geometry's distance queries: one point at a time equals the vectorised ones."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.specs import WorldSpec
from nav_bench.world.geometry import PointClearance, clearance, static_geometry


def world(obstacles: list[dict]) -> WorldSpec:
    return WorldSpec.model_validate({"name": "t", "size": [10.0, 8.0], "start": [1.0, 1.0, 0.0],
                                     "goal": [9.0, 7.0], "obstacles": obstacles})


MIXED = [
    {"box": {"center": [5.0, 4.0], "size": [2.0, 1.0], "yaw_deg": 30.0}},
    {"cylinder": {"center": [2.5, 6.0], "radius": 0.4}},
    {"wall": {"from": [7.0, 1.0], "to": [7.5, 5.0], "thickness": 0.1}},
]


def test_point_clearance_is_the_vectorised_clearance_bit_for_bit():
    geometry = static_geometry(world(MIXED))
    points = np.random.default_rng(3).uniform((-1.0, -1.0), (11.0, 9.0), size=(2000, 2))
    expected = clearance(geometry, points)
    one_by_one = np.array([PointClearance(geometry)(x, y) for x, y in points.tolist()])
    assert np.array_equal(one_by_one, expected)


@pytest.mark.parametrize(("bucket", "reach"), [(0.5, 1.0), (0.3, 0.2), (2.0, 0.05)])
def test_point_clearance_by_squares_equals_clearance_near_and_far(bucket, reach):
    """Near obstacles the answer comes from a square's short list, elsewhere from all
    primitives: both bit for bit the vectorised clearance, inside, near, far and off the map."""
    geometry = static_geometry(world(MIXED))
    rng = np.random.default_rng(7)
    near = rng.uniform(-0.4, 0.4, size=(3000, 2)) + np.repeat(
        [[5.0, 4.0], [2.5, 6.0], [7.0, 1.0], [7.5, 5.0], [0.0, 3.0], [10.0, 8.0]], 500, axis=0)
    points = np.concatenate([near, rng.uniform((-2.0, -2.0), (12.0, 10.0), size=(1000, 2))])
    at = PointClearance(geometry, bucket=bucket, reach=reach)
    one_by_one = np.array([at(x, y) for x, y in points.tolist()])
    assert np.array_equal(one_by_one, clearance(geometry, points))


def test_point_clearance_of_known_points():
    at = PointClearance(static_geometry(world(MIXED)))
    assert at(2.5, 7.0) == pytest.approx(0.6)  # 1 m above the cylinder's centre, radius 0.4
    assert at(2.5, 6.0) == pytest.approx(-0.4)  # its centre: inside, 0.4 m deep
    # the box's own frame: 1.5 m along its long axis from the centre is 0.5 m past its end
    assert at(5.0 + 1.5 * math.cos(math.radians(30)), 4.0 + 1.5 * math.sin(math.radians(30))) \
        == pytest.approx(0.5)


def test_point_clearance_without_obstacles_is_infinite():
    empty = static_geometry(WorldSpec.model_validate(
        {"name": "e", "size": [4.0, 4.0], "start": [1.0, 1.0, 0.0], "goal": [3.0, 3.0],
         "boundary": False}))
    assert PointClearance(empty)(2.0, 2.0) == math.inf
