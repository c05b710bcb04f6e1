"""nav-bench: a PyBullet benchmark for navigation in a-priori unknown indoor environments."""

from __future__ import annotations

from typing import Any

__version__ = "0.1.0"


def load_results(dirs: Any) -> Any:
    """The rows of results folder(s) as a pandas DataFrame, params and settings flattened into
    columns (see :func:`nav_bench.reporting.frame.load_results`)."""
    from nav_bench.reporting.frame import load_results as _load

    return _load(dirs)
