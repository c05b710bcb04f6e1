"""nav_bench.load_results: stored rows as a DataFrame, nested fields flattened."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import nav_bench
from nav_bench.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
RUN = ROOT / "results" / "paper" / "default_suite"


def test_rows_with_params_and_settings_as_columns():
    pytest.importorskip("pandas")
    df = nav_bench.load_results(RUN)
    assert len(df) == 280
    assert {"world", "planner", "spl", "params.RR", "params.normalize", "settings.time_s",
            "run"} <= set(df.columns)
    assert "params" not in df.columns and "settings" not in df.columns
    eopc = df[df["label"] == "eopc_normalized"]
    assert len(eopc) == 35 and eopc["params.normalize"].eq(True).all()
    assert df["settings.time_s"].eq(300).all()
    # the README's default-suite table: eopc_paper reached 33 of 35
    assert int(df[df["label"] == "eopc_paper"]["success"].sum()) == 33


def test_several_folders_are_one_frame():
    pytest.importorskip("pandas")
    df = nav_bench.load_results([RUN, ROOT / "tests" / "data" / "results" / "run_a"])
    assert len(df) == 280 + 20
    assert df["run"].nunique() == 2


def test_a_clear_message_without_pandas(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now raises ImportError
    with pytest.raises(InputError, match="pip install pandas"):
        nav_bench.load_results(RUN)
