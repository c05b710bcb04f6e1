"""The report's motion columns, BARN score and success-vs-smoothness figure, on the hand-made
results folder (tests/data/results/run_a) with motion fields added by hand."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import pytest

from nav_bench.episode.motion import MOTION_FIELDS
from nav_bench.reporting.markdown import write_report

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "results" / "run_a"


@pytest.fixture
def run_with_motion(tmp_path) -> Path:
    folder = tmp_path / "run_a"
    shutil.copytree(FIXTURE, folder)
    rows = [json.loads(line) for line in (folder / "episodes.jsonl").read_text().splitlines()]
    for row in rows:
        if row["outcome"] == "error":
            continue
        # every motion field = seed + 1 (alpha) or 10 x (seed + 1) (beta); barn_score = success / 4
        scale = 1.0 if row["label"] == "alpha" else 10.0
        row.update({k: scale * (row["seed"] + 1) for k in MOTION_FIELDS})
        row["barn_score"] = 0.25 if row["success"] else 0.0
    (folder / "episodes.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    meta = json.loads((folder / "run.json").read_text())
    meta.setdefault("suite", {})["protocol"] = {
        "name": "barn", "goal_radius_m": 1.0, "time_limit_s": 100.0, "collision_ends": True,
        "stuck_ends": False, "optimal_speed_mps": 2.0, "score": "barn_score = ..."}
    (folder / "run.json").write_text(json.dumps(meta))
    return folder


def test_motion_means_over_reached_episodes_and_barn_score(run_with_motion: Path) -> None:
    report = write_report([run_with_motion])
    with (run_with_motion / "summary.csv").open() as fh:
        summary = {(r["set"], r["world"]): r for r in csv.DictReader(fh)}
    # alpha reached: room seeds 0..3 and hall seeds 0..4 -> values 1..4 and 1..5
    alpha = summary[("alpha", "all")]
    for k in MOTION_FIELDS:
        assert float(alpha[k]) == pytest.approx((1 + 2 + 3 + 4 + 1 + 2 + 3 + 4 + 5) / 9)
    # beta reached only room seeds 0 and 1 -> 10 and 20; the error row has no barn_score
    beta = summary[("beta", "all")]
    assert float(beta["jerk_linear"]) == pytest.approx(15.0)
    assert float(beta["barn_score_mean"]) == pytest.approx(0.25 * 2 / 9)
    assert float(summary[("alpha", "hall")]["barn_score_mean"]) == pytest.approx(0.25)
    assert summary[("beta", "hall")]["jerk_linear"] == ""  # no success there
    text = report.read_text()
    assert "## Motion" in text and "| BARN score |" in text
    assert "Rules: protocol `barn`: success within 1 m of the goal before 100 s" in text
    assert "| alpha | 9 | 2.778 |" in text  # reached, mean |a| = 25 / 9 with three digits
    assert (run_with_motion / "figures" / "success_vs_smoothness.png").stat().st_size > 10_000


def test_rows_without_motion_fields_give_no_motion_section(tmp_path) -> None:
    folder = tmp_path / "run_a"
    shutil.copytree(FIXTURE, folder)
    text = write_report([folder]).read_text()
    assert "## Motion" not in text and "BARN score" not in text
    assert not (folder / "figures" / "success_vs_smoothness.png").exists()


def test_error_bars_are_never_negative_at_a_success_rate_of_one() -> None:
    # the default suite's report failed on this: Wilson's upper end at 10/10 is 1 - 1e-16
    from nav_bench.reporting.figures import error_bar
    from nav_bench.reporting.statistics import wilson_interval

    assert error_bar(1.0, (0.5, 1.0 - 1e-16)) == (0.5, 0.0)
    assert error_bar(0.0, (1e-17, 0.3)) == (0.0, 0.3)
    assert error_bar(0.4, (float("nan"), 0.6)) == (0.0, pytest.approx(0.2))
    for n in range(1, 60):
        for k in (0, n):
            below, above = error_bar(k / n, wilson_interval(k, n))
            assert below >= 0.0 and above >= 0.0
