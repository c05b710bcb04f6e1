"""What every registered planner must do (:mod:`nav_bench.testing.conformance`, on the
kinematic harness), checked on all of them.

A planner added to the registry (built in or through an entry point) is picked up here
without any change. Runtime: ~5 s for the seven built-in planners.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_bench.planners.base import Planner
from nav_bench.planners.registry import default_registry, load_planner_set
from nav_bench.testing import conformance

NAMES = default_registry().names()
CONFIGS = Path(__file__).resolve().parents[2] / "configs" / "planners"
BASELINES = ("bug2", "tangent_bug", "dstar_lite", "vfh_plus", "apf")


def planner_class(name: str) -> type[Planner]:
    return default_registry().get(name)


@pytest.mark.parametrize("name", NAMES)
def test_declares_its_parameters(name: str) -> None:
    assert planner_class(name).name == name
    conformance.check_declares_its_parameters(planner_class(name))


@pytest.mark.parametrize("limits", [(0.5, 2.0), (0.15, 0.4)], ids=["diffbot", "slow_robot"])
@pytest.mark.parametrize("name", NAMES)
def test_commands_are_finite_and_within_the_robot_limits(name: str, limits: tuple[float, float]) -> None:
    conformance.check_commands_are_bounded(planner_class(name), *limits)


@pytest.mark.parametrize("name", NAMES)
def test_reaches_the_goal_in_an_open_room(name: str) -> None:
    conformance.check_reaches_the_goal_in_an_open_room(planner_class(name))


@pytest.mark.parametrize("name", NAMES)
def test_reset_forgets_the_previous_episode(name: str) -> None:
    conformance.check_reset_forgets_the_previous_episode(planner_class(name))


@pytest.mark.parametrize("name", NAMES)
def test_same_seed_same_commands(name: str) -> None:
    conformance.check_same_seed_same_commands(planner_class(name))


@pytest.mark.parametrize("name", NAMES)
def test_observation_is_not_modified(name: str) -> None:
    conformance.check_observation_is_not_modified(planner_class(name))


@pytest.mark.parametrize("name", BASELINES)
def test_shipped_parameter_set_is_valid_and_spells_out_the_defaults(name: str) -> None:
    spec = load_planner_set(CONFIGS / f"{name}.yaml")
    assert spec.planner == name
    cls = planner_class(name)
    assert spec.params == {p.name: p.default for p in cls.params}
    assert cls.reference and cls.__module__.startswith("nav_bench.planners.")
    assert cls.reference.split(",")[0].split()[0] in (cls.__doc__ or "")  # first author in the doc
