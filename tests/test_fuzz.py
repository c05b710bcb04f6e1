"""Issue 11's fuzz test: malformed worlds and suites thrown at ``validate`` and ``run``.

Each of the 240 cases (120 worlds, 120 suites) is a valid file damaged by a seeded mutation:
a deleted key, a renamed key, a swapped type, a non-finite or a huge number, or damaged YAML
text (deleted characters, stray brackets, anchors and tags). Every one must end in exit 0 or
2, print no traceback, say what is wrong in lines that each name the file, and finish within
a time bound (a hang guard, not a speed test). The CLI runs in-process through ``main()``.
``run`` is given every case ``validate`` refuses (it must refuse it too, before making its
folder); the cases that stay valid are played for real by the ``slow`` test.
"""

from __future__ import annotations

import contextlib
import copy
import random
import re
import signal
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from nav_bench.cli import main

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

CASES = 120  # of each kind
BOUND_S = 60  # per case; far above what any case needs

WORLD: dict[str, Any] = {
    "name": "fz",
    "size": [4.0, 3.0],
    "start": [0.5, 1.5, 0.0],
    "goal": [3.5, 1.5],
    "wall_height": 0.6,
    "obstacles": [
        {"box": {"center": [2.0, 0.4], "size": [0.4, 0.3], "yaw_deg": 10.0}},
        {"cylinder": {"center": [2.0, 2.6], "radius": 0.2}},
        {"wall": {"from": [1.0, 0.1], "to": [1.0, 0.6], "thickness": 0.1}},
        {"polyline": {"points": [[3.0, 2.5], [3.5, 2.5], [3.5, 2.9]], "thickness": 0.1}},
    ],
    "movers": [{"shape": {"cylinder": {"radius": 0.15}}, "path": [[1.5, 2.2], [2.5, 2.2]],
                "speed": 0.2, "mode": "pingpong"}],
}


def suite_data(world_file: Path) -> dict[str, Any]:
    return {
        "name": "fz",
        "worlds": [str(world_file)],
        "planners": {"seek": {"planner": "goal_seek", "params": {"v_max": 0.4}},
                     "bug": "bug2"},
        "seeds": 1,
        "limits": {"time_s": 4.0, "stuck_s": 2.0, "wall_s": 60.0},
        "robot": {"sonar": {"noise_std": 0.01}},
    }


SWAPS: list[Any] = ["text", 7, -1, 0, True, None, [], {}, [1, 2, 3], {"x": 1}, "1..3", 0.0]
BIG: list[Any] = [1e308, -1e308, 10**30, 1e6, -1e6, 2**63]
NON_FINITE = [float("nan"), float("inf"), float("-inf")]
TEXT_DAMAGE = ["{", "}", "[", "]", ": ", "- ", "&a ", "*a", "*nope ", "!!python/name:os.system ",
               "!!binary ", "\t", "'", '"', "<<: ", "? ", "%YAML 1.1\n", "\x00", "\u202e"]


def _paths(node: Any, prefix: tuple = ()) -> Iterator[tuple]:
    """Every key path in a tree of dicts and lists (the root excluded)."""
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(
        node, list) else ()
    for key, value in items:
        yield (*prefix, key)
        yield from _paths(value, (*prefix, key))


def _parent(tree: Any, path: tuple) -> Any:
    for key in path[:-1]:
        tree = tree[key]
    return tree


def mutate(data: dict[str, Any], rng: random.Random) -> str:
    """YAML text of ``data`` damaged by one to three seeded mutations."""
    data = copy.deepcopy(data)
    for _ in range(rng.choice((1, 1, 2, 3))):
        paths = list(_paths(data))
        numeric = [p for p in paths if isinstance(_parent(data, p)[p[-1]], (int, float))
                   and not isinstance(_parent(data, p)[p[-1]], bool)]
        kind = rng.choice(("delete", "rename", "swap", "nonfinite", "huge", "huge"))
        if kind in ("nonfinite", "huge") and numeric:
            path = rng.choice(numeric)
            _parent(data, path)[path[-1]] = rng.choice(NON_FINITE if kind == "nonfinite" else BIG)
        elif paths:
            path = rng.choice(paths)
            parent = _parent(data, path)
            if kind == "delete":
                del parent[path[-1]]
            elif kind == "rename" and isinstance(parent, dict):
                parent[str(path[-1])[:-1] + "x"] = parent.pop(path[-1])
            else:
                parent[path[-1]] = copy.deepcopy(rng.choice(SWAPS))
    text = yaml.safe_dump(data, sort_keys=False, default_flow_style=rng.random() < 0.3)
    if rng.random() < 0.3:  # damage the text itself
        at = rng.randrange(len(text))
        if rng.random() < 0.5:
            text = text[:at] + text[at + rng.randrange(1, 20):]
        else:
            text = text[:at] + rng.choice(TEXT_DAMAGE) + text[at:]
    return text


@contextlib.contextmanager
def time_bound(seconds: int) -> Iterator[None]:
    """Fail (rather than hang) if the block runs longer than ``seconds``."""
    def expired(signum: int, frame: Any) -> None:
        raise TimeoutError(f"a fuzz case ran longer than {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def check_cli(argv: list[str], path: Path, capsys: pytest.CaptureFixture[str]) -> int:
    with time_bound(BOUND_S):
        code = main(argv)
    err = capsys.readouterr().err
    assert code in (0, 2), (path.read_text(errors="replace"), err)
    assert "Traceback" not in err, err
    if code == 2:
        lines = err.strip().splitlines()
        assert lines, "exit 2 without a message"
        # one line per problem, each naming the file at fault (the suite's or its world's;
        # run's line names the command first)
        assert all(re.match(rf"(nav-bench run: error: )?{re.escape(str(path.parent))}/\S+\.yaml"
                            rf"(:\d+)?: \S", line) for line in lines), err
    return code


def cases(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    good_world = tmp_path / "good_world.yaml"
    good_world.write_text(yaml.safe_dump(WORLD, sort_keys=False))
    for i in range(CASES):
        path = tmp_path / f"world_{i}.yaml"
        path.write_text(mutate(WORLD, random.Random(i)))
        yield "world", path
    for i in range(CASES):
        rng = random.Random(10_000 + i)
        world = good_world
        if rng.random() < 0.25:  # a suite over a damaged world
            world = tmp_path / f"suite_world_{i}.yaml"
            world.write_text(mutate(WORLD, rng))
        path = tmp_path / f"suite_{i}.yaml"
        path.write_text(mutate(suite_data(world), rng))
        yield "suite", path


def test_fuzzed_worlds_and_suites_end_in_exit_0_or_2_without_a_traceback(tmp_path, capsys):
    if not hasattr(signal, "SIGALRM"):
        pytest.skip("needs SIGALRM for the time bound")
    seen = {"world": [0, 0], "suite": [0, 0]}  # kind -> [valid, refused]
    for kind, path in cases(tmp_path):
        code = check_cli(["validate", str(path)], path, capsys)
        seen[kind][code == 2] += 1
        if code == 2 and kind == "suite":
            out = tmp_path / f"out_{path.stem}"
            assert check_cli(["run", str(path), "--out", str(out), "--quiet", "--workers", "1"],
                             path, capsys) == 2
            assert not out.exists()  # refused before anything was made
    assert sum(sum(v) for v in seen.values()) >= 200
    # the mutations are mostly fatal, but not all: both outcomes are exercised
    assert seen["world"][1] > CASES // 2 and seen["suite"][1] > CASES // 2, seen
    assert seen["world"][0] > 0 and seen["suite"][0] > 0, seen


PLAYED = 6  # valid fuzzed suites played for real (a few seconds each)


@pytest.mark.slow
def test_fuzzed_suites_that_stay_valid_run_to_the_end(tmp_path, capsys):
    """The first suites ``validate`` accepts are played (real episodes, 4 s simulated each)."""
    if not hasattr(signal, "SIGALRM"):
        pytest.skip("needs SIGALRM for the time bound")
    played = 0
    for kind, path in cases(tmp_path):
        if played == PLAYED:
            break
        if kind != "suite" or main(["validate", str(path)]) != 0:
            capsys.readouterr()
            continue
        capsys.readouterr()
        out = tmp_path / f"out_{path.stem}"
        code = check_cli(["run", str(path), "--out", str(out), "--quiet", "--workers", "1",
                          "--no-report"], path, capsys)
        assert code == 0
        played += 1
    assert played == PLAYED
