"""Replay some of a suite's episodes with other engine settings, in this process (one worker).

For checks that a suite's ``limits:`` cannot express (the contact recovery rate and solver
iterations are session settings, not episode settings). Writes ``episodes.jsonl`` rows that
``benchmarks/fidelity_suite.py`` pairs with a stored run. Keep it to a few dozen episodes:
studies of hundreds belong in ``nav-bench run``.

    PYTHONPATH=. python benchmarks/fidelity_rerun.py configs/suites/default.yaml --world dynamic \\
        --physics-hz 60 --contact-recovery 20 --out results/fidelity/dynamic_60hz_contact20
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from nav_bench.batch.suite import expand, load_suite
from nav_bench.batch.worker import run_job
from nav_bench.sim.session import (
    CONTACT_RECOVERY_HZ,
    SOLVER_ITERATIONS,
    SOLVER_RESIDUAL,
    SimSession,
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("suite", help="suite YAML")
    parser.add_argument("--world", action="append", default=[], help="only these worlds")
    parser.add_argument("--label", action="append", default=[], help="only these parameter sets")
    parser.add_argument("--physics-hz", type=float, required=True)
    parser.add_argument("--contact-recovery", type=float, default=CONTACT_RECOVERY_HZ,
                        help="1/s; 0: Bullet's own contact ERP")
    parser.add_argument("--solver-iterations", type=int, default=SOLVER_ITERATIONS)
    parser.add_argument("--solver-residual", type=float, default=SOLVER_RESIDUAL,
                        help="m/s: Bullet's solver stops iterating below this velocity error "
                             "(default: the session's default)")
    parser.add_argument("--out", required=True, help="folder for episodes.jsonl")
    args = parser.parse_args()
    jobs = [j for j in expand(load_suite(args.suite))
            if (not args.world or j.world_name in args.world)
            and (not args.label or j.label in args.label)]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    recovery = args.contact_recovery or None
    with SimSession(physics_hz=args.physics_hz, contact_recovery_hz=recovery,
                    solver_iterations=args.solver_iterations,
                    solver_residual=args.solver_residual) as session, \
            open(out / "episodes.jsonl", "w", encoding="utf-8") as fh:
        for job in jobs:
            job.settings["physics_hz"] = args.physics_hz
            start = time.perf_counter()
            row = run_job(job, session).row.to_json()
            row.update(label=job.label, seed=job.seed, wall_s=time.perf_counter() - start,
                       engine={"contact_recovery_hz": recovery,
                               "solver_iterations": args.solver_iterations,
                               "solver_residual": args.solver_residual})
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            print(f"{job.world_name} {job.label} s{job.seed}: {row['outcome']}", flush=True)


if __name__ == "__main__":
    main()
