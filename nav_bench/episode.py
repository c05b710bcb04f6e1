"""The one control loop: sense -> plan -> act -> step -> record, and its result row.

``run_episode`` is the only place that drives a simulation for a planner; the CLI,
the batch runner and the tests all call it.
"""

from __future__ import annotations

import contextlib
import json
import math
import time
import traceback
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from nav_bench import metrics
from nav_bench.errors import InputError, PlannerError
from nav_bench.ids import episode_rng, params_id, robot_id
from nav_bench.interface import Command, Observation, Outcome
from nav_bench.planners.base import Planner
from nav_bench.planners.registry import full_params, make_planner
from nav_bench.specs import PlannerSetSpec, RobotSpec, WorldSpec, load_robot
from nav_bench.world.geometry import polyline_length

if TYPE_CHECKING:
    from nav_bench.sim.session import SimSession

@dataclass(frozen=True)
class EpisodeSettings:
    """How an episode is played. Times in s, distances in m, rates in Hz."""

    control_hz: float = 10.0  # planner cycles per second (the paper's control cycle)
    physics_hz: float = 240.0  # physics steps per second
    time_s: float | None = None  # simulated time limit; None: 15 s per metre of (sx + sy), >= 60 s
    stuck_s: float | None = 30.0  # "stuck" if the robot stays within stuck_radius this long; None: off
    stuck_radius: float = 0.2  # m
    # m, true distance to the goal that counts as reached. Planners stop at their own tolerance
    # (0.2 m by default) judged on odometry; the extra 0.1 m absorbs odometry drift, so success
    # measures navigation and a default-noise robot that stopped "at" the goal is not "stuck".
    goal_tolerance: float = 0.3
    record_trace: bool = True  # keep per-cycle arrays (needed for plots and traces on disk)

    def __post_init__(self) -> None:
        if self.control_hz <= 0 or self.physics_hz <= 0:
            raise InputError("control_hz and physics_hz must be positive")
        if self.physics_hz < self.control_hz:
            raise InputError("physics_hz must be at least control_hz")
        if self.time_s is not None and self.time_s <= 0:
            raise InputError("time_s must be positive")
        if self.goal_tolerance <= 0:
            raise InputError("goal_tolerance must be positive")

    def time_limit(self, world: WorldSpec) -> float:
        """The time limit (s) for ``world``."""
        if self.time_s is not None:
            return float(self.time_s)
        return max(60.0, 15.0 * (world.size[0] + world.size[1]))


@dataclass
class Trace:
    """Per-cycle record of an episode. T cycles, K sonars, M movers.

    Attributes:
        t: (T,) simulated time, s. true_pose, odom_pose: (T, 3) x, y, yaw (m, m, rad).
        cmd: (T, 2) commanded v (m/s), omega (rad/s). ranges: (T, K) sonar readings, m.
        movers: (T, M, 2) mover positions, m. events: planner events as dicts {kind, t, data}.
        planner_state: the planner's final ``debug_state()``. world: the world played.
        row: the result row.
    """

    world: WorldSpec
    t: np.ndarray
    true_pose: np.ndarray
    odom_pose: np.ndarray
    cmd: np.ndarray
    ranges: np.ndarray
    movers: np.ndarray
    events: list[dict[str, Any]] = field(default_factory=list)
    planner_state: dict[str, Any] = field(default_factory=dict)
    row: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str | Path) -> Path:
        """Write a compressed ``.npz`` (float32 arrays; events, state and row as JSON)."""
        path = Path(path)
        arrays = {k: np.asarray(getattr(self, k), dtype=np.float32)
                  for k in ("t", "true_pose", "odom_pose", "cmd", "ranges", "movers")}
        arrays["t"] = np.asarray(self.t, dtype=np.float64)
        state_arrays = {f"state__{k}": v for k, v in self.planner_state.items()
                        if isinstance(v, np.ndarray)}
        state_plain = {k: v for k, v in self.planner_state.items() if not isinstance(v, np.ndarray)}
        meta = {"world": self.world.model_dump(mode="json", by_alias=True), "events": self.events,
                "planner_state": state_plain, "row": self.row}
        with path.open("wb") as fh:
            np.savez_compressed(fh, meta=np.array(json.dumps(meta, default=_jsonable)),
                                **arrays, **state_arrays)
        return path

    @classmethod
    def load(cls, path: str | Path) -> Trace:
        """The whole trace written by :meth:`save`."""
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            state = dict(meta["planner_state"])
            state.update({k.removeprefix("state__"): data[k] for k in data.files
                          if k.startswith("state__")})
            return cls(world=WorldSpec.model_validate(meta["world"]),
                       **{k: data[k] for k in ("t", "true_pose", "odom_pose", "cmd", "ranges",
                                               "movers")},
                       events=meta["events"], planner_state=state, row=meta["row"])


def read_trace_world(path: str | Path) -> WorldSpec:
    """Only the world of a stored trace (npz members load lazily: no arrays are read)."""
    with np.load(path, allow_pickle=False) as data:
        return WorldSpec.model_validate(json.loads(str(data["meta"]))["world"])


def read_trace_positions(path: str | Path) -> np.ndarray:
    """Only the (T, 2) true positions (m) of a stored trace."""
    with np.load(path, allow_pickle=False) as data:
        return np.asarray(data["true_pose"], dtype=float)[:, :2]


@dataclass
class EpisodeResult:
    """A result row (see INTERFACES.md), the trace, and where the wall time went (s)."""

    row: dict[str, Any]
    trace: Trace
    timing: dict[str, float]


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def _check_command(cmd: Any, robot_v: float, robot_w: float) -> Command:
    if not isinstance(cmd, Command):
        raise PlannerError(f"planner returned {type(cmd).__name__}, expected Command")
    if not (math.isfinite(cmd.v) and math.isfinite(cmd.omega)):
        raise PlannerError(f"planner returned a non-finite command {cmd}")
    # the drive saturates anyway; clipping here keeps the recorded command truthful
    return Command(min(max(float(cmd.v), -robot_v), robot_v),
                   min(max(float(cmd.omega), -robot_w), robot_w))


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
    from nav_bench.sim.session import SimSession
    from nav_bench.sim.simulation import Simulation

    if session is not None and gui:
        raise InputError("an episode with the GUI opens its own session; do not pass one")
    settings = settings or EpisodeSettings()
    robot = robot or load_robot()
    params = full_params(planner)
    pid, rid = params_id(planner.planner, params), robot_id(robot)
    rng = episode_rng(world.name or "world", pid, rid, seed)
    planner_rng = rng.spawn(1)[0]
    agent = planner_instance or make_planner(planner)

    steps = max(1, round(settings.physics_hz / settings.control_hz))
    dt = steps / settings.physics_hz
    limit = settings.time_limit(world)
    goal = np.asarray(world.goal, dtype=float)
    bounds = (0.0, 0.0, float(world.size[0]), float(world.size[1]))
    rec: dict[str, list[Any]] = {k: [] for k in ("t", "true_pose", "odom_pose", "cmd", "ranges", "movers")}
    events: list[dict[str, Any]] = []
    outcome, error = Outcome.ERROR, None
    plan_s = 0.0
    wall0 = time.perf_counter()
    sim = None
    state: dict[str, Any] = {}
    host = (SimSession(gui=gui, physics_hz=settings.physics_hz) if session is None
            else contextlib.nullcontext(session))  # a session passed in stays open
    with host as session:
        session.open()  # idempotent; a worker's session is opened by its first episode
        try:
            sim = Simulation(session, world, robot, rng, physics_hz=settings.physics_hz)
            info = sim.robot_info
            stuck_anchor, stuck_since = sim.true_pose()[:2].copy(), 0.0
            first = True
            while True:
                true_pose = sim.true_pose()
                if np.hypot(*(true_pose[:2] - goal)) < settings.goal_tolerance:
                    outcome = Outcome.REACHED
                    break
                if sim.t >= limit - 1e-9:
                    outcome = Outcome.TIMEOUT
                    break
                if settings.stuck_s is not None:
                    if np.hypot(*(true_pose[:2] - stuck_anchor)) > settings.stuck_radius:
                        stuck_anchor, stuck_since = true_pose[:2].copy(), sim.t
                    elif sim.t - stuck_since >= settings.stuck_s:
                        outcome = Outcome.STUCK
                        break
                ranges = sim.sense()
                odom = sim.odometry_pose()
                obs = Observation(t=sim.t, pose=odom, goal=goal, ranges=ranges, robot=info,
                                  bounds=bounds, dt=dt)
                t0 = time.perf_counter()
                if first:
                    agent.reset(obs, planner_rng)
                    first = False
                try:
                    cmd = _check_command(agent.act(obs), info.v_max, info.omega_max)
                except PlannerError:
                    raise
                except Exception as exc:
                    raise PlannerError(f"planner {planner.planner!r} raised {type(exc).__name__}: {exc}") from exc
                plan_s += time.perf_counter() - t0
                new_events = [{"kind": e.kind, "t": e.t, "data": e.data} for e in agent.pop_events()]
                events += new_events
                if settings.record_trace:
                    rec["t"].append(sim.t)
                    rec["true_pose"].append(true_pose)
                    rec["odom_pose"].append(odom)
                    rec["cmd"].append((cmd.v, cmd.omega))
                    rec["ranges"].append(ranges)
                    rec["movers"].append(sim.mover_positions())
                if gui:
                    _draw_gui(sim, agent, obs, new_events)
                if live is not None:
                    live.update(sim.t, true_pose, agent.debug_state(), new_events)
                sim.apply(cmd)
                sim.step(steps)
                if gui:
                    time.sleep(max(0.0, dt - (time.perf_counter() - t0)))
        except Exception as exc:  # the episode ends as "error"; the batch goes on
            outcome = Outcome.ERROR
            error = "".join(traceback.format_exception(exc))
        final_true = sim.true_pose() if sim is not None else np.array(world.start_pose)
        final_odom = sim.odometry_pose() if sim is not None else final_true
        collisions = sim.collisions if sim is not None else 0
        sim_t = sim.t if sim is not None else 0.0
        timing_sim = dict(sim.timing) if sim is not None else {}
        radius = sim.robot_info.radius if sim is not None else 0.18
        try:
            state = agent.debug_state()
        except Exception:  # a broken debug_state must not lose the row
            state = {}
    wall = time.perf_counter() - wall0
    if live is not None:
        live.close()

    # the final pose counts too: record it so lengths and plots end where the robot stopped
    rec["t"].append(sim_t)
    rec["true_pose"].append(final_true)
    rec["odom_pose"].append(final_odom)
    rec["cmd"].append((0.0, 0.0))
    rec["ranges"].append(rec["ranges"][-1] if rec["ranges"] else np.zeros(0))
    rec["movers"].append(rec["movers"][-1] if rec["movers"] else np.zeros((len(world.movers), 2)))
    arrays = {k: np.asarray(v, dtype=float) for k, v in rec.items()}
    arrays["movers"] = arrays["movers"].reshape(len(rec["movers"]), len(world.movers), 2)
    xy = arrays["true_pose"][:, :2]

    travelled = polyline_length(xy)
    optimal = metrics.optimal_length(world, radius)
    success = outcome is Outcome.REACHED
    counts: dict[str, int] = {}
    for e in events:
        counts[e["kind"]] = counts.get(e["kind"], 0) + 1
    row: dict[str, Any] = {
        "world": world.name,
        "world_file": world_file,
        "planner": planner.planner,
        "params": params,
        "params_id": pid,
        "seed": int(seed),
        "success": success,
        "outcome": outcome.value,
        "time_s": round(float(sim_t), 6),
        "path_length_m": travelled,
        "optimal_length_m": optimal,
        "spl": metrics.spl(success, optimal, travelled),
        "replans": int(getattr(agent, "replans", counts.get("replan", 0))),
        "collisions": int(collisions),
        "min_clearance_m": metrics.min_clearance(world, xy, radius, arrays["movers"]),
        "wall_s": wall,
        "robot": robot.name,
        "robot_id": rid,
        "settings": asdict(settings),
        "goal_distance_m": float(np.hypot(*(final_true[:2] - goal))),
        "odometry_error_m": float(np.hypot(*(final_true[:2] - final_odom[:2]))),
        "events": counts,
        "error": error,
    }
    other = wall - sum(timing_sim.values()) - plan_s
    timing = {**timing_sim, "planning": plan_s, "other": other, "total": wall}
    trace = Trace(world=world, events=events, planner_state=state, row=row, **arrays)
    return EpisodeResult(row=row, trace=trace, timing=timing)


def _draw_gui(sim: Any, agent: Planner, obs: Observation, events: list[dict[str, Any]]) -> None:
    """Sonar rays, the planner's current aim and its last re-plan, as PyBullet debug lines."""
    hits = obs.sonar_hits()
    x, y = obs.pose[0], obs.pose[1]
    sim.draw_lines([((x, y), tuple(h)) for h in hits], color=(0.1, 0.6, 1.0), key="sonar")
    target = agent.debug_state().get("target")
    if target is not None:
        sim.draw_lines([((x, y), tuple(target)), (tuple(target), tuple(obs.goal))],
                       color=(1.0, 0.5, 0.0), key="path")
    for e in events:
        if e["kind"] == "replan" and "neighbours" in e["data"]:
            bx, by = e["data"]["breakpoint"]
            colours = {0: (0.1, 0.8, 0.1), 50: (1.0, 0.6, 0.0), 100: (0.9, 0.1, 0.1)}
            segs = [((bx, by), tuple(n)) for n in e["data"]["neighbours"]]
            risks = e["data"].get("risk", [100] * len(segs))
            for r in (0, 50, 100):
                sel = [s for s, ri in zip(segs, risks, strict=False) if ri == r]
                sim.draw_lines(sel, color=colours[r], key=f"neighbours{r}")
