"""The Python API: every entry point takes a design as a ``Design``, a path to a TOML file, a
built-in example name or an already prepared ``Problem``, prepares it once and returns a typed
result (``to_dict()``, ``to_frame()``). All arguments after the design are keyword arguments.

    import rvbacklash as rb
    sim = rb.simulate("rv80e", samples=10**6, seed=1, spec_arcmin=3.0)
    sim.to_frame()
"""

from __future__ import annotations

import dataclasses
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
    from rvbacklash.analysis.allocation import AllocationResult
    from rvbacklash.analysis.bench import BenchResult
    from rvbacklash.analysis.calibration import CalibrationResult
    from rvbacklash.analysis.capacity import CapacityResult, CapacityTrade
    from rvbacklash.analysis.losses import EfficiencyResult
    from rvbacklash.analysis.contact import NominalContact
    from rvbacklash.analysis.hysteresis import ElasticSection, HysteresisResult
    from rvbacklash.analysis.report_data import ReportData
    from rvbacklash.analysis.scenarios import Comparison, Scenario
    from rvbacklash.analysis.simulation import SimulationResult
    from rvbacklash.analysis.sensitivity_global import SensitivityResult
    from rvbacklash.analysis.service_life.calibration import WearCalibration
    from rvbacklash.analysis.service_life.results import ServiceLifeResult

DesignLike = Union[Design, str, Path, Problem]
DEFAULT_SAMPLES = 1_000_000  # = analysis.simulation.DEFAULT_SAMPLES (a test keeps them equal)
ALLOCATION_SAMPLES = 1 << 16  # per candidate of a Monte-Carlo allocation (= analysis.allocation.DEFAULT_MC_SAMPLES)
REPORT_SCENARIO_SAMPLES = 1_000_000  # scenarios of a report: at most this many samples each
REPORT_SERVICE_LIFE_SAMPLES = 2000  # units of a report's service-life production run (at most)
REPORT_SELECTION_SAMPLES = 4000  # each point of a report's yield versus the pin classes (+-1.6 points at 95 %)


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
             progress: Callable[[int], None] | None = None, stream: tuple[int, ...] = (),
             error_model: str | None = None, save_units: int = 0, life: bool = False) -> SimulationResult:
    """Monte-Carlo simulation (or ``method="exact"``): distributions of the model's outputs with
    confidence intervals, yield against the specs. Defaults: 10^6 samples, seed 0, the linear
    model, all cores. ``error_model`` (contact/elastic models) overrides the design's reading of
    the per-element errors; ``save_units`` keeps the first units with their errors (see
    ``measured_units``); ``life`` (elastic model; implied by a spec on ``life``, ``rated_torque``,
    ``weakest_bearing_life`` or ``max_pin_stress``) adds each unit's life outputs (docs/capacity.md).
    See ``rvbacklash.analysis.simulation.simulate``."""
    from rvbacklash.analysis.simulation import simulate as _simulate

    return _simulate(prepare(design), samples=samples, seed=seed, method=method, spec_arcmin=spec_arcmin,
                     specs=specs, quantiles=tuple(quantiles), workers=workers, model=model, progress=progress,
                     stream=stream, error_model=error_model, save_units=save_units, life=life)


def simulate_selected(design: DesignLike, *, select, samples: int = DEFAULT_SAMPLES, seed: int = 0,
                      spec_arcmin: float | None = None, specs: Mapping[str, float] | None = None,
                      quantiles: Iterable[float] = (), workers: int | None = None, model: str = "elastic",
                      progress: Callable[[int], None] | None = None, error_model: str | None = None,
                      save_units: int = 0):
    """A production run with random assembly and with selective assembly (``select``: a
    ``Selection`` or the ``--select`` string, e.g. "pins=5x2um,rollers=3x2um"), the same seed and
    units, side by side: a ``SelectionResult`` (docs/selective-assembly.md)."""
    from rvbacklash.analysis.selection.classes import as_selection
    from rvbacklash.analysis.selection.run import simulate_selected as _run

    selection = as_selection(select)
    if selection is None:
        raise InputError("select", None, "allowed: a Selection or a string such as 'pins=5x2um,rollers=3x2um'")
    return _run(prepare(design), selection, samples=samples, seed=seed, spec_arcmin=spec_arcmin, specs=specs,
                quantiles=tuple(quantiles), workers=workers, model=model, progress=progress,
                error_model=error_model, save_units=save_units)


def generate_batch(design: DesignLike, *, units: int, seed: int = 0):
    """A batch of ``units`` measured units (pins not chosen) and their measured pins and roller sets,
    drawn with ``seed``: (units, parts) for ``assemble`` (docs/selective-assembly.md)."""
    from rvbacklash.analysis.selection.assembly import generate_batch as _generate
    from rvbacklash.sampling.seeds import check_seed

    return _generate(prepare(design), units, check_seed(seed))


def assemble(design: DesignLike, *, units, parts, select="pins=5x2um,rollers=3x2um",
             spec_lost_motion_arcmin: float | None = None):
    """The assembly sheet of a measured batch: ``units`` (a measured-unit file or MeasuredUnit
    records), ``parts`` (a CSV of measured parts or Part records), ``select`` (a Selection or the
    ``--select`` string). Returns (AssemblySheet, the built units as assembled)."""
    from rvbacklash.analysis.selection.assembly import assemble as _assemble, read_parts
    from rvbacklash.analysis.selection.classes import as_selection
    from rvbacklash.design.measured import load_units

    problem = prepare(design)
    if isinstance(units, (str, Path)):
        units = load_units(units, problem.design)
    if isinstance(parts, (str, Path)):
        parts = read_parts(parts)
    return _assemble(problem, list(units), list(parts), as_selection(select), spec_lost_motion_arcmin)


def output_specs(model: str, spec_arcmin: float | None, lost_motion: float | None, rigidity: float | None,
                 preload: float | None = None, life_h: float | None = None,
                 rated_torque_nm: float | None = None) -> dict[str, float]:
    """The specs beside ``spec_arcmin``, by output name ({"lost_motion": X, "rigidity": K,
    "preload": P, "life": L, "rated_torque": T}); each checked against the model that has the
    output. The command line (``--spec-*`` flags) and the workbench (``"specs"``) read their specs
    through it. A life spec asks the elastic model for its life outputs (docs/capacity.md)."""
    specs = {}
    for name, key, value, models in (("spec_lost_motion_arcmin", "lost_motion", lost_motion, ("elastic",)),
                                     ("spec_rigidity_nm_per_arcmin", "rigidity", rigidity, ("elastic",)),
                                     ("spec_preload_um", "preload", preload, ("contact", "elastic")),
                                     ("spec_life_h", "life", life_h, ("elastic",)),
                                     ("spec_rated_torque_nm", "rated_torque", rated_torque_nm, ("elastic",))):
        if value is None:
            continue
        if model not in models:
            raise InputError(name, value, f"allowed with --model {' or '.join(models)} only")
        if not (math.isfinite(value) and (value >= 0 if key == "preload" else value > 0)):
            raise InputError(name, value, "allowed: a finite number >= 0" if key == "preload" else
                             "allowed: a finite number > 0")
        specs[key] = value
    if lost_motion is not None and spec_arcmin is not None:
        raise InputError("spec_lost_motion_arcmin", lost_motion, "allowed: --spec-arcmin or --spec-lost-motion-arcmin, "
                                                                 "not both (both set the lost motion's spec)")
    return specs


def te_model_and_specs(model: str, spec_te_arcsec: float | None, specs: dict) -> tuple[str, dict]:
    """A TE spec (``spec_te_arcsec``), checked before any work; with the contact model the run
    becomes the transmission model's (the same units, turned through a revolution)."""
    if spec_te_arcsec is None:
        return model, specs
    if model not in ("contact", "transmission"):
        raise InputError("spec_te_arcsec", spec_te_arcsec, "allowed with --model contact or transmission only")
    if not (math.isfinite(spec_te_arcsec) and spec_te_arcsec > 0):
        raise InputError("spec_te_arcsec", spec_te_arcsec, "allowed: a finite number > 0 [arcsec]")
    return "transmission", {**specs, "transmission_error": spec_te_arcsec}


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


def contact(design: DesignLike, *, crank_angle_deg: float | None = None, measured=None,
            unit: int | None = None):
    """Play of one unit from the exact cycloid-pin geometry: the nominal design, or the units of
    ``measured`` (a UNIT.toml path, a MeasuredUnit or a list of them; ``unit`` picks one, 0-based).
    ``crank_angle_deg`` defaults to the unit's own (0 for the nominal design). One unit gives a
    NominalContact, several a list of them."""
    from rvbacklash.analysis.contact import measured_contact, nominal_contact
    from rvbacklash.design.measured import MeasuredUnit, load_units

    if crank_angle_deg is not None:
        check_crank_angle(crank_angle_deg)
    problem = prepare(design)
    if measured is None:
        if unit is not None:
            raise InputError("unit", unit, "allowed only with measured units")
        return nominal_contact(problem, crank_angle_deg or 0.0)
    source = str(measured) if isinstance(measured, (str, Path)) else "given units"
    units = load_units(measured, problem.design) if isinstance(measured, (str, Path)) else \
        [measured] if isinstance(measured, MeasuredUnit) else list(measured)
    if unit is not None:
        if isinstance(unit, bool) or not isinstance(unit, int) or not 0 <= unit < len(units):
            raise InputError("unit", unit, f"allowed: 0 to {len(units) - 1} ({len(units)} units in {source})")
        return measured_contact(problem, units[unit], f"unit {unit} of {source}", crank_angle_deg)
    results = [measured_contact(problem, u, f"unit {k} of {source}" if len(units) > 1 else source, crank_angle_deg)
               for k, u in enumerate(units)]
    return results[0] if len(results) == 1 else results


def transmission_error(design: DesignLike, *, measured=None, unit: int | None = None, positions: int | None = None,
                       load_direction: str = "ccw", shares: bool = True, temperature_c: float | None = None):
    """Transmission error and rigid lost motion of one unit over a full output revolution
    (docs/transmission-error.md): the nominal design, or unit ``unit`` (0-based, default 0) of
    ``measured`` (a UNIT.toml path, a MeasuredUnit or a list of them), from its crank angle.
    ``positions`` per revolution (default 1024), ``load_direction`` the flank of the headline
    figures (ccw | cw), ``shares`` the TE with each error group switched off; ``temperature_c``: the
    reducer's temperature (oil and parts alike, as ``efficiency``'s) [degC]: the unit with its parts'
    differential expansion from [thermal] (docs/efficiency.md; None: the reference temperature)."""
    from rvbacklash.analysis.contact import unit_realization
    from rvbacklash.analysis.transmission import DEFAULT_POSITIONS, perfect_unit
    from rvbacklash.analysis.transmission import transmission_error as _plain_te
    from rvbacklash.design.measured import MeasuredUnit, load_units

    problem = prepare(design)
    n = DEFAULT_POSITIONS if positions is None else positions
    if temperature_c is not None:
        from rvbacklash.analysis.losses.thermal import check_temperature, clearance_change, transmission_at_temperature

        change = clearance_change(problem, problem.design.thermal, check_temperature("temperature_c", temperature_c))

        def _te(problem, r, label, n, load_direction, shares, other_stages_arcmin=None):
            return transmission_at_temperature(problem, r, change, n, load_direction, shares, label,
                                               other_stages_arcmin)
    else:
        _te = _plain_te
    if measured is None:
        if unit is not None:
            raise InputError("unit", unit, "allowed only with measured units")
        return _te(problem, perfect_unit(problem), "nominal", n, load_direction, shares)
    source = str(measured) if isinstance(measured, (str, Path)) else "given units"
    units = load_units(measured, problem.design) if isinstance(measured, (str, Path)) else \
        [measured] if isinstance(measured, MeasuredUnit) else list(measured)
    k = 0 if unit is None else unit
    if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < len(units):
        raise InputError("unit", unit, f"allowed: 0 to {len(units) - 1} ({len(units)} units in {source})")
    label = f"unit {k} of {source}" if len(units) > 1 else source
    return _te(problem, unit_realization(problem, units[k]), label, n, load_direction, shares,
               other_stages_arcmin=units[k].other_stages_arcmin)


def measured_units(design: DesignLike, result: SimulationResult):
    """The units a run saved (``simulate(..., save_units=N)``) as measured units (UNIT.toml records)."""
    from rvbacklash.analysis.contact import measured_units as _units

    return _units(prepare(design), result.units)


def make_report(design: DesignLike, *, samples: int = DEFAULT_SAMPLES, seed: int = 0, method: str = "default",
                spec_arcmin: float | None = None, specs: Mapping[str, float] | None = None,
                scenarios: Iterable[Scenario] = (), paper: bool = False, model: str = "linear",
                workers: int | None = None, sensitivity: bool = False, allocate: bool = False,
                yield_target: float | None = None, spec_rigidity_nm_per_arcmin: float | None = None,
                spec_preload_um: float | None = None, spec_te_arcsec: float | None = None,
                allocate_model: str | None = None,
                allocate_samples: int = ALLOCATION_SAMPLES,
                sweep_dir: str | Path | None = None,
                progress: Callable[[int], None] | None = None, capacity: bool = False, efficiency: bool = False,
                duty_cycle: str | Path | None = None, select=None, service_life: bool = False,
                service_life_hours: Iterable[float] = (0.0, 1000.0, 6000.0)) -> ReportData:
    """Everything a report shows (render it with ``rvbacklash.render_html``): stack-up,
    simulation, scenarios (those given, plus Fig. 4's when ``paper``), nominal contact; with
    ``model="elastic"`` the test-bench section (nominal loop, the 5 % and 95 % units' loops,
    histograms); with ``model="transmission"`` or a TE spec ``spec_te_arcsec`` (which turns the
    linear or contact model into the transmission model) the transmission-error section (curves of the
    nominal and the 5 % / 95 % units, spectrum, histogram); ``sensitivity``: Sobol indices of the model; ``allocate``: the cheapest grades
    meeting ``spec_arcmin`` [and ``spec_rigidity_nm_per_arcmin``, ``spec_preload_um``] at ``yield_target`` (with
    the Sobol chart) with ``allocate_model`` (default: ``model``; e.g. "linear" for a fast, conservative
    allocation beside a Monte-Carlo report) and ``allocate_samples`` per candidate (Monte-Carlo models);
    ``sweep_dir``: a finished sweep's results (``rvbacklash sweep``); ``capacity``: the capacity and life
    section (docs/capacity.md); ``efficiency``: the losses and efficiency section (docs/efficiency.md), with
    ``duty_cycle`` (a CSV or TOML file or a packaged cycle's name; implies ``efficiency``) its thermal balance
    and lost motion and backlash at the steady temperature; ``select`` (a Selection or the ``--select`` string; contact, elastic or
    transmission model, a spec): the selection section, the same units assembled at random (the report's
    run) and selected, and the yield versus the number of pin classes (docs/selective-assembly.md). An
    interrupted simulation skips what follows it; the data are then marked partial."""
    from rvbacklash.analysis.contact import nominal_contact
    from rvbacklash.analysis.report_data import build_report_data
    from rvbacklash.analysis.scenarios import Comparison
    from rvbacklash.analysis.scenarios import compare as _compare
    from rvbacklash.analysis.scenarios import paper_scenarios as _paper_scenarios
    from rvbacklash.analysis.simulation import simulate as _simulate

    problem = prepare(design)
    cycle = None
    if duty_cycle is not None:  # read before any work: a bad file fails first
        from rvbacklash.design.duty_cycle import read_duty_cycle

        cycle = read_duty_cycle(example_duty_cycle(duty_cycle))
        efficiency = efficiency or not service_life  # alone, it asks for the efficiency section's thermal balance
    life_cycle = life_hours = None
    life_spec = float(dict(specs or {}).get("lost_motion", spec_arcmin if model == "elastic" and spec_arcmin else 1.5))
    if service_life:  # its inputs checked before any work too
        from rvbacklash.analysis.service_life.stepping import check_hours
        from rvbacklash.design.duty_cycle import read_duty_cycle

        life_hours = check_hours(service_life_hours)
        life_cycle = cycle if cycle is not None else read_duty_cycle(example_duty_cycle("robot-joint"))
        if problem.design.elastic is None:
            raise InputError("elastic", None, "the service-life section needs the design's [elastic] table (the "
                                              "loads of the elastic model; docs/service-life.md)")
    if allocate_model is not None and allocate_model not in ("linear", "contact", "elastic", "transmission"):
        raise InputError("allocate_model", allocate_model, "allowed: linear, contact, elastic or transmission")
    if allocate_model is not None and not allocate:
        raise InputError("allocate_model", allocate_model, "allowed with allocate only")
    if allocate and (spec_arcmin is None or yield_target is None):
        raise InputError("yield_target" if spec_arcmin is not None else "spec_arcmin",
                         yield_target if spec_arcmin is not None else spec_arcmin,
                         "allowed: a value; an allocation needs spec_arcmin and yield_target")
    if spec_te_arcsec is not None:
        from rvbacklash.analysis.allocation import check_targets

        check_targets(1.0, 0.9, spec_te_arcsec=spec_te_arcsec)
        if model not in ("linear", "contact", "transmission"):  # linear: the default, it has no TE
            raise InputError("spec_te_arcsec", spec_te_arcsec, "allowed with the linear (the default), contact or "
                                                               "transmission model")
        model = "transmission"
        specs = {**dict(specs or {}), "transmission_error": float(spec_te_arcsec)}
    sweep = None
    if sweep_dir is not None:
        from rvbacklash.analysis.sweep import load_sweep

        try:
            sweep = load_sweep(sweep_dir)
        except InputError as e:
            raise e.renamed("sweep_dir") if e.field == "out" else e from None
    selection = None
    if select is not None:
        from rvbacklash.analysis.selection.classes import as_selection

        selection = as_selection(select)
        if model not in ("contact", "elastic", "transmission"):
            raise InputError("select", str(selection), "allowed with the contact, elastic or transmission model")
        if spec_arcmin is None and not specs:
            raise InputError("select", str(selection), "needs a spec to compare the yields, e.g. spec_arcmin")
    stack = _analyze(problem)
    chosen = (_paper_scenarios(problem) if paper else []) + list(scenarios)
    sim = _simulate(problem, samples=samples, seed=seed, method=method, spec_arcmin=spec_arcmin, specs=specs,
                    model=model, workers=workers, progress=progress)
    comparison = elastic = sens = alloc = transmission = None
    if chosen:
        n = min(samples, REPORT_SCENARIO_SAMPLES) if method != "exact" else samples
        comparison = Comparison(problem.name, spec_arcmin, model, method, seed, n, (), True,
                                tuple(s.name for s in chosen)) if sim.partial else \
            _compare(problem, chosen, samples=n, seed=seed, method=method, spec_arcmin=spec_arcmin, model=model,
                     workers=workers)
    if model == "elastic" and not sim.partial:
        from rvbacklash.analysis.hysteresis import elastic_section

        elastic = elastic_section(problem, simulation=sim, specs={**({"lost_motion": spec_arcmin} if spec_arcmin
                                                                       else {}), **dict(specs or {})}, seed=seed)
    if model == "transmission" and not sim.partial:
        from rvbacklash.analysis.transmission import transmission_section

        transmission = transmission_section(problem, simulation=sim, spec_te_arcsec=spec_te_arcsec, seed=seed)
    if (sensitivity or allocate) and not sim.partial:
        from rvbacklash.analysis.sensitivity_global import global_sensitivity

        sens = global_sensitivity(problem, model=model, seed=seed,
                                  samples=SENSITIVITY_SAMPLES if model == "linear" else REPORT_SENSITIVITY_SAMPLES)
    if allocate and not sim.partial:
        from rvbacklash.analysis.allocation import allocate as _allocate

        by = allocate_model or model
        alloc = _allocate(problem, spec_arcmin=spec_arcmin, yield_target=yield_target, model=by,
                          spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin if by == "elastic" else None,
                          spec_preload_um=spec_preload_um if by != "linear" else None,
                          spec_te_arcsec=spec_te_arcsec if by in ("contact", "transmission") else None, seed=seed,
                          workers=workers,
                          **({"samples": allocate_samples} if by != "linear" else {}))
    cap = trade = None
    if capacity:  # the capacity and life section (issue 37; docs/capacity.md): the nominal unit's datasheet
        from rvbacklash.analysis.capacity import capacity_rating, capacity_trade

        cap = capacity_rating(problem)
        if not sim.partial:  # and the trade: lost motion against life of the design and its what-ifs
            trade = capacity_trade(problem)
    eff = None
    if efficiency and not sim.partial:  # the losses and temperature section (issue 40; docs/efficiency.md)
        from rvbacklash.analysis.losses import efficiency_rating

        eff = efficiency_rating(problem, duty_cycle=cycle)
    chosen_run = picked_classes = None
    if selection is not None and not sim.partial:  # the same units selected, and the yield vs the pin classes
        from rvbacklash.analysis.selection.run import class_sweep, selected_beside

        chosen_run = selected_beside(problem, selection, sim, samples=samples, seed=seed, method=method,
                                     spec_arcmin=spec_arcmin,
                                     specs=specs, model=model, workers=workers)
        sweep_specs = {name: o.spec_limit for name, o in sim.outputs.items() if o.spec_limit is not None}
        width = selection.pins.width_um if selection.pins.boundaries_um is None and selection.pins.count > 1 else 2.0
        picked_classes = class_sweep(problem, counts=(1, 3, 5, 9), widths=(width,), rollers=selection.rollers,
                                     samples=min(samples, REPORT_SELECTION_SAMPLES), seed=seed,
                                     noises=(selection.noise_um,),
                                     specs=dict(list(sweep_specs.items())[:1]), workers=workers, model=model)
    life = None
    if service_life and not sim.partial:  # precision over the service life (issue 38): a modest run keeps it fast
        from rvbacklash.analysis.service_life.datasheet import service_life as _service_life

        life = _service_life(problem, life_cycle, life_hours, samples=min(samples, REPORT_SERVICE_LIFE_SAMPLES),
                             seed=seed, spec_lost_motion_arcmin=life_spec)
    return build_report_data(problem, stack, sim, spec_arcmin, comparison, nominal_contact(problem), sens, alloc,
                             elastic, sweep, transmission, cap, trade, eff, chosen_run, picked_classes, life)


def sweep(sweep, *, out: str | Path | None = None, scheduler=None, workers: int | None = None, force: bool = False,
          progress: Callable[[int, int], None] | None = None):
    """Run a design sweep (docs/sweeps.md): ``sweep`` is a SWEEP.toml path, a built-in example
    sweep, a ``SweepSpec`` or a plan from ``plan_sweep``; one Monte-Carlo run per point, point i
    on stream (i,) of the sweep's seed. ``out``: results directory written point by point
    (Parquet, CSV) and resumed by a re-run (None: rows in memory only). ``scheduler``: "inline",
    "local", an address such as "tcp://host:8786", an open ``Executor``, or None (local for more
    than 4 points to run). ``workers``: local worker processes, or inline threads per point.
    ``progress(done, total)``: points finished. Returns a ``SweepResult`` (``partial`` after
    Ctrl-C)."""
    from rvbacklash.analysis.sweep import SweepPlan, plan_sweep, run_sweep

    plan = sweep if isinstance(sweep, SweepPlan) else plan_sweep(sweep)
    return run_sweep(plan, out=out, scheduler=scheduler, workers=workers, force=force, progress=progress)


def hysteresis(design: DesignLike, *, measured: str | Path | None = None, unit: int | None = None,
               points: int = 41) -> HysteresisResult:
    """The test bench's hysteresis loop (input locked, 0 -> +T_R -> 0 -> -T_R -> 0) of the nominal
    unit, or of a unit of a measured-unit file (``measured``; ``unit``: 0-based, default the first), with its lost motion,
    backlash and torsional rigidity (docs/elastic.md). The design needs an [elastic] table.
    ``points``: loop nodes per branch (the definitions' torques are always nodes)."""
    from rvbacklash.analysis.hysteresis import hysteresis as _hysteresis

    return _hysteresis(prepare(design), measured=measured, unit=unit, points=points)


def capacity(design: DesignLike, *, duty_cycle: str | Path | None = None, angles: int | None = None,
             life_method: str | None = None) -> CapacityResult:
    """The capacity and life datasheet of the nominal unit (docs/capacity.md): every crank bearing's
    load over a revolution, rating and L10 at the stated rated torque and the rated output speed, the
    reducer's life, the derived rated torque, the momentary maximum torque and its limiting element,
    the allowable acceleration torque, the main bearings' moment rigidity and allowable moment, and a
    duty cycle's life (``duty_cycle``: a CSV or TOML file, design/duty_cycle.py). ``angles``: crank
    angles per revolution (default 24); ``life_method``: iso16281 or iso281 (default: the design's
    [capacity] life_method). The design needs [elastic] and [structure]."""
    from rvbacklash.analysis.capacity import DEFAULT_ANGLES, capacity_rating
    from rvbacklash.design.duty_cycle import read_duty_cycle

    cycle = read_duty_cycle(example_duty_cycle(duty_cycle)) if duty_cycle is not None else None
    return capacity_rating(prepare(design), angles=DEFAULT_ANGLES if angles is None else angles, duty_cycle=cycle,
                           life_method=life_method)


def efficiency(design: DesignLike, *, duty_cycle: str | Path | None = None, angles: int | None = None,
               temperature_c: float | None = None, output_speed_rpm: float | None = None, samples: int = 0,
               seed: int = 0, spec_min_efficiency: float | None = None, unit_map: bool = False,
               progress: Callable[[int], None] | None = None) -> EfficiencyResult:
    """The efficiency datasheet of the nominal unit (docs/efficiency.md): the efficiency and each
    element's loss at the rated point, the efficiency map against output torque, speed and
    temperature, the no-load running torque against input speed, the starting and back-driving
    torques; with ``duty_cycle`` (a CSV or TOML file, design/duty_cycle.py) the steady case
    temperature, its time constant, the allowable duty at the case limit, and lost motion and
    backlash at that temperature. ``angles``: crank angles per revolution (default 12);
    ``temperature_c``: the oil's (default [lubrication] temperature_c); ``output_speed_rpm``: the
    rated point's (default [capacity] rated_output_speed_rpm); ``samples``: that many units of the elastic
    model's production run with ``seed`` (the same units as ``simulate(..., model="elastic")``), each
    followed through the crank angles: their efficiency's distribution and the yield against
    ``spec_min_efficiency`` (a lower limit, 0-1); ``unit_map``: also every unit's efficiency at the map's
    output torques (``run.by_torque``, ``run.unit_map``). The design needs [elastic]."""
    from rvbacklash.analysis.losses import efficiency_rating
    from rvbacklash.analysis.losses.efficiency import DEFAULT_ANGLES, DEFAULT_TORQUE_FRACTIONS, progress_steps
    from rvbacklash.design.duty_cycle import read_duty_cycle

    from rvbacklash.analysis.losses.production import check_run

    check_run(samples, spec_min_efficiency)
    if unit_map and not samples:
        raise InputError("unit_map", unit_map, "allowed: with samples (a production run)")
    cycle = read_duty_cycle(example_duty_cycle(duty_cycle)) if duty_cycle is not None else None
    problem = prepare(design)
    if problem.design.elastic is None:
        raise InputError("elastic", None, "the losses need the design's [elastic] table (the loads of the elastic "
                                          "model; docs/efficiency.md)")
    import dataclasses

    from rvbacklash.analysis.losses.production import efficiency_run

    k = DEFAULT_ANGLES if angles is None else angles
    result = efficiency_rating(problem, angles=k, temperature_c=temperature_c, output_speed_rpm=output_speed_rpm,
                               duty_cycle=cycle, progress=progress)
    if not samples:
        return result
    steps = progress_steps(duty_cycle=cycle)
    run = efficiency_run(problem, units=samples, seed=seed, angles=k, temperature_c=result.temperature_c,
                         torque_fractions=DEFAULT_TORQUE_FRACTIONS if unit_map else (),
                         output_speed_rpm=result.rated_output_speed_rpm, spec_min_efficiency=spec_min_efficiency,
                         progress=None if progress is None else (lambda i: progress(steps + i)))
    return dataclasses.replace(result, production=run)
def service_life(design: DesignLike, *, duty_cycle: str | Path, hours: Iterable[float] = (0.0, 1000.0, 6000.0),
                 spec_lost_motion_arcmin: float = 1.5, samples: int = 2000, seed: int = 0, angles: int | None = None,
                 step_fraction: float | None = None, unit_wear: str = "own", sensitivity_samples: int = 0,
                 progress: Callable[[str, float], None] | None = None) -> "ServiceLifeResult":
    """Precision over the service life (docs/service-life.md): the nominal unit's lost motion, backlash
    and rigidity after ``hours`` of the duty cycle ``duty_cycle`` (a CSV or TOML file, or the name of an
    example cycle: ``robot-joint``), its contacts' wear rates and worn flank, and ``samples`` units of
    the production run (seeded by ``seed``; 0: none): their yield against ``spec_lost_motion_arcmin``
    versus hours and their accuracy life. ``angles``: crank angles per revolution of each step's loads
    (default 12); ``step_fraction``: the largest wear depth per time step as a share of the reference
    clearance (default 0.1); ``unit_wear``: "own" (each unit's wear from its discs' own load shares,
    re-solved every step) or "nominal" (every unit wears as the nominal unit); ``sensitivity_samples`` N > 0
    (a power of two): the first-order and total Sobol indices of the units' accuracy life at the last hour
    (as ``accuracy_life_sensitivity``, along the same trajectory). The design needs [elastic]; its [wear]
    table (optional) sets the wear coefficients and running-in (design/wear.py)."""
    from rvbacklash.analysis.service_life.datasheet import service_life as _service_life
    from rvbacklash.analysis.service_life.stepping import DEFAULT_ANGLES, DEFAULT_STEP_FRACTION
    from rvbacklash.design.duty_cycle import read_duty_cycle

    cycle = read_duty_cycle(example_duty_cycle(duty_cycle))
    return _service_life(prepare(design), cycle, hours, samples=samples, seed=seed,
                         spec_lost_motion_arcmin=spec_lost_motion_arcmin,
                         angles=DEFAULT_ANGLES if angles is None else angles,
                         step_fraction=DEFAULT_STEP_FRACTION if step_fraction is None else step_fraction,
                         unit_wear=unit_wear, sensitivity_samples=sensitivity_samples, progress=progress)


def calibrate_wear(design: DesignLike, *, duty_cycle: str | Path, measurements: Iterable[tuple[float, float]] = (),
                   sigma_arcmin: float | None = None, bench=None, hours: Iterable[float] | None = None,
                   torque_unit: str | None = None, angle_unit: str | None = None, time_unit: str | None = None,
                   columns: str | dict | None = None, format_profile: str | Path | None = None,
                   decimal: str | None = None) -> "WearCalibration":
    """The wear coefficients' common scale (k = s k_design) fitted, with a 95 % interval, to one unit's lost
    motion measured at 0 h and after some hours of ``duty_cycle``: ``measurements`` (hours, lost motion
    [arcmin]) pairs, or ``bench`` the unit's measured loops (files read as ``read_bench`` reads them,
    with the rig-format arguments) at ``hours`` (one per file, the first 0). ``sigma_arcmin``: one
    reading's repeatability (default: from the loops, the largest standard uncertainty u = U / 2 of
    their lost motions; 0.01 arcmin for ``measurements``). ``result.design`` is the calibrated design.
    docs/service-life.md, "Calibration"."""
    from rvbacklash.analysis.service_life.calibration import calibrate_wear as _calibrate
    from rvbacklash.design.duty_cycle import read_duty_cycle

    problem = prepare(design)
    sources: tuple[str, ...] = ()
    if bench is not None:
        from rvbacklash.analysis.service_life.calibration import bench_measurements

        files = [bench] if isinstance(bench, (str, Path)) else list(bench)
        read = read_bench(files, torque_unit=torque_unit, angle_unit=angle_unit, time_unit=time_unit,
                          columns=columns, format_profile=format_profile, decimal=decimal)
        measurements, sigma_read, sources = bench_measurements(read, None if hours is None else list(hours))
        sigma_arcmin = sigma_read if sigma_arcmin is None else sigma_arcmin
    result = _calibrate(problem, read_duty_cycle(example_duty_cycle(duty_cycle)), list(measurements),
                        sigma_arcmin=0.01 if sigma_arcmin is None else sigma_arcmin)
    return dataclasses.replace(result, sources=sources) if sources else result


def accuracy_life_sensitivity(design: DesignLike, *, duty_cycle: str | Path, hours: float = 6000.0,
                              spec_lost_motion_arcmin: float = 1.5, samples: int = 256, seed: int = 0,
                              resamples: int = 1000, progress: Callable[[int], None] | None = None) -> SensitivityResult:
    """Which tolerance buys hours: first-order and total Sobol indices of the accuracy life (hours of
    ``duty_cycle`` until the lost motion exceeds ``spec_lost_motion_arcmin``, censored at ``hours``) of
    the elastic model's units, each with its own wear, for every random factor group, with 95 % bootstrap
    intervals (docs/service-life.md). ``samples`` N a power of two (N (D + 2) units are worn)."""
    from rvbacklash.analysis.sensitivity_global import global_sensitivity
    from rvbacklash.analysis.service_life.sensitivity import accuracy_life_streams
    from rvbacklash.analysis.service_life.stepping import check_hours, nominal_trajectory
    from rvbacklash.design.duty_cycle import read_duty_cycle
    from rvbacklash.models.elastic import elastic_model

    problem = prepare(design)
    last = check_hours([hours])[-1]
    if last <= 0.0:
        raise InputError("hours", hours, "allowed: a number of hours > 0")
    if not (math.isfinite(spec_lost_motion_arcmin) and spec_lost_motion_arcmin > 0.0):
        raise InputError("spec_lost_motion_arcmin", spec_lost_motion_arcmin, "allowed: a number > 0 [arcmin]")
    model = elastic_model(problem)
    tr = nominal_trajectory(problem, read_duty_cycle(example_duty_cycle(duty_cycle)), [0.0, last], model=model)
    return global_sensitivity(problem, model=accuracy_life_streams(problem, tr, spec_lost_motion_arcmin, model),
                              output="accuracy_life", samples=samples, seed=seed, resamples=resamples,
                              progress=progress)


def example_duty_cycle(path: str | Path) -> Path:
    """A duty-cycle file: ``path`` when it exists, else the packaged example of that name
    (``robot-joint``: examples/duty_cycles/robot-joint.csv)."""
    p = Path(path)
    if p.is_file():
        return p
    from importlib import resources

    name = p.name if p.suffix else p.name + ".csv"
    packaged = Path(str(resources.files("rvbacklash.examples") / "duty_cycles" / name))
    return packaged if packaged.is_file() else p


def capacity_trade(design: DesignLike, *, what_ifs: Iterable | None = None, angles: int | None = None,
                   life_method: str | None = None, progress: Callable[[int], None] | None = None) -> CapacityTrade:
    """Lost motion against life (docs/capacity.md, "The trade"): the nominal unit's lost motion, reducer
    L10 at the stated rated torque and derived rated torque, for the design as given (``points[0]``)
    and for each what-if of it. ``what_ifs``: ``WhatIf`` items (design edits by dotted path;
    ``clearance_what_if(c)``, ``modification_what_if(m)`` build the usual ones) — None: the crank
    bearings' clearance at -4 (a preload), 0, 10, 20 um and the equidistance modification at 0, 2,
    10 um; (): the design alone. ``angles``: crank angles per revolution (default 24); ``progress(done)``:
    points finished. The design needs [elastic] and [structure]."""
    from rvbacklash.analysis.capacity import DEFAULT_ANGLES, capacity_trade as _trade

    return _trade(prepare(design), what_ifs, angles=DEFAULT_ANGLES if angles is None else angles,
                  life_method=life_method, progress=progress)


def elastic_section(design: DesignLike, *, simulation: SimulationResult | None = None,
                    specs: Mapping[str, float] | None = None, probabilities: Iterable[float] = (0.05, 0.95),
                    samples: int = 2000, seed: int = 0) -> ElasticSection:
    """The report's elastic section: the nominal loop and the loops of the units nearest the given
    quantiles of lost motion among ``samples`` drawn units, beside an elastic-model simulation
    (``simulate(..., model="elastic")``) if given; render with
    ``rvbacklash.report.elastic_plots.elastic_figures`` and the ``_elastic_section.html.j2`` partial."""
    from rvbacklash.analysis.hysteresis import elastic_section as _elastic_section

    return _elastic_section(prepare(design), simulation=simulation, specs=specs, probabilities=tuple(probabilities),
                            samples=samples, seed=seed)


SENSITIVITY_SAMPLES = 1 << 14  # = analysis.sensitivity_global.DEFAULT_SAMPLES
REPORT_SENSITIVITY_SAMPLES = 1 << 11  # Sobol indices of the Monte-Carlo models in a report: N (D + 2) ~ 45 000 units


def sensitivity(design: DesignLike, *, model: str = "linear", output: str | None = None,
                samples: int = SENSITIVITY_SAMPLES, seed: int = 0, resamples: int = 1000,
                progress: Callable[[int], None] | None = None) -> SensitivityResult:
    """First-order and total Sobol indices of a model's output for every random factor group, with
    95 % bootstrap intervals (docs/allocation.md). ``samples`` N: units per sample set, a power of
    two (the model runs N (D + 2) times); each factor draws from its own stream of ``seed``."""
    from rvbacklash.analysis.sensitivity_global import global_sensitivity

    return global_sensitivity(prepare(design), model=model, output=output, samples=samples, seed=seed,
                              resamples=resamples, progress=progress)


def allocate(design: DesignLike, *, spec_arcmin: float | None = None, yield_target: float, model: str | None = None,
             spec_rigidity_nm_per_arcmin: float | None = None, spec_preload_um: float | None = None,
             spec_te_arcsec: float | None = None, spec_life_h: float | None = None,
             spec_rated_torque_nm: float | None = None, samples: int = ALLOCATION_SAMPLES, seed: int = 0,
             scheduler: str = "inline", workers: int | None = None, pareto: bool = True,
             progress: Callable[[int], None] | None = None, spec_accuracy_life_h: float | None = None,
             duty_cycle: str | Path | None = None, spec_lost_motion_arcmin: float | None = None,
             angles: int | None = None, step_fraction: float | None = None,
             unit_wear: str = "own") -> AllocationResult:
    """The cheapest precision grade per part group such that P(backlash <= spec_arcmin [and
    rigidity >= spec_rigidity_nm_per_arcmin] [and preload <= spec_preload_um] [and TE peak-to-peak
    <= spec_te_arcsec: the transmission model, or the contact model's units turned through a revolution] [and
    the reducer's L10 >= spec_life_h, the derived rated torque >= spec_rated_torque_nm: the elastic model's life
    outputs, docs/capacity.md]) >= yield_target
    (backlash: the model's primary output, lost motion for the elastic model), with the uniform-grade baseline
    and the cost-yield Pareto front (docs/allocation.md). Costs: the design's [costs] table over
    the defaults. The linear model is solved exactly; the Monte-Carlo models (``samples`` per
    candidate, seeded) search locally, their candidates run on ``scheduler`` ("inline", "local" or
    a Dask address; ``workers``: threads inline, worker processes on a local cluster).

    ``spec_accuracy_life_h`` (with ``duty_cycle``, as ``service_life``'s): the cheapest grades that keep
    ``yield_target`` of the units' lost motion within ``spec_lost_motion_arcmin`` (or ``spec_arcmin``;
    default 1.5, as ``service_life``) for that many hours of the cycle, each unit with its own wear
    (``unit_wear``, ``angles``, ``step_fraction``: as ``service_life``); the elastic model (``model``
    None or "elastic"), no other spec, ``samples`` units per candidate from 100 (docs/service-life.md,
    "Allocating on the accuracy life")."""
    import contextlib

    from rvbacklash.analysis.allocation import allocate as _allocate

    problem = prepare(design)
    accuracy_life = None
    if spec_accuracy_life_h is not None:
        from rvbacklash.analysis.service_life.accuracy_yield import AccuracyLifeTarget
        from rvbacklash.analysis.service_life.stepping import DEFAULT_ANGLES, DEFAULT_STEP_FRACTION
        from rvbacklash.design.duty_cycle import read_duty_cycle

        if duty_cycle is None:
            raise InputError("duty_cycle", None, "the accuracy life is hours of a duty cycle; allowed: a duty-cycle "
                                                 "file (CSV or TOML) or a packaged cycle's name (robot-joint)")
        if spec_lost_motion_arcmin is not None and spec_arcmin is not None and spec_lost_motion_arcmin != spec_arcmin:
            raise InputError("spec_lost_motion_arcmin", spec_lost_motion_arcmin,
                             f"differs from spec_arcmin = {spec_arcmin}; allowed: one lost-motion spec")
        spec_arcmin = next((v for v in (spec_lost_motion_arcmin, spec_arcmin) if v is not None), 1.5)
        model = "elastic" if model is None else model
        accuracy_life = AccuracyLifeTarget(read_duty_cycle(example_duty_cycle(duty_cycle)), spec_accuracy_life_h,
                                           spec_arcmin, DEFAULT_ANGLES if angles is None else angles,
                                           DEFAULT_STEP_FRACTION if step_fraction is None else step_fraction,
                                           unit_wear).check()
    else:
        for name, value in (("duty_cycle", duty_cycle), ("spec_lost_motion_arcmin", spec_lost_motion_arcmin),
                            ("angles", angles), ("step_fraction", step_fraction)):
            if value is not None:
                raise InputError(name, value, "allowed with spec_accuracy_life_h only (the elastic model's lost-motion "
                                               "spec at 0 h is spec_arcmin)")
        if unit_wear != "own":
            raise InputError("unit_wear", unit_wear, "allowed with spec_accuracy_life_h only")
    model = "linear" if model is None else model
    if model == "linear" or scheduler in (None, "inline"):
        return _allocate(problem, spec_arcmin=spec_arcmin, yield_target=yield_target, model=model,
                         spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin, spec_preload_um=spec_preload_um,
                         spec_te_arcsec=spec_te_arcsec, spec_life_h=spec_life_h,
                         spec_rated_torque_nm=spec_rated_torque_nm, samples=samples, seed=seed,
                         executor=None, workers=workers, pareto=pareto, progress=progress,
                         accuracy_life=accuracy_life)
    try:
        from rvbacklash.analysis.executor import executor
    except ImportError:
        raise InputError("scheduler", scheduler, "the Dask executor is not available in this installation; "
                                                 "allowed: inline") from None
    with contextlib.ExitStack() as stack:
        ex = stack.enter_context(executor(scheduler, workers))
        return _allocate(problem, spec_arcmin=spec_arcmin, yield_target=yield_target, model=model,
                         spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin, spec_preload_um=spec_preload_um,
                         spec_te_arcsec=spec_te_arcsec, spec_life_h=spec_life_h,
                         spec_rated_torque_nm=spec_rated_torque_nm, samples=samples, seed=seed,
                         executor=ex, workers=None, pareto=pareto, progress=progress,
                         accuracy_life=accuracy_life)


def read_bench(files, *, design: DesignLike | None = None, rated_torque_nm: float | None = None,
               torque_unit: str | None = None, angle_unit: str | None = None, te_unit: str | None = None,
               time_unit: str | None = None, ratio: float | None = None, samples: int = 2000,
               seed: int = 0, columns: str | dict | None = None, format_profile: str | Path | None = None,
               decimal: str | None = None) -> BenchResult:
    """Measured hysteresis loops and TE curves (docs/bench-data.md): each file (CSV/TSV/.xlsx, units
    in the header or given here) one unit, read by the definitions the model's loops are read by,
    with an expanded uncertainty (k = 2) from the data's noise; a TE file of forward and backward
    runs one unit with its lost motion against output position. With ``design``: each figure as a
    percentile of ``samples`` predicted units of its production run (elastic model for loops,
    transmission model for TE: at most 200 units), a flag beyond 0.135-99.865 % with the factor
    groups that dominate that figure (Sobol), and the batch's unit-to-unit spread against the
    predicted one. ``rated_torque_nm``: default the design's, else the loop's peaks. Rig files
    as they come: ``columns`` a column map ("te=Transmission_Error_Fw,..." or {role: header}),
    ``format_profile`` a TOML of the rig's format, ``decimal`` "." or "," (docs/bench-data.md,
    "Rig files")."""
    from rvbacklash.analysis.bench import read_bench as _read_bench
    from rvbacklash.design.bench_files import file_format

    units = {"torque_unit": torque_unit, "angle_unit": angle_unit, "te_unit": te_unit, "time_unit": time_unit}
    fmt = file_format(columns, format_profile, decimal, units)
    problem = prepare(design) if design is not None else None
    return _read_bench([files] if isinstance(files, (str, Path)) else list(files), problem,
                       rated_torque_nm=rated_torque_nm, units=fmt, ratio=ratio, samples=samples, seed=seed)


def calibrate(design: DesignLike, *, bench, torque_unit: str | None = None, angle_unit: str | None = None,
              time_unit: str | None = None, bootstrap: int = 50, seed: int = 0, samples: int = 0,
              max_evaluations: int = 200, columns: str | dict | None = None,
              format_profile: str | Path | None = None, decimal: str | None = None) -> CalibrationResult:
    """Fit the structure's series stiffness, the friction torque and the crank bearings' clearance
    offset of the design's nominal unit to measured loops (``bench``: one file or several, one unit
    each) by least squares; 95 % confidence intervals from the Jacobian (bootstrap over units from
    three units on, ``bootstrap`` resamples); ``result.design`` is the calibrated Design
    (``rvbacklash.report.design_toml.design_toml`` writes it). ``samples`` > 0: the units' spread
    against that many predicted units. ``columns``, ``format_profile``, ``decimal``: rig files as
    they come, as ``read_bench``. docs/bench-data.md."""
    from rvbacklash.analysis.calibration import calibrate as _calibrate
    from rvbacklash.design.bench_files import file_format
    from rvbacklash.sampling.seeds import check_seed

    files = [bench] if isinstance(bench, (str, Path)) else list(bench)
    units = {"torque_unit": torque_unit, "angle_unit": angle_unit, "time_unit": time_unit}
    fmt = file_format(columns, format_profile, decimal, units)  # the unit flags with the rig's format
    return _calibrate(prepare(design), files, units_flags=fmt, bootstrap=bootstrap, seed=check_seed(seed),
                      samples=samples, max_evaluations=max_evaluations)
