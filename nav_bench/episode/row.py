"""The result row: one typed record per episode, built once from its trace.

:class:`ResultRow` is what the episode returns, what the batch store writes and reads back
(validated both ways) and what ``nav-bench episode --json`` prints. Field names and meanings
are a contract (INTERFACES.md); more fields are welcome. On disk a row is one line of JSON
(:meth:`ResultRow.to_json`, :meth:`ResultRow.from_json`); keys this version does not know are
kept in ``extra`` and written back unchanged.

Map quality (planners that build an occupancy grid and return it from ``debug_state()`` as a
:class:`~nav_bench.interface.GridState`: EO/PC, D* Lite, DWA with ``use_grid``, dwa_global;
null for the others, and then left out of the JSON line like the other optional fields, as in
rows stored before the fields existed). Measured once at the end of the episode by
:mod:`nav_bench.mapping.quality` on the planner's own cells, over the cells its sonars observed
(value != 50), a cell occupied above 65, a marked cell within one cell of a true obstacle
counted right:

* ``map_precision``: share of the cells marked occupied that are true obstacles (null: none marked);
* ``map_recall``: share of the observed true obstacle cells marked occupied (null: none observed);
* ``map_phantom_share``: share of the true free cells on the optimal path (the path of
  ``optimal_length_m``) that the map marks occupied: walls invented across the best route
  (null: goal unreachable);
* ``map_observed_cells``, ``map_occupied_cells``, ``map_path_cells``, ``map_phantom_cells``:
  the counts behind them (integers).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from nav_bench.episode import metrics
from nav_bench.episode.motion import MOTION_FIELDS, motion_metrics
from nav_bench.episode.protocol import make_protocol
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.episode.trace import Trace
from nav_bench.interface import Outcome, StuckReason
from nav_bench.mapping.quality import MAP_QUALITY_FIELDS
from nav_bench.world.geometry import polyline_length


class RowSchemaError(ValueError):
    """A result row that does not match :data:`ROW_FIELDS`; lists every problem."""


@dataclass
class ResultRow:
    """One episode's result. Lengths in m, times in s."""

    world: str
    world_file: str | None  # the path as given
    planner: str  # registered planner name
    params: dict[str, Any]  # the full parameter set, defaults filled in
    params_id: str  # short stable hash of planner + params
    seed: int
    success: bool  # reached the goal within goal_tolerance before the time limit
    outcome: Outcome
    time_s: float | None  # simulated seconds until the episode ended (null: never finished)
    path_length_m: float | None  # length of the true trajectory
    optimal_length_m: float | None  # shortest collision-free path on the true map
    spl: float  # success weighted by optimal / max(optimal, travelled)
    replans: int | None  # re-plans the planner reported
    collisions: int | None  # distinct contacts with anything but the floor
    min_clearance_m: float | None  # smallest gap between the robot's edge and true geometry
    wall_s: float  # wall-clock seconds the episode took
    robot: str | None = None  # robot (variant) label, e.g. "diffbot[sonar.noise_std=0.02]"
    robot_id: str | None = None  # stable hash of the robot's settings and URDF content
    settings: dict[str, Any] = field(default_factory=dict)  # the EpisodeSettings played
    goal_distance_m: float | None = None  # true distance to the goal at the end
    odometry_error_m: float | None = None  # true vs odometry position at the end
    events: dict[str, int] = field(default_factory=dict)  # planner events: count per kind
    error: str | None = None  # traceback text for outcome "error", else null
    # how the robot moved (nav_bench.episode.motion; null when the trace is too short)
    accel_mean_mps2: float | None = None  # mean |linear acceleration|
    accel_max_mps2: float | None = None  # largest |linear acceleration|
    jerk_linear: float | None = None  # integral of squared linear jerk, m^2/s^5
    jerk_angular: float | None = None  # integral of squared angular jerk, rad^2/s^5
    curvature_per_m: float | None = None  # angle over length, rad/m
    time_near_obstacles_s: float | None = None  # edge within settings.safety_distance_m
    plan_ms_mean: float | None = None  # planner compute time per control cycle, ms (wall clock)
    plan_ms_p95: float | None = None  # its 95th percentile, ms (wall clock)
    barn_score: float | None = None  # under protocol barn: success x OT / clip(AT, 2 OT, 8 OT)
    # what the episode cost and why it stalled (issue 16)
    cpu_s: float | None = None  # CPU seconds of the process that played the episode
    stuck_reason: StuckReason | None = None  # outcome stuck: why (planner's, else classified)
    # map quality (nav_bench.mapping.quality): the planner's final occupancy grid against the
    # true static map over the cells it observed (value != 50), occupied above 65, one cell of
    # tolerance; null for planners that keep no grid (and for rows older than the fields)
    map_precision: float | None = None  # share of occupied-marked cells that are true obstacles
    map_recall: float | None = None  # share of observed true obstacle cells marked occupied
    map_phantom_share: float | None = None  # share of the optimal path's free cells marked occupied
    map_observed_cells: int | None = None  # cells the sonars said anything about
    map_occupied_cells: int | None = None  # cells marked occupied
    map_path_cells: int | None = None  # true free cells on the optimal path
    map_phantom_cells: int | None = None  # of those, marked occupied (invented walls on the route)
    # set by the batch runner
    job_id: str | None = None  # stable id of (world, parameter set, robot, seed, limits)
    label: str | None = None  # the suite's name for the parameter set, e.g. "eopc_rr[RR=0.4]"
    time_limit_s: float | None = None
    trace: str | None = None  # traces/<job_id>.npz, relative to the results folder
    trace_error: str | None = None  # why the trace could not be kept
    extra: dict[str, Any] = field(default_factory=dict)  # stored keys this version does not know

    # -- built once --------------------------------------------------------------------
    @classmethod
    def from_trace(cls, trace: Trace, *, outcome: Outcome, error: str | None, world_file: str | None,
                   planner: str, params: dict[str, Any], params_id: str, seed: int,
                   robot: str | None, robot_id: str, settings: dict[str, Any], time_s: float,
                   robot_radius: float, replans: int, collisions: int, wall_s: float) -> ResultRow:
        """The row of a played episode: its numbers measured on ``trace``."""
        world = trace.world
        xy = trace.true_pose[:, :2]
        gaps = metrics.clearances(world, xy, robot_radius, trace.movers)
        safety = float(settings.get("safety_distance_m", EpisodeSettings.safety_distance_m))
        plan_s = trace.plan_s if len(trace.plan_s) else np.full(len(trace.t), np.nan)
        motion = motion_metrics(trace.t, trace.true_pose, gaps, plan_s, safety)
        final_true, final_odom = trace.true_pose[-1], trace.odom_pose[-1]
        travelled = polyline_length(xy)
        optimal = metrics.optimal_length(world, robot_radius)
        success = outcome is Outcome.REACHED
        protocol = make_protocol(settings.get("protocol", "nav_bench"),
                                 settings.get("protocol_options"))
        scores = protocol.score(success, optimal, time_s)
        quality = metrics.planner_map_quality(world, trace.planner_state, robot_radius)
        mapping = quality.row_fields() if quality is not None else {}
        return cls(
            world=world.name, world_file=world_file, planner=planner, params=params,
            params_id=params_id, seed=int(seed), success=success, outcome=outcome,
            time_s=round(float(time_s), 6), path_length_m=travelled, optimal_length_m=optimal,
            spl=metrics.spl(success, optimal, travelled), replans=int(replans),
            collisions=int(collisions),
            min_clearance_m=float(gaps.min()) if len(gaps) else float("nan"),
            wall_s=wall_s, robot=robot, robot_id=robot_id, settings=settings,
            goal_distance_m=float(np.hypot(*(final_true[:2] - np.asarray(world.goal, float)))),
            odometry_error_m=float(np.hypot(*(final_true[:2] - final_odom[:2]))),
            events=count_events(trace.events), error=error, **motion, **scores, **mapping)

    @classmethod
    def failure(cls, *, world: str, world_file: str | None, planner: str, params: dict[str, Any],
              params_id: str, seed: int, settings: dict[str, Any], error: str,
              wall_s: float) -> ResultRow:
        """The row of an episode that did not finish: outcome ``error``, measurements null."""
        return cls(world=world, world_file=world_file, planner=planner, params=params,
                   params_id=params_id, seed=seed, success=False, outcome=Outcome.ERROR,
                   time_s=None, path_length_m=None, optimal_length_m=None, spl=0.0, replans=None,
                   collisions=None, min_clearance_m=None, wall_s=wall_s, settings=settings,
                   error=error)

    # -- JSON --------------------------------------------------------------------------
    def to_json(self) -> dict[str, Any]:
        """The row as a JSON object, in the stored key order (batch identity first)."""
        out: dict[str, Any] = {}
        if self.job_id is not None:
            out["job_id"], out["label"] = self.job_id, self.label
        for name in EPISODE_FIELDS:
            value = getattr(self, name)
            if value is None and name in _OMITTED_WHEN_NULL:
                continue  # an episode that never finished has no final pose, a short one no motion
            out[name] = value.value if isinstance(value, (Outcome, StuckReason)) else value
        if self.time_limit_s is not None:
            out["time_limit_s"] = self.time_limit_s
        if self.job_id is not None:
            out["trace"] = self.trace
        if self.trace_error is not None:
            out["trace_error"] = self.trace_error
        out.update(self.extra)
        return out

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> ResultRow:
        """A stored row; :class:`RowSchemaError` lists every way it is not a valid row."""
        check_row(data)
        known = {k: v for k, v in data.items() if k in _FIELD_NAMES}
        known["outcome"] = Outcome(known["outcome"])
        if known.get("stuck_reason") is not None:
            known["stuck_reason"] = StuckReason(known["stuck_reason"])
        return cls(**known, extra={k: v for k, v in data.items() if k not in _FIELD_NAMES})


def count_events(events: list[dict[str, Any]]) -> dict[str, int]:
    """Planner events by kind, for the row's ``events``. An event whose data names a
    ``trigger`` (EO/PC's re-plans: ``eo_stop``, ``blocked_path``) is also counted as
    ``kind.trigger``, so ``replan`` stays the total and ``replan.eo_stop`` one of its parts."""
    counts: dict[str, int] = {}
    for e in events:
        keys = [e["kind"]]
        trigger = (e.get("data") or {}).get("trigger")
        if isinstance(trigger, str):
            keys.append(f"{e['kind']}.{trigger}")
        for key in keys:
            counts[key] = counts.get(key, 0) + 1
    return counts


_MEASURED_AT_THE_END = frozenset({"goal_distance_m", "odometry_error_m"})
_COST_FIELDS = frozenset({"cpu_s", "stuck_reason"})  # absent from rows that have none
SCORE_FIELDS = ("barn_score",)  # protocols' scores: only rows played under that protocol have one
_OMITTED_WHEN_NULL = (_MEASURED_AT_THE_END | frozenset(MOTION_FIELDS) | frozenset(SCORE_FIELDS)
                      | _COST_FIELDS
                      | frozenset(MAP_QUALITY_FIELDS))  # no grid: no map fields in the line
_FIELD_NAMES = frozenset(f.name for f in dataclasses.fields(ResultRow)) - {"extra"}
EPISODE_FIELDS = tuple(f.name for f in dataclasses.fields(ResultRow)
                       if f.name not in {"job_id", "label", "time_limit_s", "trace", "trace_error",
                                         "extra"})

# What a stored row must hold (INTERFACES.md plus the runner's fields): field -> accepted JSON
# types. ``float`` fields accept JSON integers too (``1`` and ``1.0`` are the same in JSON).
ROW_FIELDS: dict[str, tuple[type, ...]] = {
    "job_id": (str,), "label": (str,), "world": (str,), "world_file": (str,), "planner": (str,),
    "params": (dict,), "params_id": (str,), "robot": (str,), "robot_id": (str,), "seed": (int,),
    "success": (bool,), "outcome": (str,), "time_s": (float,), "path_length_m": (float,),
    "optimal_length_m": (float, type(None)), "spl": (float,), "replans": (int,),
    "collisions": (int,), "min_clearance_m": (float, type(None)), "wall_s": (float,),
    "settings": (dict,), "error": (str, type(None)), "events": (dict,),
}

# Measured quantities an ``error`` row may leave null: the episode never finished.
ERROR_NULLABLE = frozenset({"time_s", "path_length_m", "replans", "collisions", "min_clearance_m"})
OUTCOMES = tuple(o.value for o in Outcome)
STUCK_REASONS = tuple(r.value for r in StuckReason)
# fields measured on the wall clock: two plays of the same episode differ only in these
WALL_CLOCK_FIELDS = frozenset({"wall_s", "plan_ms_mean", "plan_ms_p95", "cpu_s"})
# optional fields (rows stored before they existed lack them): field -> accepted JSON types
OPTIONAL_FIELDS: dict[str, tuple[type, ...]] = {
    name: (float, type(None)) for name in (*MOTION_FIELDS, *SCORE_FIELDS, "cpu_s")}
OPTIONAL_FIELDS.update({name: (int, type(None)) if name.endswith("_cells") else (float, type(None))
                        for name in MAP_QUALITY_FIELDS})


def row_problems(row: dict[str, Any]) -> list[str]:
    """Every way ``row`` differs from :data:`ROW_FIELDS` and the row's rules (empty: valid)."""
    problems = []
    is_error = row.get("outcome") == Outcome.ERROR.value
    for name, types in ROW_FIELDS.items():
        if name not in row:
            problems.append(f"missing field {name!r}")
            continue
        value = row[name]
        if value is None and is_error and name in ERROR_NULLABLE:
            continue
        accepted = types + ((int,) if float in types else ())
        # bool is an int subclass in Python but not a number in a row
        if not isinstance(value, accepted) or (isinstance(value, bool) and bool not in types):
            expected = " or ".join("null" if t is type(None) else t.__name__ for t in types)
            problems.append(f"field {name!r} should be {expected}, got {value!r:.60}")
    for name, types in OPTIONAL_FIELDS.items():
        value = row.get(name)
        if value is not None and (isinstance(value, bool) or not isinstance(value, (*types, int))):
            problems.append(f"field {name!r} should be a number or null, got {value!r:.60}")
    reason = row.get("stuck_reason")
    if reason is not None and reason not in STUCK_REASONS:
        problems.append(f"stuck_reason {reason!r} is not one of {', '.join(STUCK_REASONS)}")
    if not problems:
        if row["outcome"] not in OUTCOMES:
            problems.append(f"outcome {row['outcome']!r} is not one of {', '.join(OUTCOMES)}")
        if row["success"] != (row["outcome"] == Outcome.REACHED.value):
            problems.append(f"success {row['success']} disagrees with outcome {row['outcome']!r}")
        if (row["error"] is not None) != is_error:
            problems.append("error text must be present exactly when outcome is 'error'")
        if not 0.0 <= row["spl"] <= 1.0:
            problems.append(f"spl {row['spl']} is outside [0, 1]")
        if row["seed"] < 0:
            problems.append(f"seed {row['seed']} is negative")
    return problems


def check_row(row: dict[str, Any]) -> None:
    """Raise :class:`RowSchemaError` listing every problem of ``row``; return if it is valid."""
    problems = row_problems(row)
    if problems:
        raise RowSchemaError("; ".join(problems))
