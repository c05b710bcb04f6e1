"""The episodes a planner did not reach, with what decides their class (dwa_global_s16).

    python failures.py ROWS.jsonl [ROWS.jsonl ...] [--label L]

For each unreached row: the outcome and stuck reason, the true distance to the goal at the end
(m), the odometry error then (m), the time (s), the path (m), DWA's ``blocked`` events (turns on
the spot with no admissible motion) and the episodes with a contact. A ``stopped`` ending within
``goal_tolerance`` of the odometric goal and farther than the episode's 0.3 m of the true one is
the odometry's; the rest need the picture.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rows", nargs="+", type=Path)
    ap.add_argument("--label", help="only this planner label")
    args = ap.parse_args()
    print("| file | label | world | outcome | reason | goal m | odom err m | t s | path m | blocked | contacts |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for path in args.rows:
        for line in path.read_text().splitlines():
            row = json.loads(line)
            label = row.get("label") or row.get("planner")
            if row["outcome"] == "reached" or (args.label and label != args.label):
                continue
            print(f"| {path.parent.name} | {label} | {row['world']} | {row['outcome']} | "
                  f"{row.get('stuck_reason') or ''} | {row['goal_distance_m']:.2f} | "
                  f"{row['odometry_error_m']:.2f} | {row['time_s']:.0f} | {row['path_length_m']:.1f} | "
                  f"{row['events'].get('blocked', 0)} | {row['collisions']} |")


if __name__ == "__main__":
    main()
