"""One episode, one control cycle at a time: the loop's parts as an object.

:class:`EpisodeStepper` holds everything an episode is made of: the generator derived from
what the episode plays, the simulation, the endings, the observers (the trace recorder
first) and, at the end, the trace and the result row. Two drivers share it, so there is one
loop, not two that can drift apart:

* :func:`~nav_bench.episode.loop.play` (``nav-bench episode``, the batch workers): a planner
  answers each :meth:`~EpisodeStepper.observe` with a command;
* :class:`nav_bench.gym.SonarNavEnv`: a Gymnasium ``step(action)`` is one
  :meth:`~EpisodeStepper.advance` and the next :meth:`~EpisodeStepper.observe`.

A cycle: :meth:`observe` checks the endings on the true pose, then senses and returns the
:class:`Observation` (``None`` once the episode has ended); :meth:`advance` hands the cycle to
the observers, applies the command and steps the physics.
"""

from __future__ import annotations

import traceback
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from nav_bench.episode.ending import AREA_WINDOW, Stuck, classify_stuck, first_ending
from nav_bench.episode.observers import Cycle, Observer
from nav_bench.episode.protocol import protocol_of
from nav_bench.episode.row import ResultRow
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.episode.trace import Trace, TraceRecorder
from nav_bench.ids import episode_rng, robot_id
from nav_bench.interface import Command, Observation, Outcome, RobotInfo, StuckReason
from nav_bench.planners.base import Planner
from nav_bench.planners.registry import full_params, set_id
from nav_bench.sim.session import SimSession
from nav_bench.sim.simulation import Simulation
from nav_bench.specs import PlannerSetSpec, RobotSpec, WorldSpec, load_robot


@dataclass
class EpisodeResult:
    """The result row, the trace, and where the wall time went (s)."""

    row: ResultRow
    trace: Trace
    timing: dict[str, float]


class EpisodeStepper:
    """An episode of ``world`` in an open ``session``, advanced a control cycle at a time.

    Args:
        session: an open session (its world is reset here).
        world: the validated world. planner: the parameter set the row names; with the robot
            and the seed it derives the episode's generator (:func:`episode_rng`), as in a batch.
        seed: the episode seed. robot: default ``robots/diffbot.yaml``. settings: rates, limits.
        world_file: the path as given, recorded in the row.
        observers: watch every cycle after the trace recorder (GUI, live view).

    Attributes:
        outcome: ``None`` while the episode runs, then how it ended. error: the traceback of
        an ``error`` outcome. events: the planner events so far. plan_s: wall time spent
        planning (the driver adds to it). planner_rng: the planner's generator.
    """

    def __init__(self, session: SimSession, world: WorldSpec, planner: PlannerSetSpec, *,
                 seed: int, robot: RobotSpec | None = None,
                 settings: EpisodeSettings | None = None, world_file: str | None = None,
                 observers: Sequence[Observer] = ()) -> None:
        self.world, self.planner, self.seed, self.world_file = world, planner, int(seed), world_file
        self.settings = settings = settings or EpisodeSettings()
        self.robot = robot = robot or load_robot()
        self.params = full_params(planner)
        self.params_id, self.robot_id = set_id(planner.planner, self.params), robot_id(robot)
        self.rng = episode_rng(world.name or "world", self.params_id, self.robot_id, seed)
        self.planner_rng = self.rng.spawn(1)[0]
        self.recorder = TraceRecorder(world)
        self.observers: list[Observer] = [self.recorder] if settings.record_trace else []
        self.observers += list(observers)
        self.outcome: Outcome | None = None
        self.error: str | None = None
        self.events: list[dict[str, Any]] = []
        self.plan_s = 0.0
        self.sim: Simulation | None = None
        self._cycle: tuple[np.ndarray, Observation] | None = None
        # what every observation repeats: the goal (2,) m and the grids' area, built once
        self._goal = np.array(world.goal, dtype=float)
        self._goal.flags.writeable = False  # shared by every observation: no planner may change it
        self._bounds = (0.0, 0.0, float(world.size[0]), float(world.size[1]))
        try:
            self.sim = Simulation(session, world, robot, self.rng, physics_hz=settings.physics_hz)
            sim = self.sim
            self._checks = protocol_of(settings).endings(settings, world, sim.true_pose()[:2].copy(),
                                                         collisions=lambda: sim.collisions)
        except Exception as exc:  # the episode ends as "error"; the batch goes on
            self.fail(exc)

    # -- the cycle -------------------------------------------------------------------------------
    @property
    def done(self) -> bool:
        return self.outcome is not None

    @property
    def robot_info(self) -> RobotInfo:
        assert self.sim is not None
        return self.sim.robot_info

    @property
    def t(self) -> float:
        return self.sim.t if self.sim is not None else 0.0

    @property
    def collisions(self) -> int:
        return self.sim.collisions if self.sim is not None else 0

    def true_pose(self) -> np.ndarray:
        return self.sim.true_pose() if self.sim is not None else np.array(self.world.start_pose)

    def observe(self) -> Observation | None:
        """End the episode if an ending holds (``None``), else sense: this cycle's observation."""
        if self.outcome is not None:
            return None
        try:
            sim = self.sim
            assert sim is not None
            true_pose = sim.true_pose()
            outcome = first_ending(self._checks, sim.t, true_pose[:2])
            if outcome is not None:
                self.outcome = outcome
                return None
            obs = self._observation(sim)
        except Exception as exc:
            self.fail(exc)
            return None
        self._cycle = (true_pose, obs)
        return obs

    def advance(self, cmd: Command, events: Sequence[dict[str, Any]] = (),
                agent: Planner | None = None, plan_s: float = float("nan")) -> None:
        """Show the cycle to the observers, apply ``cmd`` and step one control period.

        ``plan_s``: wall-clock seconds the planner's ``act()`` took this cycle (NaN: no
        planner, e.g. a Gymnasium action), kept in the trace for the row's compute-time metrics.
        """
        assert self._cycle is not None and self.sim is not None, "advance() follows observe()"
        if self.outcome is not None:
            return
        true_pose, obs = self._cycle
        self._cycle = None
        self.events += events
        sim = self.sim
        try:
            cycle = Cycle(sim.t, true_pose, obs, cmd, list(events), agent, sim, plan_s=plan_s)
            for observer in self.observers:
                observer.on_cycle(cycle)
            sim.apply(cmd)  # act
            sim.step(self.settings.steps_per_cycle)  # step
        except Exception as exc:
            self.fail(exc)

    def final_observation(self) -> Observation | None:
        """What the robot senses now, outside the trace (an environment's last observation)."""
        if self.sim is None:
            return None
        return self._observation(self.sim)

    def fail(self, exc: BaseException) -> None:
        """End the episode as ``error`` with ``exc``'s traceback."""
        self.outcome = Outcome.ERROR
        self.error = "".join(traceback.format_exception(exc))

    def _observation(self, sim: Simulation) -> Observation:
        return Observation(t=sim.t, pose=sim.odometry_pose(), goal=self._goal, ranges=sim.sense(),
                           robot=sim.robot_info, bounds=self._bounds, dt=self.settings.cycle_s)

    # -- the end ---------------------------------------------------------------------------------
    def finish(self, *, wall_s: float, planner_state: dict[str, Any] | None = None,
               replans: int | None = None, cpu_s: float | None = None,
               stuck_reason: StuckReason | None = None) -> EpisodeResult:
        """Close the observers; the trace and the row (built once, from the trace).

        ``cpu_s``: the process's CPU seconds for the episode (the driver measures it).
        ``stuck_reason``: the planner's own reason, if the episode ended ``stuck``; without one
        the episode classifies the true motion and the commands (:func:`classify_stuck`).
        """
        if self.outcome is None:
            self.outcome = Outcome.ERROR
            self.error = "the episode was finished before it ended"
        for observer in self.observers:
            observer.close()
        state = dict(planner_state or {})
        identity = dict(world_file=self.world_file, planner=self.planner.planner,
                        params=self.params, params_id=self.params_id, seed=self.seed,
                        settings=asdict(self.settings))
        sim = self.sim
        if sim is None:  # the simulation could not be built: nothing was measured
            row = ResultRow.failure(world=self.world.name, error=self.error or "", wall_s=wall_s,
                                    **identity)
            row.cpu_s = cpu_s
            row.robot, row.robot_id = self.robot.name, self.robot_id
            start = np.array(self.world.start_pose)
            trace = self.recorder.finish(0.0, start, start, self.events, state)
            trace.row = row.to_json()
            return EpisodeResult(row=row, trace=trace, timing={"total": wall_s})
        trace = self.recorder.finish(sim.t, sim.true_pose(), sim.odometry_pose(), self.events,
                                     state)
        if replans is None:
            replans = sum(e["kind"] == "replan" for e in self.events)
        row = ResultRow.from_trace(trace, outcome=self.outcome, error=self.error,
                                   robot=self.robot.name, robot_id=self.robot_id, time_s=sim.t,
                                   robot_radius=sim.robot_info.radius, replans=replans,
                                   collisions=sim.collisions, wall_s=wall_s, **identity)
        row.cpu_s = cpu_s
        if self.outcome is Outcome.STUCK:
            row.stuck_reason = stuck_reason or classify_stuck(
                trace.t, trace.true_pose, trace.cmd, self._stuck_window_s())
        trace.row = row.to_json()
        timing_sim = dict(sim.timing)
        timing = {**timing_sim, "planning": self.plan_s,
                  "other": wall_s - sum(timing_sim.values()) - self.plan_s, "total": wall_s}
        return EpisodeResult(row=row, trace=trace, timing=timing)

    def _stuck_window_s(self) -> float:
        """The seconds of motion the stuck rule that fired judged (s)."""
        stuck = next(c for c in self._checks if isinstance(c, Stuck))
        return stuck.seconds * (AREA_WINDOW if stuck.fired == "area" else 1.0)

    @staticmethod
    def robot_info_of(session: SimSession, robot: RobotSpec,
                      settings: EpisodeSettings | None = None) -> RobotInfo:
        """The geometry and limits ``robot`` shows a planner (read from its URDF in a small
        empty world; the session's world is reset)."""
        probe = WorldSpec.model_validate({"name": "probe", "size": [3.0, 3.0],
                                          "start": [1.0, 1.0, 0.0], "goal": [2.0, 2.0]})
        physics_hz = (settings or EpisodeSettings()).physics_hz
        return Simulation(session, probe, robot, np.random.default_rng(0),
                          physics_hz=physics_hz).robot_info
