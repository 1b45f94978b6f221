"""The workbench's JSON endpoints answer what the command line writes for the same inputs, bad
input is one line naming the field, bodies are size-limited and no path is ever opened."""

from __future__ import annotations

import asyncio
import json
import tomllib

import pytest
from starlette.testclient import TestClient

from helpers import run_cli
from rvbacklash.app import create_app
from rvbacklash.app.endpoints import MAX_BODY_BYTES
from rvbacklash.design.loading import example_text
from rvbacklash.report.files import render_json


def timeless(data):
    """A JSON output without its wall times (the only numbers two equal runs may differ in)."""
    if isinstance(data, dict):
        return {k: timeless(v) for k, v in data.items() if "elapsed" not in k}
    if isinstance(data, list):
        return [timeless(v) for v in data]
    return data


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app("rv80e")) as c:
        yield c


def cli_json(*args) -> dict:
    p = run_cli(*map(str, args), "--json", "-")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


# (model, samples, the request's specs, the command line's flags for them)
CASES = [
    ("linear", 20000, {"arcmin": 3.0}, ["--spec-arcmin", "3"]),
    ("contact", 2000, {"arcmin": 3.0, "preload_um": 10.0}, ["--spec-arcmin", "3", "--spec-preload-um", "10"]),
    ("elastic", 2000, {"lost_motion_arcmin": 1.5, "rigidity_nm_per_arcmin": 450.0},
     ["--spec-lost-motion-arcmin", "1.5", "--spec-rigidity-nm-per-arcmin", "450"]),
]


@pytest.mark.parametrize("model,samples,specs,flags", CASES, ids=[c[0] for c in CASES])
def test_simulate_answers_the_clis_json(client, model, samples, specs, flags):
    r = client.post("/api/simulate", json={"design": "rv80e", "model": model, "samples": samples, "seed": 1,
                                           "specs": specs, "request_id": 7})
    assert r.status_code == 200, r.text
    assert r.headers["x-request-id"] == "7"
    ours = r.json()
    theirs = cli_json("simulate", "rv80e", "--model", model, "-n", samples, "--seed", 1, *flags)
    assert timeless(ours) == timeless(theirs)
    assert ours["outputs"][next(iter(ours["outputs"]))]["yield"]["fraction"] > 0  # a spec was applied


def test_simulate_csv_is_the_clis_csv(client):
    r = client.post("/api/simulate", json={"design": "sun2014", "samples": 5000, "seed": 3, "specs": {"arcmin": 3},
                                           "format": "csv"})
    p = run_cli("simulate", "sun2014", "-n", "5000", "--seed", "3", "--spec-arcmin", "3", "--csv", "-")
    assert r.status_code == 200 and p.returncode == 0
    drop = lambda text: [row for row in text.splitlines() if "elapsed" not in row]  # noqa: E731
    assert drop(r.text) == drop(p.stdout) and len(drop(r.text)) > 3


def test_an_edited_design_downloads_with_its_comments_and_reruns_on_the_cli(client, tmp_path):
    edits = {"grades.cycloid": 4, "factors.bearing_eccentricity.plus_minus_um": None,
             "factors.bearing_eccentricity.lower_um": -1.0, "factors.bearing_eccentricity.upper_um": 2.5,
             "factors.pin_hole_clearance.lower_um": 0.0, "factors.pin_hole_clearance.upper_um": 6.0}
    r = client.post("/api/design", json={"design": "rv80e", "edits": edits, "format": "toml"})
    assert r.status_code == 200, r.text
    text = r.text
    data = tomllib.loads(text)
    assert data["grades"]["cycloid"] == 4 and data["grades"]["involute"] == 5
    assert data["factors"]["bearing_eccentricity"] == {
        "note": "half the radial run-out of a P5 bearing (ISO 492 class 5), supplier data",
        "lower_um": -1.0, "upper_um": 2.5}
    assert data["factors"]["pin_hole_clearance"] == {"lower_um": 0.0, "upper_um": 6.0}
    original = example_text("rv80e")
    comments = [line.strip() for line in original.splitlines() if line.strip().startswith("#")]
    assert comments and all(c in text for c in comments)  # every comment kept
    # the heading comment of [elastic] still stands right above it (the new keys went before it)
    assert "# docs/elastic.md): input locked, output loaded 0 -> +T_R -> 0 -> -T_R -> 0.\n[elastic]" in text
    path = tmp_path / "edited.toml"
    path.write_text(text)
    page = client.post("/api/simulate", json={"design": "rv80e", "edits": edits, "model": "contact", "samples": 2000,
                                              "seed": 2, "specs": {"arcmin": 3}})
    assert page.status_code == 200
    cli = cli_json("simulate", path, "--model", "contact", "-n", 2000, "--seed", 2, "--spec-arcmin", 3)
    assert timeless(page.json()) == timeless(cli)
    plain = client.post("/api/simulate", json={"design": "rv80e", "model": "contact", "samples": 2000, "seed": 2,
                                               "specs": {"arcmin": 3}}).json()
    assert plain["outputs"]["backlash"]["mean"] != page.json()["outputs"]["backlash"]["mean"]  # the edits count


def test_the_controls_show_every_zone_with_its_origin(client):
    c = client.post("/api/design", json={"design": "rv80e", "edits": {"grades.crank": 7}}).json()
    assert c["name"] == "rv80e" and c["grades"]["crank"] == 7 and c["grades"]["range"] == [0, 12]
    assert set(c["models"]) == {"linear", "contact", "elastic", "transmission"}
    assert len(c["factors"]) == 19 and set(c["modifications"]) == {"second_stage.equidistance_modification_um",
                                                                    "second_stage.moving_distance_modification_um"}
    by_key = {f["key"]: f for f in c["factors"]}
    assert by_key["bearing_eccentricity"]["explicit"] and by_key["bearing_eccentricity"]["upper_um"] == 2.0
    assert "grade 7" in by_key["crank_bearing_clearance"]["origin"] or "IT7" in by_key["crank_bearing_clearance"]["origin"]
    finer = client.post("/api/design", json={"design": "rv80e", "edits": {"grades.crank": 3}}).json()
    fine = {f["key"]: f for f in finer["factors"]}
    assert fine["crank_bearing_clearance"]["upper_um"] - fine["crank_bearing_clearance"]["lower_um"] < \
        by_key["crank_bearing_clearance"]["upper_um"] - by_key["crank_bearing_clearance"]["lower_um"]


def test_a_bad_zone_is_the_clis_one_line(client, tmp_path):
    edits = {"factors.pin_hole_clearance.lower_um": 8.0, "factors.pin_hole_clearance.upper_um": 2.0}
    r = client.post("/api/simulate", json={"design": "rv80e", "edits": edits, "samples": 1000})
    assert r.status_code == 422
    err = r.json()
    assert err["field"] == "factors.pin_hole_clearance" and "\n" not in err["error"]
    assert "lower_um = 8.0 > upper_um = 2.0" in err["error"]
    bad = example_text("rv80e") + "\n[factors.pin_hole_clearance]\nlower_um = 8.0\nupper_um = 2.0\n"
    (tmp_path / "bad.toml").write_text(bad)
    p = run_cli("simulate", tmp_path / "bad.toml", "-n", "1000")
    assert p.returncode == 2 and p.stderr.strip() == "error: " + err["error"]


@pytest.mark.parametrize("body,field,fragment", [
    ({"specs": {"lost_motion_arcmin": 1.0}}, "specs.lost_motion_arcmin", "allowed with --model elastic only"),
    # the request's field, not the API's parameter (spec_arcmin): the page puts the line beside its control
    ({"specs": {"arcmin": -1}}, "specs.arcmin", "specs.arcmin = -1.0: allowed: a finite number > 0"),
    ({"specs": {"wobble": 1}}, "specs", "allowed: an object with keys"),
    ({"samples": 0}, "samples", "allowed: a whole number 1 to"),
    ({"samples": 2.5}, "samples", "allowed: a whole number"),
    ({"seed": -1}, "seed", "allowed: a whole number 0"),
    ({"model": "fem"}, "model", "allowed: linear, contact, elastic, transmission"),
    ({"colour": "red"}, "colour", "unknown field"),
    ({"edits": {"grades.cycloid": 40}}, "grades.cycloid", "allowed"),
    ({"edits": {"../../etc": 1}}, "edits", "dotted path"),
    ({"design": ""}, "design", "allowed: TOML text of a design or a built-in example"),
])
def test_bad_input_names_its_field_in_one_line(client, body, field, fragment):
    r = client.post("/api/simulate", json={"design": "rv80e", "samples": 1000, **body})
    assert r.status_code == 422, r.text
    err = r.json()
    assert err["field"] == field and fragment in err["error"] and "\n" not in err["error"]
    assert "Traceback" not in r.text


@pytest.mark.parametrize("body,field,fragment", [
    ({"spec_arcmin": 3, "yield": 2}, "yield", "yield = 2.0: allowed: a probability 0.5 < P < 1"),
    ({"spec_arcmin": -3, "yield": 0.99}, "spec_arcmin", "spec_arcmin = -3.0: allowed: a finite number > 0"),
    ({"spec_arcmin": 3, "yield": 0.99, "model": "contact", "spec_rigidity_nm_per_arcmin": 400},
     "spec_rigidity_nm_per_arcmin", "spec_rigidity_nm_per_arcmin = 400.0"),
    ({"spec_arcmin": 3, "yield": 0.99, "spec_life_h": 6000}, "spec_life_h",
     "spec_life_h = 6000.0: the life outputs come from the elastic model"),
    ({"spec_arcmin": 3, "yield": 0.99, "model": "elastic", "spec_rated_torque_nm": -1}, "spec_rated_torque_nm",
     "spec_rated_torque_nm = -1.0: allowed: a finite number > 0"),
])
def test_an_allocations_bad_input_names_the_requests_field(client, body, field, fragment):
    """The request's "yield", not the API's yield_target (issue 35, 2.10)."""
    r = client.post("/api/allocate", json={"design": "rv80e", **body})
    assert r.status_code == 422, r.text
    err = r.json()
    assert err["field"] == field and err["error"].startswith(fragment) and "\n" not in err["error"], err


def test_deeply_nested_json_is_the_one_line_refusal(client):
    """100 000 "[" used to end in a RecursionError (HTTP 500, issue 35, 2.5); nesting past what any
    request needs is refused as well, before anything reads it (edits, the cache's key)."""
    for content in (b"[" * 100_000, b'{"design": "rv80e", "edits": {"a": ' + b"[" * 500 + b"]" * 500 + b"}}"):
        r = client.post("/api/simulate", content=content, headers={"Content-Type": "application/json"})
        assert r.status_code == 422, r.text[:300]
        assert r.json() == {"error": "body: nested too deep; allowed: a JSON object nested at most 16 deep",
                            "field": "body"}
    r = client.post("/api/simulate", json={"design": "rv80e", "samples": 1000, "request_id": "x" * 5000})
    assert r.status_code == 422 and r.json()["field"] == "request_id" and "at most 200 characters" in r.json()["error"]


def test_the_body_is_size_limited(client):
    big = {"design": "x" * (MAX_BODY_BYTES + 10)}
    r = client.post("/api/simulate", json=big)
    assert r.status_code == 413 and str(MAX_BODY_BYTES) in r.json()["error"]

    def chunks():  # no Content-Length: counted as it arrives
        for _ in range(40):
            yield b"x" * (MAX_BODY_BYTES // 32)
    r = client.post("/api/simulate", content=chunks(), headers={"Content-Type": "application/json"})
    assert r.status_code == 413
    assert client.post("/api/simulate", content=b"[1, 2]", headers={"Content-Type": "application/json"}
                       ).json()["field"] == "body"
    # a form another site's page could post without asking: refused before anything runs
    r = client.post("/api/simulate", content=b'{"design": "rv80e"}', headers={"Content-Type": "text/plain"})
    assert r.status_code == 422 and r.json()["field"] == "Content-Type"


def test_no_path_is_ever_opened(client, tmp_path):
    path = tmp_path / "design.toml"
    path.write_text(example_text("rv80e"))
    for design in (str(path), path.as_uri(), "rv80e.toml", "../examples/rv80e.toml"):
        r = client.post("/api/design", json={"design": design, "origin": str(path)})
        assert r.status_code == 422 and "malformed TOML" in r.json()["error"], design
    # the same text sent as text is a design
    assert client.post("/api/design", json={"design": path.read_text(), "origin": "mine.toml"}).status_code == 200


def test_an_upload_that_is_not_a_design_gets_the_clis_message(client, tmp_path):
    path = tmp_path / "notes.toml"
    path.write_text("this is not [ a design\n")
    r = client.post("/api/design", json={"design": path.read_text(), "origin": str(path)})
    p = run_cli("simulate", path, "-n", "100")
    assert r.status_code == 422 and p.returncode == 2
    assert p.stderr.strip() == "error: " + r.json()["error"]


def test_hysteresis_te_sensitivity_and_allocate_answer_the_clis_json(client):
    h = client.post("/api/hysteresis", json={"design": "rv80e", "points": 21})
    assert h.status_code == 200
    assert timeless(h.json()) == timeless(cli_json("hysteresis", "rv80e", "--points", 21))
    section = client.post("/api/elastic-section", json={"design": "rv80e", "samples": 200, "seed": 1})
    assert section.status_code == 200
    from rvbacklash.api import elastic_section

    assert timeless(section.json()) == timeless(json.loads(render_json(elastic_section("rv80e", samples=200, seed=1)
                                                                       .to_dict())))
    assert set(section.json()["quantile_units"]) == {"5 %", "95 %"}
    te = client.post("/api/transmission-error", json={"design": "rv80e", "positions": 400})
    assert te.status_code == 200
    assert timeless(te.json()) == timeless(cli_json("transmission-error", "rv80e", "--positions", 400))
    s = client.post("/api/sensitivity", json={"design": "rv80e", "samples": 256, "seed": 4, "request_id": "sobol-1"})
    assert s.status_code == 200
    assert timeless(s.json()) == timeless(cli_json("sensitivity", "rv80e", "-n", 256, "--seed", 4))
    assert client.get("/api/progress", params={"id": "sobol-1"}).json()["state"] == "finished"
    a = client.post("/api/allocate", json={"design": "rv80e", "spec_arcmin": 3, "yield": 0.99})
    assert a.status_code == 200
    assert timeless(a.json()) == timeless(cli_json("allocate", "rv80e", "--spec-arcmin", 3, "--yield", 0.99))


def test_a_newer_request_supersedes_an_older_one_on_its_channel():
    import httpx2

    async def main():
        app = create_app("rv80e")
        transport = httpx2.ASGITransport(app=app)
        async with httpx2.AsyncClient(transport=transport, base_url="http://wb") as c:
            slow = asyncio.create_task(c.post("/api/simulate", json={
                "design": "rv80e", "model": "contact", "samples": 400_000, "seed": 1, "request_id": 1,
                "channel": "page"}))
            await asyncio.sleep(0.3)  # the slow one is running
            fast = await c.post("/api/simulate", json={"design": "sun2014", "samples": 1000, "seed": 1,
                                                        "request_id": 2, "channel": "page"})
            old = await slow
            other = await c.post("/api/simulate", json={"design": "sun2014", "samples": 1000, "request_id": 3})
            return old, fast, other, app.state.jobs.active()

    old, fast, other, active = asyncio.run(main())
    assert old.status_code == 409 and old.json()["superseded"] and "request 2" in old.json()["error"]
    assert old.headers["x-request-id"] == "1"
    assert fast.status_code == 200 and fast.headers["x-request-id"] == "2" and fast.json()["samples_done"] == 1000
    assert other.status_code == 200 and active == 0  # no channel: nothing superseded, nothing left running


def test_the_page_and_its_scripts_are_served_from_the_package(client):
    page = client.get("/")
    assert page.status_code == 200 and "/static/plotly.min.js" in page.text
    assert "http://" not in page.text and "https://" not in page.text  # nothing from a CDN
    js = client.get("/static/plotly.min.js")
    assert js.status_code == 200 and len(js.content) > 1_000_000
    assert client.get("/static/workbench.js").status_code == 200
    assert client.get("/api/initial").json() == {"design": "rv80e", "origin": None}


def test_an_on_demand_job_shows_its_progress_and_can_be_cancelled():
    import httpx2

    async def main():
        app = create_app("rv80e")
        async with httpx2.AsyncClient(transport=httpx2.ASGITransport(app=app), base_url="http://wb") as c:
            job = asyncio.create_task(c.post("/api/sensitivity", json={
                "design": "rv80e", "model": "contact", "samples": 1 << 14, "request_id": "sobol-9"}))
            seen = None
            for _ in range(600):  # until it has done some of its model runs
                await asyncio.sleep(0.05)
                p = await c.get("/api/progress", params={"id": "sobol-9"})
                if p.status_code == 200 and p.json()["done"] > 0:
                    seen = p.json()
                    break
            cancel = await c.post("/api/cancel", json={"id": "sobol-9"})
            answer = await job
            after = (await c.get("/api/progress", params={"id": "sobol-9"})).json()
            return seen, cancel, answer, after, app.state.jobs.active()

    seen, cancel, answer, after, active = asyncio.run(main())
    assert seen is not None and seen["state"] == "running" and 0 < seen["done"] < seen["total"]
    assert seen["total"] == (1 << 14) * (19 + 2)  # N (D + 2) model runs, as the command line counts them
    assert cancel.status_code == 200 and answer.status_code == 409 and answer.json()["superseded"]
    assert after["state"] == "cancelled" and active == 0


def test_the_report_downloads_as_html(client):
    r = client.post("/api/report", json={"design": "sun2014", "samples": 2000, "seed": 1, "specs": {"arcmin": 3}})
    assert r.status_code == 200 and r.text.startswith("<!DOCTYPE html>")
    assert "attachment" in r.headers["content-disposition"] and "sun2014" in r.text


def test_the_capacity_card_answers_the_clis_json_and_the_trade(client):
    """The card's datasheet is `rvbacklash capacity --json` (less the loads over a revolution); its point of
    lost motion against life is the API's capacity_trade of the edited design alone."""
    import rvbacklash as rb
    from rvbacklash.app.designs import edited_text

    edits = {"second_stage.equidistance_modification_um": 2.0}
    r = client.post("/api/capacity", json={"design": "rv80e", "edits": edits, "request_id": 5})
    assert r.status_code == 200, r.text
    card = r.json()
    text = edited_text(example_text("rv80e"), edits)
    theirs = rb.capacity(rb.load_design("rv80e").model_validate(tomllib.loads(text))).to_dict()
    theirs.pop("loads")
    assert card["capacity"] == json.loads(render_json({"capacity": theirs}))["capacity"]
    assert card["schema_version"] and card["rvbacklash_version"]
    point = card["trade"]["points"][0]
    assert point["equidistance_modification_um"] == 2.0 and card["trade"]["points"][0]["edits"] == {}
    alone = rb.capacity_trade(rb.load_design("rv80e").model_validate(tomllib.loads(text)), what_ifs=()).points[0]
    assert point["lost_motion_arcmin"] == alone.lost_motion_arcmin
    assert point["reducer_life_h"] == alone.reducer_life_h
    assert card["capacity"]["limiting_element"] and card["capacity"]["main_bearings"]["allowable_moment_nm"] > 0
    # bad input: one line naming the request's field; a design without [structure] says so
    bad = client.post("/api/capacity", json={"design": "rv80e", "angles": 0})
    assert bad.status_code == 422 and bad.json()["field"] == "angles"
    none = client.post("/api/capacity", json={"design": "sun2014"})
    assert none.status_code == 422 and none.json()["field"] in ("elastic", "structure"), none.text


def test_the_efficiency_cards_answer_the_clis_json(client):
    """The efficiency and temperature cards (issue 40): `rvbacklash efficiency --json --duty-cycle robot-joint`
    of the edited design; bad input names the request's field."""
    import rvbacklash as rb

    r = client.post("/api/efficiency", json={"design": "rv80e", "request_id": 7})
    assert r.status_code == 200, r.text
    card = r.json()
    theirs = json.loads(render_json(rb.efficiency("rv80e", duty_cycle="robot-joint").to_dict()))
    for k in ("efficiency_at_rated", "starting_torque_nm", "contacts_loop_friction_at_rated_nm", "elements"):
        assert card[k] == theirs[k], k
    assert card["thermal"]["steady_temperature_c"] == theirs["thermal"]["steady_temperature_c"]
    # the temperature card's TE at the steady temperature (and the reference's beside it) is the CLI's
    hot, ref = card["thermal"]["precision"][-1], card["thermal"]["precision"][0]
    assert hot["temperature_c"] == card["thermal"]["steady_temperature_c"]
    assert hot["te_peak_to_peak_arcsec"] == theirs["thermal"]["precision"][-1]["te_peak_to_peak_arcsec"] > 0.0
    assert ref["te_peak_to_peak_arcsec"] == theirs["thermal"]["precision"][0]["te_peak_to_peak_arcsec"]
    bad = client.post("/api/efficiency", json={"design": "rv80e", "duty_cycle": "../etc/passwd"})
    assert bad.status_code == 422 and bad.json()["field"] == "duty_cycle"
