"""The Python API: every entry point takes a design as a ``Design``, a path to a TOML file, a
built-in example name or an already prepared ``Problem``, prepares it once and returns a typed
result (``to_dict()``, ``to_frame()``). All arguments after the design are keyword arguments.

    import rvbacklash as rb
    sim = rb.simulate("rv80e", samples=10**6, seed=1, spec_arcmin=3.0)
    sim.to_frame()
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterable, Mapping, Union

from rvbacklash.analysis.stackup import StackupResult
from rvbacklash.analysis.stackup import analyze as _analyze
from rvbacklash.design.loading import load_design_source
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem
from rvbacklash.problem import prepare as _prepare

# The analyses below load the compiled kernels (numba) and scipy: imported where they are used,
# so that `analyze` and the command line start fast.
if TYPE_CHECKING:
    from rvbacklash.analysis.contact import NominalContact
    from rvbacklash.analysis.report_data import ReportData
    from rvbacklash.analysis.scenarios import Comparison, Scenario
    from rvbacklash.analysis.simulation import SimulationResult

DesignLike = Union[Design, str, Path, Problem]
DEFAULT_SAMPLES = 1_000_000  # = analysis.simulation.DEFAULT_SAMPLES (a test keeps them equal)
REPORT_SCENARIO_SAMPLES = 1_000_000  # scenarios of a report: at most this many samples each


def prepare(design: DesignLike) -> Problem:
    """A Problem from a Design, a TOML path, an example name, or a Problem (returned as is)."""
    if isinstance(design, Problem):
        return design
    if isinstance(design, Design):
        return _prepare(design)
    if isinstance(design, (str, Path)):
        d, origin, text = load_design_source(design)
        return _prepare(d, origin, text)
    raise InputError("design", type(design).__name__, "allowed: a Design, a path to a TOML file, an example name "
                                                      "or a Problem")


def analyze(design: DesignLike) -> StackupResult:
    """Stack-up and sensitivities of the linear model (Sun et al. 2014, Tables 2-3, Eq. (1)-(7))."""
    return _analyze(prepare(design))


def simulate(design: DesignLike, *, samples: int = DEFAULT_SAMPLES, seed: int = 0, method: str = "default",
             spec_arcmin: float | None = None, specs: Mapping[str, float] | None = None,
             quantiles: Iterable[float] = (), workers: int | None = None, model: str | Callable = "linear",
             progress: Callable[[int], None] | None = None, stream: tuple[int, ...] = ()) -> SimulationResult:
    """Monte-Carlo simulation (or ``method="exact"``): distributions of the model's outputs with
    confidence intervals, yield against the specs. Defaults: 10^6 samples, seed 0, the linear
    model, all cores. See ``rvbacklash.analysis.simulation.simulate``."""
    from rvbacklash.analysis.simulation import simulate as _simulate

    return _simulate(prepare(design), samples=samples, seed=seed, method=method, spec_arcmin=spec_arcmin,
                     specs=specs, quantiles=tuple(quantiles), workers=workers, model=model, progress=progress,
                     stream=stream)


def exact(design: DesignLike, *, spec_arcmin: float | None = None, quantiles: Iterable[float] = ()) -> SimulationResult:
    """The linear model's exact output distribution (closed form, or FFT convolution)."""
    from rvbacklash.analysis.simulation import exact_result

    return exact_result(prepare(design), spec_arcmin=spec_arcmin, quantiles=tuple(quantiles))


def paper_scenarios(design: DesignLike) -> list[Scenario]:
    """The four precision-grade scenarios of the paper's Fig. 4 for this design."""
    from rvbacklash.analysis.scenarios import paper_scenarios as _paper_scenarios

    return _paper_scenarios(prepare(design))


def compare(design: DesignLike, scenarios: Iterable[Scenario] = (), *, paper: bool = False,
            samples: int = DEFAULT_SAMPLES, seed: int = 0, method: str = "default", spec_arcmin: float | None = None,
            model: str = "linear", workers: int | None = None,
            progress: Callable[[int], None] | None = None) -> Comparison:
    """Simulate precision-grade scenarios of one design alike (``paper=True`` adds Fig. 4's)."""
    from rvbacklash.analysis.scenarios import compare as _compare
    from rvbacklash.analysis.scenarios import paper_scenarios as _paper_scenarios

    problem = prepare(design)
    chosen = (_paper_scenarios(problem) if paper else []) + list(scenarios)
    return _compare(problem, chosen, samples=samples, seed=seed, method=method, spec_arcmin=spec_arcmin,
                    model=model, workers=workers, progress=progress)


def check_crank_angle(crank_angle_deg: float) -> float:
    if isinstance(crank_angle_deg, bool) or not isinstance(crank_angle_deg, (int, float)) \
            or not math.isfinite(crank_angle_deg) or abs(crank_angle_deg) > 360:
        raise InputError("crank_angle_deg", crank_angle_deg, "allowed: -360 <= angle <= 360 [deg]")
    return float(crank_angle_deg)


def contact(design: DesignLike, *, crank_angle_deg: float = 0.0) -> NominalContact:
    """Play of the nominal design from the exact cycloid-pin geometry at one crank angle."""
    from rvbacklash.analysis.contact import nominal_contact

    return nominal_contact(prepare(design), check_crank_angle(crank_angle_deg))


def make_report(design: DesignLike, *, samples: int = DEFAULT_SAMPLES, seed: int = 0, method: str = "default",
           spec_arcmin: float | None = None, scenarios: Iterable[Scenario] = (), paper: bool = False,
           model: str = "linear", workers: int | None = None,
           progress: Callable[[int], None] | None = None) -> ReportData:
    """Everything a report shows (render it with ``rvbacklash.render_html``): stack-up,
    simulation, scenarios (those given, plus Fig. 4's when ``paper``), nominal contact. An
    interrupted simulation skips the scenarios; the data are then marked partial."""
    from rvbacklash.analysis.contact import nominal_contact
    from rvbacklash.analysis.report_data import build_report_data
    from rvbacklash.analysis.scenarios import Comparison
    from rvbacklash.analysis.scenarios import compare as _compare
    from rvbacklash.analysis.scenarios import paper_scenarios as _paper_scenarios
    from rvbacklash.analysis.simulation import simulate as _simulate

    problem = prepare(design)
    stack = _analyze(problem)
    chosen = (_paper_scenarios(problem) if paper else []) + list(scenarios)
    sim = _simulate(problem, samples=samples, seed=seed, method=method, spec_arcmin=spec_arcmin, model=model,
                    workers=workers, progress=progress)
    comparison = None
    if chosen:
        n = min(samples, REPORT_SCENARIO_SAMPLES) if method != "exact" else samples
        comparison = Comparison(problem.name, spec_arcmin, model, method, seed, n, (), True,
                                tuple(s.name for s in chosen)) if sim.partial else \
            _compare(problem, chosen, samples=n, seed=seed, method=method, spec_arcmin=spec_arcmin, model=model,
                     workers=workers)
    return build_report_data(problem, stack, sim, spec_arcmin, comparison, nominal_contact(problem))
