"""The workbench's selection card (issue 39, continued): /api/selection answers what `simulate --select
--json` gives for the same design, run and classes (less the two runs' full figures); bad input one
line naming the request's field."""

import json

import pytest
from starlette.testclient import TestClient

from helpers import run_cli
from rvbacklash.app.endpoints import create_app


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app("rv80e")) as c:
        yield c


def test_selection_card_answers_the_clis_json(client):
    body = {"design": "rv80e", "model": "contact", "samples": 500, "seed": 2, "specs": {"arcmin": 1.0},
            "select": "pins=5x2um,rollers=3x2um", "request_id": 7}
    r = client.post("/api/selection", json=body)
    assert r.status_code == 200, r.text
    card = r.json()
    p = run_cli("simulate", "rv80e", "--model", "contact", "-n", "500", "--seed", "2", "--spec-arcmin", "1",
                "--select", "pins=5x2um,rollers=3x2um", "--json", "-")
    assert p.returncode == 0, p.stderr
    theirs = json.loads(p.stdout)
    assert "random_run" not in card and card["yields"] == theirs["yields"] and card["classes"] == theirs["classes"]
    assert card["yields"][0]["selected"]["fraction"] > card["yields"][0]["random"]["fraction"]
    # an edited design is selected as edited; the same request again answers from the cache
    edits = {"second_stage.equidistance_modification_um": 3.0}
    moved = client.post("/api/selection", json={**body, "edits": edits}).json()
    assert moved["yields"][0]["random"] != card["yields"][0]["random"]
    assert client.post("/api/selection", json=body).json() == card


@pytest.mark.parametrize("change, field", [({"select": "pins=5"}, "select"), ({"select": 3}, "select"),
                                           ({"model": "linear"}, "model"), ({"specs": {}}, "specs"),
                                           ({"select": ""}, "select")])
def test_selection_card_bad_input_names_the_field(client, change, field):
    body = {"design": "rv80e", "model": "contact", "samples": 200, "seed": 1, "specs": {"arcmin": 1.0},
            "select": "pins=5x2um", **change}
    r = client.post("/api/selection", json=body)
    assert r.status_code == 422 and r.json()["field"] == field, r.text
    assert "\n" not in r.json()["error"]
