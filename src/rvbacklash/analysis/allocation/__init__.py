"""Tolerance allocation: the cheapest precision grade for each part group such that the output
meets its spec at the target yield, P(backlash <= s [and rigidity >= K]) >= P.

Formulation (discrete, chance-constrained; Chase, Greenwood, Loosli & Hauglund, Manufacturing
Review 3(1) (1990) 49-59, for the discrete choice of processes)::

    minimise    sum_j sum_g c_jg x_jg                     (cost of group j at grade g)
    subject to  sum_g x_jg = 1 for every group j,  x_jg in {0, 1},
                P(Y(x) <= s) >= P.

The modules: ``entry`` (``allocate``: the linear model to the MILP, the others to the search),
``milp`` (the linear model: exact yields, outer approximation), ``search`` (the Monte-Carlo
models: common random numbers, verification), ``candidates`` (moves, uniform grades and result
pieces both use), ``specs`` (the targets' checks) and ``results`` (the typed results).
"""

from rvbacklash.analysis.allocation.entry import allocate
from rvbacklash.analysis.allocation.milp import (CALIBRATION_MARGIN, CALIBRATIONS, MAX_OA_ITERATIONS, PARETO_YIELDS,
                                                 SEARCH_GRID_POINTS, ExactYields, LinearSolution, allocate_linear,
                                                 brute_force, solve_linear)
from rvbacklash.analysis.allocation.results import AllocationResult, Baseline, Binding, FrontPoint, GroupGrade
from rvbacklash.analysis.allocation.search import (DEFAULT_MC_SAMPLES, SEARCH_STREAM, VERIFY_STREAM, Evaluation,
                                                   allocate_monte_carlo, evaluate_candidate, search_monte_carlo)
from rvbacklash.analysis.allocation.specs import SPEC_PARAMETERS, check_targets, extra_specs

__all__ = [
    "AllocationResult", "Baseline", "Binding", "CALIBRATIONS", "CALIBRATION_MARGIN", "DEFAULT_MC_SAMPLES",
    "Evaluation", "ExactYields", "FrontPoint", "GroupGrade", "LinearSolution", "MAX_OA_ITERATIONS", "PARETO_YIELDS",
    "SEARCH_GRID_POINTS", "SEARCH_STREAM", "SPEC_PARAMETERS", "VERIFY_STREAM", "allocate", "allocate_linear",
    "allocate_monte_carlo", "brute_force", "check_targets", "evaluate_candidate", "extra_specs",
    "search_monte_carlo", "solve_linear",
]
