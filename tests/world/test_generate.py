"""Seeded world generators: determinism, validity, reachability, what each setting does, errors."""

from __future__ import annotations

import hashlib
import itertools
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import yaml

from nav_bench.errors import InputError, UnknownNameError
from nav_bench.paths import project_file
from nav_bench.world.generate import (
    add_movers,
    generate_world,
    list_generators,
    world_yaml_text,
    write_world_yaml,
)
from nav_bench.world.generate.cellular import smooth
from nav_bench.world.generate.clutter import covered_fraction
from nav_bench.world.generate.common import (
    attempt_rng,
    clean_world_data,
    primitive_count,
    resolve_settings,
)
from nav_bench.world.generate.maze import maze_walls
from nav_bench.world.generate.movers import point_segment_distance
from nav_bench.world.generate.placement import shape_gaps
from nav_bench.world.geometry import clearance, static_geometry
from nav_bench.world.load import load_world, world_from_data
from nav_bench.world.optimal import optimal_path

KINDS = sorted(list_generators())
ROBOT = 0.18


def static_part(data: dict) -> dict:
    return {k: v for k, v in data.items() if k != "meta"}


def resample(points: np.ndarray, step: float = 0.02) -> np.ndarray:
    """Points every ``step`` m along a polyline (N, 2)."""
    out = []
    for a, b in itertools.pairwise(np.asarray(points, dtype=float)):
        n = max(1, math.ceil(np.hypot(*(b - a)) / step))
        out.append(a + np.linspace(0.0, 1.0, n, endpoint=False)[:, None] * (b - a))
    return np.vstack([*out, points[-1:]])


def path_clearance(data: dict) -> np.ndarray:
    world = world_from_data(data)
    path = optimal_path(world, ROBOT)
    assert path.length_m is not None
    return clearance(static_geometry(world), resample(path.points))


def box_area(data: dict) -> float:
    return sum(o["box"]["size"][0] * o["box"]["size"][1] for o in data["obstacles"] if "box" in o)


# --------------------------------------------------------------------------- every generator
@pytest.fixture(scope="module")
def default_worlds() -> dict[tuple[str, int], dict]:
    return {(kind, seed): generate_world(kind, seed) for kind in KINDS for seed in (0, 1, 2)}


def test_registry_lists_the_families_with_documented_settings():
    gens = list_generators()
    assert set(gens) == {"maze", "barn", "office", "clutter", "long_wall", "u_trap", "comb"}
    for name, info in gens.items():
        assert info.name == name and info.doc
        names = [s[0] for s in info.settings]
        assert len(names) == len(set(names))
        assert {"robot_radius", "max_attempts", "movers"} <= set(names)
        for s in info.settings:
            assert s[2] and s[3], f"{name}.{s[0]} needs a unit and a doc"
            assert s.check(s.default, name) == s.default  # every default passes its own check


@pytest.mark.parametrize("kind", KINDS)
def test_same_seed_same_bytes_and_seeds_differ(kind, tmp_path, default_worlds):
    a = write_world_yaml(generate_world(kind, 0), tmp_path / "a.yaml").read_bytes()
    b = write_world_yaml(default_worlds[(kind, 0)], tmp_path / "b.yaml").read_bytes()
    assert a == b
    layouts = [static_part(default_worlds[(kind, seed)]) for seed in (0, 1, 2)]
    assert layouts[0] != layouts[1] and layouts[1] != layouts[2] and layouts[0] != layouts[2]


@pytest.mark.parametrize("kind", KINDS)
def test_worlds_validate_and_the_goal_is_reachable(kind, tmp_path, default_worlds):
    for seed in (0, 1, 2):
        data = default_worlds[(kind, seed)]
        world = world_from_data(data)
        assert optimal_path(world, ROBOT).length_m > 0
        gen = data["meta"]["generator"]
        assert (gen["kind"], gen["seed"]) == (kind, seed)
        assert gen["settings"] == clean_world_data(resolve_settings(list_generators()[kind], {}))
        # sensible obstacle counts: merged walls, not one primitive per cell
        assert 1 <= primitive_count(data["obstacles"]) <= 120
    path = write_world_yaml(default_worlds[(kind, 0)], tmp_path / f"{kind}.yaml")
    assert load_world(path).name == kind


def test_committed_examples_regenerate_byte_for_byte():
    files = sorted(project_file("worlds/generated").glob("*.yaml"))
    assert {f.stem for f in files} >= {f"{k}_s0" for k in KINDS}
    for path in files:
        gen = load_world(path).meta["generator"]
        again = world_yaml_text(generate_world(gen["kind"], gen["seed"], gen["settings"]))
        assert again == path.read_text(encoding="utf-8"), (
            f"{path} is stale or generation changed; regenerate it with its header command")


def test_written_yaml_round_trips_and_says_how_to_regenerate(tmp_path):
    data = generate_world("maze", 3, {"cells": "5,4", "corridor": 1.2})
    text = world_yaml_text(data)
    assert yaml.safe_load(text) == data
    path = write_world_yaml(data, tmp_path / "m.yaml")
    first = path.read_text().splitlines()[0]
    assert first == "# Generated by: nav-bench generate maze --seed 3 --set cells=5,4 --set corridor=1.2"
    assert "\n- wall: {from: [" in path.read_text()  # one obstacle per line


def test_identical_bytes_in_another_process_with_another_hash_seed():
    code = ("from nav_bench.world.generate import generate_world, world_yaml_text, list_generators\n"
            "import hashlib\n"
            "print(hashlib.sha256(''.join(world_yaml_text(generate_world(k, 5, {'movers': 1}))"
            " for k in sorted(list_generators())).encode()).hexdigest())")
    env = dict(os.environ, PYTHONHASHSEED="12345")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True)
    here = hashlib.sha256("".join(world_yaml_text(generate_world(k, 5, {"movers": 1}))
                                  for k in KINDS).encode()).hexdigest()
    assert out.stdout.strip() == here


def test_retries_are_recorded_and_reproducible():
    # without carving, dense BARN fields are often blocked: the generator redraws
    settings = {"fill": 0.25, "smoothing": 4, "connect": False}
    attempts = {seed: generate_world("barn", seed, settings)["meta"]["generator"]["attempt"]
                for seed in range(4)}
    assert max(attempts.values()) > 0
    seed = max(attempts, key=attempts.get)
    data = generate_world("barn", seed, settings)
    gen = data["meta"]["generator"]
    info = list_generators()["barn"]
    rebuilt = clean_world_data(info.build(attempt_rng("barn", seed, gen["attempt"]),
                                          resolve_settings(info, settings)))
    assert rebuilt["obstacles"] == data["obstacles"]
    for earlier in range(gen["attempt"]):  # every earlier attempt was unreachable
        bad = clean_world_data(info.build(attempt_rng("barn", seed, earlier),
                                          resolve_settings(info, settings)))
        assert optimal_path(world_from_data(bad), ROBOT).length_m is None


# --------------------------------------------------------------------------- maze
def test_perfect_maze_is_a_spanning_tree_and_loops_remove_walls():
    rng = np.random.default_rng(0)
    for algorithm in ("backtracker", "wilson"):
        h, v = maze_walls(rng, 7, 5, algorithm, 0.0)
        walls_total = 6 * 5 + 7 * 4  # interior cell edges of a 7 x 5 grid
        assert walls_total - (h.sum() + v.sum()) == 7 * 5 - 1  # a tree opens cells - 1 walls
    h0, v0 = maze_walls(np.random.default_rng(1), 7, 5, "wilson", 0.0)
    h1, v1 = maze_walls(np.random.default_rng(1), 7, 5, "wilson", 0.5)
    assert (h1 <= h0).all() and (v1 <= v0).all()  # loops only remove walls of the same tree
    assert h1.sum() + v1.sum() == (h0.sum() + v0.sum()) - round(0.5 * (h0.sum() + v0.sum()))


def test_maze_walls_are_merged_and_loops_shorten_the_way():
    perfect = generate_world("maze", 4, {"cells": [10, 10]})
    edges_with_walls = 10 * 9 * 2 - (10 * 10 - 1)
    assert len(perfect["obstacles"]) < 0.6 * edges_with_walls
    looped = generate_world("maze", 4, {"cells": [10, 10], "loop_fraction": 0.3})
    length = {k: optimal_path(world_from_data(d), ROBOT).length_m
              for k, d in (("perfect", perfect), ("looped", looped))}
    assert length["looped"] <= length["perfect"] + 1e-6
    wilson = generate_world("maze", 4, {"cells": [10, 10], "algorithm": "wilson"})
    assert wilson["obstacles"] != perfect["obstacles"]


def test_wider_maze_corridor_gives_more_clearance_along_the_optimal_path():
    narrow = generate_world("maze", 2, {"cells": [6, 6], "corridor": 0.7})
    wide = generate_world("maze", 2, {"cells": [6, 6], "corridor": 1.5})
    assert narrow["size"] == pytest.approx([4.7, 4.7]) and wide["size"] == pytest.approx([9.5, 9.5])
    c_narrow, c_wide = path_clearance(narrow), path_clearance(wide)
    assert c_narrow.min() >= ROBOT - 0.03 and c_wide.min() >= ROBOT - 0.03
    assert c_wide.mean() > c_narrow.mean() + 0.15
    assert c_narrow.max() <= 0.35 * math.sqrt(2) + 0.02  # half a corridor, more at a turn


def test_maze_start_and_goal_in_opposite_corner_cells():
    data = generate_world("maze", 0, {"cells": [5, 3], "corridor": 1.0, "wall_thickness": 0.1})
    assert data["start"] == [0.5, 0.5]
    assert data["goal"] == [4 * 1.1 + 0.5, 2 * 1.1 + 0.5]


# --------------------------------------------------------------------------- barn
def test_smoothing_rule_of_barn():
    grid = np.zeros((7, 7), bool)
    grid[3, 3] = True  # a lone filled cell: fewer than 2 filled neighbours -> empty
    grid[1, 1:4] = grid[2, 1] = grid[2, 3] = True  # (2, 2) has 5 filled neighbours -> filled
    out = smooth(grid, 1)
    assert not out[3, 3] and out[2, 2]
    assert smooth(grid, 0).tolist() == grid.tolist()


def test_barn_boxes_partition_the_filled_cells():
    data = generate_world("barn", 5, {"fill": 0.3})
    cell, margin = 0.15, 1.0
    centres = np.stack(np.meshgrid((np.arange(30) + 0.5) * cell,
                                   margin + (np.arange(30) + 0.5) * cell), axis=-1).reshape(-1, 2)
    count = np.zeros(len(centres), int)
    for o in data["obstacles"]:
        (cx, cy), (w, h) = o["box"]["center"], o["box"]["size"]
        count += (np.abs(centres[:, 0] - cx) < w / 2) & (np.abs(centres[:, 1] - cy) < h / 2)
    assert count.max() == 1  # no cell covered twice
    filled = count.sum()
    assert box_area(data) == pytest.approx(filled * cell**2)  # boxes hold whole cells only
    assert len(data["obstacles"]) < filled / 4  # merged, not one box per cell


def test_barn_layout_fill_and_carving():
    data = generate_world("barn", 0)
    sx, sy = data["size"]
    assert (sx, sy) == (pytest.approx(4.5), pytest.approx(6.5))
    for o in data["obstacles"]:  # clutter only between the start band and the goal band
        cy, hy = o["box"]["center"][1], o["box"]["size"][1] / 2
        assert cy - hy >= 1.0 - 1e-6 and cy + hy <= sy - 1.0 + 1e-6
    assert data["start"][1] < 1.0 < sy - 1.0 < data["goal"][1]
    sparse = box_area(generate_world("barn", 7, {"fill": 0.15}))
    dense = box_area(generate_world("barn", 7, {"fill": 0.35}))
    assert dense > sparse + 1.0
    carved = generate_world("barn", 7, {"fill": 0.45, "smoothing": 2})
    assert carved["meta"]["generator"]["attempt"] == 0  # carving, not redrawing, made it passable


# --------------------------------------------------------------------------- office
def _door_gaps(data: dict, thickness: float) -> list[float]:
    """Free gaps between consecutive collinear wall segments (the doors)."""
    lines: dict[tuple[str, float], list[tuple[float, float]]] = {}
    for o in data["obstacles"]:
        if "wall" in o:
            (ax, ay), (bx, by) = o["wall"]["from"], o["wall"]["to"]
            key, span = (("v", ax), (ay, by)) if ax == bx else (("h", ay), (ax, bx))
            lines.setdefault(key, []).append(span)
    gaps = []
    for spans in lines.values():
        spans.sort()
        gaps += [b0 - a1 - thickness for (_, a1), (b0, _) in itertools.pairwise(spans)]
    return gaps


def test_office_doors_have_the_given_width_and_join_every_room():
    data = generate_world("office", 1, {"rooms": [3, 3], "door_width": 1.1, "extra_doors": 0.0})
    gaps = _door_gaps(data, 0.1)
    assert len(gaps) == 3 * 3 - 1  # a spanning tree of the rooms, no extras
    assert gaps == pytest.approx([1.1] * len(gaps), abs=2e-3)
    more = generate_world("office", 1, {"rooms": [3, 3], "extra_doors": 1.0})
    assert len(_door_gaps(more, 0.1)) == 12  # every shared wall


def test_office_furniture_density_keeps_doors_and_start_clear():
    empty = generate_world("office", 2, {"furniture": 0.0})
    full = generate_world("office", 2, {"furniture": 0.25})
    assert all("wall" in o for o in empty["obstacles"])
    assert box_area(full) + sum(math.pi * o["cylinder"]["radius"] ** 2
                                for o in full["obstacles"] if "cylinder" in o) > 0.12 * 6 * 14
    world = world_from_data(full)
    geometry = static_geometry(world)
    assert clearance(geometry, np.array([world.start[:2], world.goal])).min() >= 0.6 - 1e-3
    assert optimal_path(world, ROBOT).length_m is not None


# --------------------------------------------------------------------------- clutter
def test_clutter_density_gap_and_clear_zones():
    loose = generate_world("clutter", 3, {"density": 0.05})
    dense = generate_world("clutter", 3, {"density": 0.15})
    assert covered_fraction(loose) == pytest.approx(0.05, abs=0.02)
    assert covered_fraction(dense) == pytest.approx(0.15, abs=0.02)
    shapes = []
    for o in dense["obstacles"]:
        if "box" in o:
            b = o["box"]
            shapes.append(("box", np.array([*b["center"], *b["size"],
                                            math.radians(b.get("yaw_deg", 0.0))])))
        else:
            c = o["cylinder"]
            shapes.append(("disc", np.array([*c["center"], c["radius"]])))
    for i, shape in enumerate(shapes):
        others = shapes[:i] + shapes[i + 1:]
        boxes = np.array([p for k, p in others if k == "box"]).reshape(-1, 5)
        discs = np.array([p for k, p in others if k == "disc"]).reshape(-1, 3)
        assert shape_gaps(shape, boxes, discs).min() >= 0.5 - 2e-3  # min_gap, to the mm
    geometry = static_geometry(world_from_data(dense))
    ends = np.array([dense["start"][:2], dense["goal"]])
    assert clearance(geometry, ends).min() >= 0.8 - 1e-3


# --------------------------------------------------------------------------- traps
def test_long_wall_side_and_length():
    for side, sign in (("left", 1), ("right", -1)):
        data = generate_world("long_wall", 0, {"side": side, "jitter": 0.0, "wall_length": 6.0})
        (wall,) = data["obstacles"]
        assert abs(wall["wall"]["to"][1] - wall["wall"]["from"][1]) == pytest.approx(6.0)
        assert sign * (data["goal"][1] - data["start"][1]) == pytest.approx(2.0)
        assert data["start"][0] < wall["wall"]["from"][0] < data["goal"][0]
    sides = {generate_world("long_wall", s)["description"].split()[-2] for s in range(8)}
    assert sides == {"left", "right"}


def test_u_trap_nesting_and_opening():
    one = generate_world("u_trap", 0, {"levels": 1, "jitter": 0.0})
    three = generate_world("u_trap", 0, {"levels": 3, "jitter": 0.0})
    assert primitive_count(one["obstacles"]) == 3 and primitive_count(three["obstacles"]) == 9
    # cavity towards the start: the arms' free ends are nearer the start than the back
    pts = np.array(one["obstacles"][0]["polyline"]["points"])
    assert pts[0, 0] < pts[1, 0] and one["start"][0] < pts[0, 0] < one["goal"][0]
    assert pts[0, 1] < one["start"][1] < pts[3, 1]  # the straight line runs into the cavity
    away = generate_world("u_trap", 0, {"levels": 1, "jitter": 0.0, "opening": "away"})
    pts_away = np.array(away["obstacles"][0]["polyline"]["points"])
    assert pts_away[0, 0] > pts_away[1, 0]
    lengths = [optimal_path(world_from_data(d), ROBOT).length_m for d in (one, three)]
    assert lengths[1] > lengths[0]  # each level widens the detour


def test_comb_bays_and_depth():
    data = generate_world("comb", 0, {"bays": 6, "depth_jitter": 0.0})
    assert len(data["obstacles"]) == 6 + 2  # spine + teeth
    shallow = generate_world("comb", 0, {"bay_depth": 1.0, "depth_jitter": 0.0})
    deep = generate_world("comb", 0, {"bay_depth": 3.0, "depth_jitter": 0.0})
    lengths = [optimal_path(world_from_data(d), ROBOT).length_m for d in (shallow, deep)]
    assert lengths[1] > lengths[0] + 1.5


# --------------------------------------------------------------------------- movers
def test_movers_keep_clear_and_leave_the_static_map_alone():
    plain = generate_world("clutter", 1, {"density": 0.08})
    moving = generate_world("clutter", 1, {"density": 0.08, "movers": 3})
    assert moving["obstacles"] == plain["obstacles"] and moving["start"] == plain["start"]
    world = world_from_data(moving)
    geometry = static_geometry(world)
    assert len(world.movers) == 3
    for m in moving["movers"]:
        (a, b) = np.array(m["path"])
        r = m["shape"]["cylinder"]["radius"]
        assert 0.2 <= m["speed"] <= 0.5 and r == 0.2
        assert clearance(geometry, resample(np.array([a, b]))).min() >= r
        for end in (moving["start"][:2], moving["goal"]):
            assert point_segment_distance(np.array([end]), a, b)[0] >= r + ROBOT + 0.5 - 1e-3


def test_add_movers_standalone_loop_mode_and_too_many():
    base = generate_world("long_wall", 0)
    out = add_movers(base, seed=3, count=2, mode="loop")
    assert "movers" not in base  # the input is not modified
    assert [len(m["path"]) for m in out["movers"]] == [4, 4]
    assert out["meta"]["movers"]["count"] == 2 and add_movers(base, 3, 2, mode="loop") == out
    world_from_data(clean_world_data(out))
    with pytest.raises(InputError, match="could place only"):
        add_movers(generate_world("maze", 0, {"cells": [3, 3]}), seed=0, count=30, size=0.4)


# --------------------------------------------------------------------------- errors
def test_bad_names_and_settings_give_clear_errors():
    with pytest.raises(UnknownNameError, match="Did you mean 'maze'"):
        generate_world("mazee", 0)
    with pytest.raises(InputError, match=r"no setting 'corridr'\. Did you mean 'corridor'"):
        generate_world("maze", 0, {"corridr": 1.0})
    with pytest.raises(InputError, match="'corridor' must be > 0 m"):
        generate_world("maze", 0, {"corridor": -1})
    with pytest.raises(InputError, match="'cells' expects two numbers"):
        generate_world("maze", 0, {"cells": "abc"})
    with pytest.raises(InputError, match="'cells' expects a whole number"):
        generate_world("maze", 0, {"cells": [4.5, 4]})
    with pytest.raises(InputError, match=r"'side' must be one of .*did you mean 'left'"):
        generate_world("long_wall", 0, {"side": "lefft"})
    with pytest.raises(InputError, match="'aligned' expects true or false"):
        generate_world("clutter", 0, {"aligned": "maybe"})
    with pytest.raises(InputError, match="'box_size' is a range"):
        generate_world("clutter", 0, {"box_size": [1.0, 0.5]})
    with pytest.raises(InputError, match="seed must be a whole number >= 0"):
        generate_world("maze", -1)
    with pytest.raises(InputError, match=r"'corridor' .* must exceed the robot's diameter"):
        generate_world("maze", 0, {"corridor": 0.3})
    with pytest.raises(InputError, match="no valid layout in 3 attempts"):
        generate_world("barn", 0, {"fill": 0.6, "connect": False, "max_attempts": 3})
    # command-line strings are converted like YAML values
    assert generate_world("maze", 1, {"cells": "4,3", "corridor": "1"}) == \
        generate_world("maze", 1, {"cells": [4, 3], "corridor": 1.0})
