"""Fixtures for the simulator tests: one headless session per test module, quiet robot specs."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from nav_bench.sim import SimSession
from nav_bench.specs import RobotSpec, load_robot


@pytest.fixture(scope="module")
def session() -> Iterator[SimSession]:
    """A DIRECT session shared by a module's tests (each Simulation resets its world).

    Pinned at 240 Hz: these tests count physics steps (``step(240)`` is one second).
    test_sim_fidelity.py runs the physics at the default rate and at 240 Hz both.
    """
    with SimSession(physics_hz=240.0) as s:
        yield s


@pytest.fixture(scope="session")
def exact_robot() -> RobotSpec:
    """The default robot with sonar and odometry noise switched off."""
    return load_robot(overrides={"sonar": {"noise_std": 0.0, "dropout": 0.0},
                                 "odometry": {"wheel_noise": 0.0}})
