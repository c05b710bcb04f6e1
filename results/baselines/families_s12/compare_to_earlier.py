"""Compare the twelfth session's D* Lite, dwa_global and APF family rows with the rows the
families table quotes (outcome, time, path length, contacts), per planner.

    python results/baselines/families_s12/compare_to_earlier.py
"""

import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
EARLIER = {  # planner -> (rows the table quotes, their label)
    "dstar_lite": (HERE.parent / "dstar_s6/episodes.jsonl", "dstar_lite"),
    "dwa_global": (HERE.parent / "dwa_global_s7/families/episodes.jsonl", "dwa_global_la06_kc06"),
    "apf": (HERE.parent / "apf_dwa_s7/episodes.jsonl", "apf"),
}
FIELDS = ("outcome", "time_s", "path_length_m", "collisions")


def rows(path: Path, label: str) -> dict[str, dict]:
    """Rows of ``label`` in ``path`` by world."""
    with path.open() as fh:
        return {r["world"]: r for r in map(json.loads, fh) if r["label"] == label}


for planner, (path, label) in EARLIER.items():
    old, new = rows(path, label), rows(HERE / "grid_planners.jsonl", planner)
    worlds = sorted(set(old) & set(new))
    equal = sum(all(old[w][f] == new[w][f] for f in FIELDS) for w in worlds)
    reached = sum(new[w]["outcome"] == "reached" for w in worlds)
    print(f"{planner}: {len(worlds)} layouts, {equal} rows equal, {reached} reached")
