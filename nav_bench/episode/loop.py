"""The one control loop: sense -> plan -> act -> step, until an ending holds.

:func:`run_episode` is the only place that drives a simulation for a planner; the CLI, the
batch workers and the tests all call it. It sets the episode up (generator, planner, session,
observers), :func:`play` runs the loop, and the row is built once from the recorded trace.
"""

from __future__ import annotations

import contextlib
import math
import time
import traceback
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from nav_bench.episode.ending import endings, first_ending
from nav_bench.episode.observers import Cycle, GuiView, LiveFeed, Observer
from nav_bench.episode.row import ResultRow
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.episode.trace import Trace, TraceRecorder
from nav_bench.errors import InputError, PlannerError
from nav_bench.ids import episode_rng, params_id, robot_id
from nav_bench.interface import Command, Observation, Outcome, RobotInfo
from nav_bench.planners.base import Planner
from nav_bench.planners.registry import full_params, make_planner
from nav_bench.sim.session import SimSession
from nav_bench.sim.simulation import Simulation
from nav_bench.specs import PlannerSetSpec, RobotSpec, WorldSpec, load_robot


@dataclass
class EpisodeResult:
    """The result row, the trace, and where the wall time went (s)."""

    row: ResultRow
    trace: Trace
    timing: dict[str, float]


@dataclass
class Played:
    """How :func:`play` ended: the outcome (and traceback), the planner's events, the time it
    spent planning (s), and the simulation (None if it could not be built)."""

    outcome: Outcome = Outcome.ERROR
    error: str | None = None
    events: list[dict[str, Any]] = field(default_factory=list)
    plan_s: float = 0.0
    sim: Simulation | None = None


def play(session: SimSession, world: WorldSpec, robot: RobotSpec, rng: np.random.Generator,
         agent: Planner, planner_rng: np.random.Generator, settings: EpisodeSettings,
         observers: list[Observer], name: str) -> Played:
    """Run the control loop in ``session`` until an ending holds or something fails."""
    played = Played()
    try:
        sim = played.sim = Simulation(session, world, robot, rng, physics_hz=settings.physics_hz)
        goal = np.asarray(world.goal, dtype=float)
        bounds = (0.0, 0.0, float(world.size[0]), float(world.size[1]))
        checks = endings(settings, world, sim.true_pose()[:2].copy())
        first = True
        while True:
            true_pose = sim.true_pose()
            outcome = first_ending(checks, sim.t, true_pose[:2])
            if outcome is not None:
                played.outcome = outcome
                break
            ranges = sim.sense()  # sense
            obs = Observation(t=sim.t, pose=sim.odometry_pose(), goal=goal, ranges=ranges,
                              robot=sim.robot_info, bounds=bounds, dt=settings.cycle_s)
            t0 = time.perf_counter()
            if first:
                agent.reset(obs, planner_rng)
                first = False
            cmd = checked_act(agent, obs, sim.robot_info, name)  # plan
            played.plan_s += time.perf_counter() - t0
            events = [{"kind": e.kind, "t": e.t, "data": e.data} for e in agent.pop_events()]
            played.events += events
            cycle = Cycle(sim.t, true_pose, obs, cmd, events, agent, sim)
            for observer in observers:
                observer.on_cycle(cycle)
            sim.apply(cmd)  # act
            sim.step(settings.steps_per_cycle)  # step
    except Exception as exc:  # the episode ends as "error"; the batch goes on
        played.outcome = Outcome.ERROR
        played.error = "".join(traceback.format_exception(exc))
    return played


def checked_act(agent: Planner, obs: Observation, robot: RobotInfo, name: str) -> Command:
    """The command of planner ``name``, checked and clipped to the robot's limits."""
    try:
        cmd = agent.act(obs)
    except PlannerError:
        raise
    except Exception as exc:
        raise PlannerError(f"planner {name!r} raised {type(exc).__name__}: {exc}") from exc
    if not isinstance(cmd, Command):
        raise PlannerError(f"planner returned {type(cmd).__name__}, expected Command")
    if not (math.isfinite(cmd.v) and math.isfinite(cmd.omega)):
        raise PlannerError(f"planner returned a non-finite command {cmd}")
    # the drive saturates anyway; clipping here keeps the recorded command truthful
    v, w = robot.v_max, robot.omega_max
    return Command(min(max(float(cmd.v), -v), v), min(max(float(cmd.omega), -w), w))


def run_episode(world: WorldSpec, planner: PlannerSetSpec, *, seed: int,
                robot: RobotSpec | None = None, settings: EpisodeSettings | None = None,
                world_file: str | None = None, gui: bool = False, live: Any = None,
                planner_instance: Planner | None = None,
                session: SimSession | None = None) -> EpisodeResult:
    """Play one episode and return its result row and trace.

    Args:
        world: a validated world. planner: the parameter set (name + overrides).
        seed: episode seed; the episode's generator derives from it (see :func:`episode_rng`).
        robot: robot config (default ``robots/diffbot.yaml``). settings: rates and limits.
        world_file: the path as given, recorded in the row. gui: open the PyBullet GUI.
        live: optional live view with ``update(t, pose, state, events)`` and ``close()``.
        planner_instance: play this planner object instead of building one from ``planner``.
        session: play in this headless session (opened if need be, left open afterwards)
            instead of a client of the episode's own. A batch worker keeps one across its
            episodes: connecting costs 1-15 ms, more than the rest of a short episode's set-up.
            Every episode resets the world first, so the row is the same either way.
    Raises:
        InputError: bad planner name or parameters (nothing simulated). Failures during the
        episode (a planner that raises, a physics error) do not raise: they give outcome ``error``.
    """
    if session is not None and gui:
        raise InputError("an episode with the GUI opens its own session; do not pass one")
    settings = settings or EpisodeSettings()
    robot = robot or load_robot()
    params = full_params(planner)
    pid, rid = params_id(planner.planner, params), robot_id(robot)
    rng = episode_rng(world.name or "world", pid, rid, seed)
    planner_rng = rng.spawn(1)[0]
    agent = planner_instance or make_planner(planner)
    recorder = TraceRecorder(world)
    observers: list[Observer] = [recorder] if settings.record_trace else []
    observers += [GuiView(settings.cycle_s)] if gui else []
    observers += [LiveFeed(live)] if live is not None else []
    wall0 = time.perf_counter()
    host = (SimSession(gui=gui, physics_hz=settings.physics_hz) if session is None
            else contextlib.nullcontext(session))  # a session passed in stays open
    with host as session:
        session.open()  # idempotent; a worker's session is opened by its first episode
        played = play(session, world, robot, rng, agent, planner_rng, settings, observers,
                      planner.planner)
        sim = played.sim
        if sim is not None:
            final = (sim.t, sim.true_pose(), sim.odometry_pose(), sim.collisions,
                     dict(sim.timing), sim.robot_info.radius)
        try:
            state = agent.debug_state()
        except Exception:  # a broken debug_state must not lose the row
            state = {}
    wall = time.perf_counter() - wall0
    for observer in observers:
        observer.close()
    identity = dict(world_file=world_file, planner=planner.planner, params=params, params_id=pid,
                    seed=seed, settings=asdict(settings))
    if sim is None:  # the simulation could not be built: nothing was measured
        row = ResultRow.failure(world=world.name, error=played.error or "", wall_s=wall, **identity)
        row.robot, row.robot_id = robot.name, rid
        trace = recorder.finish(0.0, np.array(world.start_pose), np.array(world.start_pose),
                                played.events, state)
        trace.row = row.to_json()
        return EpisodeResult(row=row, trace=trace, timing={"total": wall})
    sim_t, true_end, odom_end, collisions, timing_sim, radius = final
    trace = recorder.finish(sim_t, true_end, odom_end, played.events, state)
    replans = getattr(agent, "replans", sum(e["kind"] == "replan" for e in played.events))
    row = ResultRow.from_trace(trace, outcome=played.outcome, error=played.error, robot=robot.name,
                               robot_id=rid, time_s=sim_t, robot_radius=radius, replans=replans,
                               collisions=collisions, wall_s=wall, **identity)
    trace.row = row.to_json()
    timing = {**timing_sim, "planning": played.plan_s,
              "other": wall - sum(timing_sim.values()) - played.plan_s, "total": wall}
    return EpisodeResult(row=row, trace=trace, timing=timing)
