"""The simulator facade the episode loop uses: a world, a robot, its sonars and odometry.

::

    with SimSession() as session:
        sim = Simulation(session, world, robot_spec, rng)
        for _ in range(cycles):
            ranges = sim.sense()                 # (K,) m
            cmd = planner.act(... sim.odometry_pose() ...)
            sim.apply(cmd)
            sim.step(round(physics_hz / control_hz))

Noise (sonar, odometry) is drawn from ``rng`` only, in a fixed order, so the same inputs
give the same trace bit for bit.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pybullet

from nav_bench.errors import SimulationError
from nav_bench.interface import Command, RobotInfo, SonarInfo
from nav_bench.sim.contacts import CONTACT_DISTANCE, ContactEpisodes, ContactWindow
from nav_bench.sim.movers import MoverBodies
from nav_bench.sim.robot import DiffDriveRobot
from nav_bench.sim.scene import DEFAULT_LAYOUT, SceneLayout, StaticScene, build_static_scene
from nav_bench.sim.session import SimSession
from nav_bench.sim.sonar import SonarArray, noisy_readings
from nav_bench.specs import RobotSpec, WorldSpec
from nav_bench.world.geometry import static_geometry


class Simulation:
    """A world with the robot standing at its start pose, ready to sense and drive.

    Creating it resets the session's world (scene, movers, robot), so each episode starts from
    the same state.

    Args:
        session: an open :class:`SimSession`.
        world: the validated world.
        robot_spec: the robot config (URDF and sensing/actuation settings).
        rng: the episode's generator; sonar and odometry noise are drawn from it.
        physics_hz: physics rate; ``None`` keeps the session's.
        layout: how static obstacles are grouped into bodies (for benchmarks; keep the default).
        contact_checks: ``"when_near"`` reads Bullet's contacts only in physics steps where the
            robot could touch something (:class:`~nav_bench.sim.contacts.ContactWindow`);
            ``"every_step"`` reads them always. The counts are the same; the first is cheaper.

    Attributes:
        robot_info: geometry and limits for the planner (from the URDF and the config).
        timing: cumulative wall-clock seconds in ``"physics"`` (:meth:`step`) and
            ``"sensing"`` (:meth:`sense`).
        contact_reads: physics steps in which Bullet's contact points were read.
    """

    def __init__(self, session: SimSession, world: WorldSpec, robot_spec: RobotSpec,
                 rng: np.random.Generator, physics_hz: float | None = None, *,
                 layout: SceneLayout = DEFAULT_LAYOUT, contact_checks: str = "when_near") -> None:
        if contact_checks not in ("when_near", "every_step"):
            raise SimulationError(f"contact_checks must be 'when_near' or 'every_step', "
                                  f"got {contact_checks!r}")
        session.ensure_empty(physics_hz)
        self.session = session
        self.world = world
        self.robot_spec = robot_spec
        self.rng = rng
        self.dt = session.dt
        client = session.client
        gui = session.gui
        if gui:
            client.configureDebugVisualizer(pybullet.COV_ENABLE_RENDERING, 0)
        geometry = static_geometry(world)
        self.scene: StaticScene = build_static_scene(client, geometry, gui=gui, layout=layout)
        self.movers = MoverBodies(client, list(world.movers), world.wall_height, gui=gui)
        self.robot = DiffDriveRobot(client, robot_spec, world.start_pose, self.dt)
        model = self.robot.model
        self.sonar = SonarArray(client, model.sonar_mounts, model.sonar_yaws, robot_spec.sonar)
        if gui:
            sx, sy = world.size
            session.show_floor(sx, sy)
            client.resetDebugVisualizerCamera(cameraDistance=0.9 * max(sx, sy), cameraYaw=0.0,
                                              cameraPitch=-89.0,
                                              cameraTargetPosition=[sx / 2, sy / 2, 0.0])
            client.configureDebugVisualizer(pybullet.COV_ENABLE_RENDERING, 1)

        spec = robot_spec
        r_min = min(model.wheel_radius)
        self.robot_info = RobotInfo(
            radius=model.radius, wheel_base=model.wheel_base,
            v_max=r_min * spec.drive.max_wheel_speed,
            omega_max=2.0 * r_min * spec.drive.max_wheel_speed / model.wheel_base,
            sonar=SonarInfo(angles=model.sonar_yaws.copy(),
                            offsets=model.sonar_mounts[:, :2].copy(),
                            cone=math.radians(spec.sonar.cone_deg),
                            min_range=spec.sonar.min_range, max_range=spec.sonar.max_range))
        self.timing = {"physics": 0.0, "sensing": 0.0}
        self._steps = 0
        self._contacts = ContactEpisodes()
        self._contact_window = (ContactWindow(geometry, list(world.movers), model.radius,
                                              max(model.wheel_radius) * spec.drive.max_wheel_speed,
                                              model.wheel_base)
                                if contact_checks == "when_near" else None)
        self._contact_free_until = -math.inf  # sim time (s) until which nothing can be touched
        self.contact_reads = 0  # physics steps whose contacts were read
        self._ground = session.ground_id
        self._robot_id = self.robot.body_id
        self._step_physics = client.stepSimulation
        self._contact_points = client.getContactPoints
        self._matrix_of = client.getMatrixFromQuaternion
        self._debug_items: dict[str, list[int]] = {}
        # what was read at a physics step (self._steps), for the several readers of a cycle
        self._pose_step = self._movers_step = -1
        self._pose = np.zeros(3)
        self._movers_xy = np.zeros((0, 2))

    # -- time ----------------------------------------------------------------------------------
    @property
    def t(self) -> float:
        """Simulated time since the start, s (steps x dt: no drift from summing)."""
        return self._steps * self.dt

    def step(self, n: int = 1) -> None:
        """Advance ``n`` physics steps: movers, wheel motors, physics, odometry, contacts.

        The odometry noise gains (one per wheel, ``1 + N(0, wheel_noise)``) are drawn once per
        call and scale every wheel increment of the call: the episode calls ``step`` once per
        control cycle, so the error is per control period, whatever the physics rate.
        """
        if n < 0:
            raise SimulationError(f"cannot step a negative number of steps ({n})")
        if n == 0:
            return
        start = time.perf_counter()
        noise = self.rng.standard_normal(2) * self.robot_spec.odometry.wheel_noise
        gain_l, gain_r = 1.0 + float(noise[0]), 1.0 + float(noise[1])
        robot, movers, dt = self.robot, self.movers, self.dt
        has_movers = bool(movers.body_ids)
        free_until = self._contact_window_end((self._steps + n) * dt)
        try:
            for _ in range(n):
                robot.before_physics_step()
                if has_movers:
                    movers.place((self._steps + 1) * dt)  # where they are when the step ends
                self._step_physics()
                self._steps += 1
                robot.after_physics_step(gain_l, gain_r)
                if self._steps * dt > free_until:
                    self._contacts.update(self._touching())
                    self.contact_reads += 1
        except pybullet.error as exc:
            raise SimulationError(f"PyBullet failed while stepping: {exc}") from exc
        finally:
            self.timing["physics"] += time.perf_counter() - start

    def _contact_window_end(self, t_end: float) -> float:
        """Sim time (s) until which the robot surely touches nothing; renewed from its
        clearance now when the current window ends before ``t_end``."""
        window = self._contact_window
        if window is None:
            return -math.inf
        if self._contact_free_until < t_end and not self._contacts.touching:
            xy = self.true_pose()[:2]
            self._contact_free_until = self.t + window.free_for(xy, self.mover_positions())
        return self._contact_free_until

    def _touching(self) -> set[int]:
        # the base link only: its body cylinder encloses the wheels in plan view, so anything
        # but the floor meets it first, and the wheels' floor contacts (up to 8 points) are
        # not turned into Python tuples every physics step
        ground = self._ground
        return {p[2] for p in self._contact_points(bodyA=self._robot_id, linkIndexA=-1)
                if p[2] != ground and p[8] < CONTACT_DISTANCE}

    # -- robot -----------------------------------------------------------------------------------
    def apply(self, cmd: Command) -> None:
        """Drive with ``cmd`` (v m/s, omega rad/s) from the next physics step on."""
        if not (math.isfinite(cmd.v) and math.isfinite(cmd.omega)):
            raise SimulationError(f"command must be finite, got v={cmd.v}, omega={cmd.omega}")
        self.robot.command(cmd)

    def sense(self) -> np.ndarray:
        """(K,) sonar readings in m, in ``robot_info.sonar`` order (noise and dropout applied)."""
        start = time.perf_counter()
        pos, orn = self.robot.link_pose()
        rotation = np.asarray(self._matrix_of(orn)).reshape(3, 3)
        ranges, hit = self.sonar.cast(pos, rotation)
        out = noisy_readings(ranges, hit, self.robot_spec.sonar, self.rng)
        self.timing["sensing"] += time.perf_counter() - start
        return out

    def true_pose(self) -> np.ndarray:
        """(3,) true pose x, y, yaw (m, m, rad), a new array each call."""
        if self._pose_step != self._steps:  # read from Bullet once per physics step
            self._pose = self.robot.true_pose()
            self._pose_step = self._steps
        return self._pose.copy()

    def odometry_pose(self) -> np.ndarray:
        """(3,) wheel-odometry pose estimate x, y, yaw (m, m, rad); what the planner gets."""
        return self.robot.odometry_pose()

    @property
    def collisions(self) -> int:
        """Contact episodes with anything but the floor so far."""
        return self._contacts.count

    @property
    def contact_now(self) -> bool:
        """Whether the robot touches anything but the floor after the last physics step."""
        return bool(self._contacts.touching)

    def mover_positions(self) -> np.ndarray:
        """(M, 2) mover positions now, m (read-only: the trace and the contact window share
        one array per physics step)."""
        if self._movers_step != self._steps:
            self._movers_xy = self.movers.positions(self.t)
            self._movers_xy.flags.writeable = False
            self._movers_step = self._steps
        return self._movers_xy

    # -- GUI helpers (no-ops headless) ---------------------------------------------------------
    def draw_lines(self, segments: np.ndarray, color: tuple[float, float, float] = (1.0, 0.0, 0.0),
                   key: str = "lines", width: float = 1.5, z: float = 0.05) -> None:
        """Show line segments, replacing those drawn before under the same ``key``.

        Args:
            segments: (N, 2, 2) or (N, 2, 3) start and end points, m (2-D ones drawn at ``z``).
            color: RGB in 0..1.
        """
        if not self.session.gui:
            return
        seg = np.asarray(segments, dtype=float)
        if seg.size == 0:
            seg = seg.reshape(0, 2, 3)
        if seg.shape[-1] == 2:
            seg = np.concatenate([seg, np.full((*seg.shape[:-1], 1), z)], axis=-1)
        c = self.session.client
        old = self._debug_items.get(key, [])
        new = []
        for i, (a, b) in enumerate(seg.tolist()):
            kw = {"replaceItemUniqueId": old[i]} if i < len(old) else {}
            new.append(c.addUserDebugLine(a, b, list(color), lineWidth=width, **kw))
        for item in old[len(new):]:
            c.removeUserDebugItem(item)
        self._debug_items[key] = new

    def draw_rays(self) -> None:
        """Show the rays of the last :meth:`sense`: echoes red, misses green."""
        rays = self.sonar.last_rays()
        if rays is None or not self.session.gui:
            return
        seg = np.stack([rays.starts, rays.ends], axis=1)
        self.draw_lines(seg[rays.hit], (0.9, 0.1, 0.1), key="rays_hit", width=1.0)
        self.draw_lines(seg[~rays.hit], (0.1, 0.7, 0.1), key="rays_miss", width=1.0)
