"""Scenario comparison: the same design at different precision grades (Sun et al. 2014,
section 5, Fig. 4 (a)-(d)), each scenario simulated with the same seed."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping

from rvbacklash.analysis.simulation import DEFAULT_SAMPLES, SimulationResult, simulate
from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.loading import design_from_dict
from rvbacklash.design.schema import OPTIONAL_FACTORS, Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS
from rvbacklash.interrupt import stop_requested
from rvbacklash.problem import Problem, prepare
from rvbacklash.results import Result

STAGE_KEYS = ("involute", "cycloid", "crank")
OVERRIDE_KEYS = STAGE_KEYS + ("all", "edition") + FACTOR_KEYS


@dataclass(frozen=True, repr=False)
class Scenario(Result):
    """A named set of grade overrides: stage keys (involute, cycloid, crank), ``all``, ``edition``
    ("1995" | "2013") or a factor key, each with a grade."""

    name: str
    overrides: Mapping[str, int | str]

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError("scenario.name", self.name, "allowed: a non-empty name")
        if not self.overrides:
            raise InputError(f"scenario {self.name!r}", dict(self.overrides), "allowed: at least one key=grade")
        for key, value in self.overrides.items():
            if key not in OVERRIDE_KEYS:
                raise InputError(f"scenario {self.name!r}", key, f"unknown key; allowed: {', '.join(STAGE_KEYS)}, all, "
                                                                 f"edition, or a factor key")
            if key in OPTIONAL_FACTORS:
                raise InputError(f"scenario {self.name!r}", key, "a designed modification has no grade")
            if key == "edition":
                if value not in ("1995", "2013"):
                    raise InputError(f"scenario {self.name!r}.edition", value, "allowed: 1995, 2013")
            elif isinstance(value, bool) or not isinstance(value, int):
                raise InputError(f"scenario {self.name!r}.{key}", value, "allowed: an integer grade")


def apply_overrides(design: Design, overrides: Mapping[str, int | str]) -> Design:
    """The design with changed grades. A stage grade does not touch explicit zones; a factor
    grade replaces that factor's explicit zone (the scenario names the factor)."""
    data = design.model_dump(exclude_none=True)
    grades = data.setdefault("grades", {})
    factors = data.setdefault("factors", {})
    for key, value in overrides.items():
        if key == "edition":
            grades["edition"] = value
        elif key == "all":
            for s in STAGE_KEYS:
                grades[s] = value
        elif key in STAGE_KEYS:
            grades[key] = value
        else:
            grades.setdefault("factors", {})[key] = value
            zone = factors.get(key)
            if zone is not None:
                for k in ("lower_um", "upper_um", "plus_minus_um", "value_um"):
                    zone.pop(k, None)
                if zone.get("distribution") == "fixed":
                    zone.pop("distribution")
    return design_from_dict(data)


def paper_scenarios(problem: Problem, top: int = 3) -> list[Scenario]:
    """Fig. 4 of Sun et al. 2014: (a) grade 6 in both stages, (b) stage 1 grade 5, (c) stage 2
    grade 5, (d) grade 5 on the ``top`` factors with the largest variance share in (a)."""
    a = {"involute": 6, "cycloid": 6, "crank": 6}
    base = prepare(apply_overrides(problem.design, a))
    graded = [f for f, z in zip(CATALOG, base.zones) if not z.origin.startswith(("explicit", "second_stage"))]
    if not graded:
        raise InputError("paper", problem.name, "no factor takes its tolerance from a grade; give the design a "
                                                "[grades] table (e.g. the rv80e example)")
    shares = {f.key: f.variance_share for f in analyze(base).factors}
    best = sorted(graded, key=lambda f: -shares[f.key])[:top]
    return [
        Scenario("a: grade 6 / 6", a),
        Scenario("b: stage 1 grade 5", {**a, "involute": 5}),
        Scenario("c: stage 2 grade 5", {**a, "cycloid": 5}),
        Scenario(f"d: grade 5 on {', '.join(f.key for f in best)}", {**a, **{f.key: 5 for f in best}}),
    ]


@dataclass(frozen=True, repr=False)
class ScenarioResult(Result):
    name: str
    overrides: Mapping[str, int | str]
    factors_changed: int  # factors whose zone differs from the first scenario's
    result: SimulationResult

    def row(self) -> dict:
        r = self.result
        q = r.quantiles.at(0.99865)
        y = r.yield_
        return {"name": self.name, "factors_changed": self.factors_changed, "mean_arcmin": r.mean_arcmin,
                "sigma_arcmin": r.sigma_arcmin, "q99865_arcmin": q.value, "q99865_ci95_low_arcmin": q.ci95_low,
                "q99865_ci95_high_arcmin": q.ci95_high, "q99865_bounded": q.bounded,
                "yield": y.fraction if y else None,
                "yield_ci95_low": y.ci95_low if y else None, "yield_ci95_high": y.ci95_high if y else None,
                "overrides": ";".join(f"{k}={v}" for k, v in self.overrides.items()),
                "samples_done": r.samples_done, "partial": r.partial}

    def rows(self) -> list[dict]:
        return [self.row()]

    def summary(self) -> list[str]:
        r = self.row()
        return [f"{self.name}: mean {r['mean_arcmin']:.4f}, sigma {r['sigma_arcmin']:.4f}, "
                f"q99.865 {r['q99865_arcmin']:.4f} arcmin"]


@dataclass(frozen=True, repr=False)
class Comparison(Result):
    """The scenarios of one design, simulated alike; iterates over its ScenarioResults."""

    design_name: str
    spec_arcmin: float | None
    model: str
    method: str
    seed: int | None
    samples: int | None
    scenarios: tuple[ScenarioResult, ...]
    partial: bool = False  # interrupted: the last scenario is partial or scenarios are missing
    requested: tuple[str, ...] = field(default_factory=tuple)  # names of every scenario asked for
    _frame_index = "name"

    def __iter__(self):
        return iter(self.scenarios)

    def __len__(self) -> int:
        return len(self.scenarios)

    def __getitem__(self, i: int) -> ScenarioResult:
        return self.scenarios[i]

    def to_dict(self) -> dict:
        return {"design": self.design_name, "spec_arcmin": self.spec_arcmin, "model": self.model,
                "method": self.method, "seed": self.seed, "samples": self.samples, "partial": self.partial,
                "scenarios_requested": list(self.requested),
                "scenarios": [{**s.row(), "overrides": dict(s.overrides)} for s in self.scenarios]}

    def rows(self) -> list[dict]:
        return [s.row() for s in self.scenarios]

    def summary(self) -> list[str]:
        head = f"{self.design_name}: {len(self.scenarios)} scenarios, {self.model} model, method {self.method}"
        if self.partial:
            head += f"  [PARTIAL: {len(self.scenarios)} of {len(self.requested)} scenarios, interrupted]"
        return [head] + [line for s in self.scenarios for line in s.summary()]


def compare(problem: Problem, scenarios: list[Scenario], *, samples: int = DEFAULT_SAMPLES, seed: int = 0,
            method: str = "default", spec_arcmin: float | None = None, model: str = "linear",
            workers: int | None = None, progress: Callable[[int], None] | None = None) -> Comparison:
    """Simulate every scenario with the same samples, seed and method. Ctrl-C stops the whole
    comparison: the scenarios finished so far (the last one possibly partial), marked partial."""
    if not scenarios:
        raise InputError("scenarios", [], "allowed: at least one scenario")
    names = [s.name for s in scenarios]
    if len(set(names)) != len(names):
        raise InputError("scenarios", names, "allowed: distinct scenario names")
    out: list[ScenarioResult] = []
    first_zones = None
    partial = False
    with stop_requested() as stop:
        for sc in scenarios:
            if stop.is_set():
                partial = True
                break
            p = prepare(apply_overrides(problem.design, sc.overrides))
            zones = [(z.lower_um, z.upper_um) for z in p.zones]
            first_zones = first_zones or zones
            changed = sum(a != b for a, b in zip(zones, first_zones))
            r = simulate(p, samples=samples, seed=seed, method=method, spec_arcmin=spec_arcmin, model=model,
                         workers=workers, progress=progress)
            out.append(ScenarioResult(sc.name, dict(sc.overrides), changed, r))
            if r.partial:
                partial = True
                break
    partial = partial or len(out) < len(scenarios)
    return Comparison(problem.name, spec_arcmin, model, method, seed if method != "exact" else None,
                      samples if method != "exact" else None, tuple(out), partial, tuple(names))
