# ruff: noqa  (measurement scripts: patch before import, terse)
"""CPU of the kernels warm-up in a fresh process (cache present, or NUMBA_CACHE_DIR empty: cold)."""
import time
t0 = time.process_time()
import numpy as np
from nav_bench.planners import carving, vfh_plus
t1 = time.process_time()
carving._load_compiled_code()
t2 = time.process_time()
vfh_plus._load_compiled_code()
t3 = time.process_time()
print(f"import {t1-t0:.2f} s, carving+clearance warm-up {t2-t1:.2f} s, VFH+ window warm-up {t3-t2:.2f} s (CPU)")
