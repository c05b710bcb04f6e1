"""The physics rate's effect on a suite: the same episodes at a reference rate and at others.

Reads stored results only (``episodes.jsonl`` of each run folder) and pairs episodes by
(world, label, seed): the same world, parameter set and seed, played at two physics rates.
Per parameter set (label) and overall it reports

* success rate per run with a Wilson 95 % interval, and the paired change: episodes reached
  only at the reference / only at the other rate, with the two-sided exact sign test on them;
* the outcome transition matrix reference -> other;
* for episodes reached in both runs, the paired differences of path length and time
  (other - reference: median and interquartile range) and the share within 1 cm / 0.1 s;
* collisions (contact episodes) per run;
* the episode cost: worker wall seconds per run and their ratio to the reference (each run had
  one worker; runs on a shared machine at the same time see similar load, not equal load).

Run::

    PYTHONPATH=. python benchmarks/fidelity_suite.py --ref results/fidelity/run_240 \\
        --run 120=results/fidelity/run_120 --run 60=results/fidelity/run_60 --out results/fidelity

Writes ``suite.md`` and ``suite.json`` in ``--out`` (``--stem`` to rename them).
"""

from __future__ import annotations

import argparse
import json
import math
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

Key = tuple[str, str, int]  # (world, label, seed)
OUTCOME_ORDER = ("reached", "collision", "stuck", "timeout", "error")


@dataclass(frozen=True)
class Episode:
    """The fields of a result row this comparison reads (s, m)."""

    outcome: str
    path_length_m: float | None
    time_s: float | None
    collisions: int
    wall_s: float


@dataclass
class PairedStats:
    """One group's comparison of a run against the reference (``n`` paired episodes)."""

    group: str
    n: int
    success_ref: float
    success_ref_ci: tuple[float, float]
    success: float
    success_ci: tuple[float, float]
    only_ref: int  # reached at the reference only
    only_other: int  # reached at the other rate only
    sign_test_p: float
    both_reached: int
    path_diff_median_m: float
    path_diff_iqr_m: tuple[float, float]
    path_same_1cm: float
    time_diff_median_s: float
    time_diff_iqr_s: tuple[float, float]
    time_same_0_1s: float
    collisions_ref: int
    collisions: int
    wall_ref_s: float
    wall_s: float


def read_run(folder: Path) -> dict[Key, Episode]:
    """The episodes of a results folder, by (world, label, seed)."""
    out: dict[Key, Episode] = {}
    with open(folder / "episodes.jsonl", encoding="utf-8") as fh:
        for line in fh:
            if not line.strip():
                continue
            row = json.loads(line)
            out[(row["world"], row["label"], int(row["seed"]))] = Episode(
                outcome=row["outcome"], path_length_m=row.get("path_length_m"),
                time_s=row.get("time_s"), collisions=int(row.get("collisions") or 0),
                wall_s=float(row.get("wall_s") or 0.0))
    return out


def wilson(successes: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion (95 % by default)."""
    if n == 0:
        return (math.nan, math.nan)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))


def sign_test(a: int, b: int) -> float:
    """Two-sided exact binomial test of a vs b discordant pairs (McNemar's exact test)."""
    n = a + b
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, k) for k in range(min(a, b) + 1)) / 2.0 ** n
    return min(1.0, 2.0 * tail)


def _quartiles(values: np.ndarray) -> tuple[float, tuple[float, float]]:
    if values.size == 0:
        return math.nan, (math.nan, math.nan)
    q1, med, q3 = np.percentile(values, [25, 50, 75])
    return float(med), (float(q1), float(q3))


def paired_stats(group: str, ref: dict[Key, Episode], other: dict[Key, Episode],
                 keys: list[Key]) -> PairedStats:
    n = len(keys)
    ok_ref = np.array([ref[k].outcome == "reached" for k in keys], dtype=bool)
    ok = np.array([other[k].outcome == "reached" for k in keys], dtype=bool)
    both = [k for k, a, b in zip(keys, ok_ref, ok, strict=True) if a and b]
    dpath = np.array([other[k].path_length_m - ref[k].path_length_m for k in both])
    dtime = np.array([other[k].time_s - ref[k].time_s for k in both])
    path_med, path_iqr = _quartiles(dpath)
    time_med, time_iqr = _quartiles(dtime)
    only_ref, only_other = int(np.sum(ok_ref & ~ok)), int(np.sum(ok & ~ok_ref))
    return PairedStats(
        group=group, n=n,
        success_ref=float(ok_ref.mean()) if n else math.nan,
        success_ref_ci=wilson(int(ok_ref.sum()), n),
        success=float(ok.mean()) if n else math.nan, success_ci=wilson(int(ok.sum()), n),
        only_ref=only_ref, only_other=only_other, sign_test_p=sign_test(only_ref, only_other),
        both_reached=len(both), path_diff_median_m=path_med, path_diff_iqr_m=path_iqr,
        path_same_1cm=float(np.mean(np.abs(dpath) < 0.01)) if both else math.nan,
        time_diff_median_s=time_med, time_diff_iqr_s=time_iqr,
        time_same_0_1s=float(np.mean(np.abs(dtime) < 0.1 + 1e-9)) if both else math.nan,
        collisions_ref=sum(ref[k].collisions for k in keys),
        collisions=sum(other[k].collisions for k in keys),
        wall_ref_s=sum(ref[k].wall_s for k in keys), wall_s=sum(other[k].wall_s for k in keys))


def transitions(ref: dict[Key, Episode], other: dict[Key, Episode],
                keys: list[Key]) -> dict[str, dict[str, int]]:
    """counts[reference outcome][other outcome]."""
    counts = Counter((ref[k].outcome, other[k].outcome) for k in keys)
    seen = {o for pair in counts for o in pair}
    order = [o for o in OUTCOME_ORDER if o in seen] + sorted(seen - set(OUTCOME_ORDER))
    return {a: {b: counts.get((a, b), 0) for b in order} for a in order}


def compare(ref: dict[Key, Episode], other: dict[Key, Episode], by: int = 1) -> dict:
    """Overall, per label (``by=1``) or per world (``by=0``) stats, and the transitions."""
    keys = sorted(set(ref) & set(other))
    groups = sorted({k[by] for k in keys})
    return {"pairs": len(keys), "missing": len(set(ref) - set(other)),
            "overall": paired_stats("all", ref, other, keys),
            "groups": [paired_stats(g, ref, other, [k for k in keys if k[by] == g])
                       for g in groups],
            "transitions": transitions(ref, other, keys)}


# -------------------------------------------------------------------------------------- report
def _pct(p: float, ci: tuple[float, float]) -> str:
    return f"{100 * p:.0f} % [{100 * ci[0]:.0f}, {100 * ci[1]:.0f}]"


def _p(p: float) -> str:
    return f"{p:.2f}" if p >= 0.01 else f"{p:.0e}"


def _diff(med: float, iqr: tuple[float, float], unit: str) -> str:
    if math.isnan(med):
        return "-"
    return f"{med:+.2f} [{iqr[0]:+.2f}, {iqr[1]:+.2f}] {unit}"


def stats_table(name: str, ref_name: str, stats: list[PairedStats]) -> list[str]:
    lines = [f"| group | n | success {ref_name} | success {name} | only {ref_name} / only {name} "
             f"(p) | both reached | path {name} - {ref_name}: median [IQR] | same path (1 cm) "
             f"| time {name} - {ref_name}: median [IQR] | same time (0.1 s) | collisions "
             f"{ref_name} / {name} | worker s {ref_name} / {name} (x) |",
             "|---|" + "---:|" * 11]
    for s in stats:
        speed = s.wall_ref_s / s.wall_s if s.wall_s else math.nan
        same_path = "-" if math.isnan(s.path_same_1cm) else f"{100 * s.path_same_1cm:.0f} %"
        same_time = "-" if math.isnan(s.time_same_0_1s) else f"{100 * s.time_same_0_1s:.0f} %"
        lines.append(
            f"| {s.group} | {s.n} | {_pct(s.success_ref, s.success_ref_ci)} | "
            f"{_pct(s.success, s.success_ci)} | {s.only_ref} / {s.only_other} "
            f"({_p(s.sign_test_p)}) | {s.both_reached} | "
            f"{_diff(s.path_diff_median_m, s.path_diff_iqr_m, 'm')} | {same_path} | "
            f"{_diff(s.time_diff_median_s, s.time_diff_iqr_s, 's')} | {same_time} | "
            f"{s.collisions_ref} / {s.collisions} | {s.wall_ref_s:.0f} / {s.wall_s:.0f} "
            f"({speed:.2f}) |")
    return lines


def transition_table(ref_name: str, name: str, matrix: dict[str, dict[str, int]]) -> list[str]:
    cols = list(next(iter(matrix.values())))
    lines = [f"| {ref_name} \\ {name} | " + " | ".join(cols) + " |",
             "|---|" + "---:|" * len(cols)]
    lines.extend(f"| {a} | " + " | ".join(str(row[b]) for b in cols) + " |"
                 for a, row in matrix.items())
    return lines


def report(ref_name: str, results: dict[str, dict], by_world: dict[str, dict],
           title: str | None = None) -> str:
    title = title or "Paired suite study: the physics rate's effect on outcomes, paths and cost"
    lines = [f"## {title}", "",
             "Episodes paired by (world, parameter set, seed). Success with its Wilson 95 % "
             "interval; `only A / only B` counts episodes reached in one run only, with the "
             "exact two-sided sign (McNemar) test's p; path and time differences over episodes "
             "reached in both runs. Worker seconds: one worker per run, concurrent runs on a "
             "shared 2-core machine (the ratio is indicative, not a clean benchmark).", ""]
    for name, res in results.items():
        lines.extend([f"### {name} vs {ref_name} ({res['pairs']} pairs, {res['missing']} "
                      "missing)", "", "By parameter set:", ""])
        lines.extend(stats_table(name, ref_name, [*res["groups"], res["overall"]]))
        lines.extend(["", "By world:", ""])
        lines.extend(stats_table(name, ref_name, by_world[name]["groups"]))
        lines.extend(["", f"Outcome transitions {ref_name} -> {name} (rows: {ref_name}):", ""])
        lines.extend(transition_table(ref_name, name, res["transitions"]))
        lines.append("")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--ref", default="results/fidelity/run_240",
                        help="results folder of the reference rate")
    parser.add_argument("--ref-name", default="240")
    parser.add_argument("--run", action="append", default=[], metavar="NAME=FOLDER",
                        help="a run to compare (repeatable), e.g. 60=results/fidelity/run_60")
    parser.add_argument("--out", default="results/fidelity", help="folder for the tables")
    parser.add_argument("--stem", default="suite", help="file names: STEM.md and STEM.json")
    parser.add_argument("--title", default=None, help="heading of the markdown")
    args = parser.parse_args()
    if not args.run:
        parser.error("give at least one --run NAME=FOLDER")
    ref = read_run(Path(args.ref))
    results, by_world = {}, {}
    for spec in args.run:
        name, _, folder = spec.partition("=")
        if not folder:
            parser.error(f"--run {spec!r}: expected NAME=FOLDER")
        other = read_run(Path(folder))
        results[name] = compare(ref, other, by=1)
        by_world[name] = compare(ref, other, by=0)
    text = report(args.ref_name, results, by_world, args.title)
    print(text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{args.stem}.md").write_text(text + "\n")

    def plain(res: dict) -> dict:
        return {**res, "overall": asdict(res["overall"]),
                "groups": [asdict(g) for g in res["groups"]]}

    (out / f"{args.stem}.json").write_text(json.dumps(
        {"reference": args.ref, "runs": {n: plain(r) for n, r in results.items()},
         "by_world": {n: plain(r) for n, r in by_world.items()}}, indent=1) + "\n")


if __name__ == "__main__":
    main()
