"""Compile cost of the Numba kernels, in CPU seconds per module: each module's warm-up (which
calls every kernel once) on a fresh copy of the package, run twice: cold, then with the cache.

    mkdir DIR && git archive HEAD nav_bench | tar -x -C DIR
    PYTHONPATH=DIR python results/speed/planning_s15/cold_compile.py   # cold
    PYTHONPATH=DIR python results/speed/planning_s15/cold_compile.py   # warm
"""

import time

START = time.process_time()

import numba  # noqa: E402, F401  (its import, timed apart)

IMPORTED = time.process_time()

from nav_bench.mapping import occupancy  # noqa: E402
from nav_bench.planners import carving, dstar_lite, vfh_plus  # noqa: E402

WARM_UPS = [("D* Lite search", dstar_lite._load_compiled_code),
            ("sonar map", occupancy._load_compiled_code),
            ("carving + clearance", carving._load_compiled_code),
            ("VFH+ window", vfh_plus._load_compiled_code)]

print(f"import numba {IMPORTED - START:.2f} s CPU")
for name, warm_up in WARM_UPS:
    t0 = time.process_time()
    warm_up()
    print(f"{name}: {time.process_time() - t0:.2f} s CPU")
print(f"total {time.process_time() - START:.2f} s CPU")
