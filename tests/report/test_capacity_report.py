"""The report's capacity and life section (issue 37): rendered from the CapacityResult and the
CapacityTrade it is given."""

import re

import rvbacklash as rb
from rvbacklash.report.html import render_html


def test_report_with_the_capacity_section():
    data = rb.make_report("rv80e", samples=2000, seed=1, capacity=True)
    assert data.capacity is not None and data.to_dict()["capacity"]["derived_rated_torque_nm"] > 0
    page = render_html(data)
    for text in ('id="capacity"', "Capacity and life", 'id="capacity-bearings"', "needle d0 c0", "momentary maximum",
                 'data-key="capacity.derived_rated_torque_nm"', "<svg"):
        assert text in page, text
    # the trade: lost motion against life of the design and its what-ifs, as the API computes them
    trade = data.to_dict()["capacity_trade"]
    assert [p["name"] for p in trade["points"]] == [p.name for p in rb.capacity_trade("rv80e").points]
    section = page[page.index('id="capacity"'):page.index("</section>", page.index('id="capacity"'))]
    for text in ('id="fig-capacity-trade"', 'id="capacity-trade"', "lost motion against life",
                 "crank bearings preloaded 4 um", "equidistance modification 10 um"):
        assert text in section, text
    assert section.count("<svg") == 2  # the loads and the trade
    for i, p in enumerate(trade["points"]):
        for key in ("lost_motion_arcmin", "reducer_life_h"):
            shown = re.search(rf'data-key="capacity_trade\.points\.{i}\.{key}" data-value="([^"]+)"', page)
            assert shown and float(shown.group(1)) == p[key], (i, key)
    assert 'id="capacity"' not in render_html(rb.make_report("rv80e", samples=2000, seed=1))
