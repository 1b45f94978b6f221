"""The typed problem: a validated design with everything derived from it, built once by
``prepare`` and handed to every model and analysis."""

from rvbacklash.problem.problem import Problem, derive_geometry, prepare

__all__ = ["Problem", "derive_geometry", "prepare"]
