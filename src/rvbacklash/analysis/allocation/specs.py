"""The targets of an allocation: the check of the spec and yield arguments, the specs beside the
primary output's by output name, and their text in labels.
"""

from __future__ import annotations

import math
from typing import Mapping

from rvbacklash.errors import InputError


def check_targets(spec_arcmin, yield_target, spec_rigidity_nm_per_arcmin=None, spec_preload_um=None,
                  spec_te_arcsec=None, spec_life_h=None, spec_rated_torque_nm=None) -> None:
    if spec_arcmin is None or isinstance(spec_arcmin, bool) or not isinstance(spec_arcmin, (int, float)) or \
            not (math.isfinite(spec_arcmin) and spec_arcmin > 0):
        raise InputError("spec_arcmin", spec_arcmin, "allowed: a finite number > 0 [arcmin]")
    if yield_target is None or isinstance(yield_target, bool) or not isinstance(yield_target, (int, float)) or \
            not 0.5 < yield_target < 1:
        raise InputError("yield_target", yield_target, "allowed: a probability 0.5 < P < 1, e.g. 0.99")
    if spec_rigidity_nm_per_arcmin is not None and (
            isinstance(spec_rigidity_nm_per_arcmin, bool) or not isinstance(spec_rigidity_nm_per_arcmin, (int, float))
            or not (math.isfinite(spec_rigidity_nm_per_arcmin) and spec_rigidity_nm_per_arcmin > 0)):
        raise InputError("spec_rigidity_nm_per_arcmin", spec_rigidity_nm_per_arcmin,
                         "allowed: a finite number > 0 [N m/arcmin]")
    if spec_preload_um is not None and (
            isinstance(spec_preload_um, bool) or not isinstance(spec_preload_um, (int, float))
            or not (math.isfinite(spec_preload_um) and spec_preload_um >= 0)):
        raise InputError("spec_preload_um", spec_preload_um, "allowed: a finite number >= 0 [um]")
    if spec_te_arcsec is not None and (
            isinstance(spec_te_arcsec, bool) or not isinstance(spec_te_arcsec, (int, float))
            or not (math.isfinite(spec_te_arcsec) and spec_te_arcsec > 0)):
        raise InputError("spec_te_arcsec", spec_te_arcsec, "allowed: a finite number > 0 [arcsec]")
    for name, value, unit in (("spec_life_h", spec_life_h, "h"), ("spec_rated_torque_nm", spec_rated_torque_nm, "N m")):
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))
                                  or not (math.isfinite(value) and value > 0)):
            raise InputError(name, value, f"allowed: a finite number > 0 [{unit}]")


SPEC_PARAMETERS = {"rigidity": "spec_rigidity_nm_per_arcmin", "preload": "spec_preload_um",
                   "transmission_error": "spec_te_arcsec", "life": "spec_life_h",
                   "rated_torque": "spec_rated_torque_nm"}  # output -> the API parameter of its spec
LIFE_SPECS = ("life", "rated_torque")  # the elastic model's life outputs (docs/capacity.md): lower limits


def extra_specs(spec_rigidity_nm_per_arcmin: float | None, spec_preload_um: float | None,
                spec_te_arcsec: float | None = None, spec_life_h: float | None = None,
                spec_rated_torque_nm: float | None = None) -> dict[str, float]:
    """The specs beside the primary output's, by output name."""
    return {k: float(v) for k, v in (("rigidity", spec_rigidity_nm_per_arcmin), ("preload", spec_preload_um),
                                     ("transmission_error", spec_te_arcsec), ("life", spec_life_h),
                                     ("rated_torque", spec_rated_torque_nm)) if v is not None}


def specs_text(specs: Mapping[str, float]) -> str:
    words = {"rigidity": "rigidity >= {:g} N m/arcmin", "preload": "preload <= {:g} um",
             "transmission_error": "TE peak-to-peak <= {:g} arcsec", "life": "L10 >= {:g} h",
             "rated_torque": "rated torque >= {:g} N m"}
    return "".join(f", {words[k].format(v)}" for k, v in specs.items())
