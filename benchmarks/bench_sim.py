"""Simulator speed: physics stepping, sensing, and what static obstacles cost per step.

    python benchmarks/bench_sim.py [--boxes 1000] [--seconds 20] [--repeats 3]

Prints a table. Figures are CPU time of this process (``time.process_time``, so other jobs on
the machine inflate them less than wall-clock would), median of ``--repeats`` runs, with the
robot driving a circle so its contacts and the broadphase do real work. Scene layouts compared
on the same world of ``--boxes`` random boxes:

* compound (default): 16 boxes per static body, grouped by place, maximal coordinates;
* compound, multibody: the same bodies as static multibodies (PyBullet's default);
* compound, file order: 16 boxes per body in file order (each group spans the map);
* one body per box: 1 box per static body (maximal coordinates);
* one multibody per box: what a naive loader does.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from nav_bench.interface import Command
from nav_bench.sim import SimSession, Simulation
from nav_bench.sim.scene import SceneLayout
from nav_bench.specs import WorldSpec, load_robot

SIZE = 30.0  # m, square world
START = (SIZE / 2, SIZE / 2, 0.0)
CLEAR = 3.0  # m kept free around the start: the robot circles with radius 1 m beside it


def random_boxes(n: int, seed: int = 0) -> list[dict]:
    """``n`` random boxes (0.1-0.5 m, any yaw) outside a disc around the start."""
    rng = np.random.default_rng(seed)
    out: list[dict] = []
    while len(out) < n:
        x, y = rng.uniform(0.5, SIZE - 0.5, size=2)
        if np.hypot(x - START[0], y - START[1]) < CLEAR:
            continue
        sx, sy = rng.uniform(0.1, 0.5, size=2)
        out.append({"box": {"center": [float(x), float(y)], "size": [float(sx), float(sy)],
                            "yaw_deg": float(rng.uniform(0, 180))}})
    return out


def world(boxes: int) -> WorldSpec:
    return WorldSpec.model_validate({
        "name": f"bench_{boxes}", "size": [SIZE, SIZE], "start": list(START),
        "goal": [SIZE - 1, SIZE - 1], "obstacles": random_boxes(boxes)})


def measure(session: SimSession, w: WorldSpec, layout: SceneLayout, seconds: float,
            repeats: int) -> dict[str, float]:
    """Median step time (us), sense time (us) and scene build time (ms)."""
    robot = load_robot()
    steps = round(seconds * session.physics_hz)
    step_us, sense_us, build_ms = [], [], []
    for _ in range(repeats):
        t0 = time.process_time()
        sim = Simulation(session, w, robot, np.random.default_rng(0), layout=layout)
        build_ms.append((time.process_time() - t0) * 1e3)
        sim.apply(Command(0.5, 0.5))
        sim.step(240)  # settle and accelerate
        t0 = time.process_time()
        for _ in range(steps // 24):  # 10 Hz control cycles
            sim.step(24)
        step_us.append((time.process_time() - t0) / (steps // 24 * 24) * 1e6)
        t0 = time.process_time()
        for _ in range(1000):
            sim.sense()
        sense_us.append((time.process_time() - t0) / 1000 * 1e6)
        assert sim.collisions == 0, "the benchmark robot must not hit anything"
    return {"step_us": statistics.median(step_us), "sense_us": statistics.median(sense_us),
            "build_ms": statistics.median(build_ms), "bodies": session.client.getNumBodies()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--boxes", type=int, default=1000, help="obstacles in the cluttered world")
    parser.add_argument("--seconds", type=float, default=20.0, help="simulated seconds per run")
    parser.add_argument("--repeats", type=int, default=3, help="runs per case (median reported)")
    args = parser.parse_args()

    empty, cluttered = world(0), world(args.boxes)
    cases = [
        ("robot alone (empty world)", empty, SceneLayout()),
        ("compound: 16/body, by place (default)", cluttered, SceneLayout()),
        ("compound as multibodies", cluttered, SceneLayout(maximal_coordinates=False)),
        ("compound in file order", cluttered, SceneLayout(group_by_place=False)),
        ("one body per box", cluttered, SceneLayout(shapes_per_body=1)),
        ("one multibody per box", cluttered,
         SceneLayout(shapes_per_body=1, maximal_coordinates=False)),
    ]
    rows = []
    with SimSession() as session:
        for label, w, layout in cases:
            rows.append((label, measure(session, w, layout, args.seconds, args.repeats)))

    base = rows[0][1]["step_us"]
    print(f"\nnav-bench simulator benchmark: {args.boxes} boxes in a {SIZE:g} m world, "
          f"{args.seconds:g} s simulated per run, median of {args.repeats}\n")
    print(f"{'case':40s} {'bodies':>6s} {'build ms':>9s} {'step us':>8s} {'steps/s':>8s} "
          f"{'x empty':>8s} {'sense us':>9s}")
    for label, r in rows:
        print(f"{label:40s} {r['bodies']:6d} {r['build_ms']:9.1f} {r['step_us']:8.1f} "
              f"{1e6 / r['step_us']:8.0f} {r['step_us'] / base:8.2f} {r['sense_us']:9.1f}")
    print("\nstep us: one physics step of Simulation.step (movers, motors, physics, odometry, "
          "contacts);\nsense us: one Simulation.sense (6 sonars x 7 rays, one rayTestBatch, "
          "noise); bodies include robot and ground.")


if __name__ == "__main__":
    main()
