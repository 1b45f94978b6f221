"""rvbacklash: design-stage backlash (lost motion) of RV reducers.

Data path: ``design`` (validated input, derived geometry) -> ``factors`` (catalog,
transfers) -> ``model`` (Eq. (1)/(2) of Sun et al. 2014) -> ``analysis`` (stack-up,
sensitivity) -> ``cli``.

Typical use from Python (see examples/quickstart.py)::

    from rvbacklash import load_design, analyze, simulate
    design = load_design("sun2014")          # or a path to a TOML file
    analyze(design).to_frame()               # factor table (pandas)
    simulate(design, 10**6, seed=1, spec_arcmin=3).stats["yield"]
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("rvbacklash")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0"

from rvbacklash.analysis.stackup import StackupResult, analyze
from rvbacklash.design.loading import available_examples, load_design
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.model.linear import LinearModel, build_linear_model

# Imported on first use: they load the compiled sampling kernels (numba), which takes a moment.
_LAZY = {
    "simulate": "rvbacklash.analysis.simulation",
    "SimulationResult": "rvbacklash.analysis.simulation",
    "compare": "rvbacklash.analysis.scenarios",
    "paper_scenarios": "rvbacklash.analysis.scenarios",
    "Comparison": "rvbacklash.analysis.scenarios",
    "make_report": "rvbacklash.report.html",
    "render_html": "rvbacklash.report.html",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'rvbacklash' has no attribute {name!r}")


__all__ = [
    "Comparison",
    "SimulationResult",
    "compare",
    "make_report",
    "paper_scenarios",
    "render_html",
    "simulate",
    "Design",
    "InputError",
    "LinearModel",
    "StackupResult",
    "analyze",
    "available_examples",
    "build_linear_model",
    "load_design",
    "__version__",
]
