"""Episode pictures from a gate's stored traces (the plot ``nav-bench episode --plot`` draws,
without playing the episode again).

    python plot_traces.py OUT_DIR SUFFIX TRACE.npz [TRACE.npz ...]

Writes ``OUT_DIR/<world>_s<seed>_<SUFFIX>.png`` for each trace.
"""

from __future__ import annotations

import sys
from pathlib import Path

from nav_bench.episode.trace import Trace
from nav_bench.reporting.episode_plot import plot_episode

out, suffix = Path(sys.argv[1]), sys.argv[2]
for name in sys.argv[3:]:
    world, _planner, _robot, seed = Path(name).name.split("__")[:4]
    print(plot_episode(Trace.load(name), out / f"bug2_{world}_{seed}_{suffix}.png"))
