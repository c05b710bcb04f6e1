"""Validated models of the YAML files users write: worlds, robots, planner parameter sets.

Every model forbids unknown keys. ``load_*`` functions read a file and raise
:class:`~nav_bench.errors.SpecError` naming the file, the key path and the line.
Units: metres, seconds, degrees only where a field name says ``_deg``.
The suite file lives in :mod:`nav_bench.batch.suite`; a world file is loaded (schema, then geometry)
by :mod:`nav_bench.world.load`, a parameter set (schema, then the planner's parameters) by
:mod:`nav_bench.planners.registry`.
"""

from __future__ import annotations

import difflib
import functools
import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, PositiveFloat, model_serializer, model_validator

from nav_bench.errors import SpecError, format_key_path
from nav_bench.paths import project_file
from nav_bench.yamlio import LineIndex, load_yaml, validate

Vec2 = tuple[float, float]
PositiveInt = Annotated[int, Field(gt=0)]
NonNegFloat = Annotated[float, Field(ge=0.0)]
Probability = Annotated[float, Field(ge=0.0, le=1.0)]


class Strict(BaseModel):
    """Base for every spec model: unknown keys are errors, instances are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


def _one_of(kinds: tuple[str, ...], what: str):
    """A ``mode='before'`` validator: the mapping has exactly one key, one of ``kinds``."""

    def check(data: Any) -> Any:
        if not isinstance(data, dict):
            raise ValueError(f"{what} must be a mapping with one key, one of: {', '.join(kinds)}")
        keys = list(data)
        if len(keys) != 1 or keys[0] not in kinds:
            unknown = [k for k in keys if k not in kinds]
            hint = ""
            if unknown:
                close = difflib.get_close_matches(str(unknown[0]), kinds, n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
            raise ValueError(
                f"{what} must have exactly one key, one of: {', '.join(kinds)} "
                f"(got {', '.join(map(str, keys)) or 'none'}){hint}"
            )
        return data

    return check


def _drop_unused_kinds(self: BaseModel, handler: Any) -> Any:
    """Dump a one-key model as that one key, so a dump validates again (round trip)."""
    data = handler(self)
    return {k: v for k, v in data.items() if v is not None} if isinstance(data, dict) else data


# --------------------------------------------------------------------------- world
class Wall(Strict):
    """A straight wall of given thickness between two points (metres)."""

    from_: Vec2 = Field(alias="from")
    to: Vec2
    thickness: PositiveFloat = 0.15

    @model_validator(mode="after")
    def _nonzero(self) -> Wall:
        if math.dist(self.from_, self.to) <= 0.0:
            raise ValueError("a wall needs two different points 'from' and 'to'")
        return self


class Box(Strict):
    """A box: centre and size in metres, rotated by ``yaw_deg`` about its centre."""

    center: Vec2
    size: tuple[PositiveFloat, PositiveFloat]
    yaw_deg: float = 0.0


class Cylinder(Strict):
    """An upright cylinder: centre and radius in metres."""

    center: Vec2
    radius: PositiveFloat


class Polyline(Strict):
    """A chain of walls through ``points``; ``closed`` joins the last point to the first."""

    points: Annotated[list[Vec2], Field(min_length=2)]
    thickness: PositiveFloat = 0.15
    closed: bool = False


OBSTACLE_KINDS = ("wall", "box", "cylinder", "polyline")


class Obstacle(Strict):
    """One static obstacle: a mapping with exactly one key naming its kind."""

    wall: Wall | None = None
    box: Box | None = None
    cylinder: Cylinder | None = None
    polyline: Polyline | None = None

    _check = model_validator(mode="before")(
        lambda data: _one_of(OBSTACLE_KINDS, "an obstacle")(data)
    )
    _dump = model_serializer(mode="wrap")(_drop_unused_kinds)

    @property
    def kind(self) -> str:
        return next(k for k in OBSTACLE_KINDS if getattr(self, k) is not None)

    @property
    def shape(self) -> Wall | Box | Cylinder | Polyline:
        return getattr(self, self.kind)


class MoverCylinder(Strict):
    radius: PositiveFloat


class MoverBox(Strict):
    size: tuple[PositiveFloat, PositiveFloat]


class MoverShape(Strict):
    """The footprint of a moving obstacle: ``{cylinder: {radius}}`` or ``{box: {size}}``."""

    cylinder: MoverCylinder | None = None
    box: MoverBox | None = None

    _check = model_validator(mode="before")(
        lambda data: _one_of(("cylinder", "box"), "a mover shape")(data)
    )
    _dump = model_serializer(mode="wrap")(_drop_unused_kinds)


class Mover(Strict):
    """A moving obstacle following waypoints at constant speed (m/s)."""

    shape: MoverShape
    path: Annotated[list[Vec2], Field(min_length=2)]
    speed: PositiveFloat
    mode: Literal["pingpong", "loop"] = "pingpong"
    phase_s: NonNegFloat = 0.0  # start this many seconds into the motion


class WorldSpec(Strict):
    """A world layout (see INTERFACES.md). The world is [0, sx] x [0, sy] metres."""

    name: str | None = None
    description: str = ""
    size: tuple[PositiveFloat, PositiveFloat]
    boundary: bool = True
    wall_height: PositiveFloat = 0.6
    start: Annotated[list[float], Field(min_length=2, max_length=3)]
    goal: Vec2
    obstacles: list[Obstacle] = Field(default_factory=list)
    movers: list[Mover] = Field(default_factory=list)
    meta: dict[str, Any] = Field(default_factory=dict)  # provenance: source, licence, generator

    @property
    def start_pose(self) -> tuple[float, float, float]:
        """Start (x, y, yaw) with yaw in radians; default yaw faces the goal."""
        x, y = self.start[0], self.start[1]
        if len(self.start) == 3:
            return (x, y, math.radians(self.start[2]))
        return (x, y, math.atan2(self.goal[1] - y, self.goal[0] - x))


# --------------------------------------------------------------------------- robot
class SonarSpec(Strict):
    """Ray-cast sonar model shared by every sonar of the robot."""

    cone_deg: Annotated[float, Field(gt=0, lt=180)] = 25.0  # full opening angle of the cone
    rays: Annotated[int, Field(ge=1, le=64)] = 7  # rays cast per cone, spread over its width
    min_range: NonNegFloat = 0.05  # m; closer returns read min_range
    max_range: PositiveFloat = 3.0  # m; nothing hit reads max_range
    noise_std: NonNegFloat = 0.01  # m; Gaussian noise on each reading
    dropout: Probability = 0.0  # chance a reading is lost (reads max_range)

    @model_validator(mode="after")
    def _ranges(self) -> SonarSpec:
        if self.min_range >= self.max_range:
            raise ValueError("min_range must be below max_range")
        return self


class OdometrySpec(Strict):
    """Wheel odometry noise: each wheel's angle increment is scaled by (1 + N(0, wheel_noise))."""

    wheel_noise: NonNegFloat = 0.002  # fraction of each wheel increment per control cycle


class DriveSpec(Strict):
    """Wheel actuation limits."""

    max_wheel_speed: PositiveFloat = 12.0  # rad/s
    max_wheel_accel: PositiveFloat = 40.0  # rad/s^2
    wheel_force: PositiveFloat = 20.0  # N*m, velocity-motor torque limit


class RobotSpec(Strict):
    """A robot: its URDF (path relative to this file) and sensing/actuation settings."""

    name: str | None = None
    urdf: str = "diffbot.urdf"
    left_wheel_joint: str = "left_wheel_joint"
    right_wheel_joint: str = "right_wheel_joint"
    sonar_link_prefix: str = "sonar_"
    sonar: SonarSpec = SonarSpec()
    odometry: OdometrySpec = OdometrySpec()
    drive: DriveSpec = DriveSpec()
    base_dir: str | None = None  # folder the urdf path is relative to (set by load_robot)

    @property
    def urdf_path(self) -> Path:
        p = Path(self.urdf)
        if not p.is_absolute() and self.base_dir:
            p = Path(self.base_dir) / p
        return p


def default_robot_file() -> Path:
    """``robots/diffbot.yaml`` of the project (or of the installed package data)."""
    return project_file("robots/diffbot.yaml")


@functools.cache
def default_robot_radius() -> float:
    """Body radius (m) of the default robot, read from its URDF: the circle about the root
    link's origin that holds the link's collision cylinders and spheres. The simulator reads
    the same number from the same shapes; world tools without a simulator (generators,
    importers, difficulty) default their ``robot_radius`` to it."""
    urdf = load_robot().urdf_path
    root = ET.parse(urdf).getroot()
    children = {j.find("child").get("link") for j in root.iter("joint")}
    base = next(link for link in root.iter("link") if link.get("name") not in children)
    radius = 0.0
    for shape in base.iter("collision"):
        origin = shape.find("origin")
        x, y = ([float(v) for v in origin.get("xyz", "0 0 0").split()][:2]
                if origin is not None else (0.0, 0.0))
        geometry = next(iter(shape.find("geometry")))
        if geometry.tag not in ("cylinder", "sphere"):
            raise SpecError(f"the base link's collision {geometry.tag} gives no radius here; "
                            f"pass robot_radius explicitly", file=urdf)
        radius = max(radius, math.hypot(x, y) + float(geometry.get("radius")))
    return radius


def load_robot(path: str | Path | None = None, overrides: dict[str, Any] | None = None) -> RobotSpec:
    """Read a robot config file (default ``robots/diffbot.yaml``), with nested overrides."""
    path = Path(path) if path is not None else default_robot_file()
    data, index = load_yaml(path)
    data = dict(data or {})
    data.setdefault("base_dir", str(path.parent.resolve()))
    if overrides:
        data = deep_merge(data, overrides)
    robot = validate(RobotSpec, data, file=path, index=index)
    if robot.name is None:
        robot = robot.model_copy(update={"name": path.stem})
    return robot


def deep_merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``base`` updated by ``over``, recursing into nested mappings."""
    out = dict(base)
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = deep_merge(out[k], v)
        else:
            out[k] = v
    return out


# --------------------------------------------------------------------------- planner set
class PlannerSetSpec(Strict):
    """A planner parameter set: a registered planner name and parameter overrides."""

    planner: str
    params: dict[str, Any] = Field(default_factory=dict)


def raise_at(problem: str, *, file: str | Path | None, index: LineIndex | None,
             loc: tuple[str | int, ...]) -> None:
    """Raise a :class:`SpecError` at key path ``loc`` of a parsed file."""
    raise SpecError(problem, file=file, key_path=format_key_path(loc),
                    line=index.line_of(loc) if index else None)
