"""Protocols: the rules an episode is judged by, one object each.

A protocol says what counts as success (the goal radius), how long an episode may last, which
events end it, and which score the row gets. The episode asks its protocol for its endings
(:meth:`Protocol.endings`) and its score (:meth:`Protocol.score`); nothing else in the loop
knows which protocol is playing. Suites choose one with ``protocol: NAME`` or
``protocol: {name: NAME, <setting>: value}``; ``nav-bench episode --protocol NAME``.

* ``nav_bench`` (the default): success within ``limits.goal_tolerance`` (0.3 m) of the goal
  before the time limit (``limits.time_s``); a robot that stays within a small circle for
  ``limits.stuck_s``, or whose positions over 3 x ``stuck_s`` fit in a disc of radius
  ``limits.stuck_area_radius`` (0.6 m: an oscillating robot), is ``stuck``; collisions are
  counted, not fatal. No extra score.
* ``barn``: the BARN Challenge's rules (Perille et al. 2020; Xiao et al., "Autonomous Ground
  Navigation in Highly Constrained Spaces: Lessons learned from the BARN Challenge at ICRA
  2022"; its ``run.py``): success within 1 m of the goal before 100 s of simulated time; the
  first collision ends the episode as a failure (outcome ``collision``); no stuck rule. Its
  score, ``barn_score`` in the row, is ``success * OT / clip(AT, 2 OT, 8 OT)`` with the actual
  time ``AT`` and the optimal time ``OT = optimal path length / 2 m/s``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from nav_bench.episode.ending import (
    Collided,
    Ending,
    GoalReached,
    Stuck,
    TimeLimit,
)
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.errors import InputError
from nav_bench.specs import WorldSpec


@dataclass(frozen=True)
class Protocol:
    """Rules of the ``nav_bench`` protocol; a subclass changes what differs.

    Attributes:
        name: the protocol's name in suites and rows.
        goal_radius_m: true distance to the goal that counts as reached; None: the episode
            settings' ``goal_tolerance``.
        time_limit_s: simulated time limit; None: the settings' limit (``limits.time_s``).
        collision_ends: the first collision ends the episode (outcome ``collision``).
        stuck_ends: the settings' stuck rule ends the episode (outcome ``stuck``).
    """

    name: str = "nav_bench"
    goal_radius_m: float | None = None
    time_limit_s: float | None = None
    collision_ends: bool = False
    stuck_ends: bool = True

    def __post_init__(self) -> None:
        for name in ("goal_radius_m", "time_limit_s"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise InputError(f"protocol {self.name!r}: {name} must be > 0, got {value!r}")

    def goal_radius(self, settings: EpisodeSettings) -> float:
        """Success radius, m."""
        return self.goal_radius_m if self.goal_radius_m is not None else settings.goal_tolerance

    def time_limit(self, settings: EpisodeSettings, world: WorldSpec) -> float:
        """Simulated time limit, s."""
        return self.time_limit_s if self.time_limit_s is not None else settings.time_limit(world)

    def endings(self, settings: EpisodeSettings, world: WorldSpec, start_xy: np.ndarray,
                collisions: Callable[[], int]) -> list[Ending]:
        """The end conditions of an episode, in the order they are checked."""
        out: list[Ending] = [Collided(collisions)] if self.collision_ends else []
        out += [GoalReached(np.asarray(world.goal, dtype=float), self.goal_radius(settings)),
                TimeLimit(self.time_limit(settings, world))]
        if self.stuck_ends and settings.stuck_s is not None:
            out.append(Stuck(settings.stuck_s, settings.stuck_radius, start_xy,
                             area_radius=settings.stuck_area_radius))
        return out

    def score(self, success: bool, optimal_m: float | None, time_s: float | None) -> dict[str, Any]:
        """The protocol's own score fields for the row (none for ``nav_bench``)."""
        return {}

    def rules(self, settings: EpisodeSettings | None = None) -> dict[str, Any]:
        """The rules as plain data (run.json, the report's header); with ``settings`` the
        values that come from them are filled in."""
        out: dict[str, Any] = {"name": self.name}
        for f in dataclasses.fields(self):
            if f.name != "name":
                out[f.name] = getattr(self, f.name)
        if settings is not None:
            out["goal_radius_m"] = self.goal_radius(settings)
            out["stuck_ends"] = self.stuck_ends and settings.stuck_s is not None
            if self.time_limit_s is None:
                out["time_limit_s"] = settings.time_s  # None: scales with the world's size
        out["score"] = self.score_text()
        return out

    def score_text(self) -> str:
        return "none (success, SPL and the rest of the row)"

    def describe(self, settings: EpisodeSettings | None = None) -> str:
        """One line for the report's header (:func:`rules_text` of :meth:`rules`)."""
        return rules_text(self.rules(settings))


def rules_text(r: dict[str, Any]) -> str:
    """One line saying what a protocol's stored rules (:meth:`Protocol.rules`) mean."""
    limit = (f"{r['time_limit_s']:g} s" if r.get("time_limit_s") is not None
             else "15 s per metre of the world's width + height (at least 60 s)")
    radius = (f"{r['goal_radius_m']:g} m" if r.get("goal_radius_m") is not None
              else "limits.goal_tolerance")
    ends = ["the goal", "the time limit"]
    ends += ["the first collision (a failure)"] if r.get("collision_ends") else []
    ends += ["being stuck"] if r.get("stuck_ends") else []
    return (f"protocol `{r.get('name', '?')}`: success within {radius} of the goal before {limit}; "
            f"an episode ends at {', '.join(ends)}; score: {r.get('score', 'none')}")


@dataclass(frozen=True)
class BarnProtocol(Protocol):
    """The BARN Challenge's rules (Xiao et al. 2022, ``run.py`` of the-barn-challenge).

    Attributes (beyond :class:`Protocol`):
        optimal_speed_mps: speed that turns the optimal path length into the optimal time OT.
    """

    name: str = "barn"
    goal_radius_m: float | None = 1.0
    time_limit_s: float | None = 100.0
    collision_ends: bool = True
    stuck_ends: bool = False
    optimal_speed_mps: float = 2.0

    def __post_init__(self) -> None:
        super().__post_init__()
        if not self.optimal_speed_mps > 0:
            raise InputError(f"protocol 'barn': optimal_speed_mps must be > 0, got {self.optimal_speed_mps!r}")

    def score(self, success: bool, optimal_m: float | None, time_s: float | None) -> dict[str, Any]:
        """``barn_score``: success x OT / clip(AT, 2 OT, 8 OT); null without an optimal length."""
        return {"barn_score": barn_score(success, optimal_m, time_s, self.optimal_speed_mps)}

    def score_text(self) -> str:
        return (f"barn_score = success x OT / clip(AT, 2 OT, 8 OT), OT = optimal length / "
                f"{self.optimal_speed_mps:g} m/s")


def barn_score(success: bool, optimal_m: float | None, time_s: float | None,
               optimal_speed_mps: float = 2.0) -> float | None:
    """BARN's score: ``success * OT / clip(AT, 2 OT, 8 OT)``, ``OT = optimal_m / optimal_speed_mps``.

    In [0.125, 0.5] for a success (0.5 when AT <= 2 OT), 0 for a failure; None when the optimal
    length is unknown (no path on the true map)."""
    if optimal_m is None or not np.isfinite(optimal_m) or optimal_m <= 0:
        return None
    if not success or time_s is None:
        return 0.0
    ot = optimal_m / optimal_speed_mps
    return float(ot / min(max(time_s, 2 * ot), 8 * ot))


# name -> (class, settings a suite may set, each with its unit and meaning)
PROTOCOLS: dict[str, tuple[type[Protocol], dict[str, str]]] = {
    "nav_bench": (Protocol, {}),
    "barn": (BarnProtocol, {
        "goal_radius_m": "m, success radius (BARN: 1 m)",
        "time_limit_s": "s, simulated time limit (BARN: 100 s)",
        "optimal_speed_mps": "m/s, speed of the optimal time OT (BARN: 2 m/s, the Jackal's top speed)",
    }),
}
DEFAULT = "nav_bench"


def make_protocol(name: str, options: dict[str, Any] | None = None) -> Protocol:
    """The protocol ``name`` with ``options`` (its settings); :class:`InputError` names the
    allowed protocols or settings."""
    if name not in PROTOCOLS:
        raise InputError(f"unknown protocol {name!r}; allowed: {', '.join(PROTOCOLS)}")
    cls, allowed = PROTOCOLS[name]
    options = dict(options or {})
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        have = ", ".join(allowed) if allowed else "none"
        raise InputError(f"protocol {name!r} has no setting {unknown[0]!r}; its settings: {have}")
    for key, value in options.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(f"protocol {name!r}: {key} expects a number ({allowed[key]}), got {value!r}")
    return cls(**{k: float(v) for k, v in options.items()})


def protocol_of(settings: EpisodeSettings) -> Protocol:
    """The protocol an episode's settings name."""
    return make_protocol(settings.protocol, dict(settings.protocol_options))
