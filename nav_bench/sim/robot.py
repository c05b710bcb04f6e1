"""The robot: its URDF read into a :class:`RobotModel`, differential-drive actuation and odometry.

Everything about the robot's shape comes from its URDF, so a user changes the robot by
editing that file only (see ``robots/README.md``):

* wheel joints and sonar frames are found **by name** (``RobotSpec.left_wheel_joint``,
  ``right_wheel_joint``, and links ``<sonar_link_prefix><n>`` ordered by n);
* wheel radius = radius of each wheel link's collision cylinder (or sphere);
* wheel base = distance between the two wheel joint origins in the ground plane;
* body radius = smallest circle about the base frame origin enclosing the base link's
  collision shapes, in the ground plane;
* sonar mounts = position and yaw of each sonar link frame relative to the base link frame.

Frames: the base link frame is the robot pose; x forward, y left. PyBullet reports a body's
*centre of mass* frame as its "base pose"; this module converts to and from the link frame.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pybullet
from pybullet_utils.bullet_client import BulletClient

from nav_bench.errors import RobotModelError
from nav_bench.interface import Command, wrap_angle
from nav_bench.sim.session import GROUP_ROBOT, ROBOT_MASK, quiet_c_stdout
from nav_bench.specs import DriveSpec, RobotSpec

_IDENTITY = (0.0, 0.0, 0.0, 1.0)


@dataclass(frozen=True)
class RobotModel:
    """What nav-bench reads from a robot URDF (lengths in m, angles in rad, base link frame).

    Attributes:
        urdf: the file it was read from.
        left_joint, right_joint: PyBullet joint indices of the driven wheels.
        left_sign, right_sign: +1 when a positive joint rotation drives that wheel forward,
            -1 when the joint axis points the other way.
        wheel_radius: (left, right) radii of the wheels' collision shapes.
        wheel_base: distance between the wheel contact lines.
        radius: body radius (footprint circle about the base frame origin).
        sonar_links: link indices of the sonar frames in the URDF as written, ordered by their
            numeric suffix; empty in the simulated body, where fixed links are merged.
        sonar_names: their link names.
        sonar_mounts: (K, 3) sonar frame origins x, y, z in the base link frame.
        sonar_yaws: (K,) sonar axis yaw relative to the robot heading (CCW +).
        rest_height: height of the base frame above the floor when the robot stands on it.
        com_offset: (position, quaternion) of the centre-of-mass frame in the base link frame.
    """

    urdf: Path
    left_joint: int
    right_joint: int
    left_sign: float
    right_sign: float
    wheel_radius: tuple[float, float]
    wheel_base: float
    radius: float
    sonar_links: tuple[int, ...]
    sonar_names: tuple[str, ...]
    sonar_mounts: np.ndarray
    sonar_yaws: np.ndarray
    rest_height: float
    com_offset: tuple[tuple[float, float, float], tuple[float, float, float, float]]


def load_robot_body(client: BulletClient, spec: RobotSpec) -> tuple[int, RobotModel]:
    """Load the URDF of ``spec`` at the origin and read its model.

    Returns:
        ``(body_id, model)``; the body stands at the origin, facing +x.
    Raises:
        RobotModelError: the file is missing or unreadable, or lacks the wheel joints or
            sonar frames named by ``spec`` (the message lists the names that do exist).
    """
    path = spec.urdf_path
    if not path.is_file():
        raise RobotModelError(f"{path}: robot URDF not found (robot config key 'urdf')")
    flags = (pybullet.URDF_USE_IMPLICIT_CYLINDER  # true cylinders, not faceted hulls
             | pybullet.URDF_USE_INERTIA_FROM_FILE  # the URDF's inertias, not recomputed ones
             | pybullet.URDF_MAINTAIN_LINK_ORDER)
    try:
        with quiet_c_stdout():
            body = client.loadURDF(str(path), basePosition=[0, 0, 0],
                                   baseOrientation=list(_IDENTITY), flags=flags)
    except pybullet.error as exc:
        raise RobotModelError(f"{path}: PyBullet could not load this URDF ({exc}); "
                              "check the XML and any mesh files it names") from exc
    try:
        model = _read_model(client, body, spec, path)
    finally:
        client.removeBody(body)
    # The model is read from the URDF as written (sonar frames are links there); the body that
    # is simulated has its fixed links (sonar frames, caster) merged into the base. Bullet
    # otherwise integrates each of them as a link of its own: merged, a physics step costs
    # about 30 % less (41.7 -> 29.2 us on this machine), with the same shapes and masses.
    with quiet_c_stdout():
        body = client.loadURDF(str(path), basePosition=[0, 0, 0], baseOrientation=list(_IDENTITY),
                               flags=flags | pybullet.URDF_MERGE_FIXED_LINKS)
    return body, _simulated_model(client, body, spec, model)


def _simulated_model(c: BulletClient, body: int, spec: RobotSpec, model: RobotModel) -> RobotModel:
    """``model`` with the joint indices, centre of mass and rest height of the merged body."""
    joints = {c.getJointInfo(body, j)[1].decode(): j for j in range(c.getNumJoints(body))}
    dyn = c.getDynamicsInfo(body, -1)
    lowest = min(c.getAABB(body, link)[0][2] for link in range(-1, c.getNumJoints(body)))
    return dataclasses.replace(
        model, left_joint=joints[spec.left_wheel_joint], right_joint=joints[spec.right_wheel_joint],
        sonar_links=(), com_offset=(tuple(map(float, dyn[3])), tuple(map(float, dyn[4]))),
        rest_height=float(-lowest))


def _read_model(client: BulletClient, body: int, spec: RobotSpec, path: Path) -> RobotModel:
    c = client
    joints: dict[str, int] = {}
    links: dict[str, int] = {}
    for j in range(c.getNumJoints(body)):
        info = c.getJointInfo(body, j)
        joints[info[1].decode()] = j
        links[info[12].decode()] = j
    base_name = c.getBodyInfo(body)[0].decode()

    missing = [n for n in (spec.left_wheel_joint, spec.right_wheel_joint) if n not in joints]
    if missing:
        raise RobotModelError(
            f"{path}: no joint named {' or '.join(map(repr, missing))} (the robot config's "
            f"left_wheel_joint / right_wheel_joint); joints in this URDF: "
            f"{', '.join(joints) or '(none)'}")
    prefix = spec.sonar_link_prefix
    sonar_named = {n: i for n, i in links.items() if n.startswith(prefix)}
    if not sonar_named:
        raise RobotModelError(
            f"{path}: no sonar frames: expected links named '{prefix}<n>' (n = 0, 1, ...; "
            f"the robot config's sonar_link_prefix); links in this URDF: "
            f"{', '.join([base_name, *links])}")
    bad = [n for n in sonar_named if not re.fullmatch(r"\d+", n[len(prefix):])]
    if bad:
        raise RobotModelError(
            f"{path}: sonar link {bad[0]!r} does not end in a number after the prefix "
            f"{prefix!r}; name sonar frames '{prefix}0', '{prefix}1', ... (the number orders them)")
    sonar_names = tuple(sorted(sonar_named, key=lambda n: int(n[len(prefix):])))
    sonar_links = tuple(sonar_named[n] for n in sonar_names)

    # Link frames relative to the base link frame (the body was loaded at the origin).
    def frame(link: int) -> tuple[np.ndarray, np.ndarray]:
        state = c.getLinkState(body, link, computeForwardKinematics=True)
        rot = np.asarray(c.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        return _from_float32(state[4]), rot

    left, right = joints[spec.left_wheel_joint], joints[spec.right_wheel_joint]
    signs, radii, centres = [], [], []
    for name, j in ((spec.left_wheel_joint, left), (spec.right_wheel_joint, right)):
        info = c.getJointInfo(body, j)
        if info[2] != pybullet.JOINT_REVOLUTE:
            raise RobotModelError(f"{path}: wheel joint {name!r} must be 'continuous' or "
                                  "'revolute'")
        pos, rot = frame(j)
        axis = rot @ np.asarray(info[13])  # joint axis in the base frame
        if abs(axis[1]) < 0.99:
            raise RobotModelError(f"{path}: wheel joint {name!r} must turn about the base "
                                  f"link's y axis (left), its axis is {np.round(axis, 3).tolist()}")
        signs.append(1.0 if axis[1] > 0 else -1.0)
        radii.append(_wheel_radius(c, body, j, name, path))
        centres.append(pos)
    if centres[0][1] <= centres[1][1]:
        raise RobotModelError(f"{path}: {spec.left_wheel_joint!r} must lie left of "
                              f"{spec.right_wheel_joint!r} (larger y in the base frame)")
    wheel_base = float(np.hypot(*(centres[0][:2] - centres[1][:2])))

    mounts, yaws = [], []
    for link in sonar_links:
        pos, rot = frame(link)
        mounts.append(pos)
        yaws.append(math.atan2(rot[1, 0], rot[0, 0]))  # heading of the frame's x axis

    dyn = c.getDynamicsInfo(body, -1)
    com_offset = (tuple(map(float, dyn[3])), tuple(map(float, dyn[4])))
    lowest = min(c.getAABB(body, link)[0][2] for link in range(-1, c.getNumJoints(body)))
    return RobotModel(
        urdf=path, left_joint=left, right_joint=right, left_sign=signs[0], right_sign=signs[1],
        wheel_radius=(radii[0], radii[1]), wheel_base=wheel_base,
        radius=_body_radius(c, body, com_offset, path),
        sonar_links=sonar_links, sonar_names=sonar_names,
        sonar_mounts=np.asarray(mounts, dtype=float).reshape(-1, 3),
        sonar_yaws=np.asarray(yaws, dtype=float),
        # AABBs carry a 1 mm collision margin: the robot is dropped that far onto the floor.
        rest_height=float(-lowest), com_offset=com_offset)  # type: ignore[arg-type]


def _from_float32(values: tuple[float, ...]) -> np.ndarray:
    """Undo PyBullet's single-precision storage of link frames: the shortest decimal with the
    same float32 value (0.180000007 -> 0.18), which is the URDF's number when it has <= 7 digits."""
    return np.array([float(str(np.float32(v))) for v in values])


def _wheel_radius(c: BulletClient, body: int, joint: int, name: str, path: Path) -> float:
    shapes = c.getCollisionShapeData(body, joint)
    for shape in shapes:
        if shape[2] == pybullet.GEOM_CYLINDER:
            return float(shape[3][1])  # dimensions: (length, radius, -)
        if shape[2] == pybullet.GEOM_SPHERE:
            return float(shape[3][0])
    raise RobotModelError(f"{path}: the link of wheel joint {name!r} needs a cylinder or sphere "
                          "collision shape; nav-bench reads the wheel radius from it")


def _body_radius(c: BulletClient, body: int, com_offset: tuple, path: Path) -> float:
    """Footprint radius of the base link's collision shapes about the base frame origin."""
    shapes = c.getCollisionShapeData(body, -1)
    if not shapes:
        raise RobotModelError(f"{path}: the base link has no collision shape; nav-bench reads "
                              "the robot radius from it (a cylinder is best)")
    radius = 0.0
    for shape in shapes:
        kind, dims = shape[2], shape[3]
        # Shape frames are given relative to the centre-of-mass frame: back to the link frame.
        pos, orn = c.multiplyTransforms(com_offset[0], com_offset[1], shape[5], shape[6])
        centre = math.hypot(pos[0], pos[1])
        if kind == pybullet.GEOM_CYLINDER or kind == pybullet.GEOM_CAPSULE:
            radius = max(radius, centre + dims[1])
        elif kind == pybullet.GEOM_SPHERE:
            radius = max(radius, centre + dims[0])
        elif kind == pybullet.GEOM_BOX:
            rot = np.asarray(c.getMatrixFromQuaternion(orn)).reshape(3, 3)
            corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1)
                                for sz in (-1, 1)]) * (np.asarray(dims) / 2.0)
            xy = corners @ rot.T + np.asarray(pos)
            radius = max(radius, float(np.hypot(xy[:, 0], xy[:, 1]).max()))
        else:  # meshes: the circle around the link's bounding box
            (x0, y0, _), (x1, y1, _) = c.getAABB(body, -1)
            radius = max(radius, max(math.hypot(x, y) for x in (x0, x1) for y in (y0, y1)))
    return float(radius)


# ----------------------------------------------------------------------------- kinematics
def wheel_speeds(v: float, omega: float, wheel_base: float, radius: tuple[float, float],
                 max_speed: float) -> tuple[float, float]:
    """Wheel angular speeds (rad/s) for body velocity ``v`` (m/s) and turn rate ``omega`` (rad/s).

    ``wL = (v - omega b/2) / rL``, ``wR = (v + omega b/2) / rR``. When a wheel would exceed
    ``max_speed`` both are scaled by the same factor, which keeps the path's curvature.
    """
    wl = (v - omega * wheel_base / 2.0) / radius[0]
    wr = (v + omega * wheel_base / 2.0) / radius[1]
    peak = max(abs(wl), abs(wr))
    if peak > max_speed:
        scale = max_speed / peak
        wl, wr = wl * scale, wr * scale
    return wl, wr


def integrate_odometry(pose: tuple[float, float, float], d_left: float, d_right: float,
                       wheel_base: float) -> tuple[float, float, float]:
    """Advance ``pose`` (x, y, yaw) by wheel travel ``d_left``, ``d_right`` (m, arc length).

    Midpoint rule: the translation is applied along the heading halfway through the turn.
    """
    x, y, yaw = pose
    ds = (d_left + d_right) / 2.0
    dyaw = (d_right - d_left) / wheel_base
    mid = yaw + dyaw / 2.0
    return (x + ds * math.cos(mid), y + ds * math.sin(mid), wrap_angle(yaw + dyaw))


class DiffDriveRobot:
    """A loaded robot body: drive it by (v, omega), read its true and odometry poses.

    The command sets wheel speed targets (:func:`wheel_speeds`); every physics step each
    wheel's velocity motor (torque limit ``wheel_force``) is sent the target, but at most
    ``max_wheel_accel * dt`` away from the wheel's speed. Odometry integrates the wheel joint
    angle increments every physics step.

    Args:
        client: the session's client.
        spec: the robot config.
        pose: start pose (x, y, yaw) in m, m, rad.
        dt: physics time step, s.
    """

    def __init__(self, client: BulletClient, spec: RobotSpec, pose: tuple[float, float, float],
                 dt: float) -> None:
        self._c = client
        self.spec = spec
        self.body_id, self.model = load_robot_body(client, spec)
        self.dt = float(dt)
        m, c = self.model, client
        self._joints = [m.left_joint, m.right_joint]
        self._signs = (m.left_sign, m.right_sign)
        self._inv_com = c.invertTransform(*m.com_offset)
        drive: DriveSpec = spec.drive
        self._max_speed = float(drive.max_wheel_speed)
        self._max_delta = float(drive.max_wheel_accel) * self.dt
        self._forces = [float(drive.wheel_force)] * 2
        # Faithful rolling: no artificial velocity damping on the body.
        c.changeDynamics(self.body_id, -1, linearDamping=0.0, angularDamping=0.0)
        for link in range(-1, c.getNumJoints(self.body_id)):
            # Own collision group: sonar rays skip the robot, its links never collide together.
            c.setCollisionFilterGroupMask(self.body_id, link, GROUP_ROBOT, ROBOT_MASK)
        # Bound methods once: BulletClient builds a new partial on every attribute access.
        self._motor = c.setJointMotorControlArray
        self._joint_states = c.getJointStates
        self._base_pose = c.getBasePositionAndOrientation
        self._multiply = c.multiplyTransforms
        self.place(pose)

    # -- placement and state ---------------------------------------------------------------
    def place(self, pose: tuple[float, float, float]) -> None:
        """Stand the robot at ``pose`` (x, y, yaw), at rest; odometry restarts there."""
        x, y, yaw = map(float, pose)
        c, m = self._c, self.model
        link_orn = (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))
        com_pos, com_orn = c.multiplyTransforms((x, y, m.rest_height), link_orn, *m.com_offset)
        c.resetBasePositionAndOrientation(self.body_id, com_pos, com_orn)
        c.resetBaseVelocity(self.body_id, [0, 0, 0], [0, 0, 0])
        for j in self._joints:
            c.resetJointState(self.body_id, j, targetValue=0.0, targetVelocity=0.0)
        self._target = (0.0, 0.0)  # wheel speeds wanted by the last command, rad/s
        self._sent = (0.0, 0.0)  # velocity targets the motors have now, rad/s
        self._motor(self.body_id, self._joints, pybullet.VELOCITY_CONTROL,
                    targetVelocities=[0.0, 0.0], forces=self._forces)
        self._read_wheels()
        self._odom = (x, y, wrap_angle(yaw))

    def link_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """World pose (position, quaternion) of the base link frame."""
        pos, orn = self._base_pose(self.body_id)
        return self._multiply(pos, orn, *self._inv_com)

    def true_pose(self) -> np.ndarray:
        """(3,) true pose x, y, yaw (m, m, rad) of the base link frame."""
        (x, y, _), (qx, qy, qz, qw) = self.link_pose()
        yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
        return np.array([x, y, yaw])

    def odometry_pose(self) -> np.ndarray:
        """(3,) pose x, y, yaw (m, m, rad) dead-reckoned from the wheel encoders."""
        return np.array(self._odom)

    def _read_wheels(self) -> None:
        """Wheel angles (rad) and speeds (rad/s), positive forward."""
        (a, va, _, _), (b, vb, _, _) = self._joint_states(self.body_id, self._joints)
        sl, sr = self._signs
        self._angles, self._speeds = (sl * a, sr * b), (sl * va, sr * vb)

    # -- actuation -----------------------------------------------------------------------------
    def command(self, cmd: Command) -> tuple[float, float]:
        """Set the wheel speed targets for ``cmd``; returns them (rad/s, after the speed limit)."""
        m = self.model
        self._target = wheel_speeds(float(cmd.v), float(cmd.omega), m.wheel_base,
                                    m.wheel_radius, self._max_speed)
        return self._target

    def before_physics_step(self) -> None:
        """Send motor velocity targets: the command, at most ``max_wheel_accel * dt`` away
        from each wheel's measured speed (the acceleration limit).

        Ramping from the measured speed rather than from the last target means a wheel held
        by an obstacle does not wind its target up, so a new command acts at once.
        """
        d = self._max_delta
        (wl, wr), (tl, tr) = self._speeds, self._target
        sent = (wl + min(max(tl - wl, -d), d), wr + min(max(tr - wr, -d), d))
        if sent != self._sent:
            self._sent = sent
            self._motor(self.body_id, self._joints, pybullet.VELOCITY_CONTROL,
                        targetVelocities=[self._signs[0] * sent[0], self._signs[1] * sent[1]],
                        forces=self._forces)

    def after_physics_step(self, gain_left: float = 1.0, gain_right: float = 1.0) -> None:
        """Integrate the wheel increments of the step just taken into the odometry pose.

        ``gain_left``, ``gain_right`` scale each wheel's measured increment (encoder/slip error).
        """
        a0, b0 = self._angles
        self._read_wheels()
        (rl, rr), (a1, b1) = self.model.wheel_radius, self._angles
        self._odom = integrate_odometry(self._odom, gain_left * rl * (a1 - a0),
                                        gain_right * rr * (b1 - b0), self.model.wheel_base)
