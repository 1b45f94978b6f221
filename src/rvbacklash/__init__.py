"""rvbacklash: design-stage backlash (lost motion) of RV reducers.

Data path: ``design`` (validated input, derived geometry) -> ``factors`` (catalog,
transfers) -> ``model`` (Eq. (1)/(2) of Sun et al. 2014) -> ``analysis`` (stack-up,
sensitivity) -> ``cli``.

Typical use from Python::

    from rvbacklash import load_design, analyze
    result = analyze(load_design("sun2014"))
    result.total.plus3sigma_arcmin
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

__all__ = [
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
