"""Grid maps a planner builds from its own sensing: occupancy (PMO) and visits (PMT)."""

from nav_bench.mapping.grid import Bounds, GridFrame
from nav_bench.mapping.occupancy import UNKNOWN, OccupancyGrid, log_odds_to_values
from nav_bench.mapping.visits import VisitGrid

__all__ = ["UNKNOWN", "Bounds", "GridFrame", "OccupancyGrid", "VisitGrid", "log_odds_to_values"]
