"""Suite files: validation with file/key/line, sweeps, seeds, robots, generators, job ids."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from nav_bench.batch.suite import expand, load_suite, parse_seeds, sweep
from nav_bench.errors import SpecError

ROOT = Path(__file__).resolve().parents[2]

WORLD = """\
name: {name}
size: [3.0, 3.0]
start: [0.5, 1.5, 0]
goal: [2.5, 1.5]
"""


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A working folder with two tiny worlds; relative paths resolve against it."""
    (tmp_path / "worlds").mkdir()
    for name in ("alpha", "beta"):
        (tmp_path / "worlds" / f"{name}.yaml").write_text(WORLD.format(name=name))
    monkeypatch.chdir(tmp_path)
    return tmp_path


def write(folder: Path, text: str, name: str = "suite.yaml") -> Path:
    path = folder / name
    path.write_text(text)
    return path


def spec_error(path: Path) -> SpecError:
    with pytest.raises(SpecError) as info:
        load_suite(path)
    return info.value


def test_sweep_expands_to_grid_product_with_labels(folder):
    path = write(folder, """\
name: sweep
worlds: [worlds/*.yaml]
planners:
  seek: {planner: goal_seek}
  grid: {planner: goal_seek, params: {v_max: [0.3, 0.4, 0.5], k_heading: [1.0, 2.0]}}
seeds: 3
limits: {time_s: 20}
""")
    suite = load_suite(path)
    labels = [p.label for p in suite.planners]
    assert labels == ["seek", "grid[v_max=0.3,k_heading=1]", "grid[v_max=0.3,k_heading=2]",
                      "grid[v_max=0.4,k_heading=1]", "grid[v_max=0.4,k_heading=2]",
                      "grid[v_max=0.5,k_heading=1]", "grid[v_max=0.5,k_heading=2]"]
    grid = suite.planners[3]
    assert grid.spec.params == {"v_max": 0.4, "k_heading": 1.0}
    assert grid.params["v_max"] == 0.4 and grid.params["stop_distance"] == 0.35  # defaults filled
    # the last combination is goal_seek's defaults: the same parameters as "seek"
    assert len({p.params_id for p in suite.planners}) == 6
    assert suite.planners[-1].params_id == suite.planners[0].params_id
    jobs = expand(suite)
    assert len(jobs) == 2 * 7 * 3
    assert [j.world_name for j in jobs[:21]] == ["alpha"] * 21
    assert [j.seed for j in jobs[:3]] == [0, 1, 2]
    assert len({j.job_id for j in jobs}) == len(jobs)
    assert jobs[0].world_file == "worlds/alpha.yaml"
    assert jobs[0].settings["time_s"] == 20.0 and jobs[0].settings["control_hz"] == 10.0


def test_job_ids_are_stable_and_follow_content(folder):
    text = """\
worlds: [worlds/alpha.yaml]
planners: {seek: {planner: goal_seek}}
seeds: [4, 7]
"""
    path = write(folder, text)
    first = [j.job_id for j in expand(load_suite(path))]
    assert first == [j.job_id for j in expand(load_suite(path))]
    assert first[0].startswith("alpha__seek__diffbot__s4__")
    # an edited world is a different episode
    (folder / "worlds" / "alpha.yaml").write_text(WORLD.format(name="alpha").replace("2.5, 1.5",
                                                                                      "2.4, 1.5"))
    assert expand(load_suite(path))[0].job_id != first[0]


def test_seed_forms():
    assert parse_seeds(3) == [0, 1, 2]
    assert parse_seeds([5, 2]) == [5, 2]
    assert parse_seeds("3..6") == [3, 4, 5, 6]
    for bad in (0, [], [1, 1], "5..2", "x", True, [-1]):
        with pytest.raises(ValueError):
            parse_seeds(bad)


def test_sweep_without_lists_is_one_set():
    assert sweep({"a": 1}) == [({"a": 1}, "")]


def test_robot_overrides_sweep_and_are_part_of_identity(folder):
    path = write(folder, """\
worlds: [worlds/alpha.yaml]
planners: {seek: {planner: goal_seek}}
robot: {sonar: {noise_std: [0.0, 0.02]}, odometry: {wheel_noise: 0.05}}
""")
    suite = load_suite(path)
    assert [r.label for r in suite.robots] == ["diffbot[sonar.noise_std=0]",
                                               "diffbot[sonar.noise_std=0.02]"]
    assert [r.spec.sonar.noise_std for r in suite.robots] == [0.0, 0.02]
    assert all(r.spec.odometry.wheel_noise == 0.05 for r in suite.robots)
    assert suite.robots[0].robot_id != suite.robots[1].robot_id
    jobs = expand(suite)
    assert [j.robot_label for j in jobs] == [r.label for r in suite.robots]
    assert jobs[0].job_id != jobs[1].job_id


def test_robot_urdf_swap_changes_robot_id(folder):
    urdf = (ROOT / "robots" / "diffbot.urdf").read_text()
    (folder / "other.urdf").write_text(urdf.replace("<robot name=", "<!-- changed -->\n<robot name=",
                                                    1))
    shutil.copy(ROOT / "robots" / "diffbot.urdf", folder / "same.urdf")
    path = write(folder, """\
worlds: [worlds/alpha.yaml]
planners: {seek: {planner: goal_seek}}
robot: {urdf: [same.urdf, other.urdf]}
""")
    robots = load_suite(path).robots
    assert [r.label for r in robots] == ["diffbot[urdf=same.urdf]", "diffbot[urdf=other.urdf]"]
    assert robots[0].spec.urdf_path == (folder / "same.urdf").resolve()
    assert robots[0].robot_id != robots[1].robot_id


def test_generator_family_calls_generate_world(folder, monkeypatch):
    import nav_bench.world.generate as generate

    calls = []

    def fake_generate(kind, seed, settings):
        calls.append((kind, seed, settings))
        return {"size": [4.0, 3.0], "start": [0.5, 0.5], "goal": [3.5, 2.5],
                "obstacles": [{"cylinder": {"center": [2.0, 1.5], "radius": 0.2 + 0.1 * seed}}]}

    monkeypatch.setattr(generate, "generate_world", fake_generate)
    path = write(folder, """\
worlds:
  - worlds/beta.yaml
  - {generate: maze, seeds: "2..3", set: {cells: [4, 3]}}
  - {generate: maze, name: small, seeds: 1}
planners: {seek: {planner: goal_seek}}
""")
    suite = load_suite(path)
    assert calls == [("maze", 2, {"cells": [4, 3]}), ("maze", 3, {"cells": [4, 3]}),
                     ("maze", 0, {})]
    assert [w.name for w in suite.worlds] == ["beta", "maze_2", "maze_3", "small_0"]
    assert suite.worlds[2].spec.obstacles[0].cylinder.radius == pytest.approx(0.5)
    assert suite.worlds[1].file is None
    assert suite.worlds[1].source == {"generate": "maze", "seed": 2, "set": {"cells": [4, 3]}}


def test_generator_family_with_the_real_generators(folder):
    path = write(folder, """\
worlds: [{generate: maze, seeds: 2}]
planners: {seek: {planner: goal_seek}}
""")
    suite = load_suite(path)
    assert [w.name for w in suite.worlds] == ["maze_0", "maze_1"]
    assert suite.worlds[0].digest != suite.worlds[1].digest


@pytest.mark.parametrize(("text", "key", "line", "words"), [
    ("worlds: [worlds/alpha.yaml]\nplanners: {a: goal_seek}\nseed: 3\n",
     "seed", 3, "unknown key"),
    ("worlds:\n  - worlds/alpha.yaml\n  - worlds/gamma*.yaml\nplanners: {a: goal_seek}\n",
     "worlds[1]", 3, "matches no world file"),
    ("worlds: [worlds/alpha.yaml]\nplanners:\n  rr:\n    planner: goal_seek\n"
     "    params: {v_maxx: [0.1, 0.2]}\n", "planners.rr.params.v_maxx", 5, "Did you mean 'v_max'"),
    ("worlds: [worlds/alpha.yaml]\nplanners:\n  rr: {planner: goal_sek}\n",
     "planners.rr.planner", 3, "Did you mean 'goal_seek'"),
    ("worlds: [worlds/alpha.yaml]\nplanners:\n  rr: {planner: goal_seek, params: {v_max: -1}}\n",
     "planners.rr.params.v_max", 3, ">= 0.0"),
    ("worlds: [worlds/alpha.yaml]\nplanners: {a: goal_seek}\nseeds: 0\n",
     "seeds", 3, "at least 1"),
    ("worlds: [worlds/alpha.yaml]\nplanners: {a: goal_seek}\nlimits:\n  time_s: -5\n",
     "limits.time_s", 4, "greater than 0"),
    ("worlds: [worlds/alpha.yaml]\nplanners: {a: goal_seek}\nlimits: {physics_hz: 5}\n",
     "limits", 3, "physics_hz must be at least control_hz"),
    ("worlds: [worlds/alpha.yaml]\nplanners: {a: goal_seek}\nrobot:\n  sonar:\n"
     "    noise_sd: 0.1\n", "robot.sonar.noise_sd", 5, "unknown key"),
    ("worlds: [worlds/alpha.yaml, worlds/a*.yaml]\nplanners: {a: goal_seek}\n"
     "robot: {file: nowhere.yaml}\n", "robot.file", 3, "not found"),
    ("worlds: [worlds/alpha.yaml]\nplanners:\n  'a b': goal_seek\n",
     "planners.a b", 3, "letters, digits"),
    ("worlds: [worlds/alpha.yaml]\nplanners: {a: missing.yaml}\n",
     "planners.a", 2, "not found"),
    ("worlds: [{generate: maze, seeds: 2, sett: {}}]\nplanners: {a: goal_seek}\n",
     "worlds[0].sett", 1, "unknown key"),
    ("worlds: [{generate: mase, seeds: 2}]\nplanners: {a: goal_seek}\n",
     "worlds[0].generate", 1, "Did you mean 'maze'"),
])
def test_bad_suites_name_key_and_line(folder, text, key, line, words):
    path = write(folder, text)
    err = spec_error(path)
    assert err.file == str(path)
    assert err.key_path == key
    assert err.line == line
    assert words in err.problem


def test_two_worlds_with_one_name_are_refused(folder):
    (folder / "other").mkdir()
    (folder / "other" / "alpha.yaml").write_text(WORLD.format(name="alpha"))
    path = write(folder, "worlds: [worlds/alpha.yaml, other/alpha.yaml]\nplanners: {a: goal_seek}\n")
    err = spec_error(path)
    assert err.key_path == "worlds[1]" and "two worlds are named 'alpha'" in err.problem


def test_bad_world_file_names_the_world_file(folder):
    (folder / "worlds" / "broken.yaml").write_text("size: [3, 3]\nstart: [1, 1]\ngoal: [9, 9]\n")
    path = write(folder, "worlds: [worlds/broken.yaml]\nplanners: {a: goal_seek}\n")
    err = spec_error(path)
    assert err.file.endswith("broken.yaml") and err.key_path == "goal" and err.line == 3


def test_paths_fall_back_to_the_suite_folder(folder, tmp_path_factory, monkeypatch):
    (folder / "suites").mkdir()
    path = write(folder / "suites", "worlds: [../worlds/*.yaml]\nplanners: {a: goal_seek}\n")
    monkeypatch.chdir(tmp_path_factory.mktemp("elsewhere"))
    suite = load_suite(path)
    assert [w.name for w in suite.worlds] == ["alpha", "beta"]
    assert Path(suite.worlds[0].file).resolve() == (folder / "worlds" / "alpha.yaml").resolve()


def test_shipped_suites_load(monkeypatch):
    monkeypatch.chdir(ROOT)
    smoke = load_suite(ROOT / "configs" / "suites" / "smoke.yaml")
    assert smoke.name == "smoke" and len(expand(smoke)) == 4
    default = ROOT / "configs" / "suites" / "default.yaml"
    needed = [ROOT / "configs" / "planners" / f for f in ("eopc_paper.yaml", "eopc_normalized.yaml")]
    if not all(p.exists() for p in needed):
        pytest.skip("configs/planners/eopc_*.yaml not written yet")
    suite = load_suite(default)
    assert suite.settings["time_s"] == 300.0
    assert len(suite.seeds) == 5 and len(suite.worlds) == len(list((ROOT / "worlds" / "paper")
                                                                   .glob("*.yaml")))


def test_limits_set_the_oscillating_robots_stuck_disc(folder):
    suite = load_suite(write(folder, "worlds: [worlds/alpha.yaml]\nplanners: {g: {planner: goal_seek}}\n"
                                     "limits: {stuck_area_radius: 0.8}\n"))
    assert suite.settings["stuck_area_radius"] == 0.8
    default = load_suite(write(folder, "worlds: [worlds/alpha.yaml]\nplanners: {g: {planner: goal_seek}}\n",
                               name="default.yaml"))
    assert default.settings["stuck_area_radius"] == 0.6
    err = spec_error(write(folder, "worlds: [worlds/alpha.yaml]\nplanners: {g: {planner: goal_seek}}\n"
                                   "limits: {stuck_area_radius: -1}\n", name="bad.yaml"))
    assert "stuck_area_radius" in str(err)
