"""Reports: numbers checked against a hand computation on a fixed results folder.

The folder tests/data/results/run_a is written by tests/data/results/make_fixture.py:
worlds room and hall, parameter sets alpha (eopc) and beta (goal_seek), seeds 0..4.
Runtime: ~5 s (figures).
"""

from __future__ import annotations

import csv
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

from nav_bench.batch.store import ResultsWarning
from nav_bench.errors import InputError
from nav_bench.reporting.markdown import write_report
from nav_bench.reporting.runs import load_runs
from nav_bench.reporting.statistics import (
    bootstrap_mean_interval,
    share_reached_within,
    wilson_interval,
)

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "results" / "run_a"


@pytest.mark.parametrize(("k", "n", "lo", "hi"), [
    # 95% Wilson score intervals as tabulated (Newcombe 1998; any statistics package)
    (8, 10, 0.4902, 0.9433),
    (5, 10, 0.2366, 0.7634),
    (0, 10, 0.0, 0.2775),
    (9, 10, 0.5958, 0.9821),
    (2, 10, 0.0567, 0.5098),
    (4, 5, 0.3755, 0.9638),
    (5, 5, 0.5655, 1.0),
])
def test_wilson_interval_known_values(k, n, lo, hi):
    assert wilson_interval(k, n) == pytest.approx((lo, hi), abs=1e-4)


def test_wilson_interval_of_nothing_is_everything():
    assert wilson_interval(0, 0) == (0.0, 1.0)


def test_bootstrap_interval_is_reproducible_and_sane():
    x = [0.0, 1.0, 1.0, 0.5, 0.8, 0.9, 0.0, 1.0]
    lo, hi = bootstrap_mean_interval(x)
    assert bootstrap_mean_interval(x) == (lo, hi)  # fixed seed
    assert lo < np.mean(x) < hi
    # the normal approximation is close for this n: mean +- 1.96 * sd / sqrt(n)
    half = 1.96 * np.std(x) / np.sqrt(len(x))
    assert (lo, hi) == pytest.approx((np.mean(x) - half, np.mean(x) + half), abs=0.06)
    assert bootstrap_mean_interval([0.7, 0.7, 0.7]) == (0.7, 0.7)
    assert all(np.isnan(bootstrap_mean_interval([])))


@pytest.fixture
def run_a(tmp_path) -> Path:
    folder = tmp_path / "run_a"
    shutil.copytree(FIXTURE, folder)
    return folder


def read_summary(folder: Path) -> dict[tuple[str, str], dict[str, str]]:
    with open(folder / "summary.csv", newline="") as f:
        return {(r["set"], r["world"]): r for r in csv.DictReader(f)}


def num(text: str) -> float:
    return float("nan") if text == "" else float(text)


# (set, world) -> hand-computed numbers; SPL of a reached episode = optimal / max(optimal, path)
EXPECTED = {
    ("alpha", "room"): dict(episodes=4 + 1, reached=4, timeout=1, stuck=0, error=0,
                            success_rate=0.8, success_lo=0.3755, success_hi=0.9638,
                            spl_mean=(1 + 5 / 5.5 + 5 / 6 + 5 / 6.5 + 0) / 5,
                            time_to_goal_s=(10 + 12 + 14 + 16) / 4,
                            path_length_m=(5.0 + 5.5 + 6.0 + 6.5) / 4,
                            replans_mean=3.0, collisions_mean=0.6, min_clearance_m=0.3),
    ("beta", "room"): dict(episodes=5, reached=2, timeout=1, stuck=1, error=1, success_rate=0.4,
                           success_lo=0.1176, success_hi=0.7693, spl_mean=0.4,
                           time_to_goal_s=10.0, path_length_m=5.0, replans_mean=0.0,
                           collisions_mean=0.25, min_clearance_m=(0.1 + 0.2 + 0.3 + 0.5) / 4),
    ("alpha", "hall"): dict(episodes=5, reached=5, success_rate=1.0, success_lo=0.5655,
                            success_hi=1.0, spl_mean=1.0, time_to_goal_s=20.0,
                            path_length_m=8.0),
    ("beta", "hall"): dict(episodes=5, reached=0, timeout=5, success_rate=0.0, success_lo=0.0,
                           success_hi=0.4345, spl_mean=0.0, time_to_goal_s=float("nan"),
                           path_length_m=float("nan")),
    ("alpha", "all"): dict(episodes=10, reached=9, timeout=1, success_rate=0.9,
                           success_lo=0.5958, success_hi=0.9821,
                           spl_mean=(1 + 5 / 5.5 + 5 / 6 + 5 / 6.5 + 5) / 10,
                           time_to_goal_s=(10 + 12 + 14 + 16 + 5 * 20) / 9,
                           path_length_m=(23.0 + 40.0) / 9, replans_mean=1.5),
    ("beta", "all"): dict(episodes=10, reached=2, timeout=6, stuck=1, error=1, success_rate=0.2,
                          success_lo=0.0567, success_hi=0.5098, spl_mean=0.2,
                          time_to_goal_s=10.0),
}


def test_report_numbers_match_a_hand_computation(run_a):
    report = write_report([run_a])
    assert report == run_a / "report.md"
    summary = read_summary(run_a)
    assert set(summary) == set(EXPECTED)
    for key, expected in EXPECTED.items():
        row = summary[key]
        for column, value in expected.items():
            assert num(row[column]) == pytest.approx(value, abs=1e-4, nan_ok=True), (key, column)
        assert num(row["spl_lo"]) <= num(row["spl_mean"]) <= num(row["spl_hi"])

    text = report.read_text()
    # ranking: success first (alpha 0.9 > beta 0.2)
    assert "| 1 | alpha | eopc | 10 | 0.90 [0.60, 0.98] |" in text
    assert "| 2 | beta | goal_seek | 10 | 0.20 [0.06, 0.51] |" in text
    # paired on (world, seed): dSPL per pair room 0, -0.0909, 0.8333, 0.7692, 0; hall 1 x5
    d_spl = (0 - (1 - 5 / 5.5) + 5 / 6 + 5 / 6.5 + 0 + 5) / 10
    assert f"| alpha | beta | 10 | {d_spl:+.3f} [" in text
    assert "| 2 | +0.25 [" in text  # path: both reached room s0 (0.0) and s1 (+0.5)
    assert "| 7 / 2 / 1 |" in text
    assert "RuntimeError: fixture error" in text  # the error episode is listed
    for name in ("success_spl.png", "success_vs_time.png", "trajectories_room.png",
                 "trajectories_hall.png"):
        path = run_a / "figures" / name
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert f"(figures/{name})" in text

    before = (run_a / "summary.csv").read_text()
    write_report([run_a])
    assert (run_a / "summary.csv").read_text() == before  # bootstrap intervals reproducible


def test_share_reached_within_a_time_budget(run_a):
    (run,) = load_runs([run_a])
    alpha = [r for r in run.rows if r["label"] == "alpha"]
    # reached at 10, 12, 14, 16 (room) and 20 x5 (hall), out of 10 episodes
    assert share_reached_within(alpha, np.array([0, 9.9, 10, 12, 19.9, 20, 60])) == \
        pytest.approx([0, 0, 0.1, 0.2, 0.4, 0.9, 0.9])


def test_two_runs_are_compared_with_labels_by_run(run_a, tmp_path):
    run_b = tmp_path / "run_b"
    shutil.copytree(run_a, run_b)
    report = write_report([run_a, run_b])
    assert report == run_a / "compare-run_b" / "report.md"
    summary = read_summary(report.parent)
    assert {s for s, _ in summary} == {"run_a/alpha", "run_a/beta", "run_b/alpha", "run_b/beta"}
    assert num(summary[("run_b/alpha", "all")]["success_rate"]) == pytest.approx(0.9)
    text = report.read_text()
    assert "| run_a/alpha | run_b/alpha | 10 | +0.000 [+0.000, +0.000] | 9 |" in text
    assert "| 0 / 10 / 0 |" in text


def test_a_torn_line_is_reported_and_skipped(run_a, tmp_path):
    with open(run_a / "episodes.jsonl", "ab") as f:
        f.write(b'{"job_id": "cut')
    with pytest.warns(ResultsWarning, match=r"episodes\.jsonl:21: incomplete last line"):
        report = write_report([run_a], out=tmp_path / "rep")
    assert num(read_summary(report.parent)[("alpha", "all")]["episodes"]) == 10


def test_report_without_traces_still_has_tables(run_a):
    shutil.rmtree(run_a / "traces")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        text = write_report([run_a]).read_text()
    assert "trajectories_" not in text and "| 1 | alpha |" in text


def test_report_refuses_folders_without_results(tmp_path):
    with pytest.raises(InputError, match="not a nav-bench results folder"):
        write_report([tmp_path])


def test_difficulty_thirds_from_measures_in_rows():
    from nav_bench.reporting.markdown import difficulty_table, world_difficulties

    # six worlds w0..w5 of growing tortuosity; set "a" reaches the goal in w0..w2 only
    rows = [{"world": f"w{i}", "set": s, "success": s == "b" or i < 3, "run": "r",
             "difficulty": {"tortuosity": 1.0 + i / 10, "closest_obstacle_m": 1.0}}
            for i in range(6) for s in ("a", "b") for _ in range(2)]
    measures = world_difficulties(rows, runs=[])
    assert measures["w4"] == {"tortuosity": 1.4, "closest_obstacle_m": 1.0}
    table = difficulty_table(rows, ["a", "b"], measures)
    tortuosity = [r for r in table if r[0] == "tortuosity"]
    assert [r[1:] for r in tortuosity] == [
        ["easiest", "1.00–1.10", 2, "1.00 (4)", "1.00 (4)"],
        ["middle", "1.20–1.30", 2, "0.50 (4)", "1.00 (4)"],
        ["hardest", "1.40–1.50", 2, "0.00 (4)", "1.00 (4)"]]
    assert {r[0] for r in table} == {"tortuosity", "closest_obstacle_m"}
