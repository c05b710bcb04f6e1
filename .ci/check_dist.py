"""CI: the sdist and the wheel carry the shipped data and no tests, test data or results."""

import sys
import tarfile
import zipfile
from pathlib import Path

dist = Path(sys.argv[1])
wheel = next(dist.glob("*.whl"))
sdist = next(dist.glob("*.tar.gz"))
with zipfile.ZipFile(wheel) as archive:
    wheel_names = archive.namelist()
with tarfile.open(sdist) as archive:
    sdist_names = [n.split("/", 1)[1] for n in archive.getnames() if "/" in n]
problems = []
for must in ("nav_bench/data/configs/suites/default.yaml", "nav_bench/data/configs/suites/smoke.yaml",
             "nav_bench/data/worlds/paper/open_room.yaml", "nav_bench/data/robots/diffbot.urdf"):
    if must not in wheel_names:
        problems.append(f"{wheel.name} lacks {must}")
for must in ("setup.py", "worlds/paper/open_room.yaml", "robots/diffbot.urdf",
             "configs/suites/default.yaml"):
    if must not in sdist_names:
        problems.append(f"{sdist.name} lacks {must}")
for archive, names in ((wheel.name, wheel_names), (sdist.name, sdist_names)):
    for name in names:
        if name.startswith(("tests/", "results/")) or "/tests/" in name or "/results/" in name:
            problems.append(f"{archive} carries {name}")
print("\n".join(problems) or f"{wheel.name}: {len(wheel_names)} files; "
      f"{sdist.name}: {len(sdist_names)} files; data in, tests and results out")
sys.exit(1 if problems else 0)
