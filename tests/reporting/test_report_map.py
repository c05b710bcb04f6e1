"""The report's map-quality table and summary.csv columns, on the hand-made results folder
(tests/data/results/run_a) with map-quality fields added by hand to set alpha only (set beta
stands for a planner that keeps no grid)."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import pytest

from nav_bench.reporting.markdown import write_report

FIXTURE = Path(__file__).resolve().parents[1] / "data" / "results" / "run_a"


@pytest.fixture
def run_with_maps(tmp_path) -> Path:
    folder = tmp_path / "run_a"
    shutil.copytree(FIXTURE, folder)
    rows = [json.loads(line) for line in (folder / "episodes.jsonl").read_text().splitlines()]
    for row in rows:
        if row["label"] != "alpha":
            continue  # beta: no grid, the fields absent (as in rows stored before them)
        # precision 0.9 + seed / 100, recall 0.8, a phantom on the route in seeds 0 and 1
        phantom = 2 if row["seed"] < 2 else 0
        row.update(map_precision=0.9 + row["seed"] / 100, map_recall=0.8,
                   map_phantom_share=phantom / 100, map_observed_cells=1000,
                   map_occupied_cells=100, map_path_cells=100, map_phantom_cells=phantom)
    (folder / "episodes.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    return folder


def test_map_quality_per_world_and_set_in_report_and_summary(run_with_maps: Path) -> None:
    report = write_report([run_with_maps])
    with (run_with_maps / "summary.csv").open() as fh:
        summary = {(r["set"], r["world"]): r for r in csv.DictReader(fh)}
    room = summary[("alpha", "room")]  # seeds 0..4, the timeout included
    assert float(room["map_precision_mean"]) == pytest.approx(0.92)
    assert float(room["map_recall_mean"]) == pytest.approx(0.8)
    assert float(room["map_phantom_share_mean"]) == pytest.approx(0.008)
    assert (room["map_episodes"], room["map_phantom_episodes"]) == ("5", "2")
    assert summary[("alpha", "all")]["map_phantom_episodes"] == "4"
    beta = summary[("beta", "all")]
    assert (beta["map_episodes"], beta["map_precision_mean"]) == ("0", "")
    text = report.read_text()
    assert "## Map quality" in text
    assert "| room | alpha | 5 | 0.920 | 0.800 | 0.008 | 2 / 5 |" in text
    assert "| all | alpha | 10 | 0.920 | 0.800 | 0.008 | 4 / 10 |" in text
    assert "| room | beta |" not in text  # no grid: left out of the map table


def test_no_map_section_without_map_fields(tmp_path: Path) -> None:
    folder = tmp_path / "run_a"
    shutil.copytree(FIXTURE, folder)
    assert "## Map quality" not in write_report([folder]).read_text()
