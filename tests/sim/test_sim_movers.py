"""Moving obstacles: the pure position function and the bodies in the simulator."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sim_helpers import make_sim, make_world

from nav_bench.sim import mover_position, mover_positions
from nav_bench.specs import Mover


def mover(path, speed=1.0, mode="pingpong", phase_s=0.0, shape=None) -> Mover:
    return Mover.model_validate({"shape": shape or {"cylinder": {"radius": 0.2}}, "path": path,
                                 "speed": speed, "mode": mode, "phase_s": phase_s})


@pytest.mark.parametrize(("t", "expected"), [
    (0.0, (0.0, 0.0)), (0.5, (0.5, 0.0)), (2.0, (2.0, 0.0)),  # out
    (2.5, (1.5, 0.0)), (4.0, (0.0, 0.0)),                      # and back
    (4.25, (0.25, 0.0)), (402.75, (1.25, 0.0)),                # periodic, period 4 s
])
def test_pingpong_goes_out_and_back(t, expected):
    m = mover([[0, 0], [2, 0]], speed=1.0)
    assert mover_position(m, t) == pytest.approx(expected, abs=1e-9)


def test_pingpong_over_several_segments_and_speed():
    m = mover([[0, 0], [1, 0], [1, 2]], speed=0.5)  # length 3 m, 6 s one way
    assert mover_position(m, 3.0) == pytest.approx((1.0, 0.5))  # 1.5 m along
    assert mover_position(m, 6.0) == pytest.approx((1.0, 2.0))  # far end
    assert mover_position(m, 9.0) == pytest.approx((1.0, 0.5))  # 1.5 m back


def test_loop_returns_along_the_closing_segment():
    m = mover([[0, 0], [1, 0], [1, 1]], mode="loop", speed=1.0)
    length = 2.0 + math.sqrt(2.0)
    back = 0.5 / math.sqrt(2.0)
    assert mover_position(m, 2.5) == pytest.approx((1.0 - back, 1.0 - back))
    assert mover_position(m, length) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert mover_position(m, length + 1.5) == pytest.approx((1.0, 0.5))


def test_phase_starts_the_motion_later_in_the_cycle():
    m = mover([[0, 0], [2, 0]], speed=1.0, phase_s=1.5)
    assert mover_position(m, 0.0) == pytest.approx((1.5, 0.0))
    assert mover_position(m, 1.0) == pytest.approx((1.5, 0.0))  # 2.5 s in: on the way back


def test_degenerate_paths():
    still = mover([[3, 4], [3, 4]])
    assert mover_position(still, 7.3) == (3.0, 4.0)
    repeated = mover([[0, 0], [1, 0], [1, 0], [1, 1]], mode="loop")  # zero-length segment
    assert mover_position(repeated, 1.5) == pytest.approx((1.0, 0.5))


def test_mover_positions_stacks_all_movers():
    ms = [mover([[0, 0], [2, 0]]), mover([[5, 5], [5, 9]], speed=2.0)]
    assert mover_positions(ms, 1.0) == pytest.approx(np.array([[1.0, 0.0], [5.0, 7.0]]))
    assert mover_positions([], 1.0).shape == (0, 2)


def test_bodies_follow_their_paths_in_the_simulation(session, exact_robot):
    movers = [
        {"shape": {"cylinder": {"radius": 0.2}}, "path": [[1, 8], [7, 8]], "speed": 0.6},
        {"shape": {"box": {"size": [0.3, 0.5]}}, "path": [[8, 1], [8, 4], [6, 4]],
         "speed": 0.4, "mode": "loop", "phase_s": 2.0},
    ]
    world = make_world(movers=movers)
    sim = make_sim(session, world, exact_robot)
    client = session.client
    for steps in (0, 1, 239, 960, 1200):
        sim.step(steps)
        for body, spec in zip(sim.movers.body_ids, world.movers, strict=True):
            (x, y, z), _ = client.getBasePositionAndOrientation(body)
            assert (x, y) == pytest.approx(mover_position(spec, sim.t), abs=1e-6)
            assert z == pytest.approx(world.wall_height / 2)
        assert sim.mover_positions() == pytest.approx(mover_positions(list(world.movers), sim.t))
    assert sim.t == pytest.approx(2400 / 240)


def test_readers_of_one_physics_step_share_its_reads_and_cannot_change_them(session, exact_robot):
    world = make_world(movers=[{"shape": {"cylinder": {"radius": 0.2}}, "path": [[1, 1], [5, 1]],
                                "speed": 0.5}])
    sim = make_sim(session, world, exact_robot)
    pose = sim.true_pose()
    pose[:] = 99.0  # a reader's copy: the next reader still gets the true pose
    assert sim.true_pose() == pytest.approx([2.0, 5.0, 0.0], abs=1e-3)
    first = sim.mover_positions()
    assert sim.mover_positions() is first  # read once per physics step
    with pytest.raises(ValueError):
        first[0, 0] = 0.0
    sim.step(6)
    assert sim.mover_positions() == pytest.approx(np.array([[1.0 + 0.5 * sim.t, 1.0]]))
    assert first == pytest.approx(np.array([[1.0, 1.0]]))
