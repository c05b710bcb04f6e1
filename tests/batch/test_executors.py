"""Executors: the killable local pool, and Dask on a real local cluster (loopback).

Runtime: ~25 s on 2 cores (two Dask LocalClusters start and stop; one 2 s hang is waited out).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # worker processes import tests.helpers.* by name
    sys.path.insert(0, str(ROOT))

from nav_bench.batch.executors import LocalPool, make_executor  # noqa: E402
from nav_bench.batch.runner import run_suite  # noqa: E402
from nav_bench.batch.store import ResultsStore, check_row  # noqa: E402
from nav_bench.batch.suite import expand, load_suite  # noqa: E402
from nav_bench.errors import InputError, UnknownNameError  # noqa: E402
from tests.helpers import fake_episodes, tiny  # noqa: E402


def test_local_pool_survives_raise_hang_and_death(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=5, worlds=f"['{tmp_path}/worlds/tiny_open.yaml']",
                             planners="{seek: goal_seek}", limits="{wall_s: 1.0}")
    jobs = expand(load_suite(suite))
    outcomes = list(LocalPool(2).run(jobs, fake_episodes.seed_dependent))
    rows = {o.row.seed: o.row.to_json() for o in outcomes}
    assert sorted(rows) == [0, 1, 2, 3, 4]
    for row in rows.values():
        check_row(row)
    assert rows[0]["outcome"] == "reached" and rows[4]["outcome"] == "reached"
    assert "ValueError: fake episode failure" in rows[1]["error"]
    assert "wall-clock limit of 1 s" in rows[2]["error"]
    assert rows[2]["wall_s"] == pytest.approx(1.0, abs=0.5)
    assert "worker process died (exit code 3)" in rows[3]["error"]
    assert all(r["job_id"] == j.job_id for j in jobs for r in rows.values() if r["seed"] == j.seed)


def test_local_pool_stops_when_asked(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=6, planners="{seek: goal_seek}")
    jobs = expand(load_suite(suite))
    seen = []
    for outcome in LocalPool(2).run(jobs, fake_episodes.sleepy, should_stop=lambda: len(seen) >= 2):
        seen.append(outcome)
    assert 2 <= len(seen) < len(jobs)


def test_executor_names():
    with pytest.raises(UnknownNameError, match=r"unknown executor 'ray'.*Known: dask, local"):
        make_executor("ray")
    with pytest.raises(UnknownNameError, match="Did you mean 'local'"):
        make_executor("locl")
    with pytest.raises(InputError, match="takes no address"):
        make_executor("local:tcp://x:1")
    with pytest.raises(InputError, match="at least 1"):
        make_executor("local", workers=0)
    assert make_executor("dask:tcp://10.0.0.1:8786").describe()["scheduler"] == "tcp://10.0.0.1:8786"


def comparable(rows):
    return {r["job_id"]: {k: v for k, v in r.items() if k != "wall_s"} for r in rows}


def test_dask_cluster_gives_the_rows_of_the_local_pool(tmp_path):
    import dask
    from distributed import LocalCluster

    suite = tiny.write_suite(
        tmp_path, seeds=1, limits="{time_s: 15, stuck_s: 5, wall_s: 2}",
        planners="{seek: goal_seek, hangs: {planner: 'tests.helpers.bad_planners:Hangs', "
                 "params: {after: 1}}}")
    local = run_suite(suite, workers=2, out=tmp_path / "local", progress=False)
    # a real cluster on loopback; non-daemonic workers may start killable episode processes
    with dask.config.set({"distributed.worker.daemon": False}), LocalCluster(
            host="127.0.0.1", n_workers=2, processes=True, threads_per_worker=1,
            dashboard_address=None) as cluster:
        out = run_suite(suite, out=tmp_path / "dask", progress=False,
                        executor=f"dask:{cluster.scheduler_address}")
    rows = ResultsStore(out).rows()
    assert len(rows) == 4
    for row in rows:
        check_row(row)
    assert comparable(rows) == comparable(ResultsStore(local).rows())
    hung = [r for r in rows if r["label"] == "hangs"]
    assert len(hung) == 2 and all("wall-clock limit of 2 s" in r["error"] for r in hung)
    assert all(r["outcome"] == "reached" for r in rows if r["label"] == "seek")
    executor = ResultsStore(out).read_run()["executor"]
    assert executor["name"] == "dask" and executor["workers"] == 2


def test_dask_executor_starts_its_own_local_cluster(tmp_path):
    suite = tiny.write_suite(tmp_path, seeds=3)
    out = run_suite(suite, workers=2, out=tmp_path / "out", executor="dask", progress=False,
                    episode_fn=fake_episodes.instant)
    rows = ResultsStore(out).rows()
    assert sorted(r["job_id"] for r in rows) == sorted(j.job_id for j in expand(load_suite(suite)))
    meta = ResultsStore(out).read_run()
    assert meta["executor"] == {"name": "dask", "scheduler": "LocalCluster(127.0.0.1)",
                                "workers": 2, "start_method": "forkserver"}
