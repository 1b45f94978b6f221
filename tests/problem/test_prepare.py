"""prepare(design): zones resolved once with their origins (explicit > factor grade > stage
grade), moments, correlation, linear coefficients."""

import numpy as np
import pytest

from rvbacklash.design.loading import design_from_dict
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.problem import prepare
from rvbacklash.standards.iso1328 import iso1328_tolerances


def zone(problem, key):
    return problem.zones[FACTOR_KEYS.index(key)]


def test_a_design_entirely_in_grades(rv80e_problem):
    origins = [z.origin for z in rv80e_problem.zones]
    assert sum(o == "explicit" for o in origins) == 1  # bearing eccentricity, supplier data
    assert all("ISO" in o or "assumption" in o or o.startswith(("explicit", "second_stage")) for o in origins)
    # stage 1 single pitch: RSS of centre gear (d 17.5) and planet (d 66.5), grade 5: hypot(4.7, 5.5)
    z = zone(rv80e_problem, "single_pitch")
    assert z.upper_um == pytest.approx((4.7 ** 2 + 5.5 ** 2) ** 0.5) and "ISO 1328-1:1995" in z.origin
    assert "assumption" in zone(rv80e_problem, "disc_cumulative_pitch").origin
    # designed modifications: the nominal values, fixed
    assert zone(rv80e_problem, "equidistance_modification").value_um == 5.0
    assert rv80e_problem.sigmas_um[FACTOR_KEYS.index("equidistance_modification")] == 0


def test_precedence_explicit_then_factor_grade_then_stage_grade(rv80e, rv80e_problem):
    data = rv80e.model_dump(exclude_none=True)
    data["grades"]["factors"] = {"single_pitch": 8, "tooth_alignment": 8}
    data["factors"]["tooth_alignment"] = {"plus_minus_um": 1.0}
    p = prepare(design_from_dict(data))
    planet8 = iso1328_tolerances("1995", 1.75, 66.5, 15.0, 8)
    sun8 = iso1328_tolerances("1995", 1.75, 17.5, 15.0, 8)
    assert zone(p, "single_pitch").upper_um == pytest.approx((planet8.fpt_um ** 2 + sun8.fpt_um ** 2) ** 0.5)
    assert zone(p, "tooth_alignment").upper_um == 1.0 and zone(p, "tooth_alignment").origin == "explicit"
    assert zone(p, "tooth_profile").upper_um == zone(rv80e_problem, "tooth_profile").upper_um  # stage grade 5


@pytest.mark.parametrize("edit,fragment", [
    (lambda d: d["first_stage"].pop("face_width_mm"), "first_stage.face_width_mm"),
    (lambda d: d["grades"].update(involute=13), "grades.involute"),
    (lambda d: d["grades"].update(edition="2013", cycloid=12), "allowed grades 1 to 11"),
    (lambda d: d["grades"].update(factors={"pin_wheel": 5}), "unknown factor 'pin_wheel'"),
])
def test_bad_grade_input(rv80e, edit, fragment):
    data = rv80e.model_dump(exclude_none=True)
    edit(data)
    with pytest.raises(InputError) as e:
        prepare(design_from_dict(data))
    assert fragment in str(e.value)


def test_a_fixed_factor_cannot_be_correlated(sun2014):
    data = sun2014.model_dump(exclude_none=True)
    data["factors"]["disc_runout"] = {"distribution": "fixed", "value_um": 0.0}
    data["correlation"] = {"factors": ["disc_runout", "pin_radius"], "matrix": [[1, 0.5], [0.5, 1]]}
    with pytest.raises(InputError) as e:
        prepare(design_from_dict(data))
    assert e.value.field == "correlation.factors" and e.value.value == "disc_runout"


def test_problem_holds_what_the_models_need(rv80e_problem):
    p = rv80e_problem
    assert p.source == "<object>" and p.source_sha256 is None
    assert p.sensitivities_arcmin_per_um.shape == (21,) and not p.correlated
    np.testing.assert_array_equal(p.sensitivities_arcmin_per_um, p.gains_um_per_um * p.stage_coefficients_arcmin_per_um)
    assert p.cycloid.zp == 40 and p.cycloid.discs == 2
    assert len(repr(p).splitlines()) == 1 and "rv80e" in repr(p)
    # scipy laws are built on first use only, and agree with the closed-form moments
    laws = p.marginals
    for law, m, s in zip(laws, p.means_um, p.sigmas_um):
        if law is None:
            assert s == 0
        else:
            assert (law.mean(), law.std()) == pytest.approx((m, s), rel=1e-12, abs=1e-12)


def test_a_problem_from_a_file_records_its_source(tmp_path, sun2014_toml):
    import hashlib

    from rvbacklash.api import prepare as api_prepare

    f = tmp_path / "mine.toml"
    f.write_text(sun2014_toml, encoding="utf-8")
    p = api_prepare(f)
    assert p.source == str(f) and p.source_sha256 == hashlib.sha256(sun2014_toml.encode()).hexdigest()
    assert api_prepare(p) is p
