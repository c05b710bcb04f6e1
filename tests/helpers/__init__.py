"""Helpers importable by worker processes (``tests.helpers.<module>``): planners that
misbehave and fake episode functions."""
