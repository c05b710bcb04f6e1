"""sonar_vs_true_table.py OUT...: the table of sonar_vs_true_map.md from sonar_gap.py outputs:
per episode and zone (in the gap, within 0.3 m of its midpoint; the approach), the cycles the
way-on sector is closed, the mean H^p there by class, and how many of those cycles open
(H^p under threshold_high) with the true parts alone, with only the true parts of cells
centred inside an obstacle, without class a, without class b, and on the oracle's true map.
The mechanical class: (c) when the true parts alone keep half or more of the closed cycles
closed, else (a) or (b), whichever's removal opens more; the write-up judges each row."""
import re
import sys

CLASSES = ("true", "a0", "a1", "b_expired", "b_undone", "b_forgot", "b_unpaired")
ZONE = re.compile(r"  (.+?): (\d+) closed cycles; mean H\^p while closed, by class: (.*?) \(true from cells "
                  r"centred outside the obstacle: (\d+)\)\n    of them open \(H\^p under the threshold\) with: (.*)")


def pairs(text):
    """'key v, key v' as {key: float}."""
    return {k: float(v) for k, v in (item.rsplit(" ", 1) for item in text.split(", "))}


def parse(path):
    with open(path) as fh:
        text = fh.read()
    head = re.search(r"^(\S+) seed (\d+): (\S+)", text, re.M)
    near = int(re.search(r"cycles within [\d.]+ m: (\d+)", text).group(1))
    zones = [(z, int(n), pairs(means), float(outer), pairs(op)) for z, n, means, outer, op in ZONE.findall(text)]
    return f"{head.group(1)} s{head.group(2)}", near, zones


def klass(closed, opens):
    if closed - opens.get("true only < high", 0) >= closed / 2:
        return "c"
    return "a" if opens.get("without class a < high", 0) > opens.get("without class b < high", 0) else "b"


print("| episode, zone | cycles within 1.3 m: way on closed | mean H^p while closed: true (of it from cells "
      "centred outside) / a0 + a1 / b: expired, undone, forgot, unpaired | closed cycles opened by: true parts "
      "only (< high, < low) / true parts of cells centred inside only / without a / without b / oracle map "
      "| class |")
print("|---|---|---|---|---|")
totals = dict.fromkeys(CLASSES, 0.0)
for path in sys.argv[1:]:
    name, near, zones = parse(path)
    for zone, n, m, outer, o in zones:
        for c in CLASSES:
            totals[c] += n * m[c]
        g = {k: int(v) for k, v in o.items()}
        print(f"| {name}, {zone.split(' (')[0]} | {near}: {n} | {m['true']:.0f} ({outer:.0f}) / "
              f"{m['a0'] + m['a1']:.0f} / {m['b_expired']:.0f}, {m['b_undone']:.0f}, {m['b_forgot']:.0f}, "
              f"{m['b_unpaired']:.0f} | {g.get('true only < high', 0)}, {g.get('true only < low', 0)} / "
              f"{g.get('true of cells centred inside only < high', 0)} / {g.get('without class a < high', 0)} / "
              f"{g.get('without class b < high', 0)} / {g.get('oracle whole < high', 0)} | {klass(n, o)} |")
whole = sum(totals.values())
print("magnitude summed over the closed cycles, share by class: "
      + ", ".join(f"{c} {totals[c] / whole:.2f}" for c in CLASSES))
