"""Every JSON output carries schema_version and rvbacklash_version and validates against the
schema `rvbacklash schema --output COMMAND` prints, generated from the typed results (issue 18).
The outputs are real: each command's result rendered as the CLI renders it."""

from __future__ import annotations

import json

import jsonschema
import pytest

import rvbacklash as rb
from helpers import run_cli
from rvbacklash.design.sweep_spec import Parameter, SweepSpec
from rvbacklash._version import SCHEMA_VERSION, __version__
from rvbacklash.report.files import render_json
from rvbacklash.report.schemas import OUTPUTS, output_schema


def _outputs():
    p = rb.prepare("rv80e")
    sweep = rb.sweep(SweepSpec(design="rv80e", model="linear", samples=1000, seed=1, name="t", specs={"backlash": 2.0},
                               parameters=[Parameter(path="second_stage.equidistance_modification_um",
                                                     values=[0.0, 4.0])]), scheduler="inline")
    return {
        "analyze": rb.analyze(p),
        "simulate": rb.simulate(p, samples=3000, seed=1, model="elastic",
                                specs={"lost_motion": 1.5, "rigidity": 300.0}),
        "hysteresis": rb.hysteresis(p, points=5),
        "allocate": rb.allocate(p, spec_arcmin=3.0, yield_target=0.99, pareto=False),
        "sensitivity": rb.sensitivity(p, samples=64, resamples=100),
        "sweep": sweep,
        "transmission-error": rb.transmission_error(p, positions=400),
        "contact": rb.contact(p),
        "capacity": rb.capacity(p, angles=6),
        "efficiency": _efficiency(p),
        "assemble": rb.assemble(p, units=rb.generate_batch(p, units=3, seed=1)[0],
                                parts=rb.generate_batch(p, units=3, seed=1)[1], spec_lost_motion_arcmin=1.0)[0],
        "service-life": rb.service_life(p, duty_cycle="robot-joint", hours=[0, 200], samples=50, angles=6),
        **_bench_outputs(p),
    }


def _bench_outputs(p):
    """A measured loop (the model's own, with noise) and TE curve, read and calibrated."""
    import tempfile
    from pathlib import Path

    from rvbacklash.analysis.bench_synthetic import model_loop_samples, te_curve, write_loop_csv, write_te_csv

    folder = Path(tempfile.mkdtemp())
    loop = write_loop_csv(folder / "loop.csv", *model_loop_samples(p, cycles=1, samples_per_branch=60,
                                                                   noise_arcmin=0.01, seed=1))
    te = write_te_csv(folder / "te.tsv", *te_curve({1: 5.0, 40: 1.0}, samples=800, noise_arcsec=0.1))
    return {"bench": rb.read_bench([loop, te], design=p, samples=200),
            "calibrate": rb.calibrate(p, bench=loop, bootstrap=0)}


def _efficiency(p):
    """rv80e's efficiency datasheet with a duty cycle (its thermal balance), on a small grid."""
    from rvbacklash.analysis.losses import efficiency_rating
    from rvbacklash.design.duty_cycle import DutyCycle, DutyStep

    return efficiency_rating(rb.prepare(p), angles=4, torque_fractions=(1.0,), output_speeds_rpm=(15.0,),
                             temperatures_c=(40.0,), input_speeds_rpm=(1000.0,),
                             duty_cycle=DutyCycle("test", (DutyStep(1.0, 15.0, 784.0),)))


@pytest.fixture(scope="module")
def outputs():
    return _outputs()


def test_every_listed_output_has_a_schema():
    from rvbacklash.cli.commands import SchemaOutput

    assert set(OUTPUTS) == {"simulate", "analyze", "hysteresis", "allocate", "sensitivity", "sweep",
                            "transmission-error", "contact", "bench", "calibrate", "capacity",
                            "efficiency", "assemble", "service-life"}
    assert {m.value for m in SchemaOutput} == set(OUTPUTS)  # `schema --output` offers every one


def test_the_commands_without_a_schema_are_known():
    """Every command that writes JSON (--json) has its schema but these, whose JSON is shaped by
    hand (compare, report) or in the command (the tolerance tables): a new command is caught."""
    import typer

    from rvbacklash.cli.entry import app

    def commands(group, prefix=""):
        for name, c in group.commands.items():
            yield from commands(c, f"{name} ") if hasattr(c, "commands") else [(prefix + name, c)]

    with_json = {name for name, c in commands(typer.main.get_command(app))
                 if any("--json" in getattr(p, "opts", ()) for p in c.params)}
    assert with_json - set(OUTPUTS) == {"compare", "report", "tolerance iso1328", "tolerance iso286"}


def test_transmission_error_and_contact_json_validate(tmp_path, rv80e):
    """Regression: `schema --output` had no transmission-error or contact although both commands
    write versioned JSON: their files, as the commands write them, validate against it (contact
    with one unit and with every unit of a measured-unit file)."""
    units = tmp_path / "units.toml"
    pins = ", ".join(["1.0"] * rv80e.second_stage.pins)
    units.write_text(f"[[unit]]\n[unit.pins]\nradius_um = [{pins}]\n" * 2)
    runs = {"transmission-error": [["transmission-error", "rv80e", "--positions", "400"]],
            "contact": [["contact", "rv80e"], ["contact", "rv80e", "--measured", units]]}
    for output, commands in runs.items():
        s = run_cli("schema", "--output", output)
        assert s.returncode == 0, s.stderr
        schema = json.loads(s.stdout)
        jsonschema.Draft202012Validator.check_schema(schema)
        for k, args in enumerate(commands):
            out = tmp_path / f"{output}{k}.json"
            p = run_cli(*args, "--json", out, "-q")
            assert p.returncode == 0, p.stderr
            data = json.loads(out.read_text())
            jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
            if "units" in data:
                assert len(data["units"]) == 2
            data["unexpected"] = 1  # the schema is closed: a field it does not know is refused
            with pytest.raises(jsonschema.ValidationError):
                jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)


@pytest.mark.parametrize("name", sorted(OUTPUTS))
def test_a_real_output_validates_against_its_schema(outputs, name):
    schema = output_schema(name)
    jsonschema.Draft202012Validator.check_schema(schema)
    data = json.loads(render_json(outputs[name].to_dict()))
    assert data["schema_version"] == SCHEMA_VERSION and data["rvbacklash_version"] == __version__
    assert list(data)[:2] == ["schema_version", "rvbacklash_version"]
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)


def test_the_schema_catches_a_moved_field(outputs):
    """A test that cannot fail is a defect: the old simulate layout (figures at the top level) is refused."""
    data = json.loads(render_json(outputs["simulate"].to_dict()))
    data["mean_arcmin"] = data["outputs"].pop("lost_motion")["mean"]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(data, output_schema("simulate"), cls=jsonschema.Draft202012Validator)
    data = json.loads(render_json(outputs["simulate"].to_dict()))
    data["schema_version"] = "1.0"
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(data, output_schema("simulate"), cls=jsonschema.Draft202012Validator)


def test_the_cli_prints_the_schema_and_its_json_validates(tmp_path):
    out = tmp_path / "s.json"
    p = run_cli("simulate", "rv80e", "-n", "2000", "--spec-arcmin", "3", "--json", out, "-q")
    assert p.returncode == 0, p.stderr
    s = run_cli("schema", "--output", "simulate")
    assert s.returncode == 0, s.stderr
    jsonschema.validate(json.loads(out.read_text()), json.loads(s.stdout), cls=jsonschema.Draft202012Validator)
    design = json.loads(run_cli("schema").stdout)  # backward compatible: the design file's schema by default
    assert "schema_version" not in design and "first_stage" in design["properties"]
    bad = run_cli("schema", "--output", "xml")
    assert bad.returncode == 2 and bad.stderr.startswith("error: --output = 'xml'")
