"""Map importers on real sample maps: ROS map_server, MovingAI (.map/.scen), BARN."""

from __future__ import annotations

import gzip
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from nav_bench.errors import InputError, SpecError
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.imports import (
    dump_world_yaml,
    import_barn,
    import_movingai,
    import_ros,
    merge_cells,
    read_movingai_map,
    read_scen,
    write_world_yaml,
)
from nav_bench.world.imports.barn import reference_path
from nav_bench.world.imports.rectangles import rects_to_mask
from nav_bench.world.imports.ros import read_pgm
from nav_bench.world.load import load_world, world_from_data
from nav_bench.world.optimal import grid_distances, grid_graph, optimal_path
from nav_bench.world.raster import rasterize

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data" / "maps"  # copies kept with the tests (two files gzipped)
SHARED = REPO.parent / "shared" / "maps"  # the project's shared collection, beside the clone


def sample(folder: str, tmp_path: Path) -> Path:
    """A folder of sample maps: the test copy (``.gz`` files decompressed into ``tmp_path``),
    else the shared collection; skips the test when neither exists."""
    src = DATA / folder
    if src.is_dir():
        dst = tmp_path / folder
        dst.mkdir(parents=True, exist_ok=True)
        for f in src.rglob("*"):
            if f.is_file():
                target = dst / f.relative_to(src)
                target.parent.mkdir(parents=True, exist_ok=True)
                if f.suffix == ".gz":
                    with gzip.open(f, "rb") as fin, open(target.with_suffix(""), "wb") as fout:
                        shutil.copyfileobj(fin, fout)
                else:
                    shutil.copy(f, target)
        return dst
    if (SHARED / folder).is_dir():
        return SHARED / folder
    pytest.skip(f"sample maps {folder!r} not found in {DATA} nor in {SHARED}")


# --------------------------------------------------------------------------- rectangles
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_merge_cells_is_an_exact_partition(seed):
    rng = np.random.default_rng(seed)
    occupied = rng.random((40, 57)) < (0.2 + 0.3 * seed)
    rects = merge_cells(occupied)
    count = rects_to_mask(rects, occupied.shape)
    assert count.max() <= 1  # no overlap
    assert np.array_equal(count == 1, occupied)  # union is exactly the input


def test_merge_cells_finds_whole_blocks():
    occupied = np.zeros((10, 12), bool)
    occupied[2:5, 3:9] = True  # one block
    occupied[7, :] = True  # one full row
    assert sorted(merge_cells(occupied)) == [(2, 3, 3, 6), (7, 0, 1, 12)]
    assert merge_cells(np.zeros((3, 3), bool)) == []


# --------------------------------------------------------------------------- ROS
def test_pgm_reader_binary_and_ascii(tmp_path):
    img = np.array([[0, 205, 254], [254, 0, 205]], dtype=np.uint8)
    (tmp_path / "b.pgm").write_bytes(b"P5\n# comment\n3 2\n255\n" + img.tobytes())
    (tmp_path / "a.pgm").write_text("P2\n3 2\n# c\n255\n0 205 254\n254 0 205\n")
    assert np.array_equal(read_pgm(tmp_path / "b.pgm"), img)
    assert np.array_equal(read_pgm(tmp_path / "a.pgm"), img)
    (tmp_path / "bad.pgm").write_bytes(b"P6\n3 2\n255\n" + bytes(18))
    with pytest.raises(InputError, match="P5 or P2"):
        read_pgm(tmp_path / "bad.pgm")


def test_turtlebot3_world(tmp_path):
    folder = sample("ros/turtlebot3_world", tmp_path)
    data = import_ros(folder / "map.yaml")
    world = world_from_data(data)
    meta = data["meta"]
    # 384 x 384 px at 0.05 m, origin (-10, -10); the known area is 113 x 104 px
    # (rows 132..235 from the top, cols 141..253) plus a 2 px margin each side
    assert meta["pixels"] == [117, 108]
    assert world.size == pytest.approx((117 * 0.05, 108 * 0.05))
    assert meta["crop_offset_px"] == [139, 384 - 236 - 2]
    assert meta["map_frame_of_world_origin"] == pytest.approx([-10 + 139 * 0.05, -10 + 146 * 0.05])
    assert len(world.obstacles) == 158  # merged from 5,000+ blocked pixels
    # the imported boxes reproduce the blocked pixels exactly, plus two free pixels at the
    # top edge that are cut off from the arena (filled as unreachable pockets)
    occupied = rasterize(static_geometry(world), 0.05).occupied
    blocked = read_pgm(folder / "map.pgm")[::-1][146:254, 139:256] != 254
    assert not (blocked & ~occupied).any()
    assert np.argwhere(occupied & ~blocked).tolist() == [[105, 46], [105, 48]]
    # automatic start and goal: free, far apart, connected for a 0.18 m robot
    path = optimal_path(world, 0.18)
    assert path.length_m == pytest.approx(4.83, abs=0.05)
    assert clearance(static_geometry(world), np.array([world.start[:2], world.goal])).min() > 0.28


def test_ros_start_goal_in_the_map_frame(tmp_path):
    folder = sample("ros/turtlebot3_world", tmp_path)
    data = import_ros(folder / "map.yaml", start=(-2.0, -0.5), goal=(1.9, 0.5))
    ox, oy = data["meta"]["map_frame_of_world_origin"]
    assert data["start"] == pytest.approx([-2.0 - ox, -0.5 - oy])
    assert data["goal"] == pytest.approx([1.9 - ox, 0.5 - oy])
    world_from_data(data)
    with pytest.raises(InputError, match="outside the imported area"):
        import_ros(folder / "map.yaml", start=(-9.0, -9.0), goal=(1.9, 0.5))
    with pytest.raises(InputError, match=r"lies in an (unknown|occupied) pixel"):
        import_ros(folder / "map.yaml", start=(-1.1, -1.1), goal=(1.9, 0.5))  # a pillar
    only_start = import_ros(folder / "map.yaml", start=(-2.0, -0.5))
    assert only_start["start"] == pytest.approx(data["start"])
    world_from_data(only_start)


def test_lse_arena(tmp_path):
    folder = sample("ros/lse_arena", tmp_path)
    data = import_ros(folder / "lse_arena.yaml")
    world = world_from_data(data)
    assert data["meta"]["pixels"] == [80, 60]  # fully known: nothing cropped
    assert world.size == pytest.approx((4.0, 3.0))
    assert len(world.obstacles) == 7
    raster = rasterize(static_geometry(world), 0.05)
    img = read_pgm(folder / "lse_arena.pgm")[::-1]
    assert np.array_equal(raster.occupied, img < 128)  # 0 occupied; 239 and 255 free
    assert optimal_path(world, 0.18).length_m is not None


def test_ros_unknown_as_free_and_bad_yaml(tmp_path):
    folder = sample("ros/turtlebot3_world", tmp_path)
    free = import_ros(folder / "map.yaml", unknown_as="free")
    assert free["meta"]["pixels"] == [117, 108]  # cropping ignores the treatment of unknown
    world_from_data(free)
    bad = folder / "bad.yaml"
    bad.write_text("image: map.pgm\nresolution: -0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(SpecError) as err:
        import_ros(bad)
    assert err.value.key_path == "resolution" and err.value.line == 2
    (folder / "noimage.yaml").write_text("image: nothere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n")
    with pytest.raises(InputError, match="not found"):
        import_ros(folder / "noimage.yaml")


# --------------------------------------------------------------------------- MovingAI
MAPS = ["maze-32-32-2", "room-32-32-4"]


@pytest.mark.parametrize("name", MAPS)
def test_movingai_scen_lengths_reproduced(name, tmp_path):
    folder = sample("movingai", tmp_path)
    scenarios = read_scen(folder / f"{name}-random-1.scen")
    assert len(scenarios) in (333, 341)
    # grid taken from the *imported world* (boxes rasterised at the cell size), flipped back
    world = world_from_data(import_movingai(folder / f"{name}.map", folder / f"{name}-random-1.scen"))
    blocked_world = rasterize(static_geometry(world), 0.5).occupied
    blocked = read_movingai_map(folder / f"{name}.map")
    assert np.array_equal(blocked_world[::-1], blocked)
    graph = grid_graph(blocked_world)
    worst = 0.0
    for sc in scenarios:  # every line: ~30 ms per map
        (sx, sy), (gx, gy) = sc.start, sc.goal
        d = grid_distances(blocked_world, (31 - sy, sx), graph=graph)[31 - gy, gx]
        worst = max(worst, abs(d - sc.optimal) / sc.optimal)
    assert worst < 1e-3


def test_movingai_scenario_zero_in_world_coordinates(tmp_path):
    folder = sample("movingai", tmp_path)
    data = import_movingai(folder / "maze-32-32-2.map", folder / "maze-32-32-2-random-1.scen", 0)
    # line 1: 16 maze-32-32-2.map 32 32 15 2 1 27 64.31370850
    assert data["start"] == [7.75, 14.75]  # ((15 + 0.5) * 0.5, (31 - 2 + 0.5) * 0.5)
    assert data["goal"] == [0.75, 2.25]  # ((1 + 0.5) * 0.5, (31 - 27 + 0.5) * 0.5)
    assert data["size"] == [16.0, 16.0]
    assert data["meta"]["scen_optimal_m"] == pytest.approx(64.3137085 * 0.5)
    world = world_from_data(data)
    assert world.name == "maze-32-32-2_0"
    assert len(world.obstacles) == 64
    room = import_movingai(folder / "room-32-32-4.map", folder / "room-32-32-4-random-1.scen", 3,
                           cell=1.0)
    # line 4: 7 room-32-32-4.map 32 32 22 9 2 20 28.65685425
    assert room["start"] == [22.5, 22.5] and room["goal"] == [2.5, 11.5]
    assert room["size"] == [32.0, 32.0]
    world_from_data(room)


def test_movingai_automatic_endpoints_and_errors(tmp_path):
    folder = sample("movingai", tmp_path)
    data = import_movingai(folder / "room-32-32-4.map")
    world = world_from_data(data)
    assert data["meta"]["start_goal"] == "automatic"
    length = optimal_path(world, 0.18).length_m
    assert length is not None and length > 15.0  # far apart in a 16 m map
    with pytest.raises(InputError, match="out of range"):
        import_movingai(folder / "maze-32-32-2.map", folder / "maze-32-32-2-random-1.scen", 5000)
    bad = tmp_path / "bad.map"
    bad.write_text("type octile\nheight 3\nwidth 4\nmap\n....\n..\n....\n")
    with pytest.raises(InputError, match=r"bad.map:6: expected 4 characters"):
        read_movingai_map(bad)


# --------------------------------------------------------------------------- BARN
def test_barn_world_0(tmp_path):
    folder = sample("barn", tmp_path)
    data = import_barn(folder / "worlds" / "world_0.world", folder / "path_files" / "path_0.npy")
    world = world_from_data(data)
    assert world.size == pytest.approx((4.5, 14.5))
    assert data["meta"]["barn_to_world_offset"] == [4.5, 0.0]
    assert world.start_pose == pytest.approx((2.25, 3.0, 1.57))
    assert world.goal == pytest.approx((2.25, 13.0))
    assert data["meta"]["goal_tolerance_m"] == 1.0 and data["meta"]["time_limit_s"] == 100.0
    assert len(world.obstacles) == 209
    assert {o.kind for o in world.obstacles} == {"cylinder"}
    assert {o.shape.radius for o in world.obstacles} == {0.075}
    geometry = static_geometry(world)
    # the BARN reference path runs through free space of the shifted world
    ref = reference_path(folder / "path_files" / "path_0.npy") + np.array([4.5, 0.0])
    assert clearance(geometry, ref).min() > 0.2
    assert data["meta"]["reference_path_m"] == pytest.approx(13.5923, abs=1e-3)
    length = optimal_path(world, 0.18).length_m
    assert 10.0 < length < data["meta"]["reference_path_m"]


@pytest.mark.parametrize("n", [0, 6, 12, 150, 222])
def test_barn_reference_paths_are_free(n):
    world_file = SHARED / "barn" / "worlds" / f"world_{n}.world"
    if not world_file.exists():
        pytest.skip(f"{world_file} not found (the shared map collection is not beside the clone)")
    path_file = SHARED / "barn" / "path_files" / f"path_{n}.npy"
    data = import_barn(world_file)
    world = world_from_data(data)
    ref = reference_path(path_file) + np.asarray(data["meta"]["barn_to_world_offset"])
    assert clearance(static_geometry(world), ref).min() > 0.2


# --------------------------------------------------------------------------- YAML output
def test_written_yaml_is_plain_and_valid(tmp_path):
    folder = sample("movingai", tmp_path)
    data = import_movingai(folder / "maze-32-32-2.map", folder / "maze-32-32-2-random-1.scen", 0)
    path = write_world_yaml(data, tmp_path / "out" / "maze.yaml")
    text = path.read_text()
    assert text.startswith("# nav-bench world: maze-32-32-2_0\n# source: MovingAI")
    assert "# licence: Open Data Commons Attribution" in text
    assert "- box: {center: [0.25, 8.0], size: [0.5, 16.0]}\n" in text
    assert "start: [7.75, 14.75]\n" in text
    assert yaml.safe_load(text) == data
    assert load_world(path).name == "maze-32-32-2_0"
    assert dump_world_yaml(data, header=["x"]).startswith("# x\nname:")


def test_shipped_imported_worlds_are_valid_and_attributed():
    files = sorted((REPO / "worlds" / "imported").glob("*.yaml"))
    assert len(files) >= 5
    for f in files:
        world = load_world(f)
        assert world.meta.get("source") and world.meta.get("licence"), f
        assert "unknown" not in world.meta["licence"], f
