"""The PyBullet simulator; the only package that imports PyBullet.

* :class:`SimSession` - one PyBullet client (context manager), gravity, ground plane.
* :class:`Simulation` - a world with the robot in it: ``sense``, ``apply``, ``step``, poses,
  collisions. Built from :mod:`scene` (static geometry as compound bodies), :mod:`movers`,
  :mod:`robot` (URDF model, drive, odometry) and :mod:`sonar` (ray-cast cones).
"""

from nav_bench.sim.movers import mover_position, mover_positions
from nav_bench.sim.session import SimSession
from nav_bench.sim.simulation import Simulation

__all__ = ["SimSession", "Simulation", "mover_position", "mover_positions"]
