"""How the harness layout of ``test_a_lap_round_a_pillar_beside_the_hit_wall_is_not_unreachable``
was found: very_complex's trap (a wall met diagonally, a 0.6 m pillar beside the hit point) in a
6 x 6.5 m room, the wall's left end, the pillar and the goal varied.

    python harness_search.py main > candidates.jsonl     # with main's code on the path
    python harness_search.py branch < candidates.jsonl   # with this branch's code

Step ``main``: layouts where Bug2 ends ``unreachable`` within 40 s for seeds 0, 1 and 2 (sonar
noise 0.01 m). Step ``branch``: for each, per seed (reached, contacts, unreachable events, lap
events, time s) within 150 s.
"""

from __future__ import annotations

import itertools
import json
import math
import sys

from nav_bench.planners.bug2 import Bug2
from nav_bench.testing.harness import BoxWorld, Run, run

HALF = 0.3  # m: half the pillar's side


def play(layout: list[float], seed: int, time_s: float) -> Run:
    x0, px, py, gx, gy, sy = layout
    world = BoxWorld.room((6.0, sy), [(x0, 3.425, 6.0, 3.575), (px - HALF, py - HALF, px + HALF, py + HALF)])
    return run(Bug2(), world, (1.0, 1.0, math.atan2(gy - 1.0, gx - 1.0)), (gx, gy), time_s=time_s,
               seed=seed, noise_std=0.01)


def main(step: str) -> None:
    if step == "main":
        for x0, (gx, gy), px, py in itertools.product(
                (1.2, 1.8, 2.4), ((4.5, 4.5), (4.0, 5.5), (5.0, 5.5), (3.5, 5.0)),
                (3.4, 3.6, 3.8, 4.0), (2.0, 2.2, 2.4)):
            layout = [x0, px, py, gx, gy, 6.5]
            if all(play(layout, seed, 40.0).kinds("unreachable") == 1 for seed in (0, 1, 2)):
                print(json.dumps(layout), flush=True)
        return
    for line in sys.stdin:
        layout = json.loads(line)
        runs = [play(layout, seed, 150.0) for seed in (0, 1, 2)]
        print(layout, [(r.reached, r.collisions, r.kinds("unreachable"), r.kinds("lap"), round(r.time, 1))
                       for r in runs], flush=True)


if __name__ == "__main__":
    main(sys.argv[1])
