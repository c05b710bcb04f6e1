"""Session: one client per context, closed on exit (also on error), deterministic results."""

from __future__ import annotations

import numpy as np
import pybullet
import pytest
from sim_helpers import make_sim, make_world

from nav_bench.episode import EpisodeSettings
from nav_bench.errors import SimulationError
from nav_bench.interface import Command
from nav_bench.sim import SimSession, Simulation
from nav_bench.sim.session import PHYSICS_HZ
from nav_bench.specs import load_robot


def test_session_sets_gravity_and_time_step():
    with SimSession(physics_hz=120.0) as s:
        params = s.client.getPhysicsEngineParameters()
        assert params["fixedTimeStep"] == pytest.approx(1 / 120)
        assert params["gravityAccelerationZ"] == pytest.approx(-9.81)
        assert s.client.getNumBodies() == 1  # the ground plane


def test_session_disconnects_on_exit_even_after_an_error():
    session = SimSession()
    with pytest.raises(RuntimeError), session:
        client = session.client
        raise RuntimeError("boom")
    with pytest.raises(pybullet.error):
        client.getNumBodies()  # the connection is gone
    with pytest.raises(SimulationError, match="not open"):
        session.client  # noqa: B018


def test_default_physics_rate_is_the_episodes(exact_robot):
    assert EpisodeSettings().physics_hz == PHYSICS_HZ == 60.0  # one value, two homes
    with SimSession() as s:
        assert make_sim(s, make_world(), exact_robot).dt == pytest.approx(1 / PHYSICS_HZ)


def test_session_applies_solver_iterations_and_refuses_bad_engine_settings():
    with SimSession(solver_iterations=20) as s:
        assert s.client.getPhysicsEngineParameters()["numSolverIterations"] == 20
    with pytest.raises(SimulationError, match="solver_iterations"):
        SimSession(solver_iterations=0)
    with pytest.raises(SimulationError, match="contact_recovery_hz"):
        SimSession(contact_recovery_hz=0.0)


def _drive_3s(session: SimSession, robot) -> np.ndarray:
    sim = make_sim(session, make_world(), robot)
    sim.apply(Command(0.5, 0.4))
    sim.step(round(3.0 / sim.dt))
    return sim.true_pose()


def test_solver_residual_is_applied_and_bullets_own_is_the_default(exact_robot):
    # a loose stopping threshold changes the drive (it is set), the default does not
    with SimSession() as s:
        own = _drive_3s(s, exact_robot)
        again = _drive_3s(s, exact_robot)
    with SimSession(solver_residual=1e-2) as s:
        loose = _drive_3s(s, exact_robot)
    assert np.array_equal(own, again)
    assert np.hypot(*(loose[:2] - own[:2])) > 1e-4
    with pytest.raises(SimulationError, match="solver_residual"):
        SimSession(solver_residual=0.0)


def test_simulation_physics_rate_overrides_the_session(exact_robot):
    with SimSession(physics_hz=240.0) as s:
        sim = make_sim(s, make_world(), exact_robot)
        assert sim.dt == pytest.approx(1 / 240)
        sim = Simulation(s, make_world(), exact_robot, np.random.default_rng(0), physics_hz=100.0)
        sim.step(50)
        assert sim.t == pytest.approx(0.5)
        assert s.client.getPhysicsEngineParameters()["fixedTimeStep"] == pytest.approx(0.01)


def test_bad_arguments_are_refused(session, exact_robot):
    with pytest.raises(SimulationError, match="physics_hz"):
        SimSession(physics_hz=0.0)
    sim = make_sim(session, make_world(), exact_robot)
    with pytest.raises(SimulationError, match="negative"):
        sim.step(-1)
    with pytest.raises(SimulationError, match="finite"):
        sim.apply(Command(float("nan"), 0.0))


def test_timing_accumulates_physics_and_sensing(session, exact_robot):
    sim = make_sim(session, make_world(), exact_robot)
    assert sim.timing == {"physics": 0.0, "sensing": 0.0}
    sim.step(24)
    sim.sense()
    physics, sensing = sim.timing["physics"], sim.timing["sensing"]
    assert physics > 0.0 and sensing > 0.0
    sim.step(24)
    assert sim.timing["physics"] > physics and sim.timing["sensing"] == sensing


def run_trace(seed: int) -> dict[str, np.ndarray]:
    """A scripted episode with noise and a mover; every output it produces."""
    robot = load_robot(overrides={"sonar": {"dropout": 0.1}, "odometry": {"wheel_noise": 0.02}})
    mover = {"shape": {"cylinder": {"radius": 0.3}}, "path": [[4.0, 2.0], [4.0, 8.0]],
             "speed": 0.5}
    world = make_world(start=(1.0, 5.0, 0.0), boundary=True, movers=[mover],
                       obstacles=[{"box": {"center": [6.0, 5.0], "size": [1.0, 3.0]}}])
    out: dict[str, list] = {"true": [], "odom": [], "ranges": []}
    with SimSession() as s:
        sim = make_sim(s, world, robot, seed=seed)
        for k in range(60):
            out["ranges"].append(sim.sense())
            sim.apply(Command(0.5, 0.6 * np.sin(k / 7.0)))
            sim.step(24)
            out["true"].append(sim.true_pose())
            out["odom"].append(sim.odometry_pose())
        out["collisions"] = [sim.collisions]
    return {k: np.asarray(v) for k, v in out.items()}


def test_same_seed_gives_identical_traces():
    a, b, c = run_trace(11), run_trace(11), run_trace(12)
    for key in a:
        assert np.array_equal(a[key], b[key]), key
    assert not np.array_equal(a["odom"], c["odom"])
    assert not np.array_equal(a["ranges"], c["ranges"])
    assert np.abs(a["true"][-1, :2] - a["true"][0, :2]).max() > 1.0  # it did drive
