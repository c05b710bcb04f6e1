"""Protocols: BARN's score by hand, the endings each protocol gives the loop, refusal of unknown
names and settings (exit 2), a collision ending a BARN episode, the rules in run.json."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from nav_bench.batch.suite import describe, load_suite
from nav_bench.cli import main
from nav_bench.episode.ending import Collided, GoalReached, Stuck, TimeLimit
from nav_bench.episode.loop import run_episode
from nav_bench.episode.protocol import BarnProtocol, Protocol, barn_score, make_protocol, rules_text
from nav_bench.episode.settings import EpisodeSettings
from nav_bench.errors import InputError
from nav_bench.interface import Command, Observation, Outcome
from nav_bench.planners.base import Planner
from nav_bench.specs import PlannerSetSpec
from nav_bench.world.load import load_world

ROOT = Path(__file__).resolve().parents[2]
OPEN_ROOM = ROOT / "worlds" / "paper" / "open_room.yaml"


def test_barn_score_by_hand() -> None:
    # optimal 10 m -> OT = 5 s; AT is clipped to [10 s, 40 s]
    assert barn_score(True, 10.0, 12.0) == pytest.approx(5.0 / 12.0)
    assert barn_score(True, 10.0, 3.0) == pytest.approx(0.5)  # faster than 2 OT counts as 2 OT
    assert barn_score(True, 10.0, 100.0) == pytest.approx(0.125)  # slower than 8 OT: 8 OT
    assert barn_score(False, 10.0, 12.0) == 0.0
    assert barn_score(True, None, 12.0) is None
    assert barn_score(True, 10.0, 12.0, optimal_speed_mps=1.0) == pytest.approx(10.0 / 20.0)
    assert BarnProtocol().score(True, 10.0, 12.0) == {"barn_score": pytest.approx(5.0 / 12.0)}
    assert Protocol().score(True, 10.0, 12.0) == {}


def test_each_protocol_gives_its_own_endings() -> None:
    world = load_world(OPEN_ROOM)
    settings = EpisodeSettings(time_s=50.0)
    hits = [0]
    nav = Protocol().endings(settings, world, np.zeros(2), collisions=lambda: hits[0])
    assert [type(e) for e in nav] == [GoalReached, TimeLimit, Stuck]
    assert nav[0].tolerance == 0.3 and nav[1].limit_s == 50.0
    barn = BarnProtocol().endings(settings, world, np.zeros(2), collisions=lambda: hits[0])
    assert [type(e) for e in barn] == [Collided, GoalReached, TimeLimit]  # BARN has no stuck rule
    assert barn[1].tolerance == 1.0 and barn[2].limit_s == 100.0
    assert not barn[0](1.0, np.zeros(2))
    hits[0] = 1
    assert barn[0](1.0, np.zeros(2)) and barn[0].outcome is Outcome.COLLISION
    assert make_protocol("barn", {"time_limit_s": 200}).time_limit(settings, world) == 200.0


@pytest.mark.parametrize(("name", "options", "says"), [
    ("barm", {}, "allowed: nav_bench, barn"),
    ("barn", {"goal_tolerance": 2.0}, "its settings: goal_radius_m, time_limit_s, optimal_speed_mps"),
    ("nav_bench", {"time_limit_s": 10}, "its settings: none"),
    ("barn", {"time_limit_s": "long"}, "expects a number"),
    ("barn", {"time_limit_s": -1}, "must be > 0"),
])
def test_unknown_protocols_and_settings_are_refused(name: str, options: dict, says: str) -> None:
    with pytest.raises(InputError, match=says):
        make_protocol(name, options)


@pytest.mark.parametrize(("entry", "says"), [
    ("protocol: barm", "protocol: unknown protocol 'barm'; allowed: nav_bench, barn"),
    ("protocol: {name: barn, radius: 2}", "protocol.radius: protocol 'barn' has no setting 'radius'"),
    ("protocol: barn\nlimits: {time_s: 50}", "limits.time_s: protocol 'barn' sets this itself (100)"),
    ("protocol: [barn]", "expected a protocol name (nav_bench, barn)"),
])
def test_suite_validation_refuses_bad_protocols_with_exit_2(tmp_path, capsys, entry: str, says: str) -> None:
    suite = tmp_path / "s.yaml"
    suite.write_text(f"name: s\nworlds: [{OPEN_ROOM}]\nplanners: {{g: goal_seek}}\n{entry}\n")
    assert main(["validate", str(suite)]) == 2
    err = capsys.readouterr().err
    assert says in err and "s.yaml:" in err


def test_the_suite_protocol_reaches_the_settings_and_run_json(tmp_path) -> None:
    suite = tmp_path / "s.yaml"
    suite.write_text(f"name: s\nworlds: [{OPEN_ROOM}]\nplanners: {{g: goal_seek}}\n"
                     "protocol: {name: barn, optimal_speed_mps: 1.0}\n")
    loaded = load_suite(suite)
    assert loaded.settings["protocol"] == "barn"
    assert loaded.settings["protocol_options"] == {"optimal_speed_mps": 1.0}
    rules = json.loads(json.dumps(describe(loaded)))["protocol"]
    assert rules["name"] == "barn" and rules["goal_radius_m"] == 1.0 and rules["time_limit_s"] == 100.0
    assert rules["collision_ends"] is True and rules["stuck_ends"] is False
    assert "OT = optimal length / 1 m/s" in rules["score"]
    assert "success within 1 m of the goal before 100 s" in rules_text(rules)
    default = describe(load_suite(ROOT / "configs" / "suites" / "smoke.yaml"))["protocol"]
    assert default["name"] == "nav_bench" and default["goal_radius_m"] == 0.3


class Reverse(Planner):
    """Backs straight into the wall behind the start."""

    name = "reverse"

    def act(self, obs: Observation) -> Command:
        return Command(-0.3, 0.0)


def test_a_collision_ends_a_barn_episode_as_a_failure() -> None:
    world = load_world(OPEN_ROOM)
    barn = run_episode(world, PlannerSetSpec(planner="goal_seek"), seed=0, planner_instance=Reverse(),
                       settings=EpisodeSettings(protocol="barn"))
    row = barn.row
    assert row.outcome is Outcome.COLLISION and not row.success and row.collisions == 1
    assert row.barn_score == 0.0 and row.time_s < 20.0
    assert row.settings["protocol"] == "barn"
    nav = run_episode(world, PlannerSetSpec(planner="goal_seek"), seed=0, planner_instance=Reverse(),
                      settings=EpisodeSettings(time_s=40.0))
    # under nav_bench the same contact is counted and the episode goes on (until it is stuck)
    assert nav.row.outcome is Outcome.STUCK and nav.row.collisions >= 1 and nav.row.time_s > row.time_s
    assert nav.row.barn_score is None and "barn_score" not in nav.row.to_json()


def test_a_barn_success_is_within_one_metre_and_scored() -> None:
    world = load_world(OPEN_ROOM)
    row = run_episode(world, PlannerSetSpec(planner="goal_seek"), seed=0,
                      settings=EpisodeSettings(protocol="barn")).row
    assert row.success and 0.9 < row.goal_distance_m < 1.0  # ended as soon as it was within 1 m
    expected = barn_score(True, row.optimal_length_m, row.time_s)
    assert row.barn_score == pytest.approx(expected) and 0.125 <= row.barn_score <= 0.5


def test_episode_command_refuses_an_unknown_protocol_with_exit_2(capsys) -> None:
    assert main(["episode", str(OPEN_ROOM), "--planner", "goal_seek", "--protocol", "barx"]) == 2
    assert "allowed: nav_bench, barn" in capsys.readouterr().err
    assert main(["episode", str(OPEN_ROOM), "--protocol", "barn", "--time-limit", "5"]) == 2
