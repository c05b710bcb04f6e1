"""LoopDetector: a lap around a boundary is a return to the start with a net turn of 2 pi;
a follower that turned back the way it came has not gone round anything."""

from __future__ import annotations

import math

import numpy as np

from nav_bench.planners.follow import LEFT, RIGHT, LoopDetector


def feed(detector: LoopDetector, xy: np.ndarray, yaw: np.ndarray) -> int | None:
    """Index of the first sample at which the detector fires, None if it never does."""
    detector.arm(xy[0], yaw[0])
    for i in range(1, len(xy)):
        if detector.update(xy[i], yaw[i]):
            return i
    return None


def test_a_lap_around_a_circle_fires_when_the_robot_is_back_at_the_start():
    # counter-clockwise round a 1 m circle, heading along the tangent, 200 samples per lap
    s = np.linspace(0.0, 2.2 * math.pi, 221)
    xy = np.stack([np.cos(s), np.sin(s)], axis=1)
    fired = feed(LoopDetector(radius=0.4, min_length=1.6), xy, s + math.pi / 2)
    # back within 0.4 m of (1, 0) once the chord 2 sin((2 pi - s) / 2) is under 0.4 m:
    # s > 2 pi - 0.4027, the first sample (every 0.0314 rad) past it
    assert fired is not None
    assert 2 * math.pi - 0.4027 < s[fired] < 2 * math.pi - 0.4027 + 0.0315


def test_a_clockwise_lap_inside_an_enclosure_fires_too():
    s = np.linspace(0.0, -2.2 * math.pi, 221)
    xy = 2.0 * np.stack([np.cos(s), np.sin(s)], axis=1)
    assert feed(LoopDetector(radius=0.4, min_length=1.6), xy, s - math.pi / 2) is not None


def test_turning_back_the_way_it_came_is_not_a_lap():
    # 1.5 m out along +x, a U-turn of pi, 1.5 m back: at the start again after 3 m
    out = np.stack([np.linspace(0.0, 1.5, 16), np.zeros(16)], axis=1)
    back = out[::-1]
    xy = np.concatenate([out, back])
    yaw = np.concatenate([np.zeros(16), np.full(16, math.pi)])
    assert feed(LoopDetector(radius=0.4, min_length=1.6), xy, yaw) is None


def test_a_small_circle_in_place_of_the_wall_is_not_a_lap_before_min_length():
    # a 0.2 m circle (1.26 m long) turns 2 pi but is shorter than min_length = 1.6 m
    s = np.linspace(0.0, 2 * math.pi, 101)
    xy = 0.2 * np.stack([np.cos(s), np.sin(s)], axis=1)
    assert feed(LoopDetector(radius=0.1, min_length=1.6), xy, s + math.pi / 2) is None


def test_with_a_side_only_a_lap_turning_toward_that_side_fires():
    # counter-clockwise round a 1 m circle: the circle's inside is on the robot's left
    s = np.linspace(0.0, 2.2 * math.pi, 221)
    xy = np.stack([np.cos(s), np.sin(s)], axis=1)
    assert feed(LoopDetector(radius=0.4, min_length=1.6, side=LEFT), xy, s + math.pi / 2) is not None
    # a follower keeping its boundary on the right that drove this lap went round free space
    # (a pocket, or spinning on the spot), not round anything it followed
    assert feed(LoopDetector(radius=0.4, min_length=1.6, side=RIGHT), xy, s + math.pi / 2) is None
    # clockwise round it, the circle's inside on the right
    cw = np.linspace(0.0, -2.2 * math.pi, 221)
    xy_cw = np.stack([np.cos(cw), np.sin(cw)], axis=1)
    assert feed(LoopDetector(radius=0.4, min_length=1.6, side=RIGHT), xy_cw, cw - math.pi / 2) is not None
    assert feed(LoopDetector(radius=0.4, min_length=1.6, side=LEFT), xy_cw, cw - math.pi / 2) is None
