"""Each planner's rows (seed 0) in a run of configs/suites/baselines.yaml against the study its
families column quotes (results/baselines/families.md): outcome, time, path, contacts."""
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STUDIES = {
    "dstar_lite": (ROOT / "dstar_s6/episodes.jsonl", "dstar_lite"),
    "bug2": (ROOT / "follow_s18/gate/families_after.jsonl", "bug2"),
    "tangent_bug": (ROOT / "follow_s18/gate/families_after.jsonl", "tangent_bug"),
    "vfh_plus": (ROOT / "vfh_s20/rows/families3_area05.jsonl", None),
    "apf": (ROOT / "apf_dwa_s7/episodes.jsonl", "apf"),
    "dwa_global": (ROOT / "dwa_global_s16/rows/fam_global_after.jsonl", "dwa_global"),
}
FIELDS = ("outcome", "time_s", "path_length_m", "collisions")
run = [json.loads(line) for line in Path(sys.argv[1]).read_text().splitlines()]
for label, (path, study_label) in STUDIES.items():
    mine = {r["world"]: r for r in run if r["label"] == label}
    theirs = {}
    for r in map(json.loads, path.read_text().splitlines()):
        if r["planner"] == label and r["seed"] == 0 and (study_label is None or (r.get("label") or r["planner"]) == study_label):
            theirs[r["world"]] = r
    common = sorted(set(mine) & set(theirs))
    differ = [w for w in common if any(mine[w][f] != theirs[w][f] for f in FIELDS)]
    reached = sum(mine[w]["outcome"] == "reached" for w in mine)
    print(f"{label:12s} run {len(mine):3d} rows ({reached} reached), study {len(theirs)}, paired {len(common)}, differ {len(differ)} {differ[:6]}")
