"""The Python API: a design in any form, keyword arguments, typed results that show well in a
notebook, every public name listed."""

import inspect

import pytest

import rvbacklash as rb


def test_every_public_function_is_listed():
    names = dir(rb)
    for name in ("prepare", "analyze", "simulate", "exact", "compare", "paper_scenarios", "contact", "make_report",
                 "render_html", "load_design", "available_examples", "Design", "Problem", "Scenario", "InputError",
                 "SimulationResult", "StackupResult", "__version__"):
        assert name in names and name in rb.__all__ or name == "__version__"
        assert getattr(rb, name) is not None


def test_all_arguments_after_the_design_are_keywords():
    for name in ("analyze", "simulate", "exact", "compare", "contact", "make_report"):
        params = list(inspect.signature(getattr(rb, name)).parameters.values())
        assert params[0].name == "design"
        assert all(p.kind is p.KEYWORD_ONLY for p in params[2 if name == "compare" else 1:]), name


def test_simulate_with_documented_defaults():
    """The issue's example: rb.simulate(rb.load_design("rv80e")) works; defaults 10^6 samples, seed 0."""
    r = rb.simulate(rb.load_design("rv80e"))
    assert (r.samples, r.seed, r.model, r.method) == (1_000_000, 0, "linear", "default")
    frame = r.to_frame()
    assert set(frame["statistic"]) >= {"mean", "sigma", "quantile 0.99865"}
    assert len(repr(r)) < 600 and "<table>" in r._repr_html_()


def test_a_design_in_every_form(tmp_path, rv80e, rv80e_toml):
    f = tmp_path / "d.toml"
    f.write_text(rv80e_toml)
    means = {rb.analyze(x).total.mean_arcmin for x in ("rv80e", f, str(f), rv80e, rb.prepare(rv80e))}
    assert len(means) == 1
    with pytest.raises(rb.InputError, match="allowed: a Design"):
        rb.analyze(42)


def test_library_errors_name_python_parameters():
    """Regression (issue 9): rb.simulate(design) raised '--samples = None'."""
    with pytest.raises(rb.InputError) as e:
        rb.simulate("rv80e", samples=None)
    assert str(e.value).startswith("samples = None: allowed")
    with pytest.raises(rb.InputError) as e:
        rb.contact("rv80e", crank_angle_deg=1e20)
    assert e.value.field == "crank_angle_deg"


def test_a_report_allocates_with_every_model_allocate_has():
    """Regression: `report --allocate-model` refused transmission, which `allocate --model` takes
    (and its help now lists): the check passes it, and the next one speaks."""
    from rvbacklash.analysis.simulation import MODELS

    for model in MODELS:
        with pytest.raises(rb.InputError) as e:
            rb.make_report("rv80e", allocate=True, allocate_model=model, yield_target=0.9)
        assert e.value.field == "spec_arcmin", (model, str(e.value))
    with pytest.raises(rb.InputError) as e:
        rb.make_report("rv80e", allocate=True, allocate_model="gears", yield_target=0.9)
    assert str(e.value) == "allocate_model = 'gears': allowed: linear, contact, elastic or transmission"


def test_py_typed_is_shipped():
    from importlib.resources import files

    assert files("rvbacklash").joinpath("py.typed").is_file()


def test_api_default_samples_is_the_simulations():
    from rvbacklash import api
    from rvbacklash.analysis import simulation

    assert api.DEFAULT_SAMPLES == simulation.DEFAULT_SAMPLES
