"""The design schema: every class of bad input is one InputError naming the field, the value
and what is allowed; nothing is coerced silently."""

import pytest

from rvbacklash.design.loading import design_from_dict, design_from_toml, load_design
from rvbacklash.errors import InputError

BAD = {
    # class: (text substitution (old, new), fragment the message must contain)
    "missing field": (("module_mm = 1.75\n", ""), "first_stage.module_mm: missing"),
    "unknown field": (("planets = 3\n", "planets = 3\ngear_ratio = 2\n"), "first_stage.gear_ratio"),
    "nan": (("pin_radius_mm = 4.0", "pin_radius_mm = nan"), "second_stage.pin_radius_mm = nan"),
    "inf": (("eccentricity_mm = 1.5", "eccentricity_mm = inf"), "second_stage.eccentricity_mm = inf"),
    "negative radius": (("pin_circle_radius_mm = 77.5", "pin_circle_radius_mm = -77.5"),
                        "second_stage.pin_circle_radius_mm = -77.5: Input should be greater than 0"),
    "negative teeth": (("planet_teeth = 38", "planet_teeth = -38"), "first_stage.planet_teeth = -38"),
    "K1 >= 1": (("eccentricity_mm = 1.5", "eccentricity_mm = 2.0"), "allowed 0 < K1 < 1"),
    "zp != zc + 1": (("pins = 40", "pins = 42"), "pins = cycloid_teeth + 1 = 40"),
    "lower > upper": (("lower_um = 1.0\nupper_um = 4.0", "lower_um = 4.0\nupper_um = 1.0"),
                      "factors.crank_bearing_clearance"),
    "malformed TOML": (("[second_stage]", "[second_stage"), "malformed TOML"),
    "boolean for a count": (("planets = 3", "planets = true"), "first_stage.planets = True"),
    "text for a number": (("module_mm = 1.75", 'module_mm = "1.75"'), "first_stage.module_mm = '1.75'"),
    "float for a count": (("cycloid_teeth = 39", "cycloid_teeth = 39.0"), "second_stage.cycloid_teeth = 39.0"),
    "undercut": (("eccentricity_mm = 1.5", "eccentricity_mm = 1.9"), "undercut"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_design_is_one_clear_error(case, sun2014_toml):
    (old, new), fragment = BAD[case]
    assert old in sun2014_toml
    with pytest.raises(InputError) as e:
        design_from_toml(sun2014_toml.replace(old, new, 1), "bad.toml")
    assert fragment in str(e.value) and "\n" not in str(e.value)


def test_an_integer_is_a_number(sun2014_toml):
    d = design_from_toml(sun2014_toml.replace("module_mm = 1.75", "module_mm = 2"))
    assert d.first_stage.module_mm == 2.0 and isinstance(d.first_stage.module_mm, float)


def test_utf8_bom_is_not_content(tmp_path, sun2014_toml):
    f = tmp_path / "bom.toml"
    f.write_bytes(b"\xef\xbb\xbf" + sun2014_toml.encode("utf-8"))
    assert load_design(f).name == "sun2014"
    assert design_from_toml("\ufeff" + sun2014_toml).name == "sun2014"


def test_unknown_example_names_the_choices():
    with pytest.raises(InputError) as e:
        load_design("rv90x")
    assert str(e.value) == ("design = 'rv90x': allowed: a path to an existing .toml file or a built-in example "
                            "(rv80e, sun2014)")


@pytest.mark.parametrize("body,fragment", [
    ({"plus_minus_um": 6.5, "sigma_um": 0}, "sigma_um = 0"),
    ({"plus_minus_um": 6.5, "distribution": "uniform", "sigma_um": 2}, "does not apply to distribution 'uniform'"),
    ({"plus_minus_um": 6.5, "distribution": "weibull"}, "distribution"),
    ({"plus_minus_um": 6.5, "distribution": "rayleigh"}, "errors of kind magnitude or phase"),
    ({"lower_um": 1.0}, "give both lower_um and upper_um"),
    ({"lower_um": 1.0, "upper_um": 2.0, "plus_minus_um": 1.0}, "not both"),
    ({"lower_um": 1.0, "upper_um": 1.0, "distribution": "uniform"}, "non-zero width"),
])
def test_bad_zone(body, fragment, sun2014):
    data = sun2014.model_dump(exclude_none=True)
    data["factors"]["centre_distance"] = body
    with pytest.raises(InputError, match=fragment):
        design_from_dict(data)


def test_every_factor_needs_a_tolerance(rv80e):
    data = rv80e.model_dump(exclude_none=True)
    data.pop("grades")
    with pytest.raises(InputError, match="no tolerance"):
        design_from_dict(data)


@pytest.mark.parametrize("matrix,fragment", [
    ([[1, 0.9, -0.9], [0.9, 1, 0.9], [-0.9, 0.9, 1]], "positive semi-definite"),
    ([[1, 0.5, 0], [0.4, 1, 0], [0, 0, 1]], "symmetric"),
    ([[1, 0.5], [0.5, 1]], "must be 3 x 3"),
])
def test_bad_correlation(matrix, fragment, sun2014):
    data = sun2014.model_dump(exclude_none=True)
    data["correlation"] = {"factors": ["disc_runout", "pin_radius", "pin_circle_radius"], "matrix": matrix}
    with pytest.raises(InputError, match=fragment):
        design_from_dict(data)
