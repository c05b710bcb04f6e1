"""Planners: the protocol (base), the registry, and one module per planner."""

from nav_bench.planners.base import (
    Command,
    Observation,
    Param,
    Planner,
    PlannerEvent,
    RobotInfo,
    SonarInfo,
)

__all__ = ["Command", "Observation", "Param", "Planner", "PlannerEvent", "RobotInfo", "SonarInfo"]
