"""[structure] dimensions where the torque path's formulas mean something (design/structure.py,
"Validity"): outside, one line naming the field, the value and the allowed range, exit 2."""

from __future__ import annotations

import pytest

from helpers import example_text, one_line_error, run_cli
from rvbacklash.design.loading import available_examples, design_from_toml, load_design
from rvbacklash.errors import InputError


def _rv80e_with(tmp_path, *edits: tuple[str, str]):
    text = example_text("rv80e")
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    f = tmp_path / "design.toml"
    f.write_text(text)
    return f


@pytest.mark.parametrize("edits, fragment", [
    # the reported designs: a lost motion of 4.5e11 arcmin with exit 0
    ((("crankshaft_diameter_mm = 25.0", "crankshaft_diameter_mm = 0.01"),),
     "structure.crankshaft_diameter_mm = 0.01: crankshaft span / diameter = 4500"),
    ((("pillar_width_mm = 20.0", "pillar_width_mm = 0.001"), ("pillar_depth_mm = 20.0", "pillar_depth_mm = 0.001")),
     "structure.pillar_width_mm = 0.001: pillar length / width"),
    ((("pillar_depth_mm = 20.0", "pillar_depth_mm = 0.001"),), "structure.pillar_depth_mm = 0.001: pillar length / depth"),
    # each limit
    ((("crankshaft_torsion_diameter_mm = 25.0", "crankshaft_torsion_diameter_mm = 1.0"),),
     "structure.crankshaft_torsion_diameter_mm = 1.0: twisting length / diameter = 40"),
    ((("crankshaft_support_span_mm = 45.0", "crankshaft_support_span_mm = 20.0"),),
     "structure.crankshaft_diameter_mm = 25.0: crankshaft span / diameter = 0.8"),
    ((("crankshaft_diameter_mm = 25.0", "crankshaft_diameter_mm = 14.0"),), "allowed: 15 to 33 mm"),
    ((("crankshaft_diameter_mm = 25.0", "crankshaft_diameter_mm = 34.0"),), "allowed: 15 to 33 mm"),
    ((("support_bearing_roller_length_mm = 11.0", "support_bearing_roller_length_mm = 0.01"),),
     "structure.support_bearing_roller_length_mm = 0.01: allowed: 0.5 to 4 roller diameters"),
    ((("pillar_width_mm = 20.0", "pillar_width_mm = 26.0"), ("pillar_radius_mm = 42.0", "pillar_radius_mm = 15.0")),
     "structure.pillar_width_mm = 26.0: 3 pillars this wide overlap"),
    ((("pillar_radius_mm = 42.0", "pillar_radius_mm = 70.0"),), "structure.pillar_radius_mm = 70.0: the pillars pass "
                                                                 "through the discs"),
    ((("disc_spacing_mm = 13.0 ", "disc_spacing_mm = 10.0 "),), "structure.disc_spacing_mm = 10.0: the two discs "
                                                                 "would overlap"),
    ((("disc_spacing_mm = 13.0 ", "disc_spacing_mm = 40.0 "),), "structure.crankshaft_support_span_mm = 45.0: the "
                                                                 "supports must sit outside the disc stack"),
])
def test_a_structure_outside_its_formulas_is_refused(tmp_path, edits, fragment):
    """Regression: a 0.01 mm crankshaft or 0.001 mm pillars gave a lost motion of 4.5e11 arcmin,
    exit 0; every such design is one line naming the field, exit 2, nothing written."""
    out = tmp_path / "h.json"
    line = one_line_error(run_cli("hysteresis", _rv80e_with(tmp_path, *edits), "--json", out), fragment)
    assert "allowed" in line and not out.exists()


def test_the_examples_pass_unchanged():
    """The limits refuse no built-in example; rv80e's structure is the one its numbers come from."""
    for name in available_examples():
        load_design(name)
    st = load_design("rv80e").structure
    assert (st.crankshaft_diameter_mm, st.crankshaft_support_span_mm, st.pillar_width_mm, st.pillar_length_mm) == \
        (25.0, 45.0, 20.0, 27.0)


def test_the_library_error_names_the_field_too():
    text = example_text("rv80e").replace("crankshaft_diameter_mm = 25.0", "crankshaft_diameter_mm = 0.01", 1)
    with pytest.raises(InputError) as e:
        design_from_toml(text)
    assert e.value.field == "structure.crankshaft_diameter_mm" and e.value.value == 0.01


@pytest.mark.parametrize("edits, fragment", [
    # slender parts within the design's limits that the rated torque would bend far beyond small deflections
    ((("pillar_width_mm = 20.0", "pillar_width_mm = 1.4"), ("pillar_depth_mm = 20.0", "pillar_depth_mm = 1.4")),
     "structure.pillar_width_mm = 1.4: allowed: >="),
])
def test_a_part_the_rated_torque_bends_beyond_small_deflections_is_refused(tmp_path, edits, fragment):
    """models/elastic/chain.py (SMALL_DEFLECTION): beam and shaft formulas are small-deflection
    theory; a part that deflects more than 1 % of its length at the rated torque is refused with the
    deflection it would have (rv80e's parts: ~1e-4)."""
    f = _rv80e_with(tmp_path, *edits)
    load_design(f)  # the design itself is within its dimensions' limits
    line = one_line_error(run_cli("hysteresis", f), fragment)
    assert "allowed: >= 10.33 mm (the rest as given)" in line
    assert "this carrier pillar bends 2.8 of its length at 784 N m (E = 206 GPa)" in line
