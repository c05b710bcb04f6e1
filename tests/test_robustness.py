"""Issue 11: nothing a user types can crash nav-bench, hang it, or lose their files.

One section per defect class. Every refusal is exit 2 with one line naming the file (and the
line and key where there is one), never a traceback.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_bench import yamlio
from nav_bench.cli import main
from nav_bench.errors import SpecError
from nav_bench.yamlio import load_yaml, parse_yaml

ROOT = Path(__file__).resolve().parents[1]

WORLD = """\
name: w
size: [4.0, 3.0]
start: [0.5, 1.5, 0]
goal: [3.5, 1.5]
obstacles:
  - box: {center: [2.0, 0.5], size: [0.4, 0.3], yaw_deg: 10}
"""


def _refused(capsys, argv: list[str], *needles: str) -> str:
    """Run the CLI in-process; assert exit 2, no traceback, and each needle in stderr."""
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, err
    return err


# --------------------------------------------------------------------------- class 2 and 3: YAML
BOMB = "\n".join(  # the classic nine lines: 9**9 values once expanded
    ["a: &a [" + ", ".join(['"lol"'] * 9) + "]"]
    + [f"{k}: &{k} [" + ", ".join([f"*{p}"] * 9) + "]"
       for p, k in zip("abcdefgh", "bcdefghi", strict=True)])


def test_an_alias_bomb_is_refused_before_it_grows(tmp_path, capsys):
    path = tmp_path / "bomb.yaml"
    path.write_text(BOMB + "\n")
    _refused(capsys, ["validate", str(path)], f"{path}:", "aliases expand to more than")


def test_the_alias_bound_is_a_stated_constant(monkeypatch):
    monkeypatch.setattr(yamlio, "MAX_ALIAS_NODES", 1000)
    small = "a: &a [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\n"
    parse_yaml(small)  # 100 values from aliases: fine
    with pytest.raises(SpecError, match="aliases expand"):
        parse_yaml(small + "c: [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\n")


def test_a_recursive_alias_is_refused(tmp_path, capsys):
    path = tmp_path / "rec.yaml"
    path.write_text("name: &a [*a]\nsize: [4, 3]\n")
    _refused(capsys, ["validate", str(path)], f"{path}:1: name[0]:", "recursive alias")


def test_deep_nesting_is_refused_not_a_stack_overflow(tmp_path, capsys):
    path = tmp_path / "deep.yaml"
    path.write_text("name: " + "[" * 50_000 + "]" * 50_000 + "\n")
    _refused(capsys, ["validate", str(path)], f"{path}:1:", "nested deeper than")


def test_aliases_and_merge_keys_still_work():
    data, index = parse_yaml("d: &d {x: 1, y: 2}\ne: {<<: *d, y: 3}\nf: *d\n")
    assert data == {"d": {"x": 1, "y": 2}, "e": {"x": 1, "y": 3}, "f": {"x": 1, "y": 2}}
    data["f"]["x"] = 9  # an alias is a copy, not the anchor itself
    assert data["d"]["x"] == 1
    assert index.line_of(("e", "y")) == 2


@pytest.mark.parametrize("content", [bytes(range(256)) * 3, "name: café\n".encode("latin-1")])
def test_a_file_that_is_not_utf8_text_is_bad_input(tmp_path, capsys, content):
    path = tmp_path / "x.yaml"
    path.write_bytes(content)
    _refused(capsys, ["validate", str(path)], f"{path}:", "not UTF-8 text")


def test_validate_of_a_folder_reports_every_file(tmp_path, capsys):
    (tmp_path / "a_bytes.yaml").write_bytes(b"\xff\xfe\x00garbage")
    (tmp_path / "b_good.yaml").write_text(WORLD)
    (tmp_path / "c_tag.yaml").write_text("name: !!python/name:os.system x\n")
    code = main(["validate", str(tmp_path)])
    captured = capsys.readouterr()
    assert code == 2
    assert "1 of 3 files valid" in captured.out
    assert "a_bytes.yaml" in captured.err and "c_tag.yaml" in captured.err
    assert "Traceback" not in captured.err


@pytest.mark.parametrize("text, line", [
    ("name: !!python/name:os.system x\nsize: [4, 3]\n", 1),
    ("name: w\nsize: !!python/object:__main__.X {a: 1}\n", 2),
    ("name: w\nsize: !!python/tuple [4, 3]\n", 2),
    ("name: w\nsize: [4, 3]\ngoal: !!set {a, b}\n", 3),
])
def test_python_and_other_unsupported_tags_are_refused(tmp_path, capsys, text, line):
    path = tmp_path / "t.yaml"
    path.write_text(text)
    _refused(capsys, ["validate", str(path)], f"{path}:{line}:", "unsupported YAML tag")


def test_a_bad_timestamp_or_a_mapping_as_key_is_bad_input(tmp_path, capsys):
    path = tmp_path / "t.yaml"
    path.write_text("name: 2024-02-30\n")
    _refused(capsys, ["validate", str(path)], f"{path}:1: name:", "cannot read value")
    path.write_text("? {a: 1}\n: 2\n")
    _refused(capsys, ["validate", str(path)], f"{path}:1:", "mapping key must be a plain value")


def test_yaml_values_and_lines_match_pyyaml_on_the_shipped_files():
    import yaml

    files = sorted(p for p in ROOT.glob("**/*.yaml")
                   if not {".venv", "results", "broken_worlds"} & set(p.parts))
    assert len(files) > 20
    for path in files:
        data, index = load_yaml(path)
        assert data == yaml.safe_load(path.read_text()), path
        assert index.line_of(()) is not None


# --------------------------------------------------------------------------- class 1: non-finite
def _world_with(tmp_path: Path, old: str, new: str) -> Path:
    assert old in WORLD
    path = tmp_path / "w.yaml"
    path.write_text(WORLD.replace(old, new))
    return path


@pytest.mark.parametrize("old, new, line, key", [
    ("center: [2.0, 0.5]", "center: [.nan, 0.5]", 6, "obstacles[0].box.center[0]"),
    ("size: [0.4, 0.3]", "size: [.inf, 0.3]", 6, "obstacles[0].box.size[0]"),
    ("yaw_deg: 10", "yaw_deg: -.inf", 6, "obstacles[0].box.yaw_deg"),
    ("start: [0.5, 1.5, 0]", "start: [0.5, 1.5, .NaN]", 3, "start[2]"),
    ("size: [4.0, 3.0]", "size: [4.0, .Inf]", 2, "size[1]"),
])
def test_non_finite_numbers_in_a_world_are_refused_at_their_line(tmp_path, capsys, old, new,
                                                                   line, key):
    path = _world_with(tmp_path, old, new)
    _refused(capsys, ["validate", str(path)], f"{path}:{line}: {key}: expected a finite number")


def test_non_finite_numbers_in_movers_walls_and_robots_are_refused(tmp_path, capsys):
    path = tmp_path / "m.yaml"
    path.write_text(WORLD + "  - wall: {from: [1, 1], to: [1, .nan]}\nmovers:\n"
                    "  - {shape: {cylinder: {radius: 0.2}}, path: [[1, 2], [3, 2]], speed: .inf}\n")
    _refused(capsys, ["validate", str(path)], "obstacles[1].wall.to[1]: expected a finite number")
    robot = tmp_path / "robot.yaml"
    robot.write_text("urdf: diffbot.urdf\nsonar: {noise_std: .nan}\n")
    _refused(capsys, ["validate", str(robot)], f"{robot}:2: sonar.noise_std: expected a finite")


def test_a_world_built_in_code_with_nan_is_refused_too():
    from nav_bench.specs import world_from_data

    with pytest.raises(SpecError, match=r"size\[0\]: expected a finite number"):
        world_from_data({"size": [float("nan"), 3], "start": [1, 1], "goal": [2, 2]})
    with pytest.raises(SpecError, match=r"movers\[0\]\.speed: expected a finite number"):
        world_from_data({"size": [4, 3], "start": [1, 1], "goal": [3, 2], "movers": [
            {"shape": {"cylinder": {"radius": 0.2}}, "path": [[1, 2], [3, 2]],
             "speed": float("inf")}]})


@pytest.mark.parametrize("planner", ["eopc:RR=.nan", "eopc:RR=.inf", "goal_seek:v_max=-.inf"])
def test_non_finite_planner_parameters_are_refused_on_the_command_line(capsys, planner):
    _refused(capsys, ["episode", str(ROOT / "worlds/paper/open_room.yaml"), "--planner", planner],
             "expects a finite number")


def test_non_finite_planner_parameters_in_a_set_file_name_their_line(tmp_path, capsys):
    path = tmp_path / "p.yaml"
    path.write_text("planner: eopc\nparams:\n  RR: .nan\n")
    _refused(capsys, ["validate", str(path)], f"{path}:3: params.RR: expected a finite number")


def test_non_finite_episode_limits_are_refused(capsys):
    _refused(capsys, ["episode", str(ROOT / "worlds/paper/open_room.yaml"), "--planner",
                      "goal_seek", "--time-limit", "nan"], "time_s must be a finite number")


# --------------------------------------------------------------------------- class 4: semantics
@pytest.mark.parametrize("goal", ["[0.5, 1.5]", "[0.7, 1.6]"])
def test_a_goal_within_the_success_radius_of_the_start_is_refused(tmp_path, capsys, goal):
    path = _world_with(tmp_path, "goal: [3.5, 1.5]", f"goal: {goal}")
    _refused(capsys, ["validate", str(path)], f"{path}:4: goal:", "within the success radius")


def test_a_suite_whose_success_radius_covers_a_start_is_refused(tmp_path, capsys):
    world = tmp_path / "w.yaml"
    world.write_text(WORLD)
    suite = tmp_path / "s.yaml"
    suite.write_text(f"worlds: [{world}]\nplanners: {{a: goal_seek}}\n"
                     "limits: {goal_tolerance: 3.5}\n")
    _refused(capsys, ["validate", str(suite)], f"{suite}:3: limits.goal_tolerance:",
             "within the success radius of 3.5 m")


@pytest.mark.parametrize("params, key", [
    ("{planner: eopc, params: {lambda1: 0.2}}", "lambda1"),
    ("{planner: eopc, params: {free_below: 90}}", "free_below"),
    ("{planner: goal_seek, params: {slow_distance: [0.2, 1.0]}}", "slow_distance"),
])
def test_cross_parameter_rules_are_checked_before_simulating(tmp_path, capsys, params, key):
    world = tmp_path / "w.yaml"
    world.write_text(WORLD)
    suite = tmp_path / "s.yaml"
    suite.write_text(f"worlds: [{world}]\nplanners:\n  a: {params}\n")
    _refused(capsys, ["validate", str(suite)], f"{suite}:3: planners.a.params.{key}:")
    _refused(capsys, ["run", str(suite), "--out", str(tmp_path / "out")])
    assert not (tmp_path / "out").exists()


def test_cross_parameter_rules_on_the_command_line(capsys):
    _refused(capsys, ["episode", str(ROOT / "worlds/paper/open_room.yaml"), "--planner",
                      "eopc:lambda1=0.2"], "lambda1 > lambda2")


# --------------------------------------------------------------------------- class 2: memory budget
def test_a_world_whose_rasters_exceed_the_memory_budget_is_refused(tmp_path, capsys):
    path = _world_with(tmp_path, "size: [4.0, 3.0]", "size: [100000, 100000]")
    _refused(capsys, ["validate", str(path)], f"{path}:2: size:", "over the memory budget")
    _refused(capsys, ["show", str(path), "-o", str(tmp_path / "w.png")], "over the memory budget")
    assert not (tmp_path / "w.png").exists()


def test_rasters_and_planner_grids_refuse_to_allocate_past_the_budget():
    from nav_bench.errors import InputError
    from nav_bench.mapping.grid import GridFrame
    from nav_bench.world.geometry import static_geometry
    from nav_bench.world.raster import rasterize

    world = yamlio.parse_yaml(WORLD)[0]
    from nav_bench.specs import world_from_data

    geometry = static_geometry(world_from_data(world))
    with pytest.raises(InputError, match="memory budget"):
        rasterize(geometry, 1e-4)
    with pytest.raises(InputError, match="cells a planner's map may have"):
        GridFrame.from_bounds((0, 0, 1000, 1000), 0.01)
