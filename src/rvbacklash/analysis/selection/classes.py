"""Size classes of the selected parts and the selection's settings (docs/selective-assembly.md).

A factory sorts the pins and the crank needle rollers it buys into diameter classes a few
micrometres wide and, per unit, takes all of a part kind from one class. Here a class set is
``count`` classes of ``width_um`` (diameter), centred on the mean of the part's law; the two outer
classes are open (they take every part beyond the inner cuts), so that every part bought belongs to
a class and one class is the whole law: today's random assembly.

What a class does to a unit (the part's factor law conditioned on the class's band, each part keeping
its quantile within the class: ``ClassTable``):
- pins: factor 15, the pin *radius* deviation: a class of diameter width w is a band w / 2 wide in
  radius; every pin of the unit comes from the class;
- needle rollers: factor 20, the crank bearings' radial clearance (the bore and the eccentric are
  measured; the clearance's spread is taken to come from the parts the rollers fill): a roller
  diameter class of width w is a clearance band w wide (a roller larger by x closes the radial
  clearance by x), classes numbered by roller size (class 0: the smallest rollers, the loosest fit).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.factors.distributions import (KERNEL_FIXED, KERNEL_NORMAL, KERNEL_RAYLEIGH, KERNEL_TRUNCNORM,
                                              KERNEL_UNIFORM)
from rvbacklash.results import Result

X_POINTS = 1025  # the cdf's table over the law's range
U_POINTS = 513  # each class's inverse cdf table
MAX_CLASSES = 500
PART_KINDS = ("pins", "rollers")
SELECT_SYNTAX = ("pins=COUNTxWIDTHum[,rollers=COUNTxWIDTHum][,noise=SIGMAum][,play=[MIN:]MAX][,target=ARCMIN] "
                 "(play and target in arcmin)")


@dataclass(frozen=True, repr=False)
class ClassSet(Result):
    """``count`` diameter classes of ``width_um`` each (the outer two open-ended)."""

    count: int
    width_um: float

    def __str__(self) -> str:
        return f"{self.count}x{self.width_um:g}um"


@dataclass(frozen=True, repr=False)
class Selection(Result):
    """What the factory selects and how (``parse_selection``, ``--select``):

    - ``pins``, ``rollers``: the class sets (one class: that part is assembled at random);
    - ``noise_um``: the standard uncertainty of the factory's measurement of what the pins are
      selected against (the discs' and the housing's fit, in um of pin radius) [um];
    - ``play_min_arcmin``, ``play_max_arcmin``: the window of the cycloid stage's predicted play the
      pin class aims at (negative: an interference) [arcmin]; default (-inf, 0]: the stage closed,
      any preload accepted (a unit already closed keeps the middle class);
    - ``target_arcmin``: the predicted play of the cycloid stage plus the crank bearings' share that
      the roller class aims at; None: the crank bearings' share at their law's mean clearance."""

    pins: ClassSet = ClassSet(1, 0.0)
    rollers: ClassSet = ClassSet(1, 0.0)
    noise_um: float = 0.0
    play_min_arcmin: float = -math.inf
    play_max_arcmin: float = 0.0
    target_arcmin: float | None = None

    @property
    def random(self) -> bool:
        """One class of each: today's random assembly."""
        return self.pins.count == 1 and self.rollers.count == 1

    def __str__(self) -> str:
        lo = f"{self.play_min_arcmin:g}:" if math.isfinite(self.play_min_arcmin) else ""
        s = f"pins={self.pins},rollers={self.rollers},noise={self.noise_um:g}um,play={lo}{self.play_max_arcmin:g}"
        return s + (f",target={self.target_arcmin:g}" if self.target_arcmin is not None else "")


_CLASSES = re.compile(r"^\s*(\d+)\s*x\s*([0-9.eE+-]+)\s*(um)?\s*$")
_AMOUNT = re.compile(r"^\s*([0-9.eE+-]+)\s*(um|arcmin)?\s*$")


def parse_selection(text: str, name: str = "--select") -> Selection:
    """``pins=5x2um,rollers=3x2um,noise=0.5um,target=0.4,play=0`` -> Selection; every key at most
    once; an error names ``name``, the item and the allowed form."""
    if not isinstance(text, str) or not text.strip():
        raise InputError(name, text, f"allowed: {SELECT_SYNTAX}")
    seen: dict[str, object] = {}
    for item in text.split(","):
        key, eq, value = (s.strip() for s in item.partition("="))
        if not eq or not key or not value:
            raise InputError(name, text, f"'{item.strip()}' is not key=value; allowed: {SELECT_SYNTAX}")
        if key in seen:
            raise InputError(name, text, f"key '{key}' is given twice; allowed: each key once")
        if key in PART_KINDS:
            m = _CLASSES.match(value)
            if not m:
                raise InputError(name, text, f"'{item.strip()}': allowed {key}=COUNTxWIDTHum, e.g. {key}=5x2um")
            seen[key] = class_set(int(m.group(1)), float(m.group(2)), f"{name} {key}")
        elif key == "play":
            lo, colon, hi = value.partition(":")
            try:
                seen[key] = (float(lo.removesuffix("arcmin")) if colon else -math.inf,
                             float((hi if colon else lo).removesuffix("arcmin")))
            except ValueError:
                raise InputError(name, text, f"'{item.strip()}': allowed play=MAX or play=MIN:MAX [arcmin]") from None
        elif key in ("noise", "target"):
            m = _AMOUNT.match(value)
            unit = "um" if key == "noise" else "arcmin"
            if not m or (m.group(2) and m.group(2) != unit):
                raise InputError(name, text, f"'{item.strip()}': allowed {key}=NUMBER{unit}")
            seen[key] = float(m.group(1))
        else:
            raise InputError(name, text, f"unknown key '{key}'; allowed: {SELECT_SYNTAX}")
    if not any(k in seen for k in PART_KINDS):
        raise InputError(name, text, f"no part to select; allowed: {SELECT_SYNTAX}")
    return make_selection(pins=seen.get("pins"), rollers=seen.get("rollers"), noise_um=seen.get("noise", 0.0),
                          play_arcmin=seen.get("play", (-math.inf, 0.0)), target_arcmin=seen.get("target"), name=name)


def class_set(count: int, width_um: float, name: str) -> ClassSet:
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not 1 <= count <= MAX_CLASSES:
        raise InputError(f"{name} count", count, f"allowed: 1 <= count <= {MAX_CLASSES}")
    if not (isinstance(width_um, (int, float)) and math.isfinite(width_um) and width_um > 0):
        raise InputError(f"{name} width", width_um, "allowed: a finite diameter width > 0 [um]")
    return ClassSet(int(count), float(width_um))


def make_selection(pins: ClassSet | None = None, rollers: ClassSet | None = None, noise_um: float = 0.0,
                   play_arcmin: tuple[float, float] = (-math.inf, 0.0), target_arcmin: float | None = None,
                   name: str = "selection") -> Selection:
    """A checked Selection (what the API's ``select=`` takes besides a string)."""
    lo, hi = play_arcmin
    if not (math.isfinite(hi) and (lo == -math.inf or math.isfinite(lo)) and lo <= hi):
        raise InputError(f"{name} play", f"{lo}:{hi}", "allowed: MIN <= MAX, finite numbers [arcmin] (MIN may be "
                                                       "left out: any preload)")
    for key, v in (("noise", noise_um),) + (
            (("target", target_arcmin),) if target_arcmin is not None else ()):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or \
                (key == "noise" and v < 0):
            raise InputError(f"{name} {key}", v, "allowed: a finite number" + (" >= 0 [um]" if key == "noise" else
                                                                              " [arcmin]"))
    return Selection(pins or ClassSet(1, 0.0), rollers or ClassSet(1, 0.0), float(noise_um),
                     float(lo), float(hi), None if target_arcmin is None else float(target_arcmin))


def as_selection(select) -> Selection | None:
    """``select`` as the API takes it: None, a Selection, or the ``--select`` string."""
    if select is None or isinstance(select, Selection):
        return select
    if isinstance(select, str):
        return parse_selection(select, "select")
    raise InputError("select", type(select).__name__, f"allowed: None, a Selection or a string {SELECT_SYNTAX}")


# --- a part's law, its classes and their tables ---------------------------------------------------

def factor_law(code: int, loc: float, scale: float, lower: float, upper: float, name: str):
    """The scipy law of one row of ``sampling.unit_draw.FactorLaws`` (the law the units draw)."""
    from scipy import stats

    if code == KERNEL_NORMAL:
        return stats.norm(loc, scale)
    if code == KERNEL_TRUNCNORM:
        return stats.truncnorm((lower - loc) / scale, (upper - loc) / scale, loc, scale)
    if code == KERNEL_UNIFORM:
        return stats.uniform(lower, upper - lower)
    if code == KERNEL_RAYLEIGH:
        return stats.rayleigh(loc, scale)
    if code == KERNEL_FIXED:
        raise InputError(name, "fixed", "a part with a fixed size has nothing to select; give its factor a zone")
    raise InputError(name, "tabulated law", "allowed for selection: normal, truncated normal, uniform or Rayleigh laws")


class ClassTable(NamedTuple):
    """One part kind's classes as the kernels read them [um of the factor]: the law's cdf on a grid
    (``x_um``, ``cdf``), each class's inverse cdf of its band (``ppf_um``: classes x U_POINTS at
    probabilities (k + 0.5) / U_POINTS), each class's mean (``mean_um``), and its share of the parts
    bought (``share``)."""

    x_um: np.ndarray
    cdf: np.ndarray
    ppf_um: np.ndarray
    mean_um: np.ndarray
    share: np.ndarray


def band_edges_um(law, classes: ClassSet, scale: float) -> np.ndarray:
    """The class boundaries in the factor's units: count + 1 edges, the outer two the law's support;
    the inner cuts ``scale`` x width apart (scale: factor um per diameter um), centred on the mean."""
    k = classes.count
    lo, hi = law.support()
    inner = law.mean() + scale * classes.width_um * (np.arange(1, k) - 0.5 * k)
    return np.concatenate([[lo], inner, [hi]])


def class_table(law, classes: ClassSet, scale: float) -> ClassTable:
    """The ClassTable of a law cut into ``classes`` (``band_edges_um``). A class beyond the law's support
    (no part falls in it) keeps its edge as its only size: share 0, never chosen by a rule that
    reads the shares."""
    edges = band_edges_um(law, classes, scale)
    lo, hi = law.ppf(1e-12), law.isf(1e-12)
    x = np.linspace(lo, hi, X_POINTS)
    cdf = law.cdf(x)
    f_edges = law.cdf(edges)
    u = (np.arange(U_POINTS) + 0.5) / U_POINTS
    k = classes.count
    ppf, mean, share = np.empty((k, U_POINTS)), np.empty(k), np.empty(k)
    for c in range(k):
        a, b = f_edges[c], f_edges[c + 1]
        share[c] = b - a
        if b - a > 1e-12:
            ppf[c] = law.ppf(a + u * (b - a))
            mean[c] = float(np.mean(ppf[c]))  # the band's mean (midpoint rule in probability)
        else:
            edge = float(np.clip(edges[c] if c else edges[1], lo, hi))
            ppf[c], mean[c] = edge, edge
    return ClassTable(np.ascontiguousarray(x), np.ascontiguousarray(cdf), np.ascontiguousarray(ppf),
                      mean, share)
