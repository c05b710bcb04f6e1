"""What a bug planner reads of one observation is worked out once and kept on it read-only
(issue 16): the same values as the plain computation, the same object on every call."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_bench.interface import Observation
from nav_bench.planners.follow import echo_mask, obstacle_ahead, robot_frame_hits
from nav_bench.testing.harness import default_robot


def observation(ranges: list[float]) -> Observation:
    robot = default_robot()
    return Observation(t=1.0, pose=np.array([2.0, 3.0, 0.7]), goal=np.array([5.0, 5.0]),
                       ranges=np.array(ranges, dtype=float), robot=robot, bounds=(0.0, 0.0, 6.0, 6.0), dt=0.1)


RANGES = [0.5, np.inf, 1.2, 0.3, 9.0, 0.8]  # an infinite and a beyond-max-range reading


def test_sonar_hits_are_the_echoes_in_the_world_and_are_kept_read_only() -> None:
    obs = observation(RANGES)
    yaw = obs.pose[2]
    turn = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    s = obs.robot.sonar
    # each echo: the mount point plus the range along the sonar's axis, turned into the world
    finite = np.isfinite(obs.ranges)
    local = s.offsets + obs.ranges[:, None] * np.column_stack([np.cos(s.angles), np.sin(s.angles)])
    expected = obs.pose[:2] + local[finite] @ turn.T
    hits = obs.sonar_hits()
    assert hits[finite] == pytest.approx(expected, abs=1e-12)
    assert not np.isfinite(hits[~finite]).any()  # the infinite reading stays off the map
    assert obs.sonar_hits() is hits and not hits.flags.writeable
    with pytest.raises(ValueError):
        hits[0, 0] = 0.0


def test_echo_mask_and_robot_frame_hits_are_computed_once_per_observation() -> None:
    obs = observation(RANGES)
    mask = echo_mask(obs)
    max_range = obs.robot.sonar.max_range
    assert mask.tolist() == [math.isfinite(r) and r < max_range for r in RANGES]
    assert echo_mask(obs) is mask and not mask.flags.writeable
    s = obs.robot.sonar
    r = np.where(np.isfinite(obs.ranges), obs.ranges, s.max_range)
    plain = s.offsets + r[:, None] * np.stack([np.cos(s.angles), np.sin(s.angles)], axis=1)
    np.testing.assert_array_equal(robot_frame_hits(obs), plain)
    assert robot_frame_hits(obs) is robot_frame_hits(obs)
    # a new observation is computed afresh
    assert echo_mask(observation([0.4] * 6)).all()


def test_obstacle_ahead_is_the_nearest_echo_inside_the_corridor() -> None:
    ranges = [3.0] * 6
    ranges[2] = ranges[3] = 0.3  # the +-15 deg sonars: an echo ahead
    obs = observation(ranges)
    p = robot_frame_hits(obs)[echo_mask(obs)]
    inside = (p[:, 0] > 0.0) & (p[:, 0] < 1.0) & (np.abs(p[:, 1]) < 0.25)
    assert obstacle_ahead(obs, 1.0, 0.25) == float(p[inside, 0].min())
    assert obstacle_ahead(obs, 0.1, 0.25) == math.inf
