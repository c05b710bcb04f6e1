"""What a planner sees (:class:`Observation`) and returns (:class:`Command`), and its base class.

Planners never touch the simulator: they get plain data, keep their own maps, and
return a command. Units: metres, seconds, radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from nav_bench.errors import InputError


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
        """(K, 2) world-frame points of the readings (max-range readings included), m."""
        x, y, yaw = self.pose
        s = self.robot.sonar
        c, si = math.cos(yaw), math.sin(yaw)
        ox = x + c * s.offsets[:, 0] - si * s.offsets[:, 1]
        oy = y + si * s.offsets[:, 0] + c * s.offsets[:, 1]
        ang = yaw + s.angles
        return np.stack([ox + self.ranges * np.cos(ang), oy + self.ranges * np.sin(ang)], axis=1)


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


class ParamError(InputError):
    """A bad planner parameter; ``param`` names it (for file/key/line reporting)."""

    def __init__(self, message: str, param: str) -> None:
        self.param = param
        super().__init__(message)


@dataclass(frozen=True)
class Param:
    """One planner parameter: its default, unit and one line of meaning."""

    name: str
    default: Any
    unit: str
    doc: str
    choices: tuple[Any, ...] | None = None
    minimum: float | None = None
    maximum: float | None = None

    def check(self, value: Any) -> Any:
        """The value converted to the default's type, or :class:`InputError` saying what is expected."""
        expected = type(self.default)
        if expected is bool:
            if not isinstance(value, bool):
                raise ParamError(f"parameter {self.name!r} expects true or false, got {value!r}", self.name)
        elif expected in (int, float):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ParamError(f"parameter {self.name!r} expects a number ({self.unit}), got {value!r}", self.name)
            if not math.isfinite(value):
                raise ParamError(f"parameter {self.name!r} expects a finite number ({self.unit}), "
                                 f"got {value!r}", self.name)
            if expected is int and float(value) != int(value):
                raise ParamError(f"parameter {self.name!r} expects a whole number, got {value!r}", self.name)
            value = expected(value)
            if self.minimum is not None and value < self.minimum:
                raise ParamError(f"parameter {self.name!r} must be >= {self.minimum}, got {value!r}", self.name)
            if self.maximum is not None and value > self.maximum:
                raise ParamError(f"parameter {self.name!r} must be <= {self.maximum}, got {value!r}", self.name)
        elif expected is str and not isinstance(value, str):
            raise ParamError(f"parameter {self.name!r} expects text, got {value!r}", self.name)
        if self.choices is not None and value not in self.choices:
            raise ParamError(f"parameter {self.name!r} must be one of {list(self.choices)}, got {value!r}", self.name)
        return value


class Planner:
    """Base class of every planner.

    Subclasses set ``name`` and ``params`` (a tuple of :class:`Param`), implement
    :meth:`reset` and :meth:`act`, and call :meth:`emit` for events. Parameter values
    are on ``self.p`` (a dict with defaults filled in).
    """

    name: ClassVar[str] = ""
    params: ClassVar[tuple[Param, ...]] = ()
    reference: ClassVar[str] = ""

    def __init__(self, **overrides: Any) -> None:
        self.p: dict[str, Any] = resolve_params(type(self), overrides)
        self._events: list[PlannerEvent] = []
        self.replans = 0

    # -- to implement --------------------------------------------------------
    def reset(self, obs: Observation, rng: np.random.Generator) -> None:
        """Start a new episode; ``obs`` is the first observation. Clear all episode state."""
        self._events = []
        self.replans = 0

    def act(self, obs: Observation) -> Command:
        """One control cycle: update internal state from ``obs`` and return a command."""
        raise NotImplementedError

    @classmethod
    def check_rules(cls, p: dict[str, Any]) -> None:
        """Rules between parameters (``p``: every parameter, defaults filled in), checked
        whenever a parameter set is resolved: by ``validate``, at suite expansion and on the
        command line, before anything is simulated. Raise :class:`ParamError` naming the
        parameter to fix. Optional; a rule that needs the robot or the world stays in
        :meth:`reset`."""

    def debug_state(self) -> dict[str, Any]:
        """Planner state for plots and the GUI (grids, current path...); plain data. Optional."""
        return {}

    # -- helpers ---------------------------------------------------------------
    def emit(self, kind: str, t: float, **data: Any) -> None:
        """Record an event; ``replan`` events increase :attr:`replans`."""
        if kind == "replan":
            self.replans += 1
        self._events.append(PlannerEvent(kind, t, data))

    def pop_events(self) -> list[PlannerEvent]:
        """Events since the last call (the episode drains them every cycle)."""
        events, self._events = self._events, []
        return events


def resolve_params(cls: type[Planner], overrides: dict[str, Any]) -> dict[str, Any]:
    """Defaults of ``cls.params`` updated by ``overrides``; unknown names are an error."""
    known = {p.name: p for p in cls.params}
    unknown = [k for k in overrides if k not in known]
    if unknown:
        import difflib

        close = difflib.get_close_matches(unknown[0], known, n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        raise ParamError(f"planner {cls.name!r} has no parameter {unknown[0]!r}.{hint} "
                         f"Parameters: {', '.join(known) or '(none)'}", unknown[0])
    full = {name: (p.check(overrides[name]) if name in overrides else p.default)
            for name, p in known.items()}
    cls.check_rules(full)
    return full


def wrap_angle(a: float) -> float:
    """Angle wrapped to (-pi, pi]."""
    a = (a + math.pi) % (2 * math.pi) - math.pi
    return math.pi if a == -math.pi else a
