"""One PyBullet connection, owned by a context manager and passed explicitly to everything else.

Nothing in nav-bench uses PyBullet's implicit default client: every call goes through the
:class:`~pybullet_utils.bullet_client.BulletClient` of a :class:`SimSession`, so several
sessions can live in one process (one per worker thread or episode) without sharing state.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from types import TracebackType

import pybullet
from pybullet_utils.bullet_client import BulletClient

from nav_bench.errors import SimulationError

GRAVITY = 9.81  # m/s^2
# Physics steps per simulated second by default. EpisodeSettings.physics_hz holds the same
# value (nav_bench.episode.settings cannot import this module: the batch parent process never
# imports PyBullet); tests/sim/test_sim_session.py checks that they agree. Why 60 Hz and not
# Bullet's customary 240: results/fidelity/README.md (benchmarks/bench_physics.py and the paired
# suite study of benchmarks/fidelity_suite.py).
PHYSICS_HZ = 60.0
# Contact penetration is removed at this rate (1/s): Bullet's contact ERP, the fraction of a
# penetration corrected per step, is set to CONTACT_RECOVERY_HZ / physics_hz (at most 1), so a
# contact behaves alike at every physics rate. Movers are teleported every step (static bodies
# without velocity), so the solver sees a mover pushing the robot only as penetration, removed
# at ERP x rate per second. Bullet's own ERP is fixed per step: fine at 240 Hz, but at 60 Hz a
# 0.4 m/s box mover ran through a standing robot (0.7 m/s at 120 Hz). 20/s gives at every rate
# the penetration Bullet's own ERP gives at 240 Hz (20 mm at 0.4 m/s, 50 mm at 1 m/s) and no
# mover runs through the robot up to 1 m/s; tracking, odometry, stopping and wall contacts do
# not change (benchmarks/bench_physics.py, results/fidelity/physics.md). 30/s (ERP 0.5 at
# 60 Hz) made a robot held against a mover chatter: 13 contact episodes instead of 1.
CONTACT_RECOVERY_HZ = 20.0
# Bullet's constraint solver iterations per physics step (Bullet's own default). Fewer make a
# step cheaper but the robot creeps at rest and misses its acceleration limit at 30 or fewer
# (tests/sim/test_sim_robot.py; benchmarks/bench_physics.py measures 20 and 10).
SOLVER_ITERATIONS = 50
# Bullet's solver stops iterating once every constraint's velocity error is below this (m/s or
# rad/s); None keeps Bullet's own threshold (1e-7). For fidelity studies: benchmarks/bench_physics.py
# measures what a looser one costs in tracking, odometry, stopping and contacts.
SOLVER_RESIDUAL: float | None = None

# Collision filter groups (bit masks). Two bodies collide when each one's group is in the
# other's mask. PyBullet puts mass-0 bodies (ground, walls, movers) in STATIC, whose mask
# leaves out STATIC, so static bodies are never pair-tested against each other. The robot gets
# its own bit so sonar rays can skip it with one mask. The ground keeps PyBullet's defaults:
# giving it its own group made stepping 4x slower with 1,000 boxes (measured), and horizontal
# rays above the floor cannot hit it anyway.
GROUP_ROBOT = 32
# PyBullet's ray queries carry DEFAULT's group and apply their collisionFilterMask only after
# the exact ray-shape test. Leaving DEFAULT out of the robot's mask makes the broadphase skip
# the robot for every ray instead: its cylinders straddle all 42 sonar rays, and their
# convex-cast tests cost ~2 us a ray (sense() 2-3x faster, readings identical). DEFAULT is the
# group of dynamic (mass > 0) bodies, of which a world has none but the robot: give any future
# dynamic obstacle a group of its own that ROBOT_MASK keeps.
GROUP_DEFAULT = 1
ROBOT_MASK = ~(GROUP_ROBOT | GROUP_DEFAULT)  # what the robot collides with: all static bodies
RAY_MASK = ~GROUP_ROBOT  # what sonar rays may hit: everything but the robot


@contextlib.contextmanager
def quiet_c_stdout() -> Iterator[None]:
    """Silence C-level writes to stdout (PyBullet prints ``argv[0]=`` and loader chatter there).

    Keeps stdout clean for machine-readable output (``nav-bench episode --json``). Redirects
    file descriptor 1, which is process-wide: a thread printing at the same moment is muted too.
    """
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # no real stdout (pytest capture, notebooks)
        yield
        return
    sys.stdout.flush()
    saved = os.dup(fd)
    try:
        with open(os.devnull, "wb") as devnull:
            os.dup2(devnull.fileno(), fd)
            try:
                yield
            finally:
                os.dup2(saved, fd)
    finally:
        os.close(saved)


class SimSession:
    """A PyBullet world: one client, gravity, a fixed time step and a ground plane.

    Use it as a context manager; the connection is closed on exit, also after an error::

        with SimSession() as session:
            sim = Simulation(session, world, robot, rng)
            ...

    Args:
        gui: open PyBullet's OpenGL window instead of the headless DIRECT engine.
        physics_hz: physics steps per simulated second (time step ``1 / physics_hz``).
        solver_iterations: Bullet's constraint solver iterations per step (for fidelity
            studies; keep the default).
        contact_recovery_hz: rate (1/s) at which contact penetration is removed; Bullet's
            contact ERP is this over ``physics_hz`` (at most 1). ``None`` keeps Bullet's own
            ERP (for fidelity studies).
        solver_residual: velocity error (m/s, rad/s) under which Bullet's solver stops
            iterating early; ``None`` keeps Bullet's own (for fidelity studies).

    Attributes:
        client: the BulletClient every other part of ``nav_bench.sim`` receives.
        ground_id: body id of the ground plane (z = 0).
        dt: physics time step, s.
    """

    def __init__(self, gui: bool = False, physics_hz: float = PHYSICS_HZ,
                 solver_iterations: int = SOLVER_ITERATIONS,
                 contact_recovery_hz: float | None = CONTACT_RECOVERY_HZ,
                 solver_residual: float | None = SOLVER_RESIDUAL) -> None:
        if physics_hz <= 0:
            raise SimulationError(f"physics_hz must be positive, got {physics_hz}")
        if solver_iterations < 1:
            raise SimulationError(f"solver_iterations must be at least 1, got {solver_iterations}")
        self.gui = gui
        self.physics_hz = float(physics_hz)
        self.solver_iterations = int(solver_iterations)
        if contact_recovery_hz is not None and not contact_recovery_hz > 0.0:
            raise SimulationError(f"contact_recovery_hz must be positive, got {contact_recovery_hz}")
        self.contact_recovery_hz = contact_recovery_hz
        if solver_residual is not None and not solver_residual > 0.0:
            raise SimulationError(f"solver_residual must be positive, got {solver_residual}")
        self.solver_residual = solver_residual
        self._client: BulletClient | None = None
        self._pristine = False  # True between open() and the first Simulation built on it
        self.ground_id = -1

    # -- lifetime ------------------------------------------------------------------------
    def __enter__(self) -> SimSession:
        self.open()
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def open(self) -> None:
        """Connect (idempotent) and build the empty world."""
        if self._client is not None:
            return
        if self.gui and sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
            raise SimulationError("the GUI needs a display, but $DISPLAY is not set; "
                                  "run without --gui (headless) or on a desktop session")
        mode = pybullet.GUI if self.gui else pybullet.DIRECT
        what = "GUI" if self.gui else "DIRECT"
        try:
            with quiet_c_stdout():
                client = BulletClient(connection_mode=mode)
        except pybullet.error as exc:
            raise SimulationError(f"could not connect to PyBullet ({what}): {exc}") from exc
        if client._client < 0:  # BulletClient keeps the id private; -1 means no connection
            hint = " (only one GUI window per process)" if self.gui else ""
            raise SimulationError(f"could not connect to PyBullet ({what}){hint}")
        self._client = client
        self.reset()
        self._pristine = True  # nothing added since the reset: a Simulation need not reset again

    def close(self) -> None:
        """Disconnect (idempotent)."""
        client, self._client = self._client, None
        if client is not None:
            with contextlib.suppress(pybullet.error):
                client.disconnect()

    @property
    def client(self) -> BulletClient:
        if self._client is None:
            raise SimulationError("the simulation session is not open (use `with SimSession() as s:`)")
        return self._client

    @property
    def dt(self) -> float:
        return 1.0 / self.physics_hz

    # -- world -----------------------------------------------------------------------------
    def ensure_empty(self, physics_hz: float | None = None) -> None:
        """:meth:`reset`, unless the world is still as the last reset left it (same rate)."""
        if self._pristine and physics_hz in (None, self.physics_hz):
            self._pristine = False
            return
        self.reset(physics_hz)

    def reset(self, physics_hz: float | None = None) -> None:
        """Empty the world: gravity, time step, deterministic settings and the ground plane.

        Called by every :class:`~nav_bench.sim.simulation.Simulation`, so an episode always
        starts from the same state, whatever the session simulated before.
        """
        if physics_hz is not None:
            if physics_hz <= 0:
                raise SimulationError(f"physics_hz must be positive, got {physics_hz}")
            self.physics_hz = float(physics_hz)
        c = self.client
        c.resetSimulation()
        if self.gui:
            c.configureDebugVisualizer(pybullet.COV_ENABLE_GUI, 0)
        c.setGravity(0.0, 0.0, -GRAVITY)
        c.setTimeStep(self.dt)
        # Same inputs -> same results bit for bit: pair order must not depend on memory layout.
        # Bullet's default 50 solver iterations stay (SOLVER_ITERATIONS): at 30 or fewer the
        # robot creeps at rest and acceleration limits are missed (tests/sim/test_sim_robot.py),
        # though steps get cheaper.
        # Friction pyramid instead of the cone: a physics step costs ~1.7x less when driving
        # (the wheels' contact manifolds hold 4 points each at 0.5 m/s), commanded motion is
        # still met within 0.1 % (tests/sim/test_sim_robot.py); the price is a yaw creep of
        # ~1e-4 rad per 2 s for a robot standing still.
        c.setPhysicsEngineParameter(deterministicOverlappingPairs=1, numSubSteps=0,
                                    enableConeFriction=0,
                                    numSolverIterations=self.solver_iterations)
        if self.contact_recovery_hz is not None:
            c.setPhysicsEngineParameter(contactERP=min(1.0, self.contact_recovery_hz * self.dt))
        if self.solver_residual is not None:
            c.setPhysicsEngineParameter(solverResidualThreshold=self.solver_residual)
        plane = c.createCollisionShape(pybullet.GEOM_PLANE)
        self.ground_id = c.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=plane)
        c.changeDynamics(self.ground_id, -1, lateralFriction=1.0, restitution=0.0)

    def show_floor(self, sx: float, sy: float) -> None:
        """GUI only: a visible floor tile covering [0, sx] x [0, sy] (the plane has no visual)."""
        if not self.gui:
            return
        c = self.client
        visual = c.createVisualShape(pybullet.GEOM_BOX, halfExtents=[sx / 2, sy / 2, 0.0005],
                                     rgbaColor=[0.92, 0.92, 0.90, 1.0])
        c.createMultiBody(baseMass=0.0, baseVisualShapeIndex=visual,
                          basePosition=[sx / 2, sy / 2, -0.0005])
