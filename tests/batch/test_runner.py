"""The batch runner: real episodes in worker processes, crash safety, resume, bad planners.

Runtime: ~30 s on 2 cores (real PyBullet episodes on 3-4 m worlds; two runner subprocesses).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # worker processes import tests.helpers.* by name
    sys.path.insert(0, str(ROOT))

from nav_bench import compiled  # noqa: E402
from nav_bench.batch.runner import numpy_simd, run_suite  # noqa: E402
from nav_bench.batch.store import ResultsStore, ResultsWarning, check_row  # noqa: E402
from nav_bench.batch.suite import expand, load_suite  # noqa: E402
from nav_bench.batch.worker import finish_row, run_job  # noqa: E402
from nav_bench.episode.row import WALL_CLOCK_FIELDS  # noqa: E402
from nav_bench.errors import InputError, UnknownNameError  # noqa: E402
from tests.helpers import fake_episodes, tiny  # noqa: E402


def without_wall(rows):
    return {r["job_id"]: {k: v for k, v in r.items() if k not in WALL_CLOCK_FIELDS} for r in rows}


def test_small_suite_real_episodes_valid_rows_reproducible(tmp_path):
    suite = tiny.write_suite(tmp_path)  # 2 worlds x 2 parameter sets x 2 seeds
    out = run_suite(suite, workers=2, out=tmp_path / "a", progress=False)
    rows = ResultsStore(out).rows()
    jobs = expand(load_suite(suite))
    assert len(rows) == 8 and {r["job_id"] for r in rows} == {j.job_id for j in jobs}
    for row in rows:
        check_row(row)
        assert row["outcome"] == "reached", row["error"]
        assert row["time_limit_s"] == 15.0 and row["robot"] == "diffbot"
        with np.load(out / row["trace"]) as trace:
            xy = trace["true_pose"][:, :2]
        # the stored trace is the episode's trajectory: its length is the row's path length
        assert np.hypot(*np.diff(xy, axis=0).T).sum() == pytest.approx(row["path_length_m"],
                                                                        rel=1e-4)
    seek = {(r["world"], r["seed"]): r for r in rows if r["label"] == "seek"}
    slow = {(r["world"], r["seed"]): r for r in rows if r["label"] == "slow"}
    assert all(slow[k]["time_s"] > seek[k]["time_s"] for k in seek)  # v_max 0.3 vs 0.5

    meta = json.loads((out / "run.json").read_text())
    assert meta["status"] == "complete" and meta["done"] == 8 and meta["total"] == 8
    assert meta["executor"]["name"] == "local" and meta["workers"] == 2
    for key in ("python", "pybullet", "numpy", "host", "started", "ended", "nav_bench"):
        assert meta[key], key
    assert meta["numpy_simd"] == numpy_simd()  # the rows' last bits depend on it (README)
    assert meta["numba"] == compiled.numba_version()  # the CPU times depend on it
    assert meta["suite"]["planners"]["slow"]["params"]["v_max"] == 0.3

    # the same suite again, one worker: identical rows but for wall-clock time
    again = run_suite(suite, workers=1, out=tmp_path / "b", progress=False)
    assert without_wall(ResultsStore(again).rows()) == without_wall(rows)

    # any episode replayed alone gives its row
    job = jobs[5]
    alone = finish_row(run_job(job).row, job).to_json()
    stored = without_wall(rows)[job.job_id]
    assert {k: v for k, v in alone.items() if k not in WALL_CLOCK_FIELDS | {"trace"}} == {
        k: v for k, v in stored.items() if k != "trace"}


def test_raising_and_hanging_planners_become_error_rows(tmp_path):
    suite = tiny.write_suite(
        tmp_path, seeds=1, worlds=f"['{tmp_path}/worlds/tiny_open.yaml']",
        limits="{time_s: 15, wall_s: 3}",
        planners="{seek: goal_seek, raises: 'tests.helpers.bad_planners:Raises', "
                 "hangs: {planner: 'tests.helpers.bad_planners:Hangs', params: {after: 2}}}")
    out = run_suite(suite, workers=2, out=tmp_path / "out", progress=False)
    rows = {r["label"]: r for r in ResultsStore(out).rows()}
    for row in rows.values():
        check_row(row)
    assert rows["seek"]["outcome"] == "reached"
    assert rows["raises"]["outcome"] == "error"
    assert "planner failure on purpose" in rows["raises"]["error"]
    assert rows["hangs"]["outcome"] == "error"
    assert "wall-clock limit of 3 s" in rows["hangs"]["error"]
    assert rows["hangs"]["wall_s"] == pytest.approx(3.0, abs=1.0)
    meta = json.loads((out / "run.json").read_text())
    assert meta["errors"] == 2 and meta["reached"] == 1


RUNNER_SCRIPT = textwrap.dedent("""\
    import sys
    from pathlib import Path
    sys.path.insert(0, {root!r})
    from nav_bench.batch.runner import RunInterrupted, run_suite
    from tests.helpers.fake_episodes import sleepy

    if __name__ == "__main__":  # worker processes import this file: no run there
        try:
            run_suite(sys.argv[1], workers=2, out=Path(sys.argv[2]), progress=False,
                      episode_fn=sleepy)
        except RunInterrupted as exc:
            print(exc, file=sys.stderr)
            raise SystemExit(exc.exit_code)
    """)


def start_runner(tmp_path: Path, suite: Path, out: Path) -> subprocess.Popen:
    script = tmp_path / "runner.py"
    script.write_text(RUNNER_SCRIPT.format(root=str(ROOT)))
    env = {**os.environ, "NAV_BENCH_FAKE_SLEEP": "0.25"}
    return subprocess.Popen([sys.executable, str(script), str(suite), str(out)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for_rows(out: Path, count: int, proc: subprocess.Popen, timeout: float = 60.0) -> None:
    end = time.monotonic() + timeout
    path = out / "episodes.jsonl"
    while time.monotonic() < end:
        if path.exists() and path.read_bytes().count(b"\n") >= count:
            return
        if proc.poll() is not None:
            pytest.fail(f"runner ended early: {proc.communicate()}")
        time.sleep(0.02)
    proc.kill()
    pytest.fail("runner did not write rows in time")


def test_kill_9_then_resume_gives_every_row_once(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=4)  # 16 episodes of 0.25 s (fake), 2 workers
    out = tmp_path / "out"
    proc = start_runner(tmp_path, suite, out)
    wait_for_rows(out, 3, proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait(10)
    stored = ResultsStore(out).rows()
    assert 3 <= len(stored) < 16
    with open(out / "episodes.jsonl", "ab") as f:  # as if killed in the middle of a write
        f.write(b'{"job_id": "tiny_post__seek__diffbot__s1__')
    torn_line = len(stored) + 1
    with pytest.warns(ResultsWarning, match=rf"episodes\.jsonl:{torn_line}: incomplete last line"):
        run_suite(None, resume=out, workers=2, progress=False,
                  episode_fn=fake_episodes.instant)
    lines = (out / "episodes.jsonl").read_text().splitlines()
    rows = [json.loads(line) for line in lines]
    expected = {j.job_id for j in expand(load_suite(suite))}
    assert len(rows) == 16 and {r["job_id"] for r in rows} == expected
    assert [r["job_id"] for r in rows[:len(stored)]] == [r["job_id"] for r in stored]
    meta = json.loads((out / "run.json").read_text())
    assert [s["status"] for s in meta["sessions"]] == ["running", "complete"]
    assert meta["sessions"][1]["episodes"] == 16 - len(stored)
    assert meta["status"] == "complete" and meta["done"] == 16


def test_ctrl_c_stops_cleanly_and_resumes(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=4)
    out = tmp_path / "out"
    proc = start_runner(tmp_path, suite, out)
    wait_for_rows(out, 2, proc)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, err
    assert f"resume {out}" in err
    meta = json.loads((out / "run.json").read_text())
    assert meta["status"] == "interrupted" and meta["ended"]
    data = (out / "episodes.jsonl").read_bytes()
    assert data.endswith(b"\n")  # no half-written line
    stored = ResultsStore(out).rows()
    assert meta["done"] == len(stored) < 16
    for row in stored:
        check_row(row)
    run_suite(None, resume=out, workers=2, progress=False, episode_fn=fake_episodes.instant)
    assert len(ResultsStore(out).rows()) == 16


def test_resume_of_a_finished_run_adds_nothing(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=1)
    out = run_suite(suite, workers=1, out=tmp_path / "out", progress=False,
                    episode_fn=fake_episodes.instant)
    before = (out / "episodes.jsonl").read_bytes()
    run_suite(suite, resume=out, workers=1, progress=False, episode_fn=fake_episodes.instant)
    assert (out / "episodes.jsonl").read_bytes() == before


def test_runner_refuses_bad_folders_and_executors(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=1)
    out = run_suite(suite, workers=1, out=tmp_path / "out", progress=False,
                    episode_fn=fake_episodes.instant)
    with pytest.raises(InputError, match="already holds a run; finish it with --resume"):
        run_suite(suite, out=out, progress=False, episode_fn=fake_episodes.instant)
    other = tiny.write_suite(tmp_path, name="other", seeds=2)
    with pytest.raises(InputError, match="is not the suite it ran"):
        run_suite(other, resume=out, progress=False, episode_fn=fake_episodes.instant)
    with pytest.raises(InputError, match="not a nav-bench results folder"):
        run_suite(None, resume=tmp_path / "nothing", progress=False)
    with pytest.raises(UnknownNameError, match="Did you mean 'dask'"):
        run_suite(suite, executor="dsak", progress=False)
    # an edited world changes its episodes: the old folder cannot be resumed with it
    world = tmp_path / "worlds" / "tiny_open.yaml"
    world.write_text(world.read_text().replace("goal: [2.5, 1.5]", "goal: [2.4, 1.5]"))
    with pytest.raises(InputError, match="changed since it started"):
        run_suite(None, resume=out, progress=False, episode_fn=fake_episodes.instant)


def test_generated_worlds_are_stored_with_the_results(tmp_path, monkeypatch):
    import nav_bench.world.generate as generate

    def fake_generate(kind, seed, settings):
        return {"size": [3.0 + seed, 3.0], "start": [0.5, 0.5], "goal": [2.5, 2.5]}

    monkeypatch.setattr(generate, "generate_world", fake_generate)
    suite = tiny.write_suite(tmp_path, seeds=1, worlds="[{generate: maze, seeds: 2}]")
    out = run_suite(suite, workers=1, out=tmp_path / "out", progress=False,
                    episode_fn=fake_episodes.instant)
    from nav_bench.world.load import load_world

    rows = ResultsStore(out).rows()
    assert sorted({r["world"] for r in rows}) == ["maze_0", "maze_1"]
    for row in rows:
        assert Path(row["world_file"]) == out / "worlds" / f"{row['world']}.yaml"
        assert load_world(row["world_file"]).size[0] == 3.0 + int(row["world"][-1])


def test_numpy_simd_names_the_levels_numpy_dispatches_to_after_the_environment() -> None:
    """run.json records NumPy's SIMD levels; ``NPY_DISABLE_CPU_FEATURES`` (what the README gives
    to reproduce rows recorded on a machine without AVX-512) must show in it."""
    code = "from nav_bench.batch.runner import numpy_simd; print(' '.join(numpy_simd()))"
    env = {k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"}

    def levels(extra: dict[str, str]) -> list[str]:
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                             env={**env, **extra}, timeout=120)
        return out.stdout.split()

    found = levels({})
    if not found:
        pytest.skip("NumPy dispatches to no SIMD level above its baseline on this machine")
    assert levels({"NPY_DISABLE_CPU_FEATURES": found[-1]}) == found[:-1]


def test_a_run_from_a_git_checkout_records_its_commit() -> None:
    """run.json's ``git``: the checkout nav-bench runs from (None from an installed wheel)."""
    import subprocess

    from nav_bench.batch.runner import git_state
    from nav_bench.paths import source_root

    root = source_root()
    if not (root / ".git").exists():
        pytest.skip("not a git checkout")
    head = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True,
                          check=True).stdout.strip()
    state = git_state()
    assert state is not None and state["commit"] == head
    assert isinstance(state["dirty"], bool)
