"""The robot: URDF model, wheel kinematics, drive limits, odometry and bad URDFs."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from sim_helpers import make_sim, make_world

from nav_bench.errors import RobotModelError
from nav_bench.interface import Command, wrap_angle
from nav_bench.sim.robot import integrate_odometry, wheel_speeds
from nav_bench.specs import RobotSpec, default_robot_file, default_robot_radius, load_robot

DIFFBOT_URDF = default_robot_file().parent / "diffbot.urdf"
OPEN_FLOOR = {"size": (20.0, 20.0), "start": (10.0, 10.0, 0.0)}


def drive(sim, cmd: Command, seconds: float) -> tuple[float, float]:
    """Drive ``cmd`` for ``seconds``; returns (path length m, signed turn rad) of the true pose."""
    sim.apply(cmd)
    length = turn = 0.0
    prev = sim.true_pose()
    for _ in range(round(seconds / sim.dt)):
        sim.step(1)
        pose = sim.true_pose()
        length += float(np.hypot(*(pose[:2] - prev[:2])))
        turn += wrap_angle(pose[2] - prev[2])
        prev = pose
    return length, turn


def test_robot_info_comes_from_the_urdf_and_config(session, exact_robot):
    sim = make_sim(session, make_world(), exact_robot)
    info = sim.robot_info
    assert info.radius == pytest.approx(0.18)
    assert info.radius == default_robot_radius()  # the world tools read the URDF alike
    assert info.wheel_base == pytest.approx(0.26)
    assert sim.robot.model.wheel_radius == pytest.approx((0.05, 0.05))
    assert info.v_max == pytest.approx(0.05 * exact_robot.drive.max_wheel_speed)
    assert info.v_max >= 0.6  # planners default to 0.5 m/s
    assert info.omega_max == pytest.approx(2 * info.v_max / 0.26)
    assert sim.robot.model.sonar_names == tuple(f"sonar_{i}" for i in range(6))


def test_robot_stands_still_at_the_start_pose(session, exact_robot):
    sim = make_sim(session, make_world(start=(3.0, 4.0, 30.0)), exact_robot)
    start = np.array([3.0, 4.0, math.radians(30.0)])
    assert sim.true_pose() == pytest.approx(start)
    assert sim.odometry_pose() == pytest.approx(start)
    sim.step(480)  # 2 s at rest: it settles without drifting or tipping
    pose = sim.true_pose()
    assert pose[:2] == pytest.approx(start[:2], abs=1e-4)
    # Bullet's friction pyramid (the session turns the cone off: steps ~1.7x cheaper) lets a
    # standing robot creep in yaw by ~1e-4 rad in 2 s; the cone held it to < 1e-5
    assert pose[2] == pytest.approx(start[2], abs=5e-4)
    (_, _, z), orn = sim.robot.link_pose()
    roll, pitch, _ = session.client.getEulerFromQuaternion(orn)
    assert z == pytest.approx(0.05, abs=1e-3)  # axle height = wheel radius
    assert abs(roll) < 1e-3 and abs(pitch) < 1e-3
    assert sim.collisions == 0 and not sim.contact_now


@pytest.mark.parametrize(("v", "omega"), [(0.5, 0.0), (0.3, 0.5), (0.6, -0.8), (0.2, 1.5),
                                          (-0.3, 0.0)])
def test_commanded_velocities_give_that_motion(session, exact_robot, v, omega):
    sim = make_sim(session, make_world(**OPEN_FLOOR), exact_robot)
    drive(sim, Command(v, omega), 1.0)  # accelerate
    length, turn = drive(sim, Command(v, omega), 2.0)
    assert length / 2.0 == pytest.approx(abs(v), rel=0.05, abs=1e-3)
    assert turn / 2.0 == pytest.approx(omega, rel=0.05, abs=1e-3)


def test_turning_in_place_keeps_the_axle_centre(session, exact_robot):
    sim = make_sim(session, make_world(**OPEN_FLOOR), exact_robot)
    _, turn = drive(sim, Command(0.0, 2.0), 3.0)
    ramp_s = (2.0 * 0.13 / 0.05) / exact_robot.drive.max_wheel_accel  # wheels reach speed
    assert turn == pytest.approx(2.0 * (3.0 - ramp_s / 2), rel=0.01)
    assert sim.true_pose()[:2] == pytest.approx([10.0, 10.0], abs=0.01)


def test_speed_limit_scales_both_wheels_and_keeps_the_curvature(session, exact_robot):
    wl, wr = wheel_speeds(2.0, 4.0, 0.26, (0.05, 0.05), max_speed=15.0)
    assert max(abs(wl), abs(wr)) == pytest.approx(15.0)
    v, omega = 0.05 * (wl + wr) / 2, 0.05 * (wr - wl) / 0.26
    assert omega / v == pytest.approx(4.0 / 2.0)
    sim = make_sim(session, make_world(**OPEN_FLOOR), exact_robot)
    drive(sim, Command(2.0, 0.0), 1.5)
    length, _ = drive(sim, Command(2.0, 0.0), 1.0)
    assert length == pytest.approx(sim.robot_info.v_max, rel=0.01)


def test_acceleration_is_limited(session, exact_robot):
    sim = make_sim(session, make_world(**OPEN_FLOOR), exact_robot)
    accel = exact_robot.drive.max_wheel_accel * 0.05  # m/s^2 at the rim
    length, _ = drive(sim, Command(0.5, 0.0), 0.25)
    assert length == pytest.approx(accel * 0.25**2 / 2, rel=0.1)  # uniform ramp from rest


def test_odometry_without_noise_tracks_the_true_pose(session, exact_robot):
    sim = make_sim(session, make_world(**OPEN_FLOOR), exact_robot)
    travelled = 0.0
    for cmd, seconds in [(Command(0.4, 0.4), 4.0), (Command(0.5, -0.7), 3.0),
                         (Command(0.0, 1.5), 1.0), (Command(0.3, 0.2), 2.0)]:
        travelled += drive(sim, cmd, seconds)[0]
    assert travelled > 3.5
    error = np.hypot(*(sim.odometry_pose()[:2] - sim.true_pose()[:2]))
    assert error < 0.02 * travelled
    assert wrap_angle(sim.odometry_pose()[2] - sim.true_pose()[2]) == pytest.approx(0.0, abs=0.02)


def test_odometry_noise_is_seeded_and_drifts(session):
    robot = load_robot(overrides={"odometry": {"wheel_noise": 0.05}})
    poses = []
    for seed in (4, 4, 5):
        sim = make_sim(session, make_world(**OPEN_FLOOR), robot, seed=seed)
        sim.apply(Command(0.5, 0.0))
        for _ in range(40):  # 4 s in 10 Hz control cycles
            sim.step(24)
        poses.append((sim.odometry_pose(), sim.true_pose()))
    assert np.array_equal(poses[0][0], poses[1][0])
    assert not np.array_equal(poses[0][0], poses[2][0])
    drift = np.hypot(*(poses[0][0][:2] - poses[0][1][:2]))
    assert 1e-3 < drift < 0.2


def test_integrate_odometry_midpoint_rule():
    # Quarter circle of radius 1 in one step: midpoint heading pi/4, chord length ~ arc length.
    x, y, yaw = integrate_odometry((0.0, 0.0, 0.0), math.pi / 2 * 0.87, math.pi / 2 * 1.13, 0.26)
    assert yaw == pytest.approx(math.pi / 2)
    assert (x, y) == pytest.approx((math.pi / 2 * math.cos(math.pi / 4),) * 2)


# ----------------------------------------------------------------------------- URDF handling
def urdf_variant(tmp_path: Path, edit) -> RobotSpec:
    text = edit(DIFFBOT_URDF.read_text())
    path = tmp_path / "variant.urdf"
    path.write_text(text)
    return RobotSpec(urdf=str(path))


def test_urdf_without_wheel_joints_is_refused(session, tmp_path):
    spec = urdf_variant(tmp_path, lambda t: t.replace('"left_wheel_joint"', '"lw"')
                        .replace('"right_wheel_joint"', '"rw"'))
    with pytest.raises(RobotModelError) as err:
        make_sim(session, make_world(), spec)
    msg = str(err.value)
    assert "variant.urdf" in msg and "'left_wheel_joint' or 'right_wheel_joint'" in msg
    assert "lw, rw, caster_joint" in msg  # lists the joints that exist


def test_urdf_without_sonar_frames_is_refused(session, tmp_path):
    spec = urdf_variant(tmp_path, lambda t: re.sub(r'"sonar_(\d)"', r'"ultrasound_\1"', t))
    with pytest.raises(RobotModelError, match=r"variant\.urdf: no sonar frames.*'sonar_<n>'"
                        r".*ultrasound_0"):
        make_sim(session, make_world(), spec)


def test_missing_or_broken_urdf_is_refused(session, tmp_path):
    with pytest.raises(RobotModelError, match=r"nothing\.urdf: robot URDF not found"):
        make_sim(session, make_world(), RobotSpec(urdf=str(tmp_path / "nothing.urdf")))
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'>")
    with pytest.raises(RobotModelError, match=r"broken\.urdf: PyBullet could not load"):
        make_sim(session, make_world(), RobotSpec(urdf=str(broken)))


def test_a_sonar_is_added_by_editing_the_urdf_only(session, tmp_path):
    extra = """
  <link name="sonar_6"><inertial><mass value="0.01"/><inertia ixx="1e-6" ixy="0" ixz="0"
    iyy="1e-6" iyz="0" izz="1e-6"/></inertial></link>
  <joint name="sonar_6_joint" type="fixed"><parent link="base_link"/><child link="sonar_6"/>
    <origin xyz="-0.18 0 0.05" rpy="0 0 3.141592653589793"/></joint>
</robot>"""
    spec = urdf_variant(tmp_path, lambda t: t.replace("</robot>", extra))
    sim = make_sim(session, make_world(), spec)
    info = sim.robot_info.sonar
    assert len(info.angles) == 7 and sim.sense().shape == (7,)
    assert abs(info.angles[6]) == pytest.approx(math.pi)
    assert info.offsets[6] == pytest.approx([-0.18, 0.0], abs=1e-6)


@pytest.mark.parametrize("capped", [False, True])
def test_a_turn_on_the_spot_begun_at_speed_rolls_on_unless_its_rate_keeps_the_outer_wheel(
        session, exact_robot, capped):
    # the premise of VFH+'s roll cap (results/baselines/vfh_s19/, vfh_s20/): from v0 = 0.25 m/s,
    # v = 0 with 5.77 rad/s ramps the outer wheel up and the inner down at the same rate, so the
    # centre keeps v0 until the outer wheel reaches omega b / 2, then slows: it rolls
    # v0 (omega b / 2 - v0) / a + v0^2 / a (0.19 m at a = 1 m/s^2); at omega = 2 v0 / b the outer
    # wheel already turns at the turn's speed and only the inner one reverses: v0^2 / a (0.06 m)
    sim = make_sim(session, make_world(**OPEN_FLOOR), exact_robot)
    v0, base = 0.25, sim.robot_info.wheel_base
    accel = exact_robot.drive.max_wheel_accel * 0.05  # m/s^2 at the rim
    omega = 2.0 * v0 / base if capped else 5.77
    drive(sim, Command(v0, 0.0), 1.5)  # up to speed
    roll, _ = drive(sim, Command(0.0, omega), 1.5)
    expected = v0 * max(omega * base / 2 - v0, 0.0) / accel + v0**2 / accel
    assert roll == pytest.approx(expected, rel=0.15)
    assert roll == pytest.approx(0.0625 if capped else 0.1875, abs=0.02)  # the figures quoted
