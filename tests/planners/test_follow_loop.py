"""LoopDetector: a lap around a boundary is a return to the start with a net turn of 2 pi;
a follower that turned back the way it came has not gone round anything. CirclingDetector:
a follower turning full circles away from its side within a small disc (issue 12)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from nav_bench.planners.follow import LEFT, RIGHT, CirclingDetector, LoopDetector


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


# ----------------------------------------------------------------------------- circling in place
def circle_in_place(detector: CirclingDetector, turns_per_s: float, radius: float, seconds: float,
                    t0: float = 0.0) -> int | None:
    """Feed a robot on a circle of ``radius`` m round (1, 1), heading along it, ``turns_per_s``
    full turns a second (+ counter-clockwise), at 10 Hz from ``t0`` s for ``seconds`` s; the
    index of the first cycle at which the detector says circling, None if it never does."""
    fired = None
    for i in range(round(seconds * 10) + 1):
        a = 2 * math.pi * turns_per_s * (i / 10)
        yaw = a + math.copysign(math.pi / 2, turns_per_s)
        if detector.update(t0 + i / 10, 1.0 + radius * math.cos(a), 1.0 + radius * math.sin(a), yaw) and fired is None:
            fired = i
    return fired


def test_circling_in_place_away_from_the_side_is_said_after_one_and_a_half_turns():
    # the office_2 cycle: a turn every 4 s away from a wall on the right, within 0.15 m;
    # 1.5 turns at t = 6 s (cycle 60), without waiting for the 20 s window
    assert circle_in_place(CirclingDetector(RIGHT), 0.25, 0.15, 60.0) == 60
    assert circle_in_place(CirclingDetector(LEFT), -0.25, 0.15, 60.0) == 60
    # office_13's: a turn every 10 s, within 0.43 m: at t = 15 s
    assert circle_in_place(CirclingDetector(RIGHT), 0.1, 0.3, 60.0) == 150


def test_circling_toward_the_side_is_a_lap_round_something_not_circling():
    assert circle_in_place(CirclingDetector(RIGHT), -0.25, 0.15, 60.0) is None
    assert circle_in_place(CirclingDetector(LEFT), 0.25, 0.15, 60.0) is None


def test_circling_needs_one_and_a_half_turns_in_the_window_within_the_disc():
    # 20 s: 1.4 turns away do not count, 1.6 do (at 1.5 turns, t = 18.75 s)
    assert circle_in_place(CirclingDetector(RIGHT), 1.4 / 20, 0.15, 60.0) is None
    assert circle_in_place(CirclingDetector(RIGHT), 1.6 / 20, 0.15, 60.0) == 188
    # the positions' bounding box: half-diagonal 0.3 sqrt 2 = 0.42 m counts, 0.4 sqrt 2 = 0.57 m not
    assert circle_in_place(CirclingDetector(RIGHT), 0.25, 0.30, 60.0) == 60
    assert circle_in_place(CirclingDetector(RIGHT), 0.25, 0.40, 60.0) is None


def test_the_circling_is_said_only_while_it_lasts():
    detector = CirclingDetector(RIGHT)
    circle_in_place(detector, 0.25, 0.15, 10.0)
    assert detector.fired
    # then the robot drives off east, straight: no longer circling once it is 1 m away
    for i in range(1, 31):
        detector.update(10.0 + i / 10, 1.15 + 0.05 * i, 1.0, math.pi / 2 + 2 * math.pi * 2.5)
    assert not detector.fired


def test_a_pause_in_the_follower_cycles_starts_the_watch_again():
    detector = CirclingDetector(RIGHT)
    assert circle_in_place(detector, 0.25, 0.15, 5.0) is None  # 1.25 turns
    # 1 s without a cycle (the planner drove to the goal), then circling again from t = 6 s
    assert circle_in_place(detector, 0.25, 0.15, 30.0, t0=6.0) == 60  # t = 12 s, not 7 s


def test_the_recorded_office_2_cycle_is_said_and_the_following_before_it_is_not():
    """Main's Bug2 on office_2 (families, seed 0), its odometry poses of 0-60 s: it follows the
    south room's furniture, turning 340 deg in the first 20 s and 515 deg in the next 20 s, then
    from 40 s circles in the pocket between the two boxes and the south wall (follow_s17: it
    left it after 10 s there and ended circling at the junction west of it). The detector keeps
    quiet through the following and says circling at 46.7 s, 6.7 s into the cycle."""
    rows = np.loadtxt(Path(__file__).parents[1] / "data" / "circling" / "office_2_bug2_main_odom.csv", delimiter=",")
    detector = CirclingDetector(RIGHT)
    fired = [detector.update(*row) for row in rows]
    first = fired.index(True)  # the first cycle said circling
    assert rows[first, 0] == 46.7
    assert 3.0 < rows[first, 1] < 3.8 and rows[first, 2] < 0.6  # in the pocket
