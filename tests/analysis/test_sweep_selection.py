"""A sweep of a design with a [selection] table (issue 39, continued): each point's yield selected beside
its random run, and a selection setting swept like any design field (here the measurement's noise)."""

import rvbacklash.api as api
from rvbacklash.design.loading import example_text


def test_sweep_points_carry_the_selected_yields(tmp_path):
    (tmp_path / "d.toml").write_text(example_text("rv80e") + '\n[selection]\npins = "5x2um"\nrollers = "3x2um"\n')
    (tmp_path / "s.toml").write_text('''name = "noise"
design = "d.toml"
model = "contact"
samples = 400
seed = 3
[specs]
backlash = 1.0
[[parameters]]
path = "selection.noise_um"
values = [0.0, 2.0]
''')
    r = api.sweep(tmp_path / "s.toml", scheduler="inline")
    rows = list(r.table)
    assert [row["selection.noise_um"] for row in rows] == [0.0, 2.0]
    for row in rows:
        assert row["selection"].startswith("pins=5x2um,rollers=3x2um,noise=")
        assert row["selected_backlash_yield"] > row["backlash_yield"] + 0.05
        assert row["pin_sets_per_unit"] >= 1.0
    assert rows[0]["selected_backlash_yield"] != rows[1]["selected_backlash_yield"]
