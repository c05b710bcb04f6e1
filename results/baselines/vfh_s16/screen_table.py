"""screen_table.py DIR...: the screen rows (DIR/W_sS.json or DIR/W.json = seed 0) as one table:
per world the outcome letter per seed (R reached, S stuck, P pinned, T timeout, E error) and
contacts; per folder reached, episodes with a contact, contacts."""
import json
import sys
from collections import defaultdict
from pathlib import Path

LETTER = {"reached": "R", "timeout": "T", "error": "E"}


def rows(folder: Path) -> dict:
    out = {}
    for f in sorted(folder.glob("*.json")):
        name = f.stem
        world, seed = (name.rsplit("_s", 1) if "_s" in name and name.rsplit("_s", 1)[1].isdigit() else (name, "0"))
        try:
            r = json.loads(f.read_text())
        except ValueError:
            continue
        out[(world, int(seed))] = r
    return out


def letter(r: dict) -> str:
    if r["outcome"] == "stuck":
        return "P" if r.get("stuck_reason") == "pinned" else "S"
    return LETTER.get(r["outcome"], "?")


def main(folders: list[str]) -> None:
    data = {Path(f).name: rows(Path(f)) for f in folders}
    worlds = sorted({w for d in data.values() for w, _ in d})
    print("| world | " + " | ".join(data) + " |")
    print("|---|" + "---|" * len(data))
    for w in worlds:
        cells = []
        for d in data.values():
            seeds = sorted(s for ww, s in d if ww == w)
            cells.append(" ".join(letter(d[(w, s)]) + (f"{d[(w, s)]['collisions']}" if d[(w, s)]["collisions"] else "")
                                  for s in seeds))
        print(f"| {w} | " + " | ".join(cells) + " |")
    tot = defaultdict(list)
    for name, d in data.items():
        reached = sum(r["outcome"] == "reached" for r in d.values())
        touched = sum(r["collisions"] > 0 for r in d.values())
        contacts = sum(r["collisions"] for r in d.values())
        tot[name] = [len(d), reached, touched, contacts]
    print("| episodes / reached / with a contact / contacts | " + " | ".join("/".join(map(str, v)) for v in tot.values()) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
