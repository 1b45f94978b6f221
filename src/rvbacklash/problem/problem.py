"""``prepare(design) -> Problem``: geometry, resolved zones with their origins, moments, the
correlation matrix and the linear model's coefficients, computed once. Every model and
analysis takes a Problem; nothing downstream resolves a zone or a distribution again."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS, Stage
from rvbacklash.factors.distributions import ResolvedZone, marginal, moments_um
from rvbacklash.factors.output import stage_coefficient_arcmin_per_um
from rvbacklash.geometry import reducer
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.geometry.reducer import DerivedGeometry
from rvbacklash.problem.contact_errors import ContactErrorModel, contact_error_model
from rvbacklash.problem.zones import resolve_zones


def derive_geometry(design: Design) -> DerivedGeometry:
    """The derived geometry of a design (ratio, K1, pitch radii, crank circle)."""
    s1, s2, s3 = design.first_stage, design.second_stage, design.crank_stage
    a = reducer.centre_distance_mm(s1.module_mm, s1.centre_gear_teeth, s1.planet_teeth)
    return DerivedGeometry(
        ratio=reducer.reduction_ratio(s1.centre_gear_teeth, s1.planet_teeth, s2.pins),
        K1=reducer.short_amplitude_coefficient(s2.eccentricity_mm, s2.pins, s2.pin_circle_radius_mm),
        centre_gear_pitch_radius_mm=reducer.pitch_radius_mm(s1.module_mm, s1.centre_gear_teeth),
        planet_pitch_radius_mm=reducer.pitch_radius_mm(s1.module_mm, s1.planet_teeth),
        centre_distance_mm=a,
        cycloid_pitch_radius_mm=reducer.cycloid_pitch_radius_mm(s2.eccentricity_mm, s2.cycloid_teeth),
        crank_circle_radius_mm=s3.crank_circle_radius_mm if s3.crank_circle_radius_mm is not None else a,
        crank_circle_radius_is_default=s3.crank_circle_radius_mm is None,
        pressure_angle_deg=s1.pressure_angle_deg,
        crank_eccentricity_coefficient=s3.eccentricity_transfer_coefficient,
    )


def contact_geometry(design: Design) -> ContactGeometry:
    s = design.second_stage
    return ContactGeometry(s.cycloid_teeth, s.pins, s.eccentricity_mm, s.pin_circle_radius_mm, s.pin_radius_mm,
                           s.discs)


def correlation_matrix(design: Design) -> np.ndarray:
    """Full (21, 21) correlation matrix in catalog order (identity where nothing is given)."""
    r = np.eye(len(FACTOR_KEYS))
    c = design.correlation
    if c is not None:
        idx = [FACTOR_KEYS.index(k) for k in c.factors]
        r[np.ix_(idx, idx)] = np.array(c.matrix, dtype=float)
    return r


@dataclass(frozen=True, eq=False, repr=False)
class Problem:
    """A design prepared for analysis (build it with ``prepare``). Arrays are in catalog order
    (the Table 2 numbering, ``rvbacklash.factors.CATALOG``)."""

    design: Design
    source: str  # where the design came from: a path, "example:<name>" or "<object>"
    source_sha256: str | None  # of the design file's text, when there is one
    geometry: DerivedGeometry
    cycloid: ContactGeometry
    zones: tuple[ResolvedZone, ...]
    means_um: np.ndarray  # raw quantity of each factor: mean [um]
    sigmas_um: np.ndarray  # and standard deviation [um]
    correlation: np.ndarray  # (21, 21)
    gains_um_per_um: np.ndarray  # transfer of each factor to circumferential backlash
    stage_coefficients_arcmin_per_um: np.ndarray  # Eq. (1) coefficient of each factor's stage
    contact_errors: ContactErrorModel  # tolerances of the indexed parts for the contact model
    stages: np.ndarray = field(default_factory=lambda: np.array([int(f.stage) for f in CATALOG]))

    @property
    def name(self) -> str:
        return self.design.name

    @property
    def sensitivities_arcmin_per_um(self) -> np.ndarray:
        """S_i = d(dphi)/dx_i, Eq. (6) [arcmin per um of raw quantity]."""
        return self.gains_um_per_um * self.stage_coefficients_arcmin_per_um

    @property
    def correlated(self) -> bool:
        return not np.array_equal(self.correlation, np.eye(self.correlation.shape[0]))

    @cached_property
    def marginals(self) -> tuple:
        """scipy.stats frozen law of each factor's raw quantity (None where fixed); built on first use."""
        return tuple(marginal(z) for z in self.zones)

    @property
    def random_mask(self) -> np.ndarray:
        return self.sigmas_um > 0

    def stage_mask(self, stage: Stage) -> np.ndarray:
        return self.stages == int(stage)

    def __repr__(self) -> str:
        g = self.geometry
        return (f"<Problem {self.name!r} from {self.source}: i = {g.ratio:g}, K1 = {g.K1:.4f}, "
                f"{int(self.random_mask.sum())} random factors{', correlated' if self.correlated else ''}>")


def _check_correlation(design: Design, zones: tuple[ResolvedZone, ...], sigmas: np.ndarray) -> None:
    if design.correlation is None:
        return
    for key in design.correlation.factors:
        i = FACTOR_KEYS.index(key)
        if sigmas[i] == 0:
            raise InputError("correlation.factors", key, f"this factor is fixed ({zones[i].origin}); allowed: factors "
                                                         "with a random reading")


def prepare(design: Design, source: str = "<object>", text: str | None = None) -> Problem:
    """Resolve every zone (grades through the standards), moments, correlation and the linear
    coefficients of ``design``; ``source``/``text`` record where it came from (reports)."""
    zones = resolve_zones(design)
    moments = np.array([moments_um(z) for z in zones])
    g = derive_geometry(design)
    _check_correlation(design, zones, moments[:, 1])
    return Problem(
        design=design, source=source,
        source_sha256=hashlib.sha256(text.encode("utf-8")).hexdigest() if text is not None else None,
        geometry=g, cycloid=contact_geometry(design), zones=zones,
        means_um=moments[:, 0].copy(), sigmas_um=moments[:, 1].copy(), correlation=correlation_matrix(design),
        gains_um_per_um=np.array([f.gain(g) for f in CATALOG]),
        stage_coefficients_arcmin_per_um=np.array([stage_coefficient_arcmin_per_um(f.stage, g) for f in CATALOG]),
        contact_errors=contact_error_model(design, zones),
    )
