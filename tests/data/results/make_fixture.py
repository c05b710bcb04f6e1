"""Writes ``run_a/``: a fixed, hand-made results folder for the report tests.

Two worlds (room, hall) x two parameter sets (alpha, beta) x seeds 0..4. The numbers are
chosen so the report's statistics can be computed by hand (see tests/test_report.py).
Run from this folder: ``python make_fixture.py`` (the output is committed).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
WORLDS = {
    "room": {"name": "room", "size": [6.0, 3.0], "start": [0.5, 1.5, 0.0], "goal": [5.5, 1.5],
             "obstacles": [{"box": {"center": [3.0, 0.5], "size": [0.6, 1.0]}}]},
    "hall": {"name": "hall", "size": [9.0, 2.0], "start": [0.5, 1.0, 0.0], "goal": [8.5, 1.0]},
}
# (world, set) -> per seed: (outcome, time_s, path_length_m, replans, collisions)
EPISODES = {
    ("room", "alpha"): [("reached", 10, 5.0, 1, 0), ("reached", 12, 5.5, 2, 0),
                        ("reached", 14, 6.0, 3, 1), ("reached", 16, 6.5, 4, 0),
                        ("timeout", 60, 9.0, 5, 2)],
    ("room", "beta"): [("reached", 9, 5.0, 0, 0), ("reached", 11, 5.0, 0, 0),
                       ("stuck", 30, 2.0, 0, 1), ("error", None, None, None, None),
                       ("timeout", 60, 3.0, 0, 0)],
    ("hall", "alpha"): [("reached", 20, 8.0, 0, 0)] * 5,
    ("hall", "beta"): [("timeout", 60, 4.0, 0, 0)] * 5,
}
OPTIMAL = {"room": 5.0, "hall": 8.0}
PLANNER = {"alpha": "eopc", "beta": "goal_seek"}


def main() -> None:
    out = HERE / "run_a"
    (out / "traces").mkdir(parents=True, exist_ok=True)
    lines = []
    for (world, label), episodes in EPISODES.items():
        for seed, (outcome, time_s, length, replans, collisions) in enumerate(episodes):
            job_id = f"{world}__{label}__diffbot__s{seed}__fixture"
            success = outcome == "reached"
            row = {
                "job_id": job_id, "label": label, "world": world,
                "world_file": f"worlds/{world}.yaml", "planner": PLANNER[label],
                "params": {}, "params_id": f"pid_{label}", "seed": seed, "success": success,
                "outcome": outcome, "time_s": time_s, "path_length_m": length,
                "optimal_length_m": OPTIMAL[world],
                "spl": OPTIMAL[world] / max(OPTIMAL[world], length) if success else 0.0,
                "replans": replans, "collisions": collisions,
                "min_clearance_m": None if outcome == "error" else 0.1 * (seed + 1),
                "wall_s": 1.0, "settings": {"time_s": 60.0}, "events": {},
                "error": "Traceback ...\nRuntimeError: fixture error" if outcome == "error"
                else None,
                "robot": "diffbot", "robot_id": "rid", "time_limit_s": 60.0,
                "trace": None,
            }
            if outcome != "error":
                w = WORLDS[world]
                start = np.array(w["start"][:2])
                end = np.array(w["goal"]) if success else start + np.array([1.0, 0.2 * seed])
                xy = np.linspace(w["start"][:2], end, 20)
                pose = np.column_stack([xy, np.zeros(len(xy))]).astype(np.float32)
                meta = {"world": w, "events": [], "planner_state": {}, "row": {}}
                np.savez_compressed(out / "traces" / f"{job_id}.npz", true_pose=pose,
                                    meta=np.array(json.dumps(meta)))
                row["trace"] = f"traces/{job_id}.npz"
            lines.append(json.dumps(row, separators=(",", ":")))
    (out / "episodes.jsonl").write_text("\n".join(lines) + "\n")
    run = {"format": 1, "status": "complete", "suite": {"name": "fixture"}, "total": len(lines),
           "done": len(lines), "started": "2024-06-11T10:00:00+02:00",
           "ended": "2024-06-11T10:05:00+02:00", "host": "fixture-host", "nav_bench": "0.1.0",
           "git": None, "executor": {"name": "local", "workers": 2}, "workers": 2}
    (out / "run.json").write_text(json.dumps(run, indent=2) + "\n")


if __name__ == "__main__":
    main()
