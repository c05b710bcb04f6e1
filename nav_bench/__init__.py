"""nav-bench: a PyBullet benchmark for navigation in a-priori unknown indoor environments."""

__version__ = "0.1.0"
