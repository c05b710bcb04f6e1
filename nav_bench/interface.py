"""The types every layer shares; imports nothing of nav-bench.

What a planner sees (:class:`Observation`) and returns (:class:`Command`), the robot's geometry
(:class:`RobotInfo`, :class:`SonarInfo`), what a planner reports (:class:`PlannerEvent`) and how
an episode ends (:class:`Outcome`). The simulator, the grid maps, the planners and the episode
all speak these. Units: metres, seconds, radians.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, TypeVar

import numpy as np

T = TypeVar("T")


class Outcome(str, Enum):
    """How an episode ended (a result row's ``outcome``; the value is the stored word)."""

    REACHED = "reached"  # the robot's true position came within the goal tolerance
    TIMEOUT = "timeout"  # the simulated time limit passed
    STUCK = "stuck"  # the robot stayed within a small circle for too long
    COLLISION = "collision"  # the robot touched something under a protocol where that ends it (barn)
    ERROR = "error"  # the planner or the simulation failed; the row carries the traceback

    def __str__(self) -> str:
        return self.value


class StuckReason(str, Enum):
    """Why a robot made no progress (a result row's ``stuck_reason`` when it ended ``stuck``).

    The planner says it when it knows (:meth:`nav_bench.planners.base.Planner.stuck_reason`);
    otherwise the episode classifies what it saw of the true motion.
    """

    PINNED = "pinned"  # the wheels turn but the robot does not move (pressed on a corner or wall)
    OSCILLATING = "oscillating"  # the robot moves back and forth inside a small area
    NO_PATH = "no_path"  # the planner reports that it has no path to the goal
    WAITING = "waiting"  # the planner holds the robot still on purpose (e.g. EO/PC's tier-3 wait)
    STOPPED = "stopped"  # the planner commands no motion and gives no reason

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class SonarInfo:
    """Where the sonars sit and what they can measure (fixed for an episode).

    Attributes:
        angles: (K,) mount yaw of each sonar relative to the robot heading, rad (CCW +).
        offsets: (K, 2) mount position of each sonar in the robot frame, m (x forward, y left).
        cone: full opening angle of each cone, rad.
        min_range, max_range: measurable range, m. A reading of ``max_range`` means "nothing seen".
    """

    angles: np.ndarray
    offsets: np.ndarray
    cone: float
    min_range: float
    max_range: float

    def mounts(self, x: Any, y: Any, cos_yaw: Any, sin_yaw: Any) -> tuple[np.ndarray, np.ndarray]:
        """World-frame x and y of the mounts, m, for a robot at (``x``, ``y``) whose heading has
        cosine ``cos_yaw`` and sine ``sin_yaw``: floats give (K,) arrays; (N, 1) columns of N
        poses give (N, K). The caller computes the cosine and sine (``math`` or NumPy: they may
        differ in the last bit, and a caller's rows depend on its choice)."""
        ox, oy = self.offsets[:, 0], self.offsets[:, 1]
        return x + cos_yaw * ox - sin_yaw * oy, y + sin_yaw * ox + cos_yaw * oy


@dataclass(frozen=True)
class RobotInfo:
    """Robot geometry and limits a planner may use.

    Attributes:
        radius: body radius, m. wheel_base: distance between the wheels, m.
        v_max: top translation speed the drive allows, m/s. omega_max: top turn rate, rad/s.
    """

    radius: float
    wheel_base: float
    v_max: float
    omega_max: float
    sonar: SonarInfo


@dataclass(frozen=True)
class Observation:
    """One control cycle's input to a planner.

    Attributes:
        t: simulated time since the start, s.
        pose: (3,) odometry pose estimate ``x, y, yaw`` (m, m, rad) in the world frame.
        goal: (2,) goal position, m.
        ranges: (K,) sonar readings, m, in ``robot.sonar`` order; ``max_range`` = no echo.
        robot: geometry and limits.
        bounds: ``(xmin, ymin, xmax, ymax)`` of the area the grids should cover, m
            (the world's extent; the paper sizes its fixed grid map from it).
        dt: control period, s.
    """

    t: float
    pose: np.ndarray
    goal: np.ndarray
    ranges: np.ndarray
    robot: RobotInfo
    bounds: tuple[float, float, float, float]
    dt: float

    def sonar_hits(self) -> np.ndarray:
        """(K, 2) world-frame points of the readings (max-range readings included), m; read-only.

        Computed on the first call and kept on the observation (its fields are its readings,
        fixed once sensed): a bug planner and its wall followers ask for them several times
        a cycle (issue 16)."""
        return once_per_observation(self, "_sonar_hits", _sonar_hits)


def _sonar_hits(obs: Observation) -> np.ndarray:
    x, y, yaw = obs.pose
    s = obs.robot.sonar
    c, si = math.cos(yaw), math.sin(yaw)
    ox, oy = s.mounts(x, y, c, si)
    ang = yaw + s.angles
    hits = np.empty((len(ang), 2))  # the columns as np.stack would lay them out
    hits[:, 0] = ox + obs.ranges * np.cos(ang)
    hits[:, 1] = oy + obs.ranges * np.sin(ang)
    return hits


def once_per_observation(obs: Observation, key: str, compute: Callable[[Observation], T]) -> T:
    """``compute(obs)``, worked out on the first call and kept on ``obs`` under ``key``
    (arrays made read-only, as every reader shares them).

    Why: a bug planner, its wall followers and their helpers read the same echoes of one
    observation several times a cycle (issue 16: TangentBug asked for 7 echo masks a cycle);
    an observation's readings are fixed once sensed."""
    value = obs.__dict__.get(key)
    if value is None:
        value = compute(obs)
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
        obs.__dict__[key] = value  # a frozen dataclass refuses setattr, not its dict
    return value


@dataclass(frozen=True)
class Command:
    """Body velocity command: translation ``v`` (m/s, + forward) and turn rate ``omega`` (rad/s, CCW +)."""

    v: float
    omega: float


@dataclass(frozen=True)
class PlannerEvent:
    """Something a planner wants recorded in the trace (a re-plan, a blocked cycle...).

    ``kind`` is a short word; ``replan`` events are counted in the result row's ``replans``.
    ``data`` holds plain JSON-able values (lists, floats, strings).
    """

    kind: str
    t: float
    data: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def of(cls, event: Any) -> PlannerEvent:
        """``event`` as a PlannerEvent: one already, or as the trace stores it, ``{kind, t, data}``."""
        if isinstance(event, PlannerEvent):
            return event
        return cls(str(event.get("kind", "")), float(event.get("t", 0.0)), dict(event.get("data") or {}))


# The risk index of a candidate point (EO/PC's r: safe, medium, high) and how viewers colour it
RISK_COLORS = {0: "#2ca02c", 50: "#ff9f1c", 100: "#d62728"}
NO_RISK_COLOR = "#7f7f7f"


def _points(values: Any) -> tuple[tuple[float, float], ...]:
    return tuple((float(v[0]), float(v[1])) for v in values)


@dataclass(frozen=True)
class ReplanEvent:
    """A re-plan at a breakpoint: the candidate points around it, their risk index, the one
    chosen, and why the planner re-planned. What plots, the live view and the GUI draw.

    A planner emits it with ``self.emit(REPLAN, t, **event.data())``; the trace keeps the plain
    data; :meth:`from_event` reads it back from a :class:`PlannerEvent` or a stored event.

    Attributes:
        t: s. breakpoint: (x, y) m. neighbours: the candidate points (x, y), m.
        risk: each neighbour's risk index (0, 50, 100); empty: unknown.
        candidate: whether each neighbour could be chosen; empty: all could.
        chosen: index of the chosen neighbour (None: none chosen).
        trigger: what made the planner re-plan (EO/PC: ``eo_stop`` or ``blocked_path``).
        theta_from: what the angles are measured from (EO/PC: ``heading`` or ``old_path``).
        details: the rest of the planner's numbers (scores, tiers...), plain JSON.
    """

    t: float
    breakpoint: tuple[float, float]
    neighbours: tuple[tuple[float, float], ...] = ()
    risk: tuple[int, ...] = ()
    candidate: tuple[bool, ...] = ()
    chosen: int | None = None
    trigger: str = "eo_stop"
    theta_from: str = "heading"
    details: Mapping[str, Any] = field(default_factory=dict)

    def data(self) -> dict[str, Any]:
        """The event's payload as plain JSON (what the trace stores)."""
        return {"breakpoint": list(self.breakpoint), "neighbours": [list(p) for p in self.neighbours],
                "risk": list(self.risk), "candidate": list(self.candidate), "chosen": self.chosen,
                **self.details, "trigger": self.trigger, "theta_from": self.theta_from}

    @classmethod
    def from_event(cls, event: Any) -> ReplanEvent | None:
        """The re-plan in ``event`` (a :class:`PlannerEvent` or a stored ``{kind, t, data}``);
        None if it is another kind of event or carries no breakpoint and neighbours."""
        kind, t, data = (e := PlannerEvent.of(event)).kind, e.t, e.data
        if kind != REPLAN or "breakpoint" not in data or "neighbours" not in data:
            return None
        core = {"breakpoint", "neighbours", "risk", "candidate", "chosen", "trigger", "theta_from"}
        chosen = data.get("chosen")
        return cls(t=float(t), breakpoint=_points([data["breakpoint"]])[0],
                   neighbours=_points(data["neighbours"]),
                   risk=tuple(int(r) for r in data.get("risk", ())),
                   candidate=tuple(bool(c) for c in data.get("candidate", ())),
                   chosen=None if chosen is None else int(chosen),
                   trigger=str(data.get("trigger", "eo_stop")),
                   theta_from=str(data.get("theta_from", "heading")),
                   details={k: v for k, v in data.items() if k not in core})

    def risk_of(self, i: int) -> int | None:
        """Neighbour ``i``'s risk index, None when the event has none."""
        return self.risk[i] if i < len(self.risk) else None


REPLAN = "replan"  # the event kind counted in a result row's ``replans``


@dataclass(frozen=True)
class GridState:
    """A planner's grid maps as viewers draw them.

    Attributes:
        pmo: (H, W) occupancy 0..100 (50 unknown), row 0 at ``ymin``.
        pmt: (H, W) visit counts (control cycles per cell), or None.
        bounds: ``(xmin, ymin, xmax, ymax)`` of the grids, m. cell: cell size, m, or None.
    """

    pmo: np.ndarray
    bounds: tuple[float, float, float, float]
    pmt: np.ndarray | None = None
    cell: float | None = None

    @property
    def extent(self) -> list[float]:
        """imshow extent ``[xmin, xmax, ymin, ymax]``."""
        xmin, ymin, xmax, ymax = self.bounds
        return [xmin, xmax, ymin, ymax]

    def state(self) -> dict[str, Any]:
        """The grids as entries of a planner's ``debug_state()`` (what the trace stores)."""
        out: dict[str, Any] = {"pmo": self.pmo}
        if self.pmt is not None:
            out["pmt"] = self.pmt
        out["bounds"] = list(self.bounds)
        if self.cell is not None:
            out["cell"] = self.cell
        return out

    @classmethod
    def from_state(cls, state: Mapping[str, Any] | None) -> GridState | None:
        """The grids in a ``debug_state()`` (live or stored); None if it has none."""
        if not state or "pmo" not in state or "bounds" not in state:
            return None
        pmt = state.get("pmt")
        cell = state.get("cell")
        return cls(pmo=np.asarray(state["pmo"]), bounds=tuple(float(v) for v in state["bounds"]),
                   pmt=None if pmt is None else np.asarray(pmt),
                   cell=None if cell is None else float(cell))


def wrap_angle(a: float) -> float:
    """Angle wrapped to (-pi, pi]."""
    a = (a + math.pi) % (2 * math.pi) - math.pi
    return math.pi if a == -math.pi else a
