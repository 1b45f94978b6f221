"""ISO 1328-1 gear accuracy tolerances, editions 1995 (= GB/T 10095.1-2008, = JIS B 1702-1:1998)
and 2013, and the radial run-out of ISO 1328-2:1997. One function per formula.

1995: the grade-5 formulas are evaluated at the geometric mean of the limits of the size range
that holds d, m and b (clause 6.3), multiplied by 2^(0.5 (Q - 5)) for grade Q (clause 6.2) and
rounded (``rounding.round_iso1328_1``). 2013: the class-5 formulas take the actual d, m_n, b,
multiplied by sqrt(2)^(A - 5), same rounding.

Source of the formulas, steps, ranges and rounding: the standards as summarised in
``../shared/reference/anchors.md``; clause numbers are not quoted because no copy of the
standards' text was available to check them. The 1995 formulas are tested against the
printed tables (``data/iso1328-1_1995.csv``, ``data/iso1328-2_1997.csv``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from rvbacklash.errors import InputError
from rvbacklash.standards.rounding import round_iso1328_1, round_iso1328_2

# ISO 1328-1:1995, 6.3: size ranges (lower limit exclusive except the first)
D_LIMITS_1995 = (5, 20, 50, 125, 280, 560, 1000, 1600, 2500, 4000, 6000, 8000, 10000)
M_LIMITS_1995 = (0.5, 2, 3.5, 6, 10, 16, 25, 40, 70)
B_LIMITS_1995 = (4, 10, 20, 40, 80, 160, 250, 400, 650, 1000)
GRADES_1995 = range(0, 13)
CLASSES_2013 = range(1, 12)
SCOPE_2013 = {"d": (5.0, 15000.0), "m": (0.5, 70.0), "b": (4.0, 1200.0)}


def range_geometric_mean(value: float, limits: tuple[float, ...], name: str, option: str) -> float:
    """Geometric mean sqrt(lo * hi) of the ISO 1328-1:1995 size range holding ``value``
    (ranges lo < value <= hi, the first one closed). Outside the table: InputError naming
    the validity limits."""
    if not limits[0] <= value <= limits[-1]:
        raise InputError(option, value, f"ISO 1328-1:1995 covers {limits[0]} <= {name} <= {limits[-1]}")
    for lo, hi in zip(limits[:-1], limits[1:]):
        if value <= hi:
            return math.sqrt(lo * hi)
    raise AssertionError("unreachable")


def grade_factor_1995(grade: int) -> float:
    """2^(0.5 (Q - 5)): the step between ISO 1328-1:1995 grades (applied to the unrounded grade-5 value)."""
    return 2.0 ** (0.5 * (grade - 5))


def single_pitch_1995_um(m: float, d: float) -> float:
    """Grade-5 single pitch deviation, f_pt = 0.3 (m + 0.4 sqrt(d)) + 4 [um].
    Source: ISO 1328-1:1995 (generating formula of its f_pt table). m, d [mm]: range means."""
    return 0.3 * (m + 0.4 * math.sqrt(d)) + 4.0


def total_cumulative_pitch_1995_um(m: float, d: float) -> float:
    """Grade-5 total cumulative pitch deviation, F_p = 0.3 m + 1.25 sqrt(d) + 7 [um].
    Source: ISO 1328-1:1995 (generating formula of its F_p table). m, d [mm]: range means."""
    return 0.3 * m + 1.25 * math.sqrt(d) + 7.0


def total_profile_1995_um(m: float, d: float) -> float:
    """Grade-5 total profile deviation, F_alpha = 3.2 sqrt(m) + 0.22 sqrt(d) + 0.7 [um].
    Source: ISO 1328-1:1995 (generating formula of its F_alpha table). m, d [mm]: range means."""
    return 3.2 * math.sqrt(m) + 0.22 * math.sqrt(d) + 0.7


def profile_form_1995_um(m: float, d: float) -> float:
    """Grade-5 profile form deviation, f_falpha = 2.5 sqrt(m) + 0.17 sqrt(d) + 0.5 [um].
    Source: ISO 1328-1:1995, informative annex. m, d [mm]: range means."""
    return 2.5 * math.sqrt(m) + 0.17 * math.sqrt(d) + 0.5


def total_helix_1995_um(d: float, b: float) -> float:
    """Grade-5 total helix deviation, F_beta = 0.1 sqrt(d) + 0.63 sqrt(b) + 4.2 [um].
    Source: ISO 1328-1:1995 (generating formula of its F_beta table). d, b [mm]: range means."""
    return 0.1 * math.sqrt(d) + 0.63 * math.sqrt(b) + 4.2


def radial_runout_1995_um(m: float, d: float) -> float:
    """Grade-5 radial run-out, F_r = 0.8 F_p = 0.24 m + 1.0 sqrt(d) + 5.6 [um].
    Source: ISO 1328-2:1997, informative annex on run-out. m, d [mm]: range means."""
    return 0.8 * total_cumulative_pitch_1995_um(m, d)


def class_factor_2013(accuracy_class: int) -> float:
    """sqrt(2)^(A - 5): the step between ISO 1328-1:2013 classes."""
    return math.sqrt(2.0) ** (accuracy_class - 5)


def single_pitch_2013_um(m: float, d: float) -> float:
    """Class-5 single pitch tolerance, f_pT = 0.001 d + 0.4 m_n + 5 [um]. ISO 1328-1:2013.
    m_n, d [mm]: actual values. Validity: see SCOPE_2013."""
    return 0.001 * d + 0.4 * m + 5.0


def total_cumulative_pitch_2013_um(m: float, d: float) -> float:
    """Class-5 total cumulative pitch tolerance, F_pT = 0.002 d + 0.55 sqrt(d) + 0.7 m_n + 12 [um].
    ISO 1328-1:2013. m_n, d [mm]."""
    return 0.002 * d + 0.55 * math.sqrt(d) + 0.7 * m + 12.0


def profile_slope_2013_um(m: float, d: float) -> float:
    """Class-5 profile slope tolerance, f_HalphaT = 0.4 m_n + 0.001 d + 4 [um]. ISO 1328-1:2013."""
    return 0.4 * m + 0.001 * d + 4.0


def profile_form_2013_um(m: float) -> float:
    """Class-5 profile form tolerance, f_falphaT = 0.55 m_n + 5 [um]. ISO 1328-1:2013."""
    return 0.55 * m + 5.0


def total_profile_2013_um(m: float, d: float) -> float:
    """Class-5 total profile tolerance, F_alphaT = sqrt(f_HalphaT^2 + f_falphaT^2) [um]. ISO 1328-1:2013."""
    return math.hypot(profile_slope_2013_um(m, d), profile_form_2013_um(m))


def total_helix_2013_um(d: float, b: float) -> float:
    """Class-5 total helix tolerance, F_betaT = sqrt(f_HbetaT^2 + f_fbetaT^2) [um] with
    f_HbetaT = 0.05 sqrt(d) + 0.35 sqrt(b) + 4 and f_fbetaT = 0.07 sqrt(d) + 0.45 sqrt(b) + 4.
    ISO 1328-1:2013. d, b [mm]."""
    return math.hypot(0.05 * math.sqrt(d) + 0.35 * math.sqrt(b) + 4.0,
                      0.07 * math.sqrt(d) + 0.45 * math.sqrt(b) + 4.0)


def radial_runout_2013_um(m: float, d: float) -> float:
    """Class-5 radial run-out tolerance, F_rT = 0.9 F_pT [um]. ISO 1328-1:2013 run-out
    information as given in anchors.md, where it is marked unverified."""
    return 0.9 * total_cumulative_pitch_2013_um(m, d)


@dataclass(frozen=True)
class GearTolerances:
    """Tolerances of one gear [um], with where they came from."""

    standard: str
    grade: int
    module_mm: float
    diameter_mm: float
    width_mm: float
    fpt_um: float
    Fp_um: float
    Falpha_um: float
    ffalpha_um: float
    Fbeta_um: float
    Fr_um: float
    note: str

    def to_dict(self) -> dict:
        return asdict(self)


def _check_number(option: str, value: float) -> float:
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(option, value, "allowed: a finite number")
    return float(value)


def iso1328_tolerances(edition: str, module_mm: float, diameter_mm: float, width_mm: float,
                       grade: int) -> GearTolerances:
    """Every tolerance of a gear for ``edition`` '1995' or '2013'; validity limits enforced."""
    m = _check_number("module_mm", module_mm)
    d = _check_number("diameter_mm", diameter_mm)
    b = _check_number("width_mm", width_mm)
    if edition == "1995":
        if grade not in GRADES_1995:
            raise InputError("grade", grade, "allowed: ISO 1328-1:1995 grades 0 to 12")
        mm = range_geometric_mean(m, M_LIMITS_1995, "m", "module_mm")
        dm = range_geometric_mean(d, D_LIMITS_1995, "d", "diameter_mm")
        bm = range_geometric_mean(b, B_LIMITS_1995, "b", "width_mm")
        k = grade_factor_1995(grade)
        r = round_iso1328_1
        return GearTolerances(
            "ISO 1328-1:1995 (= GB/T 10095.1-2008); F_r: ISO 1328-2:1997 annex", grade, m, d, b,
            fpt_um=r(k * single_pitch_1995_um(mm, dm)), Fp_um=r(k * total_cumulative_pitch_1995_um(mm, dm)),
            Falpha_um=r(k * total_profile_1995_um(mm, dm)), ffalpha_um=r(k * profile_form_1995_um(mm, dm)),
            Fbeta_um=r(k * total_helix_1995_um(dm, bm)), Fr_um=round_iso1328_2(k * radial_runout_1995_um(mm, dm)),
            note=f"range means d = {dm:.4g} mm, m = {mm:.4g} mm, b = {bm:.4g} mm")
    if edition == "2013":
        if grade not in CLASSES_2013:
            raise InputError("grade", grade, "allowed: ISO 1328-1:2013 classes 1 to 11")
        for name, value, option in (("d", d, "diameter_mm"), ("m", m, "module_mm"), ("b", b, "width_mm")):
            lo, hi = SCOPE_2013[name]
            if not lo <= value <= hi:
                raise InputError(option, value, f"ISO 1328-1:2013 covers {lo:g} <= {name} <= {hi:g}")
        k = class_factor_2013(grade)
        r = round_iso1328_1
        return GearTolerances(
            "ISO 1328-1:2013", grade, m, d, b,
            fpt_um=r(k * single_pitch_2013_um(m, d)), Fp_um=r(k * total_cumulative_pitch_2013_um(m, d)),
            Falpha_um=r(k * total_profile_2013_um(m, d)), ffalpha_um=r(k * profile_form_2013_um(m)),
            Fbeta_um=r(k * total_helix_2013_um(d, b)), Fr_um=r(k * radial_runout_2013_um(m, d)),
            note="actual d, m_n, b (no size ranges in the 2013 edition)")
    raise InputError("edition", edition, "allowed: 1995, 2013")
