"""rvbacklash: design-stage backlash (lost motion) of RV reducers.

Layers, bottom to top (docs/architecture.md; a contract test enforces them):
units, errors, results -> geometry -> factors -> design | standards -> problem -> models ->
sampling -> analysis -> api -> report, cli.

Typical use from Python (see examples/quickstart.py)::

    import rvbacklash as rb
    design = rb.load_design("rv80e")          # or a path to a TOML file
    rb.analyze(design).to_frame()             # factor table (pandas)
    rb.simulate(design, samples=10**6, seed=1, spec_arcmin=3).to_frame()

Names are imported on first use, so that ``import rvbacklash`` stays fast: this module imports
nothing. The command line relies on it: ``rvbacklash`` and ``python -m rvbacklash`` install their
Ctrl-C handling right after importing it (``rvbacklash.cli.main``), and a press during an import
before that would end in a KeyboardInterrupt traceback (``__version__`` used to import
``importlib.metadata`` here: ~50 ms, up to half a second on a loaded machine).
"""

_EXPORTS = {
    "__version__": "rvbacklash._version",
    # api: every entry point takes a Design, a TOML path, an example name or a Problem
    "prepare": "rvbacklash.api",
    "analyze": "rvbacklash.api",
    "simulate": "rvbacklash.api",
    "exact": "rvbacklash.api",
    "compare": "rvbacklash.api",
    "paper_scenarios": "rvbacklash.api",
    "contact": "rvbacklash.api",
    "measured_units": "rvbacklash.api",
    "make_report": "rvbacklash.api",
    "sensitivity": "rvbacklash.api",
    "allocate": "rvbacklash.api",
    "hysteresis": "rvbacklash.api",
    "transmission_error": "rvbacklash.api",
    "elastic_section": "rvbacklash.api",
    "sweep": "rvbacklash.api",
    "read_bench": "rvbacklash.api",
    "calibrate": "rvbacklash.api",
    "capacity": "rvbacklash.api",
    "efficiency": "rvbacklash.api",
    "simulate_selected": "rvbacklash.api",
    "assemble": "rvbacklash.api",
    "generate_batch": "rvbacklash.api",
    "service_life": "rvbacklash.api",
    "calibrate_wear": "rvbacklash.api",
    "capacity_trade": "rvbacklash.api",
    "WhatIf": "rvbacklash.analysis.capacity",
    "clearance_what_if": "rvbacklash.analysis.capacity",
    "modification_what_if": "rvbacklash.analysis.capacity",
    "read_duty_cycle": "rvbacklash.design.duty_cycle",
    "plan_sweep": "rvbacklash.analysis.sweep",
    "load_sweep": "rvbacklash.analysis.sweep",
    "SweepResult": "rvbacklash.analysis.sweep",
    "render_sweep_html": "rvbacklash.report.sweep",
    "render_html": "rvbacklash.report.html",
    # inputs
    "load_design": "rvbacklash.design.loading",
    "available_examples": "rvbacklash.design.loading",
    "example_text": "rvbacklash.design.loading",
    "Design": "rvbacklash.design.schema",
    "Problem": "rvbacklash.problem",
    "Scenario": "rvbacklash.analysis.scenarios",
    "InputError": "rvbacklash.errors",
    # results
    "StackupResult": "rvbacklash.analysis.stackup",
    "SimulationResult": "rvbacklash.analysis.simulation",
    "OutputStatistics": "rvbacklash.analysis.statistics",
    "Comparison": "rvbacklash.analysis.scenarios",
    "NominalContact": "rvbacklash.analysis.contact",
    "ReportData": "rvbacklash.analysis.report_data",
    "SensitivityResult": "rvbacklash.analysis.sensitivity_global",
    "AllocationResult": "rvbacklash.analysis.allocation",
    "HysteresisResult": "rvbacklash.analysis.hysteresis",
    "TransmissionErrorResult": "rvbacklash.analysis.transmission",
    "BenchResult": "rvbacklash.analysis.bench",
    "CalibrationResult": "rvbacklash.analysis.calibration",
    # the linear model as a function (n, 21) -> (n,)
    "LinearModel": "rvbacklash.models.linear",
    "linear_model": "rvbacklash.models.linear",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        import importlib

        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'rvbacklash' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
