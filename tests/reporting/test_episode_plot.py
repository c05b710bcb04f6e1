"""Episode figures (nav_bench.reporting.episode_plot) from a duck-typed trace."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from PIL import Image

from nav_bench.interface import Observation, ReplanEvent, RobotInfo, SonarInfo
from nav_bench.planners.base import Planner
from nav_bench.planners.eopc import EOPC
from nav_bench.planners.goal_seek import GoalSeek
from nav_bench.reporting.episode_plot import (
    chain_vertices,
    episode_title,
    label_step,
    plot_episode,
    replans,
)
from nav_bench.specs import WorldSpec

WORLD = WorldSpec(name="wall", size=(8.0, 6.0), start=[1.0, 3.0, 0.0], goal=(7.0, 3.0),
                  obstacles=[{"box": {"center": [4.075, 3.0], "size": [0.15, 4.0]}}])
ANGLES = np.radians([-90.0, -45.0, -15.0, 15.0, 45.0, 90.0])
ROBOT = RobotInfo(radius=0.18, wheel_base=0.26, v_max=0.5, omega_max=2.0, sonar=SonarInfo(
    angles=ANGLES, offsets=0.18 * np.stack([np.cos(ANGLES), np.sin(ANGLES)], 1),
    cone=math.radians(25.0), min_range=0.05, max_range=3.0))


def fake_trace(planner: Planner, row: dict | None = None) -> SimpleNamespace:
    """Straight at the wall, sonars seeing it at the true distance; the planner acts on it."""
    x = np.linspace(1.0, 3.7, 55)  # 5 cm a cycle; the last 0.30 m from the wall (centre to face)
    poses = np.column_stack([x, np.full_like(x, 3.0), np.zeros_like(x)])
    events = []
    for k, pose in enumerate(poses):
        ahead = 4.0 - pose[0] - 0.18
        ranges = np.array([3.0, ahead / math.cos(math.pi / 4), ahead, ahead,
                           ahead / math.cos(math.pi / 4), 3.0]).clip(0.05, 3.0)
        obs = Observation(t=0.1 * k, pose=pose, goal=np.array([7.0, 3.0]), ranges=ranges,
                          robot=ROBOT, bounds=(0.0, 0.0, 8.0, 6.0), dt=0.1)
        if k == 0:
            planner.reset(obs, np.random.default_rng(0))
        planner.act(obs)
        events += [{"kind": e.kind, "t": e.t, "data": e.data} for e in planner.pop_events()]
    drift = np.linspace(0, 1, len(x))[:, None] * np.array([0.05, -0.05, 0.0])
    return SimpleNamespace(t=0.1 * np.arange(len(x)), true_pose=poses, odom_pose=poses + drift,
                           events=events, planner_state=planner.debug_state(), world=WORLD,
                           row=row or {})


def test_eopc_figure_has_grid_panels_and_replans(tmp_path) -> None:
    trace = fake_trace(EOPC(), {"world": "wall", "planner": "eopc", "outcome": "timeout",
                                      "time_s": 40.0, "path_length_m": 9.87, "replans": 3, "seed": 2})
    assert len(replans(trace.events)) >= 1
    out = plot_episode(trace, tmp_path / "sub" / "eopc.png")
    image = Image.open(out)
    assert image.size[0] > 1.6 * image.size[1]  # two panels side by side
    assert episode_title(trace) == "wall - eopc, seed 2: timeout after 40.0 s, path 9.9 m, 3 re-plans"


def test_any_planner_gets_a_single_panel_and_a_title_from_the_trace(tmp_path) -> None:
    trace = fake_trace(GoalSeek())
    out = plot_episode(trace, tmp_path / "goal_seek.png", title="custom")
    width, height = Image.open(out).size
    assert width < 1.6 * height
    title = episode_title(trace)
    assert title == "wall - planner: ? after 5.4 s, path 2.7 m, 0 re-plans"
    assert plot_episode(trace, tmp_path / "goal_seek.svg").stat().st_size > 1000


def test_the_chain_joins_breakpoints_and_chosen_points_in_order() -> None:
    plans = [ReplanEvent(0.0, (1.0, 1.0), ((1.5, 1.0), (1.0, 1.5)), chosen=1),
             ReplanEvent(0.1, (1.0, 1.5), ((1.5, 1.5), (1.0, 2.0)), chosen=None),
             ReplanEvent(0.2, (1.02, 1.5), ((1.52, 1.5), (1.0, 2.0)), chosen=0)]
    assert chain_vertices(plans).tolist() == [[1.0, 1.0], [1.0, 1.5], [1.02, 1.5], [1.52, 1.5]]
    assert chain_vertices([]).shape == (0, 2)
    assert [label_step(n) for n in (1, 40, 41, 379)] == [1, 1, 2, 10]


def test_title_splits_replans_by_trigger() -> None:
    trace = fake_trace(EOPC(), {"world": "wall", "planner": "eopc", "outcome": "reached", "time_s": 9.0,
                                "path_length_m": 3.0, "replans": 5, "seed": 0,
                                "events": {"replan": 5, "replan.eo_stop": 2, "replan.blocked_path": 3}})
    assert episode_title(trace).endswith("5 re-plans (2 at EO stops, 3 on a blocked path)")
    replan = next(e for e in trace.events if e["kind"] == "replan")
    assert replan["data"]["trigger"] == "eo_stop" and replan["data"]["theta_from"] == "heading"
