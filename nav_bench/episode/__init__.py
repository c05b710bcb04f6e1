"""One episode: the control loop, its endings, its observers, its trace and its result row.

* :mod:`~nav_bench.episode.loop` - :func:`run_episode` and the loop (sense -> plan -> act ->
  step); the only module here that imports the simulator.
* :mod:`~nav_bench.episode.ending` - goal reached, time limit, stuck: one object each.
* :mod:`~nav_bench.episode.observers` - who watches a cycle (trace recorder, GUI, live view).
* :mod:`~nav_bench.episode.trace` - the trace format, written and read only there.
* :mod:`~nav_bench.episode.row` - :class:`ResultRow`, built once from a trace.
* :mod:`~nav_bench.episode.settings` - rates, limits and tolerances.

This face imports no simulator (PyBullet prints a banner when imported): import
:func:`run_episode` from :mod:`nav_bench.episode.loop`.
"""

from nav_bench.episode.row import ResultRow
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.episode.trace import Trace, read_trace_positions, read_trace_world

__all__ = ["EpisodeSettings", "ResultRow", "Trace", "read_trace_positions", "read_trace_world"]
