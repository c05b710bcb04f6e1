"""Tiny worlds and suites written into a test's folder: real episodes in a fraction of a second."""

from __future__ import annotations

from pathlib import Path

OPEN = """\
name: tiny_open
size: [3.0, 3.0]
start: [0.5, 1.5, 0]
goal: [2.5, 1.5]
"""

POST = """\
name: tiny_post
size: [4.0, 3.0]
start: [0.5, 1.2, 0]
goal: [3.5, 1.2]
obstacles:
  - cylinder: {center: [2.0, 2.5], radius: 0.25}
  - box: {center: [2.0, 0.25], size: [0.4, 0.3]}
"""


def write_worlds(folder: Path) -> list[Path]:
    """``tiny_open`` (3 m x 3 m, empty) and ``tiny_post`` (4 m x 3 m, two obstacles aside)."""
    (folder / "worlds").mkdir(parents=True, exist_ok=True)
    paths = [folder / "worlds" / "tiny_open.yaml", folder / "worlds" / "tiny_post.yaml"]
    for path, text in zip(paths, (OPEN, POST), strict=True):
        path.write_text(text)
    return paths


def write_suite(folder: Path, *, name: str = "tiny", planners: str | None = None,
                seeds: int | str = 2, limits: str = "{time_s: 15, stuck_s: 5, wall_s: 60}",
                worlds: str | None = None) -> Path:
    """A suite over the tiny worlds (written too); default: 2 worlds x 2 sets x 2 seeds.

    World paths are absolute, so the suite means the same from any working folder."""
    write_worlds(folder)
    worlds = worlds or f"['{folder / 'worlds'}/*.yaml']"
    planners = planners or "{seek: {planner: goal_seek}, slow: {planner: goal_seek, params: {v_max: 0.3}}}"
    path = folder / f"{name}.yaml"
    path.write_text(f"name: {name}\nworlds: {worlds}\nplanners: {planners}\nseeds: {seeds}\n"
                    f"limits: {limits}\n")
    return path
