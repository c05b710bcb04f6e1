"""Stored results as a pandas DataFrame: ``nav_bench.load_results(DIR)``."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from nav_bench.errors import InputError

# nested row fields spread into columns ``<field>.<key>`` (``params.RR``, ``settings.time_s``)
FLATTENED = ("params", "settings", "events")


def _flat(prefix: str, value: Any, out: dict[str, Any]) -> None:
    if isinstance(value, dict):
        for key, sub in value.items():
            _flat(f"{prefix}.{key}", sub, out)
    else:
        out[prefix] = value


def flatten_row(row: dict[str, Any]) -> dict[str, Any]:
    """The row with ``params``, ``settings`` and ``events`` spread into dotted columns."""
    out: dict[str, Any] = {}
    for key, value in row.items():
        if key in FLATTENED and isinstance(value, dict):
            _flat(key, value, out)
        else:
            out[key] = value
    return out


def load_results(dirs: str | Path | Sequence[str | Path]) -> Any:
    """The rows of one or more results folders as a :class:`pandas.DataFrame`.

    One row per episode with every field of the result row; ``params``, ``settings`` and
    ``events`` are flattened into columns (``params.RR``, ``settings.time_s``,
    ``events.replan``); ``run`` names the folder a row came from, ``set`` its label.
    Needs pandas (``pip install pandas``).
    """
    try:
        import pandas as pd
    except ImportError:
        raise InputError("load_results needs pandas, which is not installed: "
                         "pip install pandas") from None
    from nav_bench.reporting.runs import load_runs

    folders = [dirs] if isinstance(dirs, str | Path) else list(dirs)
    rows = [flatten_row(row) for run in load_runs([Path(d) for d in folders]) for row in run.rows]
    return pd.DataFrame(rows)
