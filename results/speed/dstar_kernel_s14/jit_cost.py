"""What the compiled search costs a fresh process before its first cycle: importing Numba and
the kernels, then loading them from the on-disk cache or compiling them (first calls), and the
same calls once compiled. Run it in a new process each time:

    NUMBA_CACHE_DIR=/tmp/empty python jit_cost.py    # an empty cache: compiles, then caches
    NUMBA_CACHE_DIR=/tmp/empty python jit_cost.py    # again: loads the cache
    python jit_cost.py                               # the default cache (nav_bench/planners/__pycache__)

Prints wall and CPU seconds of each step (CPU: process time, what a loaded machine does not
inflate).
"""

from __future__ import annotations

import time

T0 = time.perf_counter(), time.process_time()


def lap(what: str, since: tuple[float, float]) -> tuple[float, float]:
    now = time.perf_counter(), time.process_time()
    print(f"{what:44s} wall {now[0] - since[0]:7.3f} s   CPU {now[1] - since[1]:7.3f} s", flush=True)
    return now


def cycles() -> None:
    """A PathRepair's first plan, a cost change, a budgeted repair and a path: every kernel."""
    cost = np.ones((400, 400))
    repair = PathRepair(cost, (5, 5), (390, 390), budget=250, prefix=160, kernel="numba")
    rows, cols = np.arange(100, 300), np.full(200, 150)
    for k in range(20):
        repair.cycle((5 + k, 5 + k), rows, cols + k, np.full(200, np.inf))
    while not repair.complete:
        repair.cycle((25, 25))


import numpy as np  # noqa: E402

from nav_bench.planners.dstar_lite import PathRepair, load_kernels  # noqa: E402

t = lap("import numpy and nav_bench.planners.dstar_lite", T0)
assert load_kernels() is not None
t = lap("import numba and the kernels (load_kernels)", t)
cycles()
t = lap("first PathRepair run (cache load or compile)", t)
cycles()
t = lap("the same run again (compiled)", t)
lap("total", T0)
