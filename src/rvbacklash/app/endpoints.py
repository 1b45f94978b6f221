"""The workbench's JSON endpoints and its page (docs/workbench.md lists them with their bodies).

Every endpoint runs the API the command line runs and renders its result with the same function
(``render_json(result.to_dict())``): ``POST /api/simulate`` answers exactly what ``rvbacklash
simulate --json`` writes for the same design, model, samples, seed and specs. Bad input is one
line (``{"error": "<field> = <value>: <allowed>", "field": ...}``, HTTP 422), as the command line
prints it; a body larger than ``MAX_BODY_BYTES`` is refused (413) before it is read whole.
"""

from __future__ import annotations

import asyncio
import contextlib
import importlib.util
import json
from collections import OrderedDict
from importlib import resources
from pathlib import Path
from threading import Lock
from typing import Any, Callable

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import ClientDisconnect, Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

import rvbacklash.api as api
from rvbacklash.app.designs import MODELS, DesignCache, EditedDesign, controls
from rvbacklash.app.jobs import Cancelled, Job, Jobs, client_watched
from rvbacklash.app.requests import (MAX_BODY_BYTES, REQUEST_FIELDS, BodyTooLarge, check_fields, choice,
                                     number_or_none, read_body, samples, simulation_inputs, whole)
from rvbacklash.design.loading import available_examples
from rvbacklash.errors import InputError
from rvbacklash.interrupt import stop_on
from rvbacklash.report.files import render_csv, render_json

LIFE_HOURS = (0, 500, 1000, 2000, 4000, 6000)  # the service-life card's hours unless the request gives its own
MAX_POSITIONS = 4096  # of a TE curve in the workbench: ~1 s of one thread (65 536: ~15 s, not cancellable)


class Results:
    """The last rendered results by their inputs: going back to an earlier input answers at once
    (same inputs, same seed: the same numbers)."""

    def __init__(self, size: int = 16):
        self._items: OrderedDict[str, str] = OrderedDict()
        self._size, self._lock = size, Lock()

    def get(self, key: str) -> str | None:
        with self._lock:
            if key in self._items:
                self._items.move_to_end(key)
            return self._items.get(key)

    def put(self, key: str, value: str) -> None:
        with self._lock:
            self._items[key] = value
            while len(self._items) > self._size:
                self._items.popitem(last=False)


def plotly_js() -> Path:
    """plotly.min.js as the plotly wheel ships it (served from the installed package: no CDN)."""
    spec = importlib.util.find_spec("plotly")
    if spec is None or not spec.submodule_search_locations:
        raise RuntimeError("the plotly package is missing: pip install plotly")
    return Path(next(iter(spec.submodule_search_locations))) / "package_data" / "plotly.min.js"


def create_app(initial_design: str = "rv80e", initial_origin: str | None = None,
               allowed_hosts: list[str] | None = None, warm: bool = False) -> Starlette:
    """The workbench as an ASGI application. ``initial_design``: the example name or TOML text
    the page opens with; ``allowed_hosts``: the Host headers accepted (None: any; the server
    gives the loopback names when it listens on loopback, against DNS rebinding); ``warm``: load
    the models' kernels in the background at start-up."""
    designs, results, jobs = DesignCache(), Results(), Jobs()
    capacity_cache: dict[str, dict] = {}  # the capacity card's datasheets by design text (its pool's one thread)

    def error(e: Exception, status: int = 422, **extra) -> JSONResponse:
        return JSONResponse({"error": str(e), **extra}, status_code=status)

    def endpoint(fields: set[str] | None = None, name: str = ""):
        """A POST handler: body read and checked, bad input as one line naming the request's field,
        superseded or cancelled as 409; a client that goes away cancels its jobs."""
        renamed = REQUEST_FIELDS.get(name, {})

        def wrap(fn):
            async def handler(request: Request) -> Response:
                body: dict = {}
                try:
                    body = await read_body(request)
                    if fields is not None:
                        check_fields(body, fields)
                    async with client_watched(request):
                        response = await fn(body)
                except ClientDisconnect:  # gone before its body was in: nothing started, nobody to answer
                    return Response(status_code=400)
                except asyncio.CancelledError:  # the server stops and would not wait longer (its job is cancelled)
                    return JSONResponse({"error": "request: the workbench is stopping"}, status_code=503)
                except BodyTooLarge as e:
                    return JSONResponse({"error": f"body = {e.args[0]} bytes: allowed: at most {MAX_BODY_BYTES} bytes"},
                                        status_code=413)
                except InputError as e:
                    e = e.renamed(renamed.get(e.field, e.field))
                    response = error(e, field=e.field)
                except Cancelled as e:
                    response = JSONResponse({"error": f"request {e.job.id}: {e.job.reason}", "superseded": True},
                                            status_code=409)
                if "request_id" in body:
                    response.headers["X-Request-Id"] = str(body["request_id"])[:100]
                return response
            return handler
        return wrap

    def design_of(body: dict) -> EditedDesign:
        return designs.get(body.get("design"), body.get("edits"), body.get("origin"))

    async def run(body: dict, compute: Callable[[Job], Any], pool: str = "live", total: int | None = None):
        _, value = await jobs.run(compute, job_id=body.get("request_id"), channel=body.get("channel"), pool=pool,
                                  total=total)
        return value

    @endpoint({"format"})
    async def design(body: dict) -> Response:
        item = await run(body, lambda job: design_of(body), pool="design")
        if body.get("format") == "toml":
            return Response(item.text, media_type="application/toml")
        return JSONResponse(controls(item))

    @endpoint(name="simulate")
    async def simulate(body: dict) -> Response:
        inputs = simulation_inputs(body)
        fmt = choice(body, "format", "json", ("json", "csv"))

        def compute(job: Job) -> str:
            item = design_of(body)
            key = json.dumps([item.text, inputs, fmt], sort_keys=True)
            cached = results.get(key)
            if cached is not None:
                return cached
            result = api.simulate(item.problem, progress=job.progress, **inputs)
            text = render_json(result.to_dict()) if fmt == "json" else render_csv(result.rows())
            if not result.partial:
                results.put(key, text)
            return text

        text = await run(body, compute, total=inputs["samples"])
        return Response(text, media_type="application/json" if fmt == "json" else "text/csv")

    @endpoint(name="selection")
    async def selection(body: dict) -> Response:
        """The selection card (docs/selective-assembly.md): the run's units assembled at random and with
        ``select`` (the ``--select`` string; the design's [selection] table when left out), side by side:
        ``simulate --select --json`` without the two runs' full figures, cached by the design's text."""
        text = body.get("select")
        if text is not None and not isinstance(text, str):
            raise InputError("select", text, "allowed: a string such as 'pins=5x2um,rollers=3x2um'")
        inputs = simulation_inputs({k: v for k, v in body.items() if k != "select"})
        inputs.pop("method", None)

        def compute(job: Job) -> str:
            from rvbacklash.analysis.selection.classes import resolve_selection

            item = design_of(body)
            try:
                chosen = resolve_selection(text if text and text.strip() else None, item.problem.design, "select")
            except InputError as e:  # "select pins": the page's control is "select"
                raise (e.renamed("select") if e.field.startswith("select ") else e) from None
            if chosen is None:
                raise InputError("select", text, "allowed: pins=COUNTxWIDTHum[,rollers=...] (the design has no "
                                                 "[selection] table)")
            if inputs["model"] not in ("contact", "elastic", "transmission"):
                raise InputError("model", inputs["model"], "allowed with selection: contact, elastic, transmission")
            if not inputs["specs"] and inputs["spec_arcmin"] is None:
                raise InputError("specs", None, "selection compares yields: allowed: a spec of the model's outputs")
            key = json.dumps(["selection", item.text, str(chosen), inputs], sort_keys=True, default=str)
            cached = results.get(key)
            if cached is not None:
                return cached
            result = api.simulate_selected(item.problem, select=chosen, progress=job.progress, **inputs)
            data = result.to_dict()
            for run in ("random_run", "selected_run"):
                data.pop(run)
            out = render_json(data)
            if not result.partial:
                results.put(key, out)
            return out

        return Response(await run(body, compute, total=2 * inputs["samples"]), media_type="application/json")

    def rendered(result) -> Response:
        return Response(render_json(result.to_dict()), media_type="application/json")

    @endpoint({"points"})
    async def hysteresis(body: dict) -> Response:
        points = whole(body, "points", 41, 5, 1001)
        return rendered(await run(body, lambda job: api.hysteresis(design_of(body).problem, points=points),
                                  pool="figures"))

    @endpoint({"angles"})
    async def capacity(body: dict) -> Response:
        """The capacity card (docs/workbench.md): the edited design's capacity datasheet (``rvbacklash
        capacity --json``) and its point of lost motion against life (``capacity_trade``, the design
        alone), cached by the design's text: a what-if seen before answers at once."""
        angles = whole(body, "angles", 24, 1, 64, " in the workbench (the command line: --angles up to 4096)")

        def compute(job: Job) -> str:
            item = design_of(body)
            key = json.dumps(["capacity", item.text, angles])
            cached = results.get(key)
            if cached is not None:
                return cached
            # each half kept as it finishes: a superseded request's datasheet (which no stop interrupts)
            # serves the request that superseded it
            rating = capacity_cache.get(key)
            if rating is None:
                rating = api.capacity(item.problem, angles=angles).to_dict()
                rating.pop("loads", None)  # the loads over a revolution: the command line's --json has them
                capacity_cache[key] = rating
                while len(capacity_cache) > 16:
                    capacity_cache.pop(next(iter(capacity_cache)))
            job.check()
            trade = api.capacity_trade(item.problem, what_ifs=(), angles=angles)
            text = render_json({"capacity": rating, "trade": trade.to_dict()})
            results.put(key, text)
            return text

        return Response(await run(body, compute, pool="capacity"), media_type="application/json")

    @endpoint({"duty_cycle"})
    async def efficiency(body: dict) -> Response:
        """The efficiency and temperature cards (docs/workbench.md): the edited design's efficiency datasheet
        (``rvbacklash efficiency --json [--duty-cycle NAME]``) with a packaged duty cycle's thermal balance
        (``duty_cycle``: its name, default robot-joint; "" none), cached by the design's text."""
        cycle = body.get("duty_cycle", "robot-joint")
        if not isinstance(cycle, str) or len(cycle) > 100 or "/" in cycle or "\\" in cycle:
            raise InputError("duty_cycle", cycle, "allowed: the name of a packaged duty cycle, or \"\" for none")

        def compute(job: Job) -> str:
            item = design_of(body)
            key = json.dumps(["efficiency", item.text, cycle])
            cached = results.get(key)
            if cached is None:
                cached = render_json(api.efficiency(item.problem, duty_cycle=cycle or None).to_dict())
                results.put(key, cached)
            return cached

        return Response(await run(body, compute, pool="capacity"), media_type="application/json")

    @endpoint({"duty_cycle", "hours", "samples", "seed", "spec_lost_motion_arcmin"})
    async def service_life(body: dict) -> Response:
        """The service-life card (docs/workbench.md): the edited design's precision over the hours of a
        packaged duty cycle (``duty_cycle``, default robot-joint): ``rvbacklash service-life --json`` for
        the same hours, units, seed and lost-motion spec, cached by the design's text."""
        cycle = body.get("duty_cycle", "robot-joint")
        if not isinstance(cycle, str) or not cycle or len(cycle) > 100 or "/" in cycle or "\\" in cycle:
            raise InputError("duty_cycle", cycle, "allowed: the name of a packaged duty cycle (robot-joint)")
        hours = body.get("hours", list(LIFE_HOURS))
        if not isinstance(hours, list) or not 1 <= len(hours) <= 24 or \
                any(isinstance(h, bool) or not isinstance(h, (int, float)) for h in hours):
            raise InputError("hours", hours, "allowed: a list of 1 to 24 numbers of hours, e.g. [0, 1000, 6000]")
        n = samples(body, "service-life", "elastic", 500, 0)
        seed = whole(body, "seed", 0, 0, 2**63 - 1)
        spec = number_or_none(body, "spec_lost_motion_arcmin")
        spec = 1.5 if spec is None else spec

        def compute(job: Job) -> str:
            item = design_of(body)
            key = json.dumps(["service-life", item.text, cycle, hours, n, seed, spec])
            cached = results.get(key)
            if cached is not None:
                return cached

            def progress(stage: str, share: float) -> None:
                job.progress(int(500 * share) + (500 if stage == "units" else 0) if n else int(1000 * share))

            result = api.service_life(item.problem, duty_cycle=cycle, hours=hours, samples=n, seed=seed,
                                      spec_lost_motion_arcmin=spec, progress=progress)
            text = render_json(result.to_dict())
            if not result.partial:
                results.put(key, text)
            return text

        return Response(await run(body, compute, pool="capacity", total=1000), media_type="application/json")

    @endpoint({"samples", "seed"})
    async def elastic_section(body: dict) -> Response:
        n = samples(body, "elastic-section", "elastic", 2000, 20)
        seed = whole(body, "seed", 0, 0, 2**63 - 1)
        return rendered(await run(body, lambda job: api.elastic_section(design_of(body).problem, samples=n, seed=seed),
                                  pool="figures"))

    @endpoint({"positions", "load_direction"})
    async def transmission_error(body: dict) -> Response:
        positions = whole(body, "positions", 1024, 1, MAX_POSITIONS, " in the workbench (the command line has no limit)")
        direction = choice(body, "load_direction", "ccw", ("ccw", "cw"))
        return rendered(await run(body, lambda job: api.transmission_error(
            design_of(body).problem, positions=positions, load_direction=direction), pool="figures"))

    @endpoint({"model", "output", "samples", "seed"})
    async def sensitivity(body: dict) -> Response:
        model = choice(body, "model", "linear", MODELS)
        n = samples(body, "sensitivity", model, api.SENSITIVITY_SAMPLES, 64)  # 64: the Sobol run's least N
        seed = whole(body, "seed", 0, 0, 2**63 - 1)
        output = body.get("output")
        def compute(job: Job):
            problem = design_of(body).problem
            job.total = n * (int(problem.random_mask.sum()) + 2)  # model runs, as the command line counts them
            return api.sensitivity(problem, model=model, output=output, samples=n, seed=seed, progress=job.progress)

        return rendered(await run(body, compute, pool="demand"))

    @endpoint({"model", "spec_arcmin", "yield", "spec_rigidity_nm_per_arcmin", "spec_preload_um", "spec_te_arcsec",
               "spec_life_h", "spec_rated_torque_nm", "samples", "seed"}, name="allocate")
    async def allocate(body: dict) -> Response:
        model = choice(body, "model", "linear", MODELS)
        spec = number_or_none(body, "spec_arcmin")
        target = number_or_none(body, "yield")
        if spec is None or target is None:
            raise InputError("spec_arcmin" if spec is None else "yield", allowed="allowed: a number; an allocation "
                                                                                 "needs spec_arcmin and yield")
        kwargs = {"spec_rigidity_nm_per_arcmin": number_or_none(body, "spec_rigidity_nm_per_arcmin"),
                  "spec_preload_um": number_or_none(body, "spec_preload_um"),
                  "spec_te_arcsec": number_or_none(body, "spec_te_arcsec"),
                  "spec_life_h": number_or_none(body, "spec_life_h"),
                  "spec_rated_torque_nm": number_or_none(body, "spec_rated_torque_nm"),
                  "seed": whole(body, "seed", 0, 0, 2**63 - 1)}
        if model != "linear":  # the linear model's allocation is exact: no samples
            kwargs["samples"] = samples(body, "allocate", model, api.ALLOCATION_SAMPLES, 1000)
        return rendered(await run(body, lambda job: api.allocate(
            design_of(body).problem, spec_arcmin=spec, yield_target=target, model=model, progress=job.progress,
            **kwargs), pool="demand", total=None if model == "linear" else 200))

    @endpoint(name="report")
    async def report(body: dict) -> Response:
        inputs = simulation_inputs(body)
        if choice(body, "format", "html", ("html",)) != "html":  # pragma: no cover - one format
            raise InputError("format", body["format"], "allowed: html")
        from rvbacklash.report.html import render_html  # (seconds the first time: after the checks)
        te = inputs["specs"].pop("transmission_error", None)

        def compute(job: Job) -> str:
            data = api.make_report(design_of(body).problem, samples=inputs["samples"], seed=inputs["seed"],
                                   method=inputs["method"], spec_arcmin=inputs["spec_arcmin"],
                                   specs=inputs["specs"] or None, model=inputs["model"], spec_te_arcsec=te,
                                   progress=job.progress)
            job.check()  # cancelled while the report's later sections ran: no rendering
            return render_html(data)

        html = await run(body, compute, pool="demand", total=inputs["samples"])
        return Response(html, media_type="text/html",
                        headers={"Content-Disposition": 'attachment; filename="report.html"'})

    @endpoint({"id"})
    async def cancel(body: dict) -> Response:
        job = jobs.cancel(str(body.get("id")))
        if job is None:
            raise InputError("id", body.get("id"), "allowed: the id of a running job")
        return JSONResponse(job.to_dict())

    async def progress(request: Request) -> Response:
        job = jobs.get(request.query_params.get("id", ""))
        if job is None:
            return JSONResponse({"error": f"id = {request.query_params.get('id')!r}: allowed: a known job id"},
                                status_code=404)
        return JSONResponse(job.to_dict())

    async def status(request: Request) -> Response:
        return JSONResponse({"active_jobs": jobs.active(), "examples": list(available_examples())})

    async def initial(request: Request) -> Response:
        return JSONResponse({"design": initial_design, "origin": initial_origin})

    async def index(request: Request) -> Response:
        return Response(resources.files("rvbacklash.app").joinpath("static/index.html").read_text(encoding="utf-8"),
                        media_type="text/html")

    async def favicon(request: Request) -> Response:
        return Response(status_code=204)

    async def plotly(request: Request) -> Response:
        return FileResponse(plotly_js(), media_type="text/javascript")

    posts = {"design": design, "simulate": simulate, "hysteresis": hysteresis, "elastic-section": elastic_section,
             "capacity": capacity, "efficiency": efficiency, "service-life": service_life, "selection": selection,
             "transmission-error": transmission_error, "sensitivity": sensitivity, "allocate": allocate,
             "report": report, "cancel": cancel}
    routes = [Route("/", index), Route("/api/initial", initial), Route("/api/status", status),
              Route("/api/progress", progress), Route("/static/plotly.min.js", plotly),
              Route("/favicon.ico", favicon),
              *(Route(f"/api/{name}", fn, methods=["POST"]) for name, fn in posts.items()),
              Mount("/static", StaticFiles(packages=[("rvbacklash.app", "static")]))]
    middleware = [Middleware(TrustedHostMiddleware, allowed_hosts=allowed_hosts)] if allowed_hosts else []
    def warm_up() -> None:
        """Load the kernels of every model the first design runs (numba's cache: seconds, the first
        time ever a minute) before the first change asks for them."""
        try:
            item = designs.get(initial_design, None, initial_origin)
            with stop_on(jobs.stopping):  # Ctrl-C during the warm-up: its runs stop as a job's do
                for m in controls(item)["models"]:
                    if jobs.stopping.is_set():  # and no next model starts
                        return
                    api.simulate(item.problem, model=m, samples=256, seed=0)
            if item.problem.design.elastic is not None and not jobs.stopping.is_set():
                api.hysteresis(item.problem)
        except Exception:  # the page reports a bad design itself; a warm-up never stops the server
            pass

    @contextlib.asynccontextmanager
    async def lifespan(app):
        if warm:
            jobs.background(warm_up)
        yield
        jobs.shutdown(timeout_s=2.0)  # every job cancelled, the worker threads stopped (a few seconds at most)

    application = Starlette(routes=routes, middleware=middleware, lifespan=lifespan)
    application.state.jobs = jobs
    return application
