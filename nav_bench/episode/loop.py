"""The one control loop: sense -> plan -> act -> step, until an ending holds.

:func:`run_episode` is the only place that drives a simulation for a planner; the CLI, the
batch workers and the tests all call it. It sets the episode up (planner, session, observers),
:func:`play` runs the loop on an :class:`~nav_bench.episode.stepper.EpisodeStepper` (the
episode's parts, which the Gymnasium environment drives too), and the row is built once from
the recorded trace.
"""

from __future__ import annotations

import contextlib
import math
import time
from typing import Any

from nav_bench.episode.observers import GuiView, LiveFeed, Observer
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.episode.stepper import EpisodeResult, EpisodeStepper
from nav_bench.errors import InputError, PlannerError
from nav_bench.interface import Command, Observation, Outcome, RobotInfo
from nav_bench.planners.base import Planner
from nav_bench.planners.registry import full_params, make_planner
from nav_bench.sim.session import SimSession
from nav_bench.specs import PlannerSetSpec, RobotSpec, WorldSpec

__all__ = ["EpisodeResult", "EpisodeStepper", "checked_act", "play", "run_episode"]


def play(stepper: EpisodeStepper, agent: Planner, name: str) -> None:
    """Run the control loop with planner ``agent`` until an ending holds or something fails."""
    first = True
    while (obs := stepper.observe()) is not None:  # endings, then sense
        t0 = time.perf_counter()
        try:
            if first:
                agent.reset(obs, stepper.planner_rng)
                first = False
            t1 = time.perf_counter()
            cmd = checked_act(agent, obs, obs.robot, name)  # plan
            t2 = time.perf_counter()
        except Exception as exc:  # the episode ends as "error"; the batch goes on
            stepper.fail(exc)
            break
        stepper.plan_s += t2 - t0
        events = [{"kind": e.kind, "t": e.t, "data": e.data} for e in agent.pop_events()]
        stepper.advance(cmd, events, agent, plan_s=t2 - t1)  # observers, act, step


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
    agent = planner_instance or make_planner(planner)
    full_params(planner)  # bad parameters: InputError before anything is simulated
    observers: list[Observer] = [GuiView(settings.cycle_s)] if gui else []
    observers += [LiveFeed(live)] if live is not None else []
    wall0, cpu0 = time.perf_counter(), time.process_time()
    host = (SimSession(gui=gui, physics_hz=settings.physics_hz) if session is None
            else contextlib.nullcontext(session))  # a session passed in stays open
    with host as session:
        session.open()  # idempotent; a worker's session is opened by its first episode
        stepper = EpisodeStepper(session, world, planner, seed=seed, robot=robot,
                                 settings=settings, world_file=world_file, observers=observers)
        play(stepper, agent, planner.planner)
        try:
            state = agent.debug_state()
        except Exception:  # a broken debug_state must not lose the row
            state = {}
        try:
            reason = agent.stuck_reason() if stepper.outcome is Outcome.STUCK else None
        except Exception:  # nor a broken stuck_reason
            reason = None
        return stepper.finish(wall_s=time.perf_counter() - wall0, planner_state=state,
                              replans=agent.replans, stuck_reason=reason,
                              cpu_s=time.process_time() - cpu0)
