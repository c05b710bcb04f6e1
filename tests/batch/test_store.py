"""The results store: row schema, durable appends, torn last lines, atomic run.json."""

from __future__ import annotations

import json
import math

import pytest

from nav_bench.batch.store import ResultsStore, ResultsWarning
from nav_bench.episode.row import ROW_FIELDS, ResultRow, RowSchemaError, check_row
from nav_bench.errors import InputError


def good_row(job_id: str = "w__a__diffbot__s0__00000000", **changes) -> dict:
    row = {
        "job_id": job_id, "label": "a", "world": "w", "world_file": "worlds/w.yaml",
        "planner": "goal_seek", "params": {"v_max": 0.5}, "params_id": "abc", "robot": "diffbot",
        "robot_id": "def", "seed": 0, "success": True, "outcome": "reached", "time_s": 12.5,
        "path_length_m": 7.0, "optimal_length_m": 6.5, "spl": 6.5 / 7.0, "replans": 2,
        "collisions": 0, "min_clearance_m": 0.12, "wall_s": 0.4, "settings": {"time_s": 30.0},
        "error": None, "events": {"replan": 2},
    }
    row.update(changes)
    return row


def test_a_good_row_passes_and_covers_the_schema():
    check_row(good_row())
    assert set(good_row()) == set(ROW_FIELDS)
    check_row(good_row(time_s=12))  # a JSON integer is a number


def test_an_error_row_may_leave_measurements_null():
    check_row(good_row(success=False, outcome="error", error="Traceback ...", time_s=None,
                       path_length_m=None, replans=None, collisions=None, min_clearance_m=None,
                       spl=0.0))
    with pytest.raises(RowSchemaError, match="'time_s' should be float"):
        check_row(good_row(time_s=None))  # but a finished episode may not


@pytest.mark.parametrize(("changes", "words"), [
    ({"seed": True}, "'seed' should be int"),
    ({"replans": 1.5}, "'replans' should be int"),
    ({"success": 1}, "'success' should be bool"),
    ({"outcome": "crashed"}, "not one of reached, timeout, stuck, error"),
    ({"success": False}, "disagrees with outcome 'reached'"),
    ({"error": "boom"}, "error text must be present exactly when outcome is 'error'"),
    ({"spl": 1.2}, "outside [0, 1]"),
    ({"params": [1, 2]}, "'params' should be dict"),
])
def test_bad_rows_are_refused_with_the_reason(changes, words):
    with pytest.raises(RowSchemaError) as info:
        check_row(good_row(**changes))
    assert words in str(info.value)


def test_missing_fields_are_all_listed():
    row = good_row()
    del row["spl"], row["robot_id"]
    with pytest.raises(RowSchemaError, match="missing field 'robot_id'; missing field 'spl'"):
        check_row(row)


def test_rows_round_trip_as_strict_json(tmp_path):
    with ResultsStore(tmp_path) as store:
        store.append(ResultRow.from_json(good_row("a")))
        store.append(ResultRow.from_json(good_row("b", min_clearance_m=math.nan, optimal_length_m=math.inf)))
    lines = (tmp_path / "episodes.jsonl").read_text().splitlines()
    assert len(lines) == 2
    second = json.loads(lines[1], parse_constant=lambda c: pytest.fail(f"non-JSON {c}"))
    assert second["min_clearance_m"] is None and second["optimal_length_m"] is None
    rows = ResultsStore(tmp_path).rows()
    assert [r["job_id"] for r in rows] == ["a", "b"]
    assert rows[0] == {**good_row("a"), "trace": None}  # a stored row always names its trace
    assert ResultsStore(tmp_path).done_ids() == {"a", "b"}


@pytest.mark.parametrize("tail", [b'{"job_id": "c", "wor', b'{"job_id": "c"}'])
def test_a_torn_last_line_is_reported_skipped_and_repaired(tmp_path, tail):
    store = ResultsStore(tmp_path)
    with store:
        store.append(ResultRow.from_json(good_row("a")))
        store.append(ResultRow.from_json(good_row("b")))
    path = tmp_path / "episodes.jsonl"
    with open(path, "ab") as f:
        f.write(tail)  # a crash cut this line before its newline
    with pytest.warns(ResultsWarning, match=r"episodes\.jsonl:3: incomplete last line"):
        assert [r["job_id"] for r in store.rows()] == ["a", "b"]
    with pytest.warns(ResultsWarning, match=r"episodes\.jsonl:3: .*removed"):
        assert store.repair() == 3
    assert path.read_bytes().endswith(b"\n") and len(path.read_bytes().splitlines()) == 2
    assert store.repair() is None
    with store:
        store.append(ResultRow.from_json(good_row("c")))
    assert [r["job_id"] for r in store.rows()] == ["a", "b", "c"]


def test_damage_before_the_last_line_is_an_error(tmp_path):
    path = tmp_path / "episodes.jsonl"
    path.write_text(json.dumps(good_row("a")) + "\nnot json\n" + json.dumps(good_row("b")) + "\n")
    with pytest.raises(InputError, match=r"episodes\.jsonl:2: not a JSON row"):
        ResultsStore(tmp_path).rows()


def test_duplicate_rows_keep_the_first_with_a_warning(tmp_path):
    store = ResultsStore(tmp_path)
    with store:
        store.append(ResultRow.from_json(good_row("a", seed=1)))
        store.append(ResultRow.from_json(good_row("a", seed=2)))
    with pytest.warns(ResultsWarning, match=r"episodes\.jsonl:2: second row for job 'a'"):
        rows = store.rows()
    assert [r["seed"] for r in rows] == [1]


def test_empty_and_missing_files_have_no_rows(tmp_path):
    assert ResultsStore(tmp_path / "none").rows() == []
    (tmp_path / "episodes.jsonl").write_bytes(b"")
    assert ResultsStore(tmp_path).rows() == []


def test_run_json_is_replaced_atomically(tmp_path):
    store = ResultsStore(tmp_path)
    with pytest.raises(InputError, match="not a nav-bench results folder"):
        store.read_run()
    store.write_run({"status": "running", "x": math.nan})
    store.write_run({"status": "complete"})
    assert store.read_run() == {"status": "complete"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.json"]  # no temp files left
    assert (tmp_path / "run.json").stat().st_mode & 0o644 == 0o644
