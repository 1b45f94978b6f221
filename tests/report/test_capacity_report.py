"""The report's capacity and life section (issue 37): rendered from the CapacityResult it is given."""

import rvbacklash as rb
from rvbacklash.report.html import render_html


def test_report_with_the_capacity_section():
    data = rb.make_report("rv80e", samples=2000, seed=1, capacity=True)
    assert data.capacity is not None and data.to_dict()["capacity"]["derived_rated_torque_nm"] > 0
    page = render_html(data)
    for text in ('id="capacity"', "Capacity and life", 'id="capacity-bearings"', "needle d0 c0", "momentary maximum",
                 'data-key="capacity.derived_rated_torque_nm"', "<svg"):
        assert text in page, text
    assert 'id="capacity"' not in render_html(rb.make_report("rv80e", samples=2000, seed=1))
