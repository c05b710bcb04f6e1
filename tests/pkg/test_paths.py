"""Shipped files by name, user files first, the wheel's data folder (nav_bench.paths)."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_bench import paths
from nav_bench.cli import main
from nav_bench.errors import InputError
from nav_bench.planners.registry import parse_planner_arg

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def elsewhere(tmp_path, monkeypatch):
    """An empty working folder, as after `pip install` from anywhere."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("NAV_BENCH_HOME", raising=False)
    return tmp_path


def test_the_source_checkout_is_the_data_root():
    assert paths.data_root() == ROOT
    assert all((paths.data_root() / f).is_dir() for f in paths.DATA_FOLDERS)


@pytest.mark.parametrize(("kind", "text", "rel"), [
    ("suite", "smoke", "configs/suites/smoke.yaml"),
    ("suite", "configs/suites/smoke.yaml", "configs/suites/smoke.yaml"),
    ("world", "paper/long_wall", "worlds/paper/long_wall.yaml"),
    ("world", "paper/long_wall.yaml", "worlds/paper/long_wall.yaml"),
    ("world", "open_room", "worlds/paper/open_room.yaml"),  # a unique stem
    ("world", "imported/turtlebot3_world", "worlds/imported/turtlebot3_world.yaml"),
    ("planner set", "eopc_paper", "configs/planners/eopc_paper.yaml"),
    ("robot", "diffbot8", "robots/diffbot8.yaml"),
])
def test_names_resolve_from_any_folder(elsewhere, kind, text, rel):
    found = paths.find(kind, text)
    assert found.path == (ROOT / rel).resolve()
    assert found.given == rel  # rows record it as in a checkout, wherever nav-bench is installed


def test_a_users_file_comes_before_a_shipped_one(elsewhere):
    mine = elsewhere / "configs" / "suites" / "smoke.yaml"
    mine.parent.mkdir(parents=True)
    mine.write_text("name: mine\n")
    assert paths.find("suite", "smoke").path == mine.resolve()
    local = elsewhere / "smoke.yaml"
    local.write_text("name: local\n")
    assert paths.find("suite", "smoke.yaml") == paths.Found(local.resolve(), "smoke.yaml")
    assert paths.shipped("suite")["smoke"] == mine  # listed as the one that will be used


def test_nav_bench_home_comes_before_the_working_folder(elsewhere, tmp_path_factory, monkeypatch):
    home = tmp_path_factory.mktemp("home")
    (home / "worlds").mkdir()
    (home / "worlds" / "open_room.yaml").write_text("size: [4, 4]\nstart: [1, 1]\ngoal: [3, 3]\n")
    monkeypatch.setenv("NAV_BENCH_HOME", str(home))
    assert paths.find("world", "open_room").path == (home / "worlds" / "open_room.yaml").resolve()


def test_unknown_and_ambiguous_names_are_bad_input(elsewhere):
    with pytest.raises(InputError, match="Did you mean 'smoke'"):
        paths.find("suite", "smok")
    (elsewhere / "worlds" / "a").mkdir(parents=True)
    (elsewhere / "worlds" / "a" / "open_room.yaml").write_text("x: 1\n")
    with pytest.raises(InputError, match="ambiguous: a/open_room, paper/open_room"):
        paths.find("world", "open_room")


def test_a_planner_set_by_name_and_with_overrides(elsewhere):
    spec = parse_planner_arg("eopc_normalized")
    assert spec.planner == "eopc" and spec.params["normalize"] is True
    spec = parse_planner_arg("eopc_normalized:RR=0.4")
    assert spec.params["RR"] == 0.4 and spec.params["normalize"] is True
    assert parse_planner_arg("bug2").params == {}  # a registered planner name wins
    with pytest.raises(InputError, match="Did you mean 'eopc_paper'"):
        parse_planner_arg("eopc_papr")


def test_list_names_every_kind(elsewhere, capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in ("smoke", "default", "paper/long_wall", "imported/lse_arena", "eopc_paper",
                 "diffbot8"):
        assert f"  {name} " in out
    assert main(["list", "sets"]) == 0
    out = capsys.readouterr().out
    assert "eopc_paper" in out and "paper/long_wall" not in out


@pytest.mark.slow
def test_episode_by_names_from_an_empty_folder(elsewhere, capsys):
    import json

    code = main(["episode", "paper/open_room", "--planner", "goal_seek", "--robot", "diffbot",
                 "--json"])
    assert code == 0
    row = json.loads(capsys.readouterr().out)
    assert row["world_file"] == "worlds/paper/open_room.yaml"
    assert row["outcome"] == "reached"
