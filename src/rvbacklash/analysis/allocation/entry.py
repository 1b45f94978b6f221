"""The public entry of tolerance allocation: ``allocate`` checks the specs against the model and
picks the exact MILP (linear model, ``milp``) or the Monte-Carlo search (the others, ``search``).
"""

from __future__ import annotations

from typing import Callable

from rvbacklash.analysis.allocation.milp import allocate_linear
from rvbacklash.analysis.allocation.results import AllocationResult
from rvbacklash.analysis.allocation.search import DEFAULT_MC_SAMPLES, allocate_monte_carlo
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem


def allocate(problem: Problem, *, spec_arcmin: float, yield_target: float, model: str = "linear",
             spec_rigidity_nm_per_arcmin: float | None = None, spec_preload_um: float | None = None,
             spec_te_arcsec: float | None = None, spec_life_h: float | None = None,
             spec_rated_torque_nm: float | None = None, samples: int = DEFAULT_MC_SAMPLES, seed: int = 0,
             executor=None, workers: int | None = None, pareto: bool = True,
             progress: Callable[[int], None] | None = None, accuracy_life=None) -> AllocationResult:
    """The cheapest grades per part group meeting the spec at the target yield: exact for the
    linear model, a Monte-Carlo search for the others (modules ``milp``, ``search``). A TE spec
    (``spec_te_arcsec``) turns the contact model into the transmission model (the same units turned
    through a revolution, models.kinematics), as ``simulate`` does. A life spec (``spec_life_h``: the
    reducer's L10 at the rated torque and speed; ``spec_rated_torque_nm``: the derived rated torque;
    lower limits) asks the elastic model for each unit's life (docs/capacity.md), joined with the others.
    ``accuracy_life`` (analysis.service_life.accuracy_yield.AccuracyLifeTarget): the share of units whose
    lost motion stays within ``spec_arcmin`` for its hours of its duty cycle, the elastic model's units
    each with its own wear (docs/service-life.md); the search's, alone."""
    if accuracy_life is not None:
        return allocate_monte_carlo(problem, model=model, spec_arcmin=spec_arcmin, yield_target=yield_target,
                                    spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin,
                                    spec_preload_um=spec_preload_um, spec_te_arcsec=spec_te_arcsec,
                                    spec_life_h=spec_life_h, spec_rated_torque_nm=spec_rated_torque_nm,
                                    samples=samples, seed=seed, executor=executor, workers=workers, progress=progress,
                                    accuracy_life=accuracy_life)
    for name, value in (("spec_life_h", spec_life_h), ("spec_rated_torque_nm", spec_rated_torque_nm)):
        if value is not None and model != "elastic":
            raise InputError(name, value, "the life outputs come from the elastic model's load solution; allowed "
                                          "with the elastic model only")
    if spec_te_arcsec is not None and model == "contact":
        model = "transmission"
    if model == "linear":
        if spec_te_arcsec is not None:
            raise InputError("spec_te_arcsec", spec_te_arcsec, "the linear model has no transmission-error output; "
                                                               "allowed with the contact or transmission model")
        if spec_rigidity_nm_per_arcmin is not None:
            raise InputError("spec_rigidity_nm_per_arcmin", spec_rigidity_nm_per_arcmin,
                             "the linear model has no rigidity output; allowed with a model that has one (elastic)")
        if spec_preload_um is not None:
            raise InputError("spec_preload_um", spec_preload_um,
                             "the linear model has no preload output; allowed with the contact or elastic model")
        return allocate_linear(problem, spec_arcmin=spec_arcmin, yield_target=yield_target, pareto=pareto)
    return allocate_monte_carlo(problem, model=model, spec_arcmin=spec_arcmin, yield_target=yield_target,
                                spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin,
                                spec_preload_um=spec_preload_um, spec_te_arcsec=spec_te_arcsec,
                                spec_life_h=spec_life_h, spec_rated_torque_nm=spec_rated_torque_nm, samples=samples,
                                seed=seed,
                                executor=executor, workers=workers, progress=progress)
