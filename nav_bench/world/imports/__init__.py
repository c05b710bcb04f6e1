"""Map importers: ROS map_server maps, MovingAI grid maps, BARN Gazebo worlds.

Each ``import_*`` function returns plain world data (a dict ready for
:func:`nav_bench.world.load.world_from_data`) with attribution in ``meta`` (``source``,
``licence``); :func:`write_world_yaml` writes it as a readable world file.
"""

from nav_bench.world.imports.barn import import_barn
from nav_bench.world.imports.grid import pick_endpoints
from nav_bench.world.imports.movingai import import_movingai, read_movingai_map, read_scen
from nav_bench.world.imports.rectangles import merge_cells
from nav_bench.world.imports.ros import import_ros
from nav_bench.world.imports.yaml_out import dump_world_yaml, write_world_yaml

__all__ = [
    "dump_world_yaml",
    "import_barn",
    "import_movingai",
    "import_ros",
    "merge_cells",
    "pick_endpoints",
    "read_movingai_map",
    "read_scen",
    "write_world_yaml",
]
