"""Test a planner the way nav-bench tests its own, without PyBullet.

* :mod:`~nav_bench.testing.harness` - a kinematic world of boxes, a disc robot with the
  default sonar ring, and :func:`~nav_bench.testing.harness.run` to play a planner in it.
* :mod:`~nav_bench.testing.conformance` - what every planner must do (bounded commands,
  a clean reset, determinism, declared parameters, reaching the goal in an open room):
  ``check_planner(MyPlanner)`` raises ``AssertionError`` naming the first broken rule.
"""
