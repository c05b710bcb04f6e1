"""Static scene: obstacles grouped into compact compound bodies, every shape present."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sim_helpers import make_sim, make_world

from nav_bench.sim.scene import (
    MAX_SHAPES_PER_BODY,
    SceneLayout,
    build_static_scene,
    spatial_chunks,
)
from nav_bench.world.geometry import static_geometry


def test_spatial_chunks_cover_every_point_once_in_full_groups():
    pts = np.random.default_rng(0).uniform(0, 30, size=(1000, 2))
    chunks = spatial_chunks(pts, 16)
    assert len(chunks) == math.ceil(1000 / 16)
    assert max(map(len, chunks)) <= 16
    assert sorted(np.concatenate(chunks).tolist()) == list(range(1000))


def test_spatial_chunks_are_compact():
    pts = np.random.default_rng(1).uniform(0, 30, size=(1000, 2))
    chunks = spatial_chunks(pts, 16)
    areas = [np.ptp(pts[c, 0]) * np.ptp(pts[c, 1]) for c in chunks]
    assert np.mean(areas) < 2.0 * 900.0 / len(chunks)  # ~ the world split evenly


def test_spatial_chunks_small_inputs():
    assert spatial_chunks(np.zeros((0, 2)), 16) == []
    assert [c.tolist() for c in spatial_chunks(np.ones((3, 2)), 16)] == [[0, 1, 2]]
    with pytest.raises(ValueError):
        spatial_chunks(np.ones((3, 2)), 0)


def test_every_obstacle_is_in_the_scene(session, exact_robot):
    # 40 posts and 30 boxes: more than one compound body's worth (PyBullet silently drops
    # shapes beyond 16 per compound, so each must be checked).
    posts = [{"cylinder": {"center": [0.5 + 0.2 * i, 8.0], "radius": 0.05}} for i in range(40)]
    boxes = [{"box": {"center": [0.5 + 0.3 * i, 9.0], "size": [0.1, 0.2], "yaw_deg": 10 * i}}
             for i in range(30)]
    world = make_world(start=(5.0, 2.0, 0.0), obstacles=posts + boxes, size=(10.0, 10.0))
    sim = make_sim(session, world, exact_robot)
    assert len(sim.scene.body_ids) == math.ceil(70 / MAX_SHAPES_PER_BODY)
    assert sim.scene.shape_count == 70
    geometry = static_geometry(world)
    tops = np.concatenate([geometry.cylinders[:, :2], geometry.boxes[:, :2]])
    hits = session.client.rayTestBatch([[x, y, 1.0] for x, y in tops],
                                       [[x, y, 0.0] for x, y in tops])
    assert all(h[0] in sim.scene.body_ids for h in hits)
    assert [h[3][2] for h in hits] == pytest.approx([world.wall_height] * 70, abs=1e-4)


def test_one_body_per_obstacle_layout_for_comparison(session):
    world = make_world(obstacles=[{"cylinder": {"center": [5.0 + i, 5.0], "radius": 0.1}}
                                  for i in range(3)])
    session.reset()
    scene = build_static_scene(session.client, static_geometry(world),
                               layout=SceneLayout(shapes_per_body=1))
    assert len(scene.body_ids) == 3
    (_, _, z), _ = session.client.getBasePositionAndOrientation(scene.body_ids[2])
    assert sorted([session.client.getBasePositionAndOrientation(b)[0][0]
                   for b in scene.body_ids]) == pytest.approx([5.0, 6.0, 7.0])
    assert z == pytest.approx(world.wall_height / 2)
