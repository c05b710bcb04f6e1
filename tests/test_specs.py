"""World YAML validation: every broken file gets its own precise message (file, key, line)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from nav_bench.errors import SpecError, SpecErrors
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import load_world, world_from_data

ROOT = Path(__file__).resolve().parents[1]
BROKEN = ROOT / "tests" / "data" / "broken_worlds"

# file -> (key path, line, words the message must contain)
EXPECTED = {
    "unknown_key.yaml": ("obstacels", 4, "did you mean 'obstacles'"),
    "bad_box_size.yaml": ("obstacles[3].box.size[1]", 10, "greater than 0"),
    "unknown_obstacle_kind.yaml": ("obstacles[0]", 5, "did you mean 'wall'"),
    "start_in_obstacle.yaml": ("start", 2, "inside obstacles[0]"),
    "goal_outside.yaml": ("goal", 3, "outside the world"),
    "negative_size.yaml": ("size[1]", 1, "greater than 0"),
    "wrong_type.yaml": ("boundary", 4, "valid boolean"),
    "missing_goal.yaml": ("goal", 1, "required key is missing"),
    "bad_syntax.yaml": ("", 2, "not valid YAML"),
    "bad_mover_mode.yaml": ("movers[0].mode", 8, "'pingpong' or 'loop'"),
    "zero_length_wall.yaml": ("obstacles[0].wall", 5, "two different points"),
}


def test_every_broken_file_has_an_expectation():
    assert sorted(p.name for p in BROKEN.glob("*.yaml")) == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_broken_world_message_names_file_key_and_line(name):
    key, line, words = EXPECTED[name]
    with pytest.raises(SpecError) as info:
        load_world(BROKEN / name)
    err = info.value
    assert err.file == str(BROKEN / name)
    assert err.key_path == key
    assert err.line == line
    assert words in err.problem
    assert str(err).startswith(f"{BROKEN / name}:{line}:")


def test_several_problems_are_reported_together(tmp_path):
    path = tmp_path / "two.yaml"
    path.write_text("size: [10, 10]\nstart: [1, 1]\ngoal: [9, 9]\nwall_height: -1\ncolour: red\n")
    with pytest.raises(SpecErrors) as info:
        load_world(path)
    keys = sorted(e.key_path for e in info.value.errors)
    assert keys == ["colour", "wall_height"]
    assert sorted(e.line for e in info.value.errors) == [4, 5]


def test_name_defaults_to_file_stem_and_yaw_faces_goal(tmp_path):
    path = tmp_path / "diag.yaml"
    path.write_text("size: [10, 10]\nstart: [1, 1]\ngoal: [9, 9]\n")
    world = load_world(path)
    assert world.name == "diag"
    assert world.start_pose == pytest.approx((1.0, 1.0, math.pi / 4))


def test_explicit_start_yaw_is_degrees():
    world = world_from_data({"size": [4, 4], "start": [1, 1, 90], "goal": [3, 3]})
    assert world.start_pose[2] == pytest.approx(math.pi / 2)


def test_geometry_walls_polylines_and_boundary():
    world = world_from_data({
        "size": [10, 6], "start": [1, 1], "goal": [9, 5],
        "obstacles": [
            {"wall": {"from": [5, 0], "to": [5, 4], "thickness": 0.2}},
            {"polyline": {"points": [[1, 3], [2, 3], [2, 4]], "thickness": 0.1}},
            {"cylinder": {"center": [8, 2], "radius": 0.5}},
            {"box": {"center": [3, 1], "size": [1, 0.5], "yaw_deg": 90}},
        ]})
    geo = static_geometry(world)
    assert len(geo.boxes) == 1 + 2 + 1 + 4  # wall, two polyline segments, box, boundary
    assert len(geo.cylinders) == 1
    # distances from probe points to the nearest obstacle, by hand
    probes = [(5.6, 2.0), (8.0, 3.0), (3.0, 1.9), (1.5, 2.7), (7.0, 5.5)]
    expected = [0.5, 0.5, 0.4, 0.25, 0.5]
    assert clearance(geo, probes) == pytest.approx(expected, abs=1e-9)
    # inside the wall: negative, by half its thickness at the centre line
    assert clearance(geo, [(5.0, 2.0)])[0] == pytest.approx(-0.1)


def test_all_shipped_worlds_validate():
    files = sorted((ROOT / "worlds").rglob("*.yaml"))
    assert len(files) >= 7
    for f in files:
        load_world(f)
