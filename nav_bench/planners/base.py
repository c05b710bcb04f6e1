"""The planner base class and its parameters (:class:`Param`).

Planners never touch the simulator: they get plain data (:class:`~nav_bench.interface.Observation`),
keep their own maps, and return a :class:`~nav_bench.interface.Command`. Units: metres, seconds,
radians.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np

from nav_bench.errors import InputError
from nav_bench.interface import REPLAN, Command, Observation, PlannerEvent, StuckReason


class ParamError(InputError):
    """A bad planner parameter; ``param`` names it (for file/key/line reporting)."""

    def __init__(self, message: str, param: str) -> None:
        self.param = param
        super().__init__(message)


@dataclass(frozen=True)
class Param:
    """One planner parameter: its default, unit and one line of meaning.

    ``neutral``: the parameter chooses how the planner computes, never what (D* Lite's
    ``search_kernel``: the same results bit for bit); it is left out of the parameter set's id,
    so the episodes' ids and random streams are those of the set without it.
    """

    name: str
    default: Any
    unit: str
    doc: str
    choices: tuple[Any, ...] | None = None
    minimum: float | None = None
    maximum: float | None = None
    neutral: bool = False

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


def settings_class(owner: str, params: tuple[Param, ...], module: str) -> type:
    """A frozen dataclass with one attribute per :class:`Param` (its default as default), so
    a planner reads ``self.settings.lambda2`` and a typo fails at once."""
    fields = [(p.name, type(p.default), dataclasses.field(default=p.default)) for p in params]
    cls = dataclasses.make_dataclass(f"{owner}Settings", fields, frozen=True)
    cls.__module__, cls.__qualname__ = module, f"{owner}.Settings"  # pickled by this name
    cls.__doc__ = "Parameters of the planner, with defaults:\n\n" + "\n".join(
        f"* ``{p.name}`` = {p.default!r} {p.unit}: {p.doc}" for p in params)
    return cls


class Planner:
    """Base class of every planner.

    Subclasses set ``name`` and ``params`` (a tuple of :class:`Param`), implement
    :meth:`reset` and :meth:`act`, and call :meth:`emit` for events. Parameter values
    are attributes of ``self.settings`` (a frozen ``Settings`` object generated from
    ``params``, defaults filled in); ``self.p`` holds the same values as a read-only mapping.
    """

    name: ClassVar[str] = ""
    params: ClassVar[tuple[Param, ...]] = ()
    reference: ClassVar[str] = ""
    Settings: ClassVar[type] = settings_class("Planner", (), __name__)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls.Settings = settings_class(cls.__name__, cls.params, cls.__module__)

    def __init__(self, **overrides: Any) -> None:
        values = resolve_params(type(self), overrides)
        self.settings: Any = type(self).Settings(**values)
        self.p: Mapping[str, Any] = MappingProxyType(values)
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

    def stuck_reason(self) -> StuckReason | None:
        """Why the robot is making no progress, if the planner knows (e.g. it has no path, or
        its recovery found the robot pinned). Read when an episode ends ``stuck`` and stored as
        the row's ``stuck_reason``; None lets the episode classify the motion itself. Optional."""
        return None

    # -- helpers ---------------------------------------------------------------
    def emit(self, kind: str, t: float, **data: Any) -> None:
        """Record an event; ``replan`` events increase :attr:`replans`."""
        if kind == REPLAN:
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
