"""The stuck rule (a still robot and an oscillating one), why a robot was stuck, and cpu_s."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.ending import AREA_WINDOW, SlidingBox, Stuck, classify_stuck
from nav_bench.episode.loop import run_episode
from nav_bench.episode.row import ResultRow, row_problems
from nav_bench.interface import Command, Outcome, StuckReason
from nav_bench.planners.base import Planner
from nav_bench.specs import PlannerSetSpec
from nav_bench.world.load import load_world

ROOT = Path(__file__).resolve().parents[2]
OPEN_ROOM = ROOT / "worlds" / "paper" / "open_room.yaml"
DT = 0.1  # s, the default control cycle


def first_stuck_time(xy: np.ndarray, stuck: Stuck) -> float | None:
    """Play (T, 2) positions, one per control cycle from t = 0: when ``stuck`` fires (s)."""
    for i, p in enumerate(xy):
        t = round(i * DT, 9)
        if stuck(t, p):
            return t
    return None


def times(seconds: float) -> np.ndarray:
    return np.arange(round(seconds / DT) + 1) * DT


def test_a_robot_that_stands_still_is_stuck_after_stuck_s():
    xy = np.tile([[5.0, 5.0]], (400, 1))
    stuck = Stuck(30.0, 0.2, xy[0], area_radius=0.6)
    assert first_stuck_time(xy, stuck) == pytest.approx(30.0)
    assert stuck.fired == "radius"


def test_a_robot_rocking_back_and_forth_half_a_metre_is_stuck_after_three_stuck_s():
    t = times(300.0)
    # 0.5 m strokes at 0.25 m/s: it leaves the 0.2 m circle every few seconds, so the radius
    # rule alone never ends it (before the area rule it played to the time limit)
    x = 5.0 + 0.25 * np.sin(2 * np.pi * t / 6.3)
    xy = np.column_stack([x, np.full_like(x, 5.0)])
    assert first_stuck_time(xy, Stuck(30.0, 0.2, xy[0], area_radius=None)) is None
    stuck = Stuck(30.0, 0.2, xy[0], area_radius=0.6)
    assert first_stuck_time(xy, stuck) == pytest.approx(AREA_WINDOW * 30.0)
    assert stuck.fired == "area"


def test_a_robot_circling_a_small_area_is_stuck_once_the_window_is_full():
    t = times(300.0)
    # drives 20 s straight (1 m), then circles with radius 0.4 m (box half-diagonal 0.566 m)
    straight = np.column_stack([1.0 + 0.05 * t[t <= 20.0], np.full((t <= 20.0).sum(), 5.0)])
    tc = t[t > 20.0] - 20.0
    circle = np.column_stack([2.4 - 0.4 * np.cos(tc), 5.0 + 0.4 * np.sin(tc)])
    xy = np.vstack([straight, circle])
    stuck = Stuck(30.0, 0.2, xy[0], area_radius=0.6)
    # the last 90 s hold no straight part from t = 20 + 90 s on; a little earlier the start of
    # the window is still on the straight, within 0.6 m of the circle's box only from ~110 s
    fired = first_stuck_time(xy, stuck)
    assert fired is not None and 90.0 < fired <= 110.0 + 1e-9
    assert stuck.fired == "area"


def test_a_robot_that_progresses_slowly_is_never_stuck():
    t = times(300.0)
    # 2 cm/s in a straight line: 0.2 m every 10 s and 1.8 m per 90 s window
    xy = np.column_stack([1.0 + 0.02 * t, np.full_like(t, 5.0)])
    assert first_stuck_time(xy, Stuck(30.0, 0.2, xy[0], area_radius=0.6)) is None


def test_a_robot_wandering_a_wide_loop_is_never_stuck():
    t = times(300.0)
    # EO/PC-like chains: back and forth over 3 m for minutes is motion the rule leaves alone
    x = 3.0 + 1.5 * np.sin(2 * np.pi * t / 40.0)
    xy = np.column_stack([x, 5.0 + 0.3 * np.cos(2 * np.pi * t / 17.0)])
    assert first_stuck_time(xy, Stuck(30.0, 0.2, xy[0], area_radius=0.6)) is None


def test_the_sliding_box_is_the_brute_force_box_of_the_window():
    rng = np.random.default_rng(7)
    xy = np.cumsum(rng.normal(0.0, 0.05, size=(600, 2)), axis=0)
    box = SlidingBox(window_s=12.0)
    n = round(12.0 / DT) + 1
    for i, (x, y) in enumerate(xy):
        half = box.add(round(i * DT, 9), float(x), float(y))
        if i < n - 1:
            assert half is None
            continue
        w = xy[i - n + 1:i + 1]
        assert half == pytest.approx(0.5 * np.hypot(*(w.max(0) - w.min(0))), abs=1e-12)


def synthetic(v_cmd: float, w_cmd: float, v_true: float, w_true: float, seconds: float = 30.0):
    """A (t, true_pose, cmd) trace driven with constant commands and constant true motion."""
    t = times(seconds)
    yaw = w_true * t
    if w_true:
        x, y = v_true / w_true * np.sin(yaw), v_true / w_true * (1 - np.cos(yaw))
    else:
        x, y = v_true * t, np.zeros_like(t)
    cmd = np.tile([v_cmd, w_cmd], (len(t), 1))
    return t, np.column_stack([x, y, yaw]), cmd


def test_stuck_reasons_classified_from_the_commands_and_the_true_motion():
    assert classify_stuck(*synthetic(0.0, 0.0, 0.0, 0.0), 30.0) is StuckReason.STOPPED
    # full speed into a wall: 9 m commanded, the body stays put
    assert classify_stuck(*synthetic(0.3, 0.0, 0.0, 0.0), 30.0) is StuckReason.PINNED
    # turning in place against an obstacle that holds the body: commanded turn, none achieved
    assert classify_stuck(*synthetic(0.0, 1.0, 0.0, 0.0), 30.0) is StuckReason.PINNED
    # it moves as commanded, round and round a small circle
    assert classify_stuck(*synthetic(0.1, 0.5, 0.1, 0.5), 30.0) is StuckReason.OSCILLATING


def test_only_the_window_is_classified():
    t, pose, cmd = synthetic(0.3, 0.0, 0.0, 0.0, seconds=60.0)
    cmd[times(60.0) > 25.0] = 0.0  # pinned for 25 s, then it gave up: the last 30 s are stopped
    assert classify_stuck(t, pose, cmd, 30.0) is StuckReason.STOPPED
    assert classify_stuck(t, pose, cmd, 50.0) is StuckReason.PINNED


class Idle(Planner):
    """Commands nothing; says ``reason`` when asked why it is stuck."""

    name = "idle"

    def __init__(self, reason: StuckReason | None = None) -> None:
        super().__init__()
        self.reason = reason

    def act(self, obs):
        return Command(0.0, 0.0)

    def stuck_reason(self):
        return self.reason


class Rocking(Planner):
    """Drives 0.5 m forward and back, for ever."""

    name = "rocking"

    def act(self, obs):
        return Command(0.25 if (obs.t // 2.0) % 2 == 0 else -0.25, 0.0)


@pytest.fixture(scope="module")
def open_room():
    return load_world(OPEN_ROOM)


def play(world, planner: Planner, **settings):
    return run_episode(world, PlannerSetSpec(planner="goal_seek"), seed=0, planner_instance=planner,
                       settings=EpisodeSettings(**settings))


def test_the_row_takes_the_planners_stuck_reason(open_room):
    result = play(open_room, Idle(StuckReason.NO_PATH), time_s=20.0, stuck_s=2.0)
    assert result.row.outcome is Outcome.STUCK
    assert result.row.stuck_reason is StuckReason.NO_PATH
    assert result.row.to_json()["stuck_reason"] == "no_path"
    row = result.row
    row.job_id, row.label, row.world_file, row.trace = "j", "idle", "open_room.yaml", "t.npz"
    assert ResultRow.from_json(row.to_json()).stuck_reason is StuckReason.NO_PATH  # as stored


def test_without_one_the_episode_classifies_it(open_room):
    result = play(open_room, Idle(), time_s=20.0, stuck_s=2.0)
    assert result.row.outcome is Outcome.STUCK and result.row.stuck_reason is StuckReason.STOPPED


@pytest.mark.slow
def test_a_rocking_robot_ends_stuck_as_oscillating(open_room):
    # 4 s stuck window: the area rule judges 12 s of positions (0.5 m strokes, 0.6 m disc)
    result = play(open_room, Rocking(), time_s=60.0, stuck_s=4.0)
    assert result.row.outcome is Outcome.STUCK
    assert result.row.time_s == pytest.approx(AREA_WINDOW * 4.0, abs=0.11)
    assert result.row.stuck_reason is StuckReason.OSCILLATING


def test_rows_carry_cpu_s_and_no_stuck_reason_unless_stuck(open_room):
    result = play(open_room, Idle(), time_s=1.0)
    result.row.job_id, result.row.label, result.row.world_file = "j", "idle", "open_room.yaml"
    row = result.row.to_json()
    assert row["outcome"] == "timeout" and "stuck_reason" not in row
    assert row["cpu_s"] > 0.0
    assert row_problems(row) == []
    assert row_problems({**row, "stuck_reason": "bored"}) == [
        "stuck_reason 'bored' is not one of pinned, oscillating, no_path, waiting, stopped"]
