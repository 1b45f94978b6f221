"""The assembly sheet of a measured batch (``rvbacklash assemble``; docs/selective-assembly.md, "On
the line"): which pins and which needle-roller set go into which unit, each unit's predicted lost
motion, backlash and torsional rigidity, the probability it passes, and why a unit cannot be built.

Inputs: the batch's measured units (the measured-unit format, design/measured.py: discs, housing,
crank; their pins' radii, if any, are ignored: the pins are what is chosen; their crank bearings'
clearance is read with rollers of nominal diameter) and its measured parts (``read_parts``: one row
per pin, one per roller set, with the deviation of its diameter). Each part goes to its class
(``classes``); a unit takes z_p pins of one class and one roller set; the classes go to the units by
``inventory.assign_optimal``; then each built unit takes its class's parts in serial order, and its
figures are the elastic model's for the unit as assembled (``analysis.hysteresis``: the same
function as ``hysteresis --measured`` on the assembled unit, which the sheet can write).

The pass probability is first order: the factory's measurement error (``noise``, of the fit the pins
are chosen against) is read as every pin off by +-noise; half the difference of the two lost motions
is the lost motion's standard uncertainty, and P(pass) = Phi((spec - LM) / u) (0 or 1 without noise).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvbacklash.analysis.contact import measured_units as to_measured, unit_realization
from rvbacklash.analysis.selection.classes import Selection, band_edges_um, factor_law
from rvbacklash.analysis.selection.inventory import Assignment, assign_greedy, assign_optimal, pair_distances
from rvbacklash.analysis.selection.rules import predicted_play_arcmin
from rvbacklash.design.measured import MeasuredPins, MeasuredUnit
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.models.contact import mesh_table, pin_gaps, stage_work, unit_gaps
from rvbacklash.models.elastic import BACKLASH, LOST_MOTION, RIGIDITY, PreparedUnit, elastic_model
from rvbacklash.models.elastic.unit import other_stages_nominal, unit_from_realization
from rvbacklash.models.unit_errors import unit_errors
from rvbacklash.problem import Problem
from rvbacklash.results import Result
from rvbacklash.units import ARCMIN_PER_RAD

PART_KINDS = ("pin", "roller")
PART_COLUMNS = ("serial", "kind", "diameter_um")
LIMIT_UM = 100.0  # a diameter off by more than this is not a part of this batch


@dataclass(frozen=True, repr=False)
class Part(Result):
    serial: str
    kind: str  # "pin" | "roller" (a roller set: one unit's crank needle rollers)
    diameter_um: float  # deviation from the nominal diameter


@dataclass(frozen=True, repr=False)
class SheetRow(Result):
    """One unit of the batch on the assembly sheet (class -1 and NaN figures: not built)."""

    unit: int
    built: bool
    pin_class: int
    roller_class: int
    pin_serials: str  # ";"-joined, in pin order
    roller_serial: str
    predicted_play_arcmin: float  # the rule's: the cycloid stage with the class's mean pins
    crank_clearance_um: float
    lost_motion_arcmin: float
    backlash_arcmin: float
    rigidity_nm_per_arcmin: float
    pass_probability: float | None  # None: no spec given
    reason: str  # "" when built, in window and predicted to pass


@dataclass(frozen=True, repr=False)
class AssemblySheet(Result):
    """The assembly sheet of a batch (module docstring) with the stocks left and the greedy rule's
    count beside the optimal assignment's."""

    design_name: str
    selection: str
    spec_lost_motion_arcmin: float | None
    units: int
    units_built: int
    units_in_window: int
    units_in_window_greedy: int
    units_predicted_to_pass: int | None
    pin_sets_left: tuple[int, ...]
    roller_sets_left: tuple[int, ...]
    pins_left: int
    sheet: tuple[SheetRow, ...]

    def rows(self) -> list[dict]:
        """The sheet: one row per unit."""
        return [r.to_dict() for r in self.sheet]

    def summary(self) -> list[str]:
        s = [f"{self.design_name}: {self.units_built} of {self.units} units built ({self.units_in_window} in window; "
             f"greedy rule: {self.units_in_window_greedy}), selection {self.selection}"]
        if self.units_predicted_to_pass is not None:
            s.append(f"predicted to pass lost motion <= {self.spec_lost_motion_arcmin:g} arcmin: "
                     f"{self.units_predicted_to_pass}")
        s.append(f"left in stock: pin sets per class {list(self.pin_sets_left)} ({self.pins_left} pins), roller sets "
                 f"per class {list(self.roller_sets_left)}")
        return s + [f"unit {r.unit}: {r.reason}" for r in self.sheet if r.reason]


def read_parts(path: str | Path) -> list[Part]:
    """The measured parts of a batch: a CSV with columns serial, kind (pin | roller), diameter_um
    (the deviation of the diameter from nominal [um]); every error names the file, row and column."""
    p = Path(path)
    if not p.is_file():
        raise InputError("--parts", str(path), "allowed: an existing CSV file of measured parts")
    try:
        text = p.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError("--parts", str(path), f"not readable as UTF-8 text ({type(e).__name__})") from None
    rows = list(csv.reader(text.splitlines()))
    if not rows or [c.strip().lower() for c in rows[0]] != list(PART_COLUMNS):
        raise InputError(f"{path} header", ",".join(rows[0]) if rows else "", f"allowed: {','.join(PART_COLUMNS)}")
    parts, seen = [], set()
    for i, row in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in row):
            continue
        if len(row) != 3:
            raise InputError(f"{path} row {i}", ",".join(row), "allowed: 3 columns serial,kind,diameter_um")
        serial, kind, value = (c.strip() for c in row)
        if not serial or serial in seen:
            raise InputError(f"{path} row {i} column serial", serial, "allowed: a non-empty serial, each once")
        if kind not in PART_KINDS:
            raise InputError(f"{path} row {i} column kind", kind, f"allowed: {', '.join(PART_KINDS)}")
        try:
            d = float(value)
        except ValueError:
            d = math.nan
        if not (math.isfinite(d) and abs(d) <= LIMIT_UM):
            raise InputError(f"{path} row {i} column diameter_um", value,
                             f"allowed: a finite deviation within +-{LIMIT_UM:g} um")
        seen.add(serial)
        parts.append(Part(serial, kind, d))
    if not parts:
        raise InputError("--parts", str(path), "no parts: allowed a CSV with one row per pin and per roller set")
    return parts


def write_parts_csv(parts: list[Part]) -> str:
    lines = [",".join(PART_COLUMNS)] + [f"{p.serial},{p.kind},{p.diameter_um:.4f}" for p in parts]
    return "\n".join(lines) + "\n"


def _laws(problem: Problem):
    from rvbacklash.sampling.contact_source import contact_source

    laws = contact_source(problem, "default", 0).laws

    def law(key: str):
        f = FACTOR_KEYS.index(key)
        return factor_law(int(laws.code[f]), float(laws.loc[f]), float(laws.scale[f]), float(laws.lower[f]),
                          float(laws.upper[f]), f"select {key}")

    return law("pin_radius"), law("crank_bearing_clearance")


def generate_batch(problem: Problem, units: int, seed: int = 0, spare: float = 0.25) -> tuple[list[MeasuredUnit],
                                                                                              list[Part]]:
    """A batch for trying the line: ``units`` units drawn as the production run draws them (seed),
    measured without their pins (their crank bearings at the clearance law's mean with nominal
    rollers), and pins and roller sets for them plus ``spare`` (each kind from its law: pins from
    factor 15's, roller sets from factor 20's, a roller larger by x closing the clearance by x)."""
    from rvbacklash.analysis.simulation import simulate

    if isinstance(units, bool) or not isinstance(units, int) or not 1 <= units <= 10000:
        raise InputError("--generate", units, "allowed: 1 to 10000 units")
    run = simulate(problem, samples=units, seed=seed, model="contact", save_units=units, workers=1)
    pin_law, clearance_law = _laws(problem)
    mean_clearance = float(clearance_law.mean())
    k = FACTOR_KEYS.index("crank_bearing_clearance")
    sens = float(problem.sensitivities_arcmin_per_um[k])
    measured = []
    for r, mu in zip(run.units, to_measured(problem, run.units)):
        involute = mu.other_stages_arcmin - sens * mu.crank_bearing_clearance_um
        measured.append(mu.model_copy(update={
            "pins": MeasuredPins(radial_position_um=mu.pins.radial_position_um,
                                 tangential_position_um=mu.pins.tangential_position_um,
                                 hole_clearance_um=mu.pins.hole_clearance_um),
            "crank_bearing_clearance_um": mean_clearance,
            "other_stages_arcmin": involute + sens * mean_clearance, "cycloid_stage_arcmin": None}))
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=(39,))))
    zp = problem.cycloid.zp
    n_pins, n_rollers = int(math.ceil(units * zp * (1 + spare))), int(math.ceil(units * (1 + spare)))
    pins = 2.0 * pin_law.ppf(rng.random(n_pins))
    rollers = mean_clearance - clearance_law.ppf(rng.random(n_rollers))
    parts = [Part(f"P{i + 1:05d}", "pin", float(x)) for i, x in enumerate(pins)]
    parts += [Part(f"R{i + 1:04d}", "roller", float(x)) for i, x in enumerate(rollers)]
    return measured, parts


def _classes(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Class of each value: edges[c] <= v < edges[c + 1], the outer classes open."""
    return np.clip(np.searchsorted(edges[1:-1], values, side="right"), 0, edges.size - 2)


def assemble(problem: Problem, units: list[MeasuredUnit], parts: list[Part], selection: Selection,
             spec_lost_motion_arcmin: float | None = None) -> tuple[AssemblySheet, list[MeasuredUnit]]:
    """The assembly sheet of a batch (module docstring) and its units as assembled (the
    measured-unit records ``hysteresis --measured`` reads: the built ones, in unit order)."""
    g = problem.cycloid
    zp = g.zp
    pin_law, clearance_law = _laws(problem)
    pin_edges = band_edges_um(pin_law, selection.pins, 0.5)  # radius
    mean_clearance = float(clearance_law.mean())
    # roller classes on the roller's diameter deviation (dev = mean clearance - clearance): class 0 the smallest
    roller_edges = mean_clearance - band_edges_um(clearance_law, selection.rollers, 1.0)[::-1]
    pins = [p for p in parts if p.kind == "pin"]
    rollers = [p for p in parts if p.kind == "roller"]
    pin_r = np.array([p.diameter_um / 2 for p in pins])
    roller_d = np.array([p.diameter_um for p in rollers])
    pin_c = _classes(pin_r, pin_edges) if pins else np.zeros(0, int)
    roller_c = _classes(roller_d, roller_edges) if rollers else np.zeros(0, int)
    kp, kr = selection.pins.count, selection.rollers.count
    pin_sets = np.bincount(pin_c, minlength=kp) // zp
    roller_sets = np.bincount(roller_c, minlength=kr)
    pin_mean = np.array([pin_r[pin_c == c].mean() if np.any(pin_c == c) else 0.5 * (pin_edges[c] + pin_edges[c + 1])
                         for c in range(kp)])
    roller_mean = np.array([roller_d[roller_c == c].mean() if np.any(roller_c == c) else 0.0 for c in range(kr)])
    sens = float(problem.sensitivities_arcmin_per_um[FACTOR_KEYS.index("crank_bearing_clearance")])
    tol = 1e-9 * g.stage_geometry.pitch_radius_um
    involute0, crank0 = other_stages_nominal(problem)
    n_u = len(units)
    play = np.empty((n_u, kp))
    clearance = np.empty((n_u, kr))
    realizations = []
    for u, mu in enumerate(units):
        r = unit_realization(problem, mu.model_copy(update={"pins": mu.pins.model_copy(update={"radius_um": None})}))
        realizations.append(r)
        gaps = pin_gaps(g.discs, zp)
        unit_gaps(mesh_table(g, np.array([r.chi_rad]))[0], g.stage_geometry, unit_errors(r), gaps,
                  stage_work(g.discs, zp))
        zero = np.zeros(zp)
        for c in range(kp):
            play[u, c] = predicted_play_arcmin(gaps.gap_um, gaps.lever_um_per_rad, zero, pin_mean[c], tol)
        cl = mu.crank_bearing_clearance_um if mu.crank_bearing_clearance_um is not None else crank0
        clearance[u] = cl - roller_mean
    target = selection.target_arcmin if selection.target_arcmin is not None else sens * mean_clearance
    d = pair_distances(play, clearance, sens, (selection.play_min_arcmin, selection.play_max_arcmin), target)
    best: Assignment = assign_optimal(d, pin_sets, roller_sets)
    greedy = assign_greedy(d, pin_sets, roller_sets)
    model = elastic_model(problem)
    # each class's parts in serial order
    stock_p = {c: [i for i in sorted(range(len(pins)), key=lambda i: pins[i].serial) if pin_c[i] == c] for c in range(kp)}
    stock_r = {c: [i for i in sorted(range(len(rollers)), key=lambda i: rollers[i].serial) if roller_c[i] == c]
               for c in range(kr)}
    rows, assembled = [], []
    for u, mu in enumerate(units):
        p, q = best.pin_class[u], best.roller_class[u]
        if p < 0:
            why = _why_not_built(play[u], pin_sets, roller_sets, selection)
            rows.append(SheetRow(u, False, -1, -1, "", "", float(np.nanmin(play[u])), math.nan, math.nan, math.nan,
                                 math.nan, None if spec_lost_motion_arcmin is None else 0.0, why))
            continue
        take = [stock_p[p].pop(0) for _ in range(zp)]
        roller = stock_r[q].pop(0)
        radius = [pins[i].diameter_um / 2 for i in take]
        cl = float(clearance[u, q] + roller_mean[q] - rollers[roller].diameter_um)
        r = realizations[u]
        involute = r.involute_backlash_rad if r.involute_backlash_rad is not None else involute0
        r = r.with_(pin_radius_um=np.array(radius), crank_clearance_um=cl)
        fig = PreparedUnit(model, unit_from_realization(problem, r, involute, cl)).figures()
        lm = float(fig[LOST_MOTION])
        sigma = 0.0
        if selection.noise_um > 0 and spec_lost_motion_arcmin is not None:
            # the measurement error read as every pin off by +-noise: the lost motion's central difference
            ends = [float(PreparedUnit(model, unit_from_realization(problem, r.with_(
                pin_radius_um=np.array(radius) + e), involute, cl)).figures()[LOST_MOTION])
                for e in (selection.noise_um, -selection.noise_um)]
            sigma = abs(ends[0] - ends[1]) / 2
        done = mu.model_copy(update={
            "pins": mu.pins.model_copy(update={"radius_um": radius}), "crank_bearing_clearance_um": cl,
            "other_stages_arcmin": float(max(involute, 0.0) * ARCMIN_PER_RAD + sens * cl)})
        assembled.append(done)
        prob = None
        reason = "" if best.in_window[u] else f"out of window: predicted play {play[u, p]:.3f} arcmin with the " \
                                              f"pins it could have"
        if spec_lost_motion_arcmin is not None:
            prob = _pass_probability(lm, spec_lost_motion_arcmin, sigma)
            if prob < 0.5 and not reason:
                reason = f"predicted lost motion {lm:.3f} arcmin > spec {spec_lost_motion_arcmin:g}"
        rows.append(SheetRow(u, True, int(p), int(q), ";".join(pins[i].serial for i in take), rollers[roller].serial,
                             float(play[u, p]), cl, lm, float(fig[BACKLASH]), float(fig[RIGIDITY]), prob, reason))
    passing = None if spec_lost_motion_arcmin is None else sum(1 for r in rows if r.built and r.pass_probability >= 0.5)
    sheet = AssemblySheet(problem.name, str(selection), spec_lost_motion_arcmin, n_u, best.units_built,
                          best.units_in_window, greedy.units_in_window, passing, best.pin_sets_left,
                          best.roller_sets_left, sum(len(v) for v in stock_p.values()), tuple(rows))
    return sheet, assembled


def _pass_probability(lm: float, spec: float, sigma: float) -> float:
    if sigma <= 0:
        return 1.0 if lm <= spec else 0.0
    return float(0.5 * math.erfc((lm - spec) / (sigma * math.sqrt(2.0))))


def _why_not_built(play: np.ndarray, pin_sets: np.ndarray, roller_sets: np.ndarray, selection: Selection) -> str:
    lo, hi = selection.play_min_arcmin, selection.play_max_arcmin
    fits = [c for c in range(play.size) if lo <= play[c] <= hi]
    if not pin_sets.any():
        return "no pins: fewer than z_p pins in every class"
    if not roller_sets.any():
        return "no roller sets left"
    if fits and not any(pin_sets[c] for c in fits):
        return f"parts ran out: the pin classes that close its stage ({', '.join(map(str, fits))}) are used up"
    return "parts ran out: the batch's other units took the sets it could have had"
