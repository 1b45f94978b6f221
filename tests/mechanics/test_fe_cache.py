"""The FE results' cache (mechanics.fe_cache): the built-in examples' results ship with the package."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rvbacklash.design.loading import available_examples, load_design
from rvbacklash.errors import InputError
from rvbacklash.mechanics import fe_cache
from rvbacklash.models.elastic.bodies import elastic_model
from rvbacklash.models.elastic.rollers import SlicedRoller, fit_roller_law
from rvbacklash.problem import prepare

KINDS = ("disc_body", "carrier_body", "roller_law_fit")


@pytest.fixture
def own_cache(tmp_path, monkeypatch):
    """An empty user cache (nothing from another run) and no result in memory."""
    monkeypatch.setenv("RVBACKLASH_CACHE_DIR", str(tmp_path / "cache"))
    fe_cache.clear_memory()
    yield tmp_path / "cache" / "fe"
    fe_cache.clear_memory()


def test_a_shipped_result_is_read_not_computed(own_cache, tmp_path, monkeypatch):
    shipped = tmp_path / "shipped"
    shipped.mkdir()
    monkeypatch.setattr(fe_cache, "SHIPPED", shipped)
    inputs = {"x_mm": 1.5}
    key = fe_cache.cache_key("test_kind", 1, inputs)
    (shipped / f"{key}.json").write_text(json.dumps({"inputs": inputs, "result": {"k": 2.0}}))
    assert fe_cache.cached("test_kind", 1, inputs, lambda: pytest.fail("computed")) == {"k": 2.0}
    assert not own_cache.exists()  # nothing copied into the user's cache
    # another input (or version) misses it: computed and kept in the user's cache
    assert fe_cache.cached("test_kind", 2, inputs, lambda: {"k": 3.0}) == {"k": 3.0}
    assert [p.name for p in own_cache.iterdir()] == [f"{fe_cache.cache_key('test_kind', 2, inputs)}.json"]


def test_a_shipped_file_for_other_inputs_is_not_read(own_cache, tmp_path, monkeypatch):
    """A file whose stored inputs are not the call's (a hash collision, a hand edit) is ignored."""
    shipped = tmp_path / "shipped"
    shipped.mkdir()
    monkeypatch.setattr(fe_cache, "SHIPPED", shipped)
    key = fe_cache.cache_key("test_kind", 1, {"x_mm": 1.5})
    (shipped / f"{key}.json").write_text(json.dumps({"inputs": {"x_mm": 2.5}, "result": {"k": 2.0}}))
    assert fe_cache.cached("test_kind", 1, {"x_mm": 1.5}, lambda: {"k": 4.0}) == {"k": 4.0}


def test_the_built_in_examples_fe_results_ship_with_the_package(own_cache):
    """Regression (issue 35): a fresh clone's first `make example` meshed and solved the rv80e
    discs and carrier (tens of seconds). Every FE result the built-in examples' elastic model
    reads is in the package data, found by its key: nothing is computed into an empty cache. A
    change of those models' inputs or versions fails here: run tools/ship_fe_results.py."""
    assert fe_cache.SHIPPED is not None and any(fe_cache.SHIPPED.glob("disc_body-*.json"))
    ran = 0
    for name in available_examples():
        try:
            elastic_model(prepare(load_design(name)))
        except InputError:
            continue
        ran += 1
    computed = sorted(p.name for p in own_cache.glob("*.json") if p.name.startswith(KINDS)) if own_cache.exists() else []
    assert ran >= 1 and computed == [], f"not shipped (run tools/ship_fe_results.py): {computed}"


def test_the_shipped_roller_fits_are_what_the_fit_computes(own_cache, monkeypatch):
    """The shipped results are the models' own (here the cheapest to recompute, the rollers'
    fitted laws; the carrier's is checked against a fresh coarser mesh in test_carrier_body)."""
    files = sorted(fe_cache.SHIPPED.glob("roller_law_fit-*.json"))
    if not files:
        pytest.skip("no built-in example has profiled needle rollers")
    monkeypatch.setattr(fe_cache, "SHIPPED", None)  # computed afresh
    for f in files:
        stored = json.loads(f.read_text())
        inp = stored["inputs"]
        roller = SlicedRoller(np.array(inp["x_mm"]), np.array(inp["drop_um"]), 0.0)
        fresh = fit_roller_law(roller, *inp["law"], *inp["loads_n"], inp["points"])._asdict()
        assert fresh.keys() == stored["result"].keys()
        for k, v in stored["result"].items():
            assert math.isclose(fresh[k], v, rel_tol=1e-9, abs_tol=1e-15), (f.name, k, fresh[k], v)
