"""Scenario comparison: the same design at different precision grades (Sun et al. 2014,
section 5, Fig. 4 (a)-(d)), each scenario simulated with the same seed."""

from __future__ import annotations

from dataclasses import dataclass

from rvbacklash.analysis.simulation import SimulationResult, simulate
from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.derived import resolve_zones
from rvbacklash.design.loading import design_from_dict
from rvbacklash.design.schema import OPTIONAL_FACTORS, Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS

STAGE_KEYS = ("involute", "cycloid", "crank")


def parse_scenario(text: str) -> tuple[str, dict[str, int | str]]:
    """'NAME:key=value,key=value' -> (NAME, {key: value}). Keys: involute, cycloid, crank, all,
    edition, or a factor key; values: grades (edition: 1995 | 2013)."""
    name, sep, body = text.partition(":")
    if not sep or not name.strip():
        raise InputError("--scenario", text, "allowed: NAME:key=grade[,key=grade...], e.g. b:involute=5")
    overrides: dict[str, int | str] = {}
    for item in filter(None, (p.strip() for p in body.split(","))):
        key, eq, value = item.partition("=")
        key = key.strip()
        if not eq:
            raise InputError("--scenario", text, f"'{item}' is not key=value")
        if key not in STAGE_KEYS + ("all", "edition") + FACTOR_KEYS:
            raise InputError("--scenario", text, f"unknown key '{key}'; allowed: {', '.join(STAGE_KEYS)}, all, "
                                                 f"edition, or a factor key ({', '.join(FACTOR_KEYS)})")
        if key == "edition":
            overrides[key] = value.strip()
            continue
        try:
            overrides[key] = int(value)
        except ValueError:
            raise InputError("--scenario", text, f"grade of '{key}' must be an integer, got '{value.strip()}'") from None
    return name.strip(), overrides


def apply_overrides(design: Design, overrides: dict[str, int | str]) -> Design:
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
            if key in OPTIONAL_FACTORS:
                raise InputError("--scenario", key, "a designed modification has no grade")
            grades.setdefault("factors", {})[key] = value
            zone = factors.get(key)
            if zone is not None:
                for k in ("lower_um", "upper_um", "plus_minus_um", "value_um"):
                    zone.pop(k, None)
                if zone.get("distribution") == "fixed":
                    zone.pop("distribution")
    return design_from_dict(data)


def paper_scenarios(design: Design, top: int = 3) -> list[tuple[str, dict]]:
    """Fig. 4 of Sun et al. 2014: (a) grade 6 in both stages, (b) stage 1 grade 5, (c) stage 2
    grade 5, (d) grade 5 on the ``top`` factors with the largest variance share in (a)."""
    a = {"involute": 6, "cycloid": 6, "crank": 6}
    base = apply_overrides(design, a)
    graded = [f for f, z in zip(CATALOG, resolve_zones(base)) if not z.origin.startswith(("explicit", "second_stage"))]
    if not graded:
        raise InputError("--paper", design.name, "no factor takes its tolerance from a grade; give the design a "
                                                 "[grades] table (e.g. the rv80e example)")
    shares = {f.key: f.variance_share for f in analyze(base).factors}
    best = sorted(graded, key=lambda f: -shares[f.key])[:top]
    return [
        ("a: grade 6 / 6", a),
        ("b: stage 1 grade 5", {**a, "involute": 5}),
        ("c: stage 2 grade 5", {**a, "cycloid": 5}),
        (f"d: grade 5 on {', '.join(f.key for f in best)}", {**a, **{f.key: 5 for f in best}}),
    ]


@dataclass
class ScenarioResult:
    name: str
    overrides: dict
    tightened: int  # factors whose zone differs from the first scenario's
    result: SimulationResult

    def to_dict(self) -> dict:
        s = self.result.stats
        return {"name": self.name, "overrides": self.overrides, "factors_changed": self.tightened,
                "mean_arcmin": s["mean_arcmin"], "sigma_arcmin": s["std_arcmin"],
                "q99865_arcmin": s["quantiles"]["0.99865"]["value"],
                "q99865_ci95": s["quantiles"]["0.99865"]["ci95"], "yield": s["yield"],
                "method": self.result.method, "samples": self.result.samples, "seed": self.result.seed}


@dataclass
class Comparison:
    """The scenarios of one design, simulated alike; iterates over its ScenarioResults."""

    design_name: str
    spec_arcmin: float | None
    scenarios: list[ScenarioResult]

    def __iter__(self):
        return iter(self.scenarios)

    def __len__(self) -> int:
        return len(self.scenarios)

    def __getitem__(self, i: int) -> ScenarioResult:
        return self.scenarios[i]

    def to_dict(self) -> dict:
        return {"design": self.design_name, "spec_arcmin": self.spec_arcmin,
                "scenarios": [s.to_dict() for s in self.scenarios]}

    def rows(self) -> list[dict]:
        out = []
        for s in self.scenarios:
            d = s.to_dict()
            y = d["yield"] or {"fraction": None, "ci95": [None, None]}
            out.append({"name": d["name"], "factors_changed": d["factors_changed"], "mean_arcmin": d["mean_arcmin"],
                        "sigma_arcmin": d["sigma_arcmin"], "q99865_arcmin": d["q99865_arcmin"],
                        "yield": y["fraction"], "yield_ci95_low": y["ci95"][0], "yield_ci95_high": y["ci95"][1],
                        "overrides": ";".join(f"{k}={v}" for k, v in d["overrides"].items())})
        return out

    def to_frame(self):
        """The scenario table as a pandas DataFrame indexed by name (needs pandas)."""
        from rvbacklash.frames import to_frame

        return to_frame(self.rows(), index="name")


def compare(design: Design, scenarios: list[tuple[str, dict]], samples: int | None, seed: int | None,
            method: str = "default", spec_arcmin: float | None = None, model: str = "linear") -> Comparison:
    """Simulate every scenario with the same samples, seed and method."""
    out = []
    first_zones = None
    for name, overrides in scenarios:
        d = apply_overrides(design, overrides)
        zones = [(z.lower_um, z.upper_um) for z in resolve_zones(d)]
        first_zones = first_zones or zones
        changed = sum(a != b for a, b in zip(zones, first_zones))
        r = simulate(d, samples, seed, method, spec_arcmin, model=model)
        out.append(ScenarioResult(name, overrides, changed, r))
    return Comparison(design.name, spec_arcmin, out)
