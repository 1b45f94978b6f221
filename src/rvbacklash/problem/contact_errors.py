"""What the contact model needs to know of each indexed part of the cycloid stage: the
tolerances a sampled part must conform to (docs/contact.md, "Part errors").

An indexed part is a circle of N equally spaced elements: the teeth of a disc, the pin holes of
the housing. Its tolerances, in the definitions of ISO 1328-1 (applied to the cycloid stage as
an equivalent gear, standards/cycloid.py):
- F_p, total cumulative pitch deviation: the range (max - min) of the cumulative pitch
  deviations of all elements, measured along the pitch circle;
- f_pt, single pitch deviation: the largest difference between neighbouring elements;
- F_r, radial run-out (pin holes): the range of the radial positions (ISO 1328-2).
"""

from __future__ import annotations

from dataclasses import dataclass

from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS, factor_by_key
from rvbacklash.factors.distributions import ResolvedZone
from rvbacklash.standards import cycloid
from rvbacklash.standards.iso1328 import iso1328_tolerances

SINGLE_TO_CUMULATIVE = 0.3  # f_pt / F_p when no grade says otherwise: ISO 1328-1:1995 grade 5 at d ~ 150 mm
#                             gives 6.5 / 23 = 0.28 (ASSUMPTION, stated wherever it is used)
RUNOUT_TO_CUMULATIVE = 0.8  # F_r = 0.8 F_p, the ratio of ISO 1328-2:1997's run-out formula (annex)


@dataclass(frozen=True)
class IndexedPart:
    """Tolerances of a circle of equally spaced elements [um] and where they came from."""

    name: str
    elements: int
    cumulative_pitch_um: float  # F_p
    single_pitch_um: float  # f_pt
    runout_um: float | None  # F_r of the radial positions (None: not a tolerance of this part)
    origin: str


@dataclass(frozen=True)
class ContactErrorModel:
    """How the contact model draws the per-element errors (design ``[contact]``)."""

    error_model: str  # long_wave | independent
    disc: IndexedPart
    pin_holes: IndexedPart


def _single_pitch(design: Design, key: str, d_mm: float, explicit: float | None, fp: float) -> tuple[float, str]:
    if explicit is not None:
        return explicit, "explicit"
    graded = design.grades.grade_for(factor_by_key(key)) if design.grades is not None else None
    if graded is not None:
        grade, field = graded
        s2 = design.second_stage
        m = cycloid.equivalent_module_mm(s2.pin_circle_radius_mm, s2.pins)
        try:
            t = iso1328_tolerances(design.grades.edition, m, d_mm, 10.0, grade)
        except InputError as e:
            raise InputError(field, grade, f"{e.allowed} (equivalent gear d = {d_mm:.4g} mm, m = {m:.4g} mm)") from None
        return t.fpt_um, f"f_pt, {t.standard.split(';')[0]} grade {grade} at d = {d_mm:.4g} mm ({cycloid.ASSUMPTION})"
    return SINGLE_TO_CUMULATIVE * fp, f"assumption: f_pt = {SINGLE_TO_CUMULATIVE} F_p (no grade given)"


def contact_error_model(design: Design, zones: tuple[ResolvedZone, ...]) -> ContactErrorModel:
    """The tolerances of the disc teeth and of the pin holes. F_p is read the same way for both:
    the zone's largest magnitude (disc zone +-F_p, pin zone [0, F_p]: F_p either way)."""
    s2, c = design.second_stage, design.contact
    disc_zone = zones[FACTOR_KEYS.index("disc_cumulative_pitch")]
    pin_zone = zones[FACTOR_KEYS.index("pin_cumulative_pitch")]
    fp_disc = max(abs(disc_zone.lower_um), abs(disc_zone.upper_um))
    fp_pin = max(abs(pin_zone.lower_um), abs(pin_zone.upper_um))
    d_disc = cycloid.disc_pitch_diameter_mm(s2.pin_circle_radius_mm, s2.pins, s2.cycloid_teeth)
    fpt_disc, o_disc = _single_pitch(design, "disc_cumulative_pitch", d_disc, c.disc_single_pitch_um, fp_disc)
    fpt_pin, o_pin = _single_pitch(design, "pin_cumulative_pitch", 2 * s2.pin_circle_radius_mm,
                                   c.pin_hole_single_pitch_um, fp_pin)
    disc = IndexedPart("disc teeth", s2.cycloid_teeth, fp_disc, fpt_disc, None,
                       f"F_p: disc_cumulative_pitch ({disc_zone.origin}); {o_disc}")
    holes = IndexedPart("pin holes", s2.pins, fp_pin, fpt_pin, RUNOUT_TO_CUMULATIVE * fp_pin,
                        f"F_p: pin_cumulative_pitch ({pin_zone.origin}); {o_pin}; F_r = {RUNOUT_TO_CUMULATIVE} F_p "
                        f"(ISO 1328-2:1997 ratio, assumption)")
    return ContactErrorModel(c.error_model, disc, holes)
