"""Sonar: ranges against known geometry, cone coverage, noise, dropout and mounts from the URDF."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sim_helpers import make_sim, make_world

from nav_bench.sim.sonar import cone_offsets, noisy_readings
from nav_bench.specs import SonarSpec, load_robot

MOUNT_DEG = [-90.0, -45.0, -15.0, 15.0, 45.0, 90.0]
BODY_RADIUS = 0.18  # diffbot's sonars sit on its edge


def wall_facing(face_x: float, thickness: float = 0.2) -> dict:
    """A vertical wall whose face towards -x lies at ``face_x``."""
    x = face_x + thickness / 2
    return {"wall": {"from": [x, 0.5], "to": [x, 9.5], "thickness": thickness}}


@pytest.mark.parametrize("sonar", [2, 3, 4])
@pytest.mark.parametrize("distance", [0.3, 1.0, 1.7, 2.9])
def test_sonar_reads_the_distance_to_a_wall_it_faces(session, exact_robot, sonar, distance):
    # Turn the robot so this sonar's axis points along +x: it then sits at (x0 + 0.18, y0).
    x0 = 2.0
    world = make_world(start=(x0, 5.0, -MOUNT_DEG[sonar]),
                       obstacles=[wall_facing(x0 + BODY_RADIUS + distance)])
    sim = make_sim(session, world, exact_robot)
    assert sim.sense()[sonar] == pytest.approx(distance, abs=2e-3)


def test_obstacle_inside_the_cone_but_off_its_axis_is_seen(session, exact_robot):
    # Sonar 3 looks along +x (robot yaw -15 deg); a thin post 10 deg off its axis, 1.5 m away.
    sx, sy = 2.0 + BODY_RADIUS, 5.0
    post = {"cylinder": {"center": [sx + 1.5 * math.cos(math.radians(10)),
                                    sy + 1.5 * math.sin(math.radians(10))], "radius": 0.05}}
    world = make_world(start=(2.0, 5.0, -15.0), obstacles=[post])
    ranges = make_sim(session, world, exact_robot).sense()
    assert 1.40 < ranges[3] < 1.5
    # Outside the cone (25 deg opening) the same post is not seen by that sonar.
    post["cylinder"]["center"] = [sx + 1.5 * math.cos(math.radians(20)),
                                  sy + 1.5 * math.sin(math.radians(20))]
    world = make_world(start=(2.0, 5.0, -15.0), obstacles=[post])
    assert make_sim(session, world, exact_robot).sense()[3] == 3.0


def test_nothing_in_range_reads_max_range(session, exact_robot):
    far = {"box": {"center": [9.0, 9.0], "size": [0.5, 0.5]}}  # > 3 m from everything
    world = make_world(start=(3.0, 3.0, 0.0), obstacles=[far])
    ranges = make_sim(session, world, exact_robot).sense()
    assert ranges.tolist() == [3.0] * 6


def test_min_range_clips_close_echoes(session, exact_robot):
    # Robot pressed against the wall: the front sonars' rays start at the wall face.
    world = make_world(start=(2.0, 5.0, 0.0), obstacles=[wall_facing(2.0 + BODY_RADIUS + 0.01)])
    ranges = make_sim(session, world, exact_robot).sense()
    assert ranges[2] == ranges[3] == exact_robot.sonar.min_range


def ray_circle(origin: np.ndarray, angle: float, centre: np.ndarray, radius: float) -> float:
    """Distance along a ray to a circle (inf when it misses)."""
    d = np.array([math.cos(angle), math.sin(angle)])
    oc = origin - centre
    b = float(oc @ d)
    disc = b * b - (float(oc @ oc) - radius**2)
    return -b - math.sqrt(disc) if disc >= 0 and -b - math.sqrt(disc) > 0 else math.inf


def test_the_robot_does_not_see_itself_and_movers_are_seen(session, exact_robot):
    centre, radius = np.array([5.0, 5.0]), 0.25
    mover = {"shape": {"cylinder": {"radius": radius}}, "path": [centre.tolist(), [5.0, 5.0001]],
             "speed": 0.1}
    world = make_world(start=(2.0, 5.0, 0.0), movers=[mover])
    sim = make_sim(session, world, exact_robot)
    ranges = sim.sense()
    info = sim.robot_info.sonar
    for k in (2, 3):  # the front sonars: nearest echo over the cone's 7 rays
        origin = np.array([2.0, 5.0]) + info.offsets[k]
        expected = min(ray_circle(origin, info.angles[k] + a, centre, radius)
                       for a in cone_offsets(info.cone, 7))
        assert ranges[k] == pytest.approx(expected, abs=2e-3)
    assert ranges[[0, 1, 4, 5]].tolist() == [3.0] * 4  # no echo from the robot's own body


def test_noise_is_seeded_and_has_the_configured_spread(session):
    robot = load_robot(overrides={"sonar": {"noise_std": 0.02}})
    world = make_world(start=(2.0, 5.0, -15.0), obstacles=[wall_facing(3.18)])
    a = make_sim(session, world, robot, seed=7).sense()
    b = make_sim(session, world, robot, seed=7).sense()
    c = make_sim(session, world, robot, seed=8).sense()
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
    sim = make_sim(session, world, robot, seed=1)
    readings = np.array([sim.sense()[3] for _ in range(2000)])
    assert readings.mean() == pytest.approx(1.0, abs=0.002)
    assert readings.std() == pytest.approx(0.02, rel=0.1)


def test_dropout_reads_max_range_at_the_configured_rate(session):
    robot = load_robot(overrides={"sonar": {"noise_std": 0.0, "dropout": 0.3}})
    world = make_world(start=(2.0, 2.0, 0.0), boundary=True, size=(4.0, 4.0))  # all see walls
    sim = make_sim(session, world, robot, seed=3)
    readings = np.array([sim.sense() for _ in range(600)])  # 3,600 readings
    lost = readings == robot.sonar.max_range
    assert lost.mean() == pytest.approx(0.3, abs=0.03)
    assert np.all(readings[~lost] < 2.5)


def test_noisy_readings_keep_no_echo_at_max_range_and_clip():
    spec = SonarSpec(noise_std=0.5, min_range=0.05, max_range=3.0)
    rng = np.random.default_rng(0)
    ranges = np.array([0.06, 2.99, 3.0, 1.0])
    hit = np.array([True, True, False, True])
    out = np.array([noisy_readings(ranges, hit, spec, rng) for _ in range(500)])
    assert np.all(out[:, 2] == 3.0)
    assert out.min() >= 0.05 and out.max() <= 3.0
    assert np.any(out[:, 0] == 0.05) and np.any(out[:, 1] == 3.0)


def test_cone_rays_span_the_cone_edges():
    assert cone_offsets(math.radians(25), 7) == pytest.approx(np.radians(np.linspace(-12.5, 12.5, 7)))
    assert cone_offsets(1.0, 1).tolist() == [0.0]


def test_sonar_mounts_are_read_from_the_urdf(session, exact_robot):
    info = make_sim(session, make_world(), exact_robot).robot_info.sonar
    assert np.degrees(info.angles) == pytest.approx(MOUNT_DEG, abs=1e-5)
    assert np.hypot(*info.offsets.T) == pytest.approx([BODY_RADIUS] * 6, abs=1e-6)
    assert np.arctan2(info.offsets[:, 1], info.offsets[:, 0]) == pytest.approx(info.angles, abs=1e-6)
    assert info.cone == pytest.approx(math.radians(25.0))
    assert (info.min_range, info.max_range) == (0.05, 3.0)


def test_last_rays_end_on_the_wall_they_hit_and_at_max_range_otherwise(session, exact_robot):
    # Sonar 3 looks along +x (robot yaw -15 deg) at a wall 1.0 m ahead; sonar 0 (-90 deg from
    # the heading) looks into 10 m of empty floor.
    face_x = 2.0 + BODY_RADIUS + 1.0
    world = make_world(start=(2.0, 5.0, -MOUNT_DEG[3]), obstacles=[wall_facing(face_x)])
    sim = make_sim(session, world, exact_robot)
    assert sim.sonar.last_rays() is None
    sim.sense()
    rays = sim.sonar.last_rays()
    per_cone = exact_robot.sonar.rays
    wall = slice(3 * per_cone, 4 * per_cone)
    assert rays.hit[wall].all()
    assert rays.ends[wall, 0] == pytest.approx(np.full(per_cone, face_x), abs=1e-6)
    empty = slice(0, per_cone)
    assert not rays.hit[empty].any()
    reach = np.hypot(*(rays.ends[empty, :2] - rays.starts[empty, :2]).T)
    assert reach == pytest.approx(np.full(per_cone, exact_robot.sonar.max_range))
