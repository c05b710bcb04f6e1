"""What a looser Bullet solver threshold saves per episode, measured side by side in one process.

    PYTHONPATH=. python benchmarks/residual_cost.py --residual 1e-4 [--time-s 60]

Plays the default suite's parameter sets on its worlds (seed 0, each episode cut at ``--time-s``
simulated seconds), each episode once in a session with Bullet's own solver threshold and once
with ``--residual`` (``SimSession(solver_residual=...)``), alternating, so both see the same load.
Prints the CPU seconds (``time.process_time``) of each and their ratio, in all and per simulated
second. What the threshold does to fidelity: ``bench_physics.py --residual`` and
``results/fidelity/residual/``.
"""

from __future__ import annotations

import argparse
import time

from nav_bench.batch.suite import expand, load_suite
from nav_bench.batch.worker import run_job
from nav_bench.sim.session import SimSession


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--residual", type=float, required=True, help="m/s: the looser threshold")
    parser.add_argument("--time-s", type=float, default=60.0, help="simulated s per episode at most")
    parser.add_argument("--suite", default="configs/suites/default.yaml")
    args = parser.parse_args()
    jobs = [j for j in expand(load_suite(args.suite)) if j.seed == 0]
    cpu = {"bullet": 0.0, "loose": 0.0}
    sim_s = {"bullet": 0.0, "loose": 0.0}
    with SimSession() as bullet, SimSession(solver_residual=args.residual) as loose:
        for job in jobs:
            job.settings["time_s"] = min(args.time_s, job.settings.get("time_s") or args.time_s)
            for name, session in (("bullet", bullet), ("loose", loose)):
                start = time.process_time()
                row = run_job(job, session).row
                cpu[name] += time.process_time() - start
                sim_s[name] += row.time_s
            print(f"{job.world_name} {job.label}: CPU s so far {cpu['bullet']:.2f} / "
                  f"{cpu['loose']:.2f}", flush=True)
    per_sim = (cpu["loose"] / sim_s["loose"]) / (cpu["bullet"] / sim_s["bullet"])
    print(f"{len(jobs)} episodes x 2. CPU s: Bullet's threshold {cpu['bullet']:.2f} "
          f"({sim_s['bullet']:.0f} sim s), residual {args.residual:g} {cpu['loose']:.2f} "
          f"({sim_s['loose']:.0f} sim s); ratio {cpu['loose'] / cpu['bullet']:.3f}, "
          f"per simulated second {per_sim:.3f}")


if __name__ == "__main__":
    main()
