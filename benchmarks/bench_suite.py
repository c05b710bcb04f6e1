"""The default suite's worker CPU-seconds: an older revision and this tree, side by side.

    python benchmarks/bench_suite.py [--before REV] [--suite FILE] [--worlds W,W] [--planners L,L]
                                     [--seeds 0,1] [--out DIR] [--lockstep | --alternate]

``--before REV`` (default ``main``) is checked out as a git worktree in a temporary folder and
played with ``PYTHONPATH`` pointing at it; this tree is played the same way. Both play the same
suite (default ``configs/suites/default.yaml`` of this tree; each tree resolves its worlds and
planner files in its own folders) at the same time, one process each, so both see the same load
on the same machine. Each process plays its jobs one after the other exactly as a batch worker
does (:func:`nav_bench.batch.worker.execute_job` with the real episode function, then the trace
written compressed) and measures each job's CPU seconds with ``time.process_time()``.

Prints both totals, the ratio (this tree / before), and a per-label and outcome breakdown;
writes ``DIR/before/episodes.jsonl`` and ``DIR/after/episodes.jsonl`` (each row with
``bench_cpu_s``) and the traces next to them. ``--worlds``, ``--planners`` (suite labels) and
``--seeds`` play a subset for a quick check. Pairs are matched by (label, world, seed): job ids
differ when the revisions' settings differ.

``--lockstep``: neither process starts its next job before the other has finished the same one.
Without it the faster side finishes early and its figures come from the first part of the run
only; on a machine whose speed drifts within minutes (a shared VM), the two sides then see
different machines. In lockstep both sides play job k in the same stretch of time; the faster
one waits (sleeping, no CPU) for the slower. ``--alternate``: one job at a time, the two sides
taking turns (before's job k, then after's job k, then before's job k + 1): each job runs with
no other player beside it, so neither side's figures carry the other's contention for the
shared cache and memory, and drift reaches both sides alike; the wall time is the sum of both
sides' (about 11 minutes for the default suite against 41dac48 here). Only the jobs both sides
play are paced: give both the same suite.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


# --------------------------------------------------------------------------- one tree's player
def play(tree: Path, suite_file: Path, out: Path, worlds: set[str] | None,
         labels: set[str] | None, seeds: set[int] | None, pace: Path | None = None,
         alternate: bool = False) -> None:
    """Play the suite's selected jobs with the code of ``tree`` (on ``sys.path`` by
    ``PYTHONPATH``) and append one row per job to ``out/episodes.jsonl``. With ``pace`` (a
    folder both players share), job k starts only once the other player has finished job k - 1
    (``lockstep``), or, with ``alternate``, the before player's job k only once the after
    player has finished job k - 1 and the after player's job k only once the before player has
    finished job k (:func:`wait_for_peer`)."""
    import nav_bench
    from nav_bench.batch.suite import expand, load_suite
    from nav_bench.batch.worker import execute_job, run_job

    assert Path(nav_bench.__file__).resolve().is_relative_to(tree.resolve()), nav_bench.__file__
    jobs = [j for j in expand(load_suite(suite_file, cwd=tree))
            if (worlds is None or j.world_name in worlds) and (labels is None or j.label in labels)
            and (seeds is None or j.seed in seeds)]
    (out / "traces").mkdir(parents=True, exist_ok=True)
    with (out / "episodes.jsonl").open("a") as fh:
        for k, job in enumerate(jobs):
            if pace is not None:
                wait_for_peer(pace, out.name, k + 1 if alternate and out.name == "after" else k)
            cpu0, wall0 = time.process_time(), time.perf_counter()
            result = execute_job(job, run_job)
            if result.trace is not None:  # a worker writes the trace: part of its cost
                result.trace.save(out / "traces" / f"{job.job_id}.npz")
            row = result.row.to_json()
            row["bench_cpu_s"] = time.process_time() - cpu0
            row["bench_wall_s"] = time.perf_counter() - wall0
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            if pace is not None:
                (pace / out.name).write_text(str(k + 1))  # jobs finished


def wait_for_peer(pace: Path, me: str, k: int) -> None:
    """Sleep until the other player (its file in ``pace`` holds how many jobs it finished)
    has finished ``k`` jobs; a player that died is waited for no longer than 15 minutes."""
    peer = pace / ("after" if me == "before" else "before")
    deadline = time.monotonic() + 900.0
    while time.monotonic() < deadline:
        try:
            if int(peer.read_text() or 0) >= k:
                return
        except (FileNotFoundError, ValueError):
            if k == 0:
                return
        time.sleep(0.02)
    sys.exit(f"error: the {peer.name} player finished no job {k} in 15 minutes")


# --------------------------------------------------------------------------- the comparison
def worktree(rev: str, folder: Path) -> Path:
    """A detached git worktree of ``rev`` in ``folder``."""
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(folder), rev],
                   check=True)
    return folder


def start_player(tree: Path, args: argparse.Namespace, out: Path) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    cmd = [sys.executable, str(Path(__file__).resolve()), "--play", str(tree), "--out", str(out),
           "--suite", str(args.suite)]
    for name in ("worlds", "planners", "seeds"):
        if getattr(args, name):
            cmd += [f"--{name}", getattr(args, name)]
    if args.lockstep or args.alternate:
        cmd += ["--pace", str(out.parent / "pace")]
    if args.alternate:
        cmd += ["--alternate"]
    log = (out.parent / f"{out.name}.log").open("w")
    return subprocess.Popen(cmd, env=env, cwd=tree, stdout=log, stderr=subprocess.STDOUT)


def read_rows(folder: Path) -> dict[tuple[str, str, int], dict]:
    path = folder / "episodes.jsonl"
    rows = [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []
    return {(r["label"], r["world"], r["seed"]): r for r in rows}


def report(before: dict, after: dict, rev: str) -> None:
    keys = sorted(set(before) & set(after))
    if not keys:  # --worlds / --planners / --seeds pick from the suite's own jobs
        print("error: no episode was played on both sides: --worlds, --planners and --seeds select "
              "among the suite's jobs (its worlds, labels and seeds)", file=sys.stderr)
        sys.exit(2)
    tb = sum(before[k]["bench_cpu_s"] for k in keys)
    ta = sum(after[k]["bench_cpu_s"] for k in keys)
    sb = sum(before[k]["time_s"] or 0.0 for k in keys)
    sa = sum(after[k]["time_s"] or 0.0 for k in keys)
    print(f"{len(keys)} paired episodes (before {len(before)}, after {len(after)} rows)")
    print(f"worker CPU-s   before ({rev}): {tb:9.1f}   this tree: {ta:9.1f}   "
          f"ratio after/before {ta / tb:.3f}  (before/after {tb / ta:.2f}x)")
    print(f"simulated s    before: {sb:9.1f}   this tree: {sa:9.1f}   "
          f"CPU-s per simulated s: {tb / sb:.4f} vs {ta / sa:.4f}")
    groups: dict[tuple[str, str, str], list] = defaultdict(lambda: [0, 0.0, 0, 0.0])
    for k in keys:
        b, a = before[k], after[k]
        for side, row in ((0, b), (2, a)):
            g = groups[(k[0], b["outcome"], a["outcome"])]
            g[side] += 1
            g[side + 1] += row["bench_cpu_s"]
    print(f"\n{'label':18s} {'outcome before -> after':28s} {'n':>4s} {'CPU-s before':>13s} "
          f"{'CPU-s after':>12s} {'ratio':>6s}")
    for (label, ob, oa), (n, cb, _, ca) in sorted(groups.items()):
        print(f"{label:18s} {ob + ' -> ' + oa:28s} {n:4d} {cb:13.1f} {ca:12.1f} {ca / cb:6.2f}")
    changed = [(k, before[k]["outcome"], after[k]["outcome"]) for k in keys
               if before[k]["outcome"] != after[k]["outcome"]]
    print(f"\noutcomes changed: {len(changed)}")
    for k, ob, oa in changed:
        print(f"  {k}: {ob} -> {oa}")


def pacing_note(args: argparse.Namespace) -> str:
    return ", lockstep" if args.lockstep else ", alternate (one job at a time)" if args.alternate else ""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", default="main", help="git revision to compare with (default main)")
    ap.add_argument("--suite", type=Path, default=ROOT / "configs" / "suites" / "default.yaml")
    ap.add_argument("--worlds", help="comma-separated world names (default: all)")
    ap.add_argument("--planners", help="comma-separated suite labels (default: all)")
    ap.add_argument("--seeds", help="comma-separated seeds (default: all)")
    ap.add_argument("--out", type=Path, help="results folder (default: a new temporary one)")
    pacing = ap.add_mutually_exclusive_group()
    pacing.add_argument("--lockstep", action="store_true",
                        help="each side starts job k only once the other has finished job k - 1")
    pacing.add_argument("--alternate", action="store_true",
                        help="one job at a time, the sides taking turns (no contention between them)")
    ap.add_argument("--play", type=Path, help=argparse.SUPPRESS)  # internal: one tree's player
    ap.add_argument("--pace", type=Path, help=argparse.SUPPRESS)  # internal: the lockstep folder
    args = ap.parse_args()
    args.suite = args.suite.resolve()
    def pick(s: str | None) -> set[str] | None:
        return set(s.split(",")) if s else None
    if args.play is not None:
        play(args.play, args.suite, args.out, pick(args.worlds), pick(args.planners),
             {int(s) for s in args.seeds.split(",")} if args.seeds else None, args.pace,
             args.alternate)
        return
    out = (args.out or Path(tempfile.mkdtemp(prefix="bench_suite_"))).resolve()
    out.mkdir(parents=True, exist_ok=True)
    for side in ("before", "after"):
        if (out / side / "episodes.jsonl").exists():
            sys.exit(f"error: {out / side} already holds rows; give a new --out")
    if args.lockstep or args.alternate:
        (out / "pace").mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="bench_suite_rev_") as tmp:
        old = worktree(args.before, Path(tmp) / "before")
        try:
            t0 = time.perf_counter()
            players = [start_player(old, args, out / "before"), start_player(ROOT, args, out / "after")]
            codes = [p.wait() for p in players]
            wall = time.perf_counter() - t0
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(old)],
                           check=False)
    if any(codes):
        sys.exit(f"error: a player failed (exit {codes}); see {out}/before.log, {out}/after.log")
    print(f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at the end, "
          f"{wall:.0f} s wall{pacing_note(args)}; rows in {out}")

    report(read_rows(out / "before"), read_rows(out / "after"), args.before)


if __name__ == "__main__":
    main()
