"""From a precision grade to the tolerance zone of each of the 21 factors.

Precedence (``design.derived.resolve_zones``): an explicit zone, else a grade given for the
factor, else the grade of its stage. Each zone carries its origin: standard, edition and the
quantity used, or the assumption it rests on (docs/standards.md).

Stage 1 gear tolerances combine the centre gear and the planet as the root-sum-square of the
two gears' values (two independent gears in one mesh).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rvbacklash.geometry import reducer as geometry
from rvbacklash.errors import InputError
from rvbacklash.standards import cycloid, iso286
from rvbacklash.standards.iso1328 import GearTolerances, iso1328_tolerances


@dataclass(frozen=True)
class GradedZone:
    lower_um: float
    upper_um: float
    origin: str


def _edition_name(edition: str) -> str:
    return {"1995": "ISO 1328-1:1995", "2013": "ISO 1328-1:2013"}[edition]


def _gear(design, edition: str, d: float, m: float, grade: int, field: str) -> GearTolerances:
    b = design.first_stage.face_width_mm
    if b is None:
        raise InputError("first_stage.face_width_mm", allowed="missing; needed to take stage-1 tolerances "
                                                             "from a grade (helix tolerance depends on b) [mm]")
    try:
        return iso1328_tolerances(edition, m, d, b, grade)
    except InputError as e:
        raise InputError(field, grade, f"{e.allowed} (gear d = {d:g} mm, m = {m:g} mm, b = {b:g} mm)") from None


def _rss(a: float, b: float) -> float:
    return math.hypot(a, b)


def _it(grade: int, size: float, field: str) -> float:
    try:
        return iso286.it_um(grade, size, field)
    except InputError as e:
        raise InputError(field, grade, f"{e.allowed} (size {size:g} mm)") from None


def base_tangent_tolerance_um(runout_um: float, feed_tolerance_um: float, pressure_angle_deg: float) -> float:
    """Base tangent length tolerance T_bn = T_sn cos(alpha), T_sn = 2 tan(alpha) sqrt(F_r^2 + b_r^2).

    Tooth thickness tolerance of the backlash design practice that accompanies GB/T 10095
    (run-out and the radial feed tolerance b_r of the cutting machine). ASSUMPTION: b_r =
    IT8 at the reference diameter for grade 5, times 1.26 per grade (the practice's table:
    grade 5 IT8, 6 1.26 IT8, 7 IT9, 8 1.26 IT9, 9 IT10). Parameters [um], alpha [deg]. Returns [um].
    """
    a = math.radians(pressure_angle_deg)
    return 2.0 * math.tan(a) * math.hypot(runout_um, feed_tolerance_um) * math.cos(a)


def centre_distance_it_grade(grade: int) -> int:
    """IT grade whose half is the centre-distance limit deviation f_a for gear grade Q:
    Q 0-2: IT4, 3-4: IT6, 5-6: IT7, 7-8: IT8, 9-10: IT9, 11-12: IT11 (GB 10095-88's f_a table,
    withdrawn; ISO/TR 10064-3 gives no values). ASSUMPTION."""
    return {0: 4, 1: 4, 2: 4, 3: 6, 4: 6, 5: 7, 6: 7, 7: 8, 8: 8, 9: 9, 10: 9, 11: 11, 12: 11}[grade]


def involute_zone(key: str, grade: int, design, edition: str, field: str) -> GradedZone:
    s1 = design.first_stage
    d1 = geometry.pitch_radius_mm(s1.module_mm, s1.centre_gear_teeth) * 2
    d2 = geometry.pitch_radius_mm(s1.module_mm, s1.planet_teeth) * 2
    g1 = _gear(design, edition, d1, s1.module_mm, grade, field)
    g2 = _gear(design, edition, d2, s1.module_mm, grade, field)
    std = _edition_name(edition)
    pair = f"grade {grade}, centre gear d = {d1:g} mm and planet d = {d2:g} mm, m = {s1.module_mm:g} mm (RSS of the pair)"
    if key == "base_tangent_length":
        b_r = 1.26 ** (grade - 5) * _it(8, d2, field)
        t = base_tangent_tolerance_um(g2.Fr_um, b_r, s1.pressure_angle_deg)
        return GradedZone(-t, 0.0, f"assumption: T_bn = 2 tan(a) sqrt(F_r^2 + b_r^2) cos(a), planet F_r "
                                   f"({std} grade {grade}), b_r = 1.26^(Q-5) IT8; upper deviation 0")
    if key == "centre_distance":
        a = geometry.centre_distance_mm(s1.module_mm, s1.centre_gear_teeth, s1.planet_teeth)
        it = centre_distance_it_grade(grade)
        fa = _it(it, a, field) / 2
        return GradedZone(-fa, fa, f"assumption: f_a = IT{it}/2 at a = {a:g} mm (GB 10095-88 rule, grade {grade})")
    if key == "gear_runout":
        v = _rss(g1.Fr_um, g2.Fr_um)
        src = "ISO 1328-2:1997 annex" if edition == "1995" else "ISO 1328-1:2013"
        return GradedZone(-v, v, f"F_r, {src}, {pair}")
    if key in ("axis_parallelism_x", "axis_parallelism_y"):
        share = 1.0 if key.endswith("x") else 0.5
        v = share * g2.Fbeta_um
        return GradedZone(0.0, v, f"ISO/TR 10064-3:1996 f_Sigma = {share:g} (L/b) F_beta with L/b = 1 (assumption), "
                                  f"planet F_beta {std} grade {grade}")
    if key == "tooth_profile":
        return GradedZone(0.0, _rss(g1.ffalpha_um, g2.ffalpha_um), f"f_falpha, {std}, {pair}")
    if key == "single_pitch":
        v = _rss(g1.fpt_um, g2.fpt_um)
        return GradedZone(-v, v, f"f_pt, {std}, {pair}")
    if key == "tooth_alignment":
        v = _rss(g1.Fbeta_um, g2.Fbeta_um)
        return GradedZone(-v, v, f"F_beta, {std}, {pair}")
    if key == "bearing_eccentricity":
        v = g2.Fr_um / 2
        return GradedZone(-v, v, f"assumption: e_g = F_r / 2 of the planet ({std} grade {grade})")
    raise KeyError(key)


def cycloid_zone(key: str, grade: int, design, edition: str, field: str) -> GradedZone:
    s2 = design.second_stage
    mc = cycloid.equivalent_module_mm(s2.pin_circle_radius_mm, s2.pins)
    dc = cycloid.disc_pitch_diameter_mm(s2.pin_circle_radius_mm, s2.pins, s2.cycloid_teeth)
    dp = 2 * s2.pin_circle_radius_mm
    std = _edition_name(edition)

    def gear(d: float) -> GearTolerances:
        try:
            return iso1328_tolerances(edition, mc, d, 10.0, grade)  # b does not enter F_p, F_r, f_falpha
        except InputError as e:
            raise InputError(field, grade, f"{e.allowed} (equivalent gear d = {d:.4g} mm, m = {mc:.4g} mm)") from None

    tag = f"{cycloid.ASSUMPTION}; {std} grade {grade}"
    if key == "disc_cumulative_pitch":
        v = gear(dc).Fp_um
        return GradedZone(-v, v, f"F_p at d_c = {dc:.4g} mm, m_c = {mc:.4g} mm; {tag}")
    if key == "disc_runout":
        v = gear(dc).Fr_um
        return GradedZone(-v, v, f"F_r at d_c = {dc:.4g} mm, m_c = {mc:.4g} mm; {tag}")
    if key == "pin_cumulative_pitch":
        return GradedZone(0.0, gear(dp).Fp_um, f"F_p at 2 r_p = {dp:g} mm, m_c = {mc:.4g} mm; {tag}")
    if key in ("equidistance_modification_error", "moving_distance_modification_error"):
        v = gear(dc).ffalpha_um
        return GradedZone(-v, v, f"f_falpha at d_c = {dc:.4g} mm; {tag}")
    if key == "pin_circle_radius":
        v = _it(grade, dp, field) / 2
        return GradedZone(-v, v, f"ISO 286-1 IT{grade}/2 of the pin-circle diameter {dp:g} mm (assumption)")
    if key == "pin_radius":
        v = _it(grade, 2 * s2.pin_radius_mm, field) / 2
        return GradedZone(-v, v, f"ISO 286-1 IT{grade}/2 of the pin diameter {2 * s2.pin_radius_mm:g} mm (assumption)")
    if key == "pin_hole_clearance":
        if grade + 1 not in iso286.IT_GRADES:
            raise InputError(field, grade, "allowed: grades 1 to 11 (the hole takes IT grade + 1)")
        f = iso286.fit(f"H{grade + 1}/g{grade}", 2 * s2.pin_radius_mm)
        return GradedZone(f.clearance_min_um, f.clearance_max_um,
                          f"ISO 286 fit H{grade + 1}/g{grade} at the pin diameter {2 * s2.pin_radius_mm:g} mm (assumption)")
    raise KeyError(key)


def crank_zone(key: str, grade: int, design, edition: str, field: str) -> GradedZone:
    s3, s2 = design.crank_stage, design.second_stage
    if key == "crank_bearing_clearance":
        bore = s3.bearing_bore_mm
        if bore is None:
            raise InputError("crank_stage.bearing_bore_mm", allowed="missing; needed to take the crank bearing "
                                                                    "clearance from a grade [mm]")
        return GradedZone(0.0, _it(grade, bore, field),
                          f"assumption: radial clearance in [0, IT{grade}] of the bearing bore {bore:g} mm (ISO 286-1)")
    if key == "crank_eccentricity":
        v = _it(grade, s2.eccentricity_mm, field) / 2
        return GradedZone(-v, v, f"ISO 286-1 IT{grade}/2 of the eccentricity a = {s2.eccentricity_mm:g} mm (assumption)")
    raise KeyError(key)


def graded_zone(factor, grade: int, design, edition: str, field: str) -> GradedZone:
    """Zone of ``factor`` (catalog entry) at ``grade``; ``field`` names the input for errors."""
    fn = {1: involute_zone, 2: cycloid_zone, 3: crank_zone}[int(factor.stage)]
    return fn(factor.key, grade, design, edition, field)
