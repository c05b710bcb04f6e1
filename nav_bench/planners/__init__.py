"""Planners: the base class, the registry, and one module per planner.

``Command``, ``Observation`` and the other shared types live in :mod:`nav_bench.interface`;
they are importable from here too, so ``from nav_bench.planners import Command, Observation,
Param, Planner`` is all a planner needs.
"""

from nav_bench.interface import Command, Observation, PlannerEvent, RobotInfo, SonarInfo
from nav_bench.planners.base import Param, Planner

__all__ = ["Command", "Observation", "Param", "Planner", "PlannerEvent", "RobotInfo", "SonarInfo"]
