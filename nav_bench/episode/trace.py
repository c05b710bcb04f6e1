"""The trace format: what an episode records every control cycle, written and read only here.

A trace is one compressed ``.npz``: float arrays per cycle (``t``, ``true_pose``, ``odom_pose``,
``cmd``, ``ranges``, ``movers``), the planner's final state (its arrays as ``state__<key>``) and
a JSON ``meta`` member with the world, the planner events, the rest of the state and the row.
:class:`TraceRecorder` keeps the arrays while an episode runs; reports read stored traces with
:meth:`Trace.load`, :func:`read_trace_world` and :func:`read_trace_positions`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from nav_bench.specs import WorldSpec

if TYPE_CHECKING:
    from nav_bench.episode.observers import Cycle

ARRAYS = ("t", "true_pose", "odom_pose", "cmd", "ranges", "movers")


@dataclass
class Trace:
    """Per-cycle record of an episode. T cycles, K sonars, M movers.

    Attributes:
        t: (T,) simulated time, s. true_pose, odom_pose: (T, 3) x, y, yaw (m, m, rad).
        cmd: (T, 2) commanded v (m/s), omega (rad/s). ranges: (T, K) sonar readings, m.
        movers: (T, M, 2) mover positions, m. events: planner events as dicts {kind, t, data}.
        planner_state: the planner's final ``debug_state()``. world: the world played.
        row: the result row as stored (:meth:`nav_bench.episode.row.ResultRow.to_json`).
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
                  for k in ARRAYS}
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
                       **{k: data[k] for k in ARRAYS},
                       events=meta["events"], planner_state=state, row=meta["row"])


def read_trace_world(path: str | Path) -> WorldSpec:
    """Only the world of a stored trace (npz members load lazily: no arrays are read)."""
    with np.load(path, allow_pickle=False) as data:
        return WorldSpec.model_validate(json.loads(str(data["meta"]))["world"])


def read_trace_positions(path: str | Path) -> np.ndarray:
    """Only the (T, 2) true positions (m) of a stored trace."""
    with np.load(path, allow_pickle=False) as data:
        return np.asarray(data["true_pose"], dtype=float)[:, :2]


class TraceRecorder:
    """An episode observer that keeps the per-cycle arrays; :meth:`finish` makes the trace."""

    def __init__(self, world: WorldSpec) -> None:
        self.world = world
        self._rec: dict[str, list[Any]] = {k: [] for k in ARRAYS}

    def on_cycle(self, cycle: Cycle) -> None:
        rec = self._rec
        rec["t"].append(cycle.t)
        rec["true_pose"].append(cycle.true_pose)
        rec["odom_pose"].append(cycle.obs.pose)
        rec["cmd"].append((cycle.cmd.v, cycle.cmd.omega))
        rec["ranges"].append(cycle.obs.ranges)
        rec["movers"].append(cycle.sim.mover_positions())

    def close(self) -> None:
        pass

    def finish(self, t: float, true_pose: np.ndarray, odom_pose: np.ndarray,
               events: list[dict[str, Any]], planner_state: dict[str, Any]) -> Trace:
        """The trace, ending with the final pose (so lengths and plots end where the robot
        stopped): a last cycle at ``t`` with a zero command and the last readings."""
        rec = self._rec
        rec["t"].append(t)
        rec["true_pose"].append(true_pose)
        rec["odom_pose"].append(odom_pose)
        rec["cmd"].append((0.0, 0.0))
        rec["ranges"].append(rec["ranges"][-1] if rec["ranges"] else np.zeros(0))
        movers = len(self.world.movers)
        rec["movers"].append(rec["movers"][-1] if rec["movers"] else np.zeros((movers, 2)))
        arrays = {k: np.asarray(v, dtype=float) for k, v in rec.items()}
        arrays["movers"] = arrays["movers"].reshape(len(rec["movers"]), movers, 2)
        return Trace(world=self.world, events=events, planner_state=planner_state, **arrays)


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)
