"""Issue 11: nothing a user types can crash nav-bench, hang it, or lose their files.

One section per defect class. Every refusal is exit 2 with one line naming the file (and the
line and key where there is one), never a traceback.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from nav_bench import yamlio
from nav_bench.cli import main
from nav_bench.errors import SpecError
from nav_bench.yamlio import load_yaml, parse_yaml

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # worker processes import tests.helpers.* by name
    sys.path.insert(0, str(ROOT))

WORLD = """\
name: w
size: [4.0, 3.0]
start: [0.5, 1.5, 0]
goal: [3.5, 1.5]
wall_height: 0.5
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
    _refused(capsys, ["validate", str(path)], f"{path}:1:", "nested deeper than 100 levels")


def test_nesting_past_the_bound_but_within_libyamls_is_refused_by_the_composer(tmp_path, capsys):
    # 150 levels: libyaml's own flow limit (1000, PyYAML >= 6.0.4) does not fire, ours does
    path = tmp_path / "deep.yaml"
    path.write_text("name:\n  - " + "[" * 150 + "]" * 150 + "\n")
    _refused(capsys, ["validate", str(path)], f"{path}:2:", "nested deeper than 100 levels")


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
    ("center: [2.0, 0.5]", "center: [.nan, 0.5]", 7, "obstacles[0].box.center[0]"),
    ("size: [0.4, 0.3]", "size: [.inf, 0.3]", 7, "obstacles[0].box.size[0]"),
    ("yaw_deg: 10", "yaw_deg: -.inf", 7, "obstacles[0].box.yaw_deg"),
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
    from nav_bench.world.load import world_from_data

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


@pytest.mark.parametrize("key", ["time_s", "stuck_s", "goal_tolerance", "control_hz"])
def test_non_finite_episode_settings_are_refused(key):
    from nav_bench.episode import EpisodeSettings
    from nav_bench.errors import InputError

    with pytest.raises(InputError, match=f"{key} must be a finite number"):
        EpisodeSettings(**{key: float("nan")})


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
    from nav_bench.world.load import world_from_data

    geometry = static_geometry(world_from_data(world))
    with pytest.raises(InputError, match="memory budget"):
        rasterize(geometry, 1e-4)
    with pytest.raises(InputError, match="cells a planner's map may have"):
        GridFrame.from_bounds((0, 0, 1000, 1000), 0.01)


# --------------------------------------------------------------------------- class 5: user's code
def test_a_planner_module_that_raises_on_import_is_one_line(tmp_path, capsys, monkeypatch):
    (tmp_path / "broken_planner_mod.py").write_text("import math\n\nx = 1 / 0\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    err = _refused(capsys, ["episode", str(ROOT / "worlds/paper/open_room.yaml"), "--planner",
                            "broken_planner_mod:Planner"],
                   "planner module 'broken_planner_mod' raised on import at",
                   "broken_planner_mod.py:3: ZeroDivisionError")
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("argv, needle", [
    (["episode", "w.yaml", "--seed", "-1"], "--seed: expected a whole number >= 0, got -1"),
    (["run", "s.yaml", "--workers", "0"], "--workers: expected a whole number >= 1"),
    (["episode", "w.yaml", "--time-limit", "nan"], "--time-limit: expected a finite number > 0"),
    (["generate", "maze", "--seed", "-3", "-o", "x.yaml"], "--seed: expected a whole number"),
    (["import", "movingai", "m.map", "--cell", "inf", "-o", "x.yaml"], "--cell: expected a"),
    (["import", "ros", "m.yaml", "--start", "nan,1", "-o", "x.yaml"], "expected finite X,Y"),
])
def test_bad_numbers_on_the_command_line_are_one_line_exit_2(capsys, argv, needle):
    with pytest.raises(SystemExit) as info:
        main(argv)
    err = capsys.readouterr().err
    assert info.value.code == 2
    assert needle in err and len(err.strip().splitlines()) == 1, err


def _tiny_suite(tmp_path: Path, seeds: int = 1) -> Path:
    from tests.helpers import tiny

    return tiny.write_suite(tmp_path, seeds=seeds)


def test_out_naming_a_file_is_bad_input(tmp_path, capsys):
    suite = _tiny_suite(tmp_path)
    target = tmp_path / "a_file"
    target.write_text("mine\n")
    _refused(capsys, ["run", str(suite), "--out", str(target), "--quiet"], "is a file")
    assert target.read_text() == "mine\n"


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="root writes into read-only folders")
def test_out_in_a_read_only_folder_is_bad_input(tmp_path, capsys):
    suite = _tiny_suite(tmp_path)
    locked = tmp_path / "ro"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        _refused(capsys, ["run", str(suite), "--out", str(locked / "out"), "--quiet"],
                 "cannot write the results folder")
    finally:
        locked.chmod(0o700)


def test_an_os_error_is_one_line_not_a_traceback(tmp_path, capsys):
    code = main(["show", str(ROOT / "worlds/paper/open_room.yaml"), "-o",
                 str(tmp_path / "no_such_folder" / "w.png")])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert "no_such_folder" in err


# --------------------------------------------------------------------------- class 6: user's files
def test_out_into_a_folder_with_the_users_files_is_refused(tmp_path, capsys):
    suite = _tiny_suite(tmp_path)
    out = tmp_path / "mine"
    out.mkdir()
    (out / "report.md").write_text("my notes\n")
    (out / "summary.csv").write_text("a,b\n")
    _refused(capsys, ["run", str(suite), "--out", str(out), "--quiet"],
             "is not empty and holds no run")
    assert sorted(p.name for p in out.iterdir()) == ["report.md", "summary.csv"]
    assert (out / "report.md").read_text() == "my notes\n"


def test_a_second_writer_is_refused_naming_the_first(tmp_path):
    from nav_bench.batch.runner import run_suite
    from nav_bench.batch.store import ResultsStore
    from nav_bench.errors import InputError
    from tests.helpers import fake_episodes

    suite = _tiny_suite(tmp_path)
    out = run_suite(suite, workers=1, out=tmp_path / "out", progress=False,
                    episode_fn=fake_episodes.instant)
    first = ResultsStore(out)
    first.lock()  # as a live run (or a first --resume) holds it
    try:
        with pytest.raises(InputError, match=rf"being written by another nav-bench run "
                                             rf"\(process {os.getpid()}\)"):
            run_suite(None, resume=out, workers=1, progress=False,
                      episode_fn=fake_episodes.instant)
    finally:
        first.unlock()
    run_suite(None, resume=out, workers=1, progress=False, episode_fn=fake_episodes.instant)
    assert len(ResultsStore(out).rows()) == 4


# --------------------------------------------------------------------------- class 7: disk full
def test_a_full_disk_stops_the_run_truthfully_and_resume_redoes_lost_traces(tmp_path,
                                                                              monkeypatch):
    import errno
    import json

    from nav_bench.batch import runner, store
    from nav_bench.batch.runner import RunStorageError, run_suite
    from nav_bench.batch.store import ResultsStore
    from nav_bench.episode.trace import Trace
    from tests.helpers import fake_episodes

    suite = _tiny_suite(tmp_path, seeds=3)  # 12 episodes
    out = tmp_path / "out"
    saved = {"n": 0}
    real_save, real_write = Trace.save, store.atomic_write_text

    def save(self, path):  # the fourth trace finds the disk full
        saved["n"] += 1
        if saved["n"] >= 4:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return real_save(self, path)

    def write(path, text):  # once full, only the reserved space lets run.json be written
        if saved["n"] >= 4 and (out / store.RESERVE).exists():
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return real_write(path, text)

    monkeypatch.setattr(Trace, "save", save)
    monkeypatch.setattr(store, "atomic_write_text", write)
    with pytest.raises(RunStorageError, match="disk full") as info:
        run_suite(suite, workers=1, out=out, progress=False,
                  episode_fn=fake_episodes.instant_traced)
    assert info.value.exit_code == 1 and f"--resume {out}" in str(info.value)
    meta = json.loads((out / "run.json").read_text())
    assert meta["status"] == "failed" and "disk full" in meta["error"]
    rows = ResultsStore(out).rows()
    assert len(rows) == 4 and "trace_error" in rows[-1]
    assert not (out / store.RESERVE).exists()

    monkeypatch.undo()  # space freed
    assert runner.run_suite is run_suite
    run_suite(None, resume=out, workers=1, progress=False,
              episode_fn=fake_episodes.instant_traced)
    rows = ResultsStore(out).rows()
    assert len(rows) == 12 and len({r["job_id"] for r in rows}) == 12
    assert all("trace_error" not in r and (out / r["trace"]).exists() for r in rows)
    assert json.loads((out / "run.json").read_text())["status"] == "complete"


# --------------------------------------------------------------------------- resume, exit codes
def test_resume_retry_errors_replays_error_rows_and_strict_exits_3(tmp_path, capsys):
    from nav_bench.batch.runner import run_suite
    from nav_bench.batch.store import ResultsStore
    from tests.helpers import fake_episodes

    suite = _tiny_suite(tmp_path, seeds=2)  # seed 1 raises in seed_dependent
    out = run_suite(suite, workers=1, out=tmp_path / "out", progress=False,
                    episode_fn=fake_episodes.seed_dependent)
    errors = [r for r in ResultsStore(out).rows() if r["outcome"] == "error"]
    assert len(errors) == 4
    run_suite(None, resume=out, workers=1, progress=False, episode_fn=fake_episodes.instant)
    assert sum(r["outcome"] == "error" for r in ResultsStore(out).rows()) == 4  # kept
    run_suite(None, resume=out, workers=1, progress=False, episode_fn=fake_episodes.instant,
              retry_errors=True)
    rows = ResultsStore(out).rows()
    assert len(rows) == 8 and not any(r["outcome"] == "error" for r in rows)


def test_run_strict_exits_3_when_error_rows_exist(tmp_path, capsys, monkeypatch):
    import nav_bench.batch.runner as runner
    from tests.helpers import fake_episodes

    real = runner.run_suite
    monkeypatch.setattr(runner, "run_suite", lambda *a, **k: real(
        *a, **{**k, "episode_fn": fake_episodes.seed_dependent}))
    suite = _tiny_suite(tmp_path, seeds=2)
    argv = ["run", str(suite), "--workers", "1", "--quiet", "--no-report"]
    assert main([*argv, "--out", str(tmp_path / "a")]) == 0  # error rows are results
    assert "4 episodes ended in an error row" in capsys.readouterr().err
    assert main([*argv, "--out", str(tmp_path / "b"), "--strict"]) == 3
    assert f"--resume {tmp_path / 'b'} --retry-errors" in capsys.readouterr().err


def test_ctrl_c_outside_a_run_exits_130(monkeypatch, capsys):
    import nav_bench.cli as cli

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "cmd_planners", interrupted)
    assert main(["planners"]) == 130


# --------------------------------------------------------------------------- class 8: reports
@pytest.mark.parametrize("change, needle", [
    (lambda r: r.pop("world"), "missing field 'world'"),
    (lambda r: r.update(spl="high"), "field 'spl' should be float, got 'high'"),
    (lambda r: r.update(outcome="teleported", success=False), "outcome 'teleported' is not one of"),
    (lambda r: r.update(seed=-4), "seed -4 is negative"),
])
def test_report_refuses_rows_it_cannot_trust_naming_the_line(tmp_path, capsys, change, needle):
    import json
    import shutil

    run = tmp_path / "run_a"
    shutil.copytree(ROOT / "tests/data/results/run_a", run)
    path = run / "episodes.jsonl"
    lines = path.read_text().splitlines()
    row = json.loads(lines[2])
    change(row)
    lines[2] = json.dumps(row)
    path.write_text("\n".join(lines) + "\n")
    err = _refused(capsys, ["report", str(run)], f"{path}:3: ", needle)
    assert len(err.strip().splitlines()) == 1
