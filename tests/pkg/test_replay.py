"""nav-bench replay, --record .mp4 through the [video] extra, run --record-failures."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from PIL import Image

from nav_bench.cli import main
from nav_bench.errors import InputError

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def trace(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("replay") / "t.npz"
    assert main(["episode", "paper/long_wall", "--planner", "goal_seek", "--time-limit", "12",
                 "--trace", str(path)]) == 0
    return path


def test_replay_writes_one_gif_frame_per_interval(trace, tmp_path, capsys):
    out = tmp_path / "out.gif"
    assert main(["replay", str(trace), "--record", str(out), "--every", "2"]) == 0
    assert "(7 frames)" in capsys.readouterr().out  # t = 0, 2, ..., 12 s
    with Image.open(out) as gif:
        assert gif.n_frames == 7


def test_mp4_without_ffmpeg_on_the_path(trace, tmp_path, monkeypatch):
    pytest.importorskip("imageio_ffmpeg")
    monkeypatch.setenv("PATH", "/nonexistent")
    out = tmp_path / "out.mp4"
    assert main(["replay", str(trace), "--record", str(out), "--every", "3"]) == 0
    assert out.read_bytes()[4:8] == b"ftyp"


def test_mp4_without_any_ffmpeg_says_which_extra(trace, tmp_path, monkeypatch):
    from nav_bench.reporting.live import LiveView
    from nav_bench.specs import WorldSpec

    monkeypatch.setenv("PATH", "/nonexistent")
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    world = WorldSpec.model_validate({"size": [4, 4], "start": [1, 1], "goal": [3, 3]})
    with pytest.raises(InputError, match=r'pip install "nav-bench\[video\]"'):
        LiveView(world, save=tmp_path / "x.mp4")


def test_run_record_failures_keeps_a_gif_beside_each_failed_trace(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    suite = tmp_path / "s.yaml"
    suite.write_text("worlds: [worlds/paper/open_room.yaml, worlds/paper/long_wall.yaml]\n"
                     "planners: {goal_seek: goal_seek}\nseeds: 1\nlimits: {time_s: 25}\n")
    assert main(["run", str(suite), "--workers", "1", "--quiet", "--no-report", "--out", "r",
                 "--record-failures"]) == 0
    rows = [json.loads(line) for line in (tmp_path / "r" / "episodes.jsonl").open()]
    failed = {r["world"] for r in rows if not r["success"]}
    gifs = sorted(p.name for p in (tmp_path / "r" / "traces").glob("*.gif"))
    assert failed == {"long_wall"}  # goal_seek reaches the open room's goal in 22.3 s
    assert len(gifs) == 1 and gifs[0].startswith("long_wall__goal_seek")
    assert "failures: 1 GIFs" in capsys.readouterr().out
