"""The result row's map-quality fields (issue 12): filled from the planner's final grid for a
planner that builds one, null for one that does not, optional in stored rows."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_bench.episode import EpisodeSettings
from nav_bench.episode.loop import run_episode
from nav_bench.episode.row import ResultRow, RowSchemaError, check_row
from nav_bench.mapping.quality import MAP_QUALITY_FIELDS
from nav_bench.specs import PlannerSetSpec
from nav_bench.world.load import load_world

ROOT = Path(__file__).resolve().parents[2]
OPEN_ROOM = ROOT / "worlds" / "paper" / "open_room.yaml"


@pytest.fixture(scope="module")
def dstar_rows() -> dict[str, ResultRow]:
    """D* Lite and goal seek for 8 simulated seconds in the open room (10 m x 10 m, walls only)."""
    world = load_world(OPEN_ROOM)
    settings = EpisodeSettings(time_s=8.0)
    return {name: run_episode(world, PlannerSetSpec(planner=name), seed=0, settings=settings,
                              world_file=str(OPEN_ROOM)).row
            for name in ("dstar_lite", "goal_seek")}


def test_a_grid_building_planner_gets_map_quality_in_its_row(dstar_rows) -> None:
    row = dstar_rows["dstar_lite"]
    assert row.outcome == "timeout"  # 8 s is not enough to cross the room: the map is partial
    fields = row.to_json()
    assert all(k in fields for k in MAP_QUALITY_FIELDS)
    # the walls it saw are marked where they are; the open room has nothing on the optimal path
    assert row.map_precision is not None and row.map_precision >= 0.9
    # recall counts every true wall cell any cone touched, also the faint edges of far cones
    assert row.map_recall is not None and 0.2 <= row.map_recall <= 1.0
    # how many wall cells it marks in 8 s depends on how fast the follower starts (10 since
    # the s5d97 follower, which keeps a margin that grows with speed); what matters is that
    # it marks some and that they are where the walls are (the precision above)
    assert row.map_observed_cells > 1000 and row.map_occupied_cells > 0
    # the diagonal (1, 1) -> (9, 9) at 0.1 m cells crosses 80..160 cells, none invented
    assert 80 <= row.map_path_cells <= 160
    assert (row.map_phantom_cells, row.map_phantom_share) == (0, 0.0)
    stored = {**fields, "job_id": "j", "label": "dstar_lite"}  # as the batch store writes it
    assert ResultRow.from_json(stored).map_path_cells == row.map_path_cells


def test_a_planner_without_a_grid_has_null_map_fields(dstar_rows) -> None:
    row = dstar_rows["goal_seek"]
    assert all(getattr(row, k) is None for k in MAP_QUALITY_FIELDS)
    assert not set(MAP_QUALITY_FIELDS) & set(row.to_json())  # null: left out of the JSON line


def test_map_fields_are_optional_and_checked_in_stored_rows(dstar_rows) -> None:
    fields = {**dstar_rows["dstar_lite"].to_json(), "job_id": "j", "label": "dstar_lite"}
    old = {k: v for k, v in fields.items() if k not in MAP_QUALITY_FIELDS}
    check_row(old)  # rows stored before the fields existed stay valid
    assert ResultRow.from_json(old).map_precision is None
    with pytest.raises(RowSchemaError, match="map_precision"):
        check_row({**fields, "map_precision": "high"})
