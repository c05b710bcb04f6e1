"""Re-render a stored episode (a trace ``.npz``) as an animation: ``nav-bench replay``.

The frames are those of the live view (:class:`~nav_bench.reporting.live.LiveView`): the true
map, the trajectory so far, the robot and the latest re-plan's neighbours. A trace keeps the
planner's grids only as they were at the end, so they appear on the last frame alone.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from nav_bench.episode import Trace
from nav_bench.reporting.live import LiveView


def replay(trace_path: str | Path, out: str | Path, *, every_s: float = 0.5,
           fps: float | None = None) -> int:
    """Write ``out`` (.gif or .mp4) from the trace at ``trace_path``; returns the frame count.

    ``every_s``: simulated seconds between frames; ``fps``: playback rate (default real time).
    """
    trace = Trace.load(trace_path)
    by_t: dict[int, list[dict[str, Any]]] = {}
    for event in trace.events:  # events go with the first cycle at or after their time
        by_t.setdefault(round(float(event["t"]) * 1e6), []).append(event)
    pending = sorted(by_t.items())
    last = len(trace.t) - 1
    with LiveView(trace.world, every_s=every_s, save=out, fps=fps) as view:
        for i, t in enumerate(trace.t):
            events: list[dict[str, Any]] = []
            while pending and pending[0][0] <= round(float(t) * 1e6):
                events += pending.pop(0)[1]
            view.update(float(t), trace.true_pose[i], trace.planner_state if i == last else {},
                        events)
        frames = view.frames_drawn
    return frames


def record_failures(rows: Iterable[dict[str, Any]], folder: str | Path, *,
                    every_s: float = 1.0) -> list[Path]:
    """A GIF beside the trace of every row that did not succeed (``run --record-failures``)."""
    written = []
    for row in rows:
        trace = row.get("trace")
        if row.get("success") or not trace:
            continue
        path = Path(folder) / trace
        if path.is_file():
            gif = path.with_suffix(".gif")
            replay(path, gif, every_s=every_s, fps=10.0)
            written.append(gif)
    return written
