# ruff: noqa  (measurement scripts: patch before import, terse)
"""pytest -p force_numpy: every SeeThroughCarving (and VFH+'s window reads) on the NumPy path."""
from nav_bench.planners import carving
carving.load_kernels = lambda: None
