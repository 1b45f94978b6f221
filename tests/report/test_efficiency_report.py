"""The report's losses, efficiency and temperature section (issue 40 item 6): rendered from the
EfficiencyResult it is given; its cards show the numbers the JSON carries (``efficiency`` command's)."""

import re
from dataclasses import replace

import pytest

import rvbacklash as rb
from rvbacklash.errors import InputError
from rvbacklash.report.html import render_html


def shown(page: str, key: str) -> float:
    m = re.search(rf'data-key="{re.escape(key)}" data-value="([^"]+)"', page)
    assert m, key
    return float(m.group(1))


def test_report_with_the_efficiency_and_temperature_cards():
    data = rb.make_report("rv80e", samples=2000, seed=1, duty_cycle="robot-joint")
    eff = data.to_dict()["efficiency"]
    alone = rb.efficiency("rv80e", duty_cycle="robot-joint").to_dict()
    for key in ("efficiency_at_rated", "starting_torque_nm", "contacts_loop_friction_at_rated_nm"):
        assert eff[key] == alone[key], key  # the section is the efficiency command's datasheet
    assert eff["thermal"]["steady_temperature_c"] == alone["thermal"]["steady_temperature_c"]
    page = render_html(data)
    section = page[page.index('id="efficiency"'):page.index("</section>", page.index('id="efficiency"'))]
    for text in ("Losses, efficiency and temperature", 'id="efficiency-card"', 'id="temperature-card"',
                 'id="efficiency-elements"', "pins on flanks", 'id="fig-efficiency"', "<svg", "robot-joint"):
        assert text in section, text
    assert shown(page, "efficiency.efficiency_at_rated") == eff["efficiency_at_rated"]
    assert shown(page, "efficiency.thermal.steady_temperature_c") == eff["thermal"]["steady_temperature_c"]
    assert shown(page, "efficiency.thermal.allowable_duty_at_limit") == eff["thermal"]["allowable_duty_at_limit"]
    last = len(eff["thermal"]["precision"]) - 1
    assert shown(page, f"efficiency.thermal.precision.{last}.lost_motion_arcmin") == \
        eff["thermal"]["precision"][last]["lost_motion_arcmin"]
    # the steady temperature's lost motion is the one the card names
    assert eff["thermal"]["precision"][last]["temperature_c"] == eff["thermal"]["steady_temperature_c"]
    # TE at temperature (issue 40, continued): the card shows the nominal unit's TE at the steady temperature as
    # `efficiency --duty-cycle` gives it, the table the TE at each temperature of `precision_by_temperature`
    te_hot = alone["thermal"]["precision"][last]["te_peak_to_peak_arcsec"]
    assert te_hot > 0.0 and 'id="te-temperature-card"' in section  # the warm unit's TE moved from the reference's
    assert shown(page, f"efficiency.thermal.precision.{last}.te_peak_to_peak_arcsec") == te_hot
    assert f"{te_hot:.3f}</span> arcsec" in section
    table = section[section.index('id="efficiency-temperature"'):]
    assert "TE peak-to-peak [arcsec]" in table
    for k, p in enumerate(alone["precision_by_temperature"]):
        assert shown(page, f"efficiency.precision_by_temperature.{k}.te_peak_to_peak_arcsec") == \
            p["te_peak_to_peak_arcsec"], p["temperature_c"]
    # without a duty cycle the card names the hottest temperature of the table
    cold = render_html(replace(data, efficiency=replace(data.efficiency, thermal=None)))
    hottest = len(alone["precision_by_temperature"]) - 1
    assert shown(cold, f"efficiency.precision_by_temperature.{hottest}.te_peak_to_peak_arcsec") == \
        alone["precision_by_temperature"][hottest]["te_peak_to_peak_arcsec"]
    card = cold[cold.index('id="te-temperature-card"'):]
    assert f'transmission error at {alone["precision_by_temperature"][hottest]["temperature_c"]:.1f} °C' in card


def test_without_the_flag_no_section_and_a_bad_duty_cycle_fails_first(tmp_path):
    assert 'id="efficiency"' not in render_html(rb.make_report("rv80e", samples=500, seed=1))
    bad = tmp_path / "cycle.csv"
    bad.write_text("time_share,output_torque_nm\n1.0,100\n")  # no speed column
    with pytest.raises(InputError):
        rb.make_report("rv80e", samples=500, seed=1, duty_cycle=bad)
