"""One unit's capacity (docs/capacity.md): its bearings' lives at any output torque and speed, its
static limits, and the ratings derived from them (rated torque, momentary maximum torque,
allowable acceleration torque), all from the elastic solution at K crank angles per revolution.

``UnitCapacity`` prepares the unit once at its crank angles (``revolution.CrankAngles``); each
torque then costs K solves of the chain (cached per torque), so that a root search (the rated
torque, the momentary maximum) re-solves only the torques it tries.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from rvbacklash.analysis.capacity.life import (BearingLife, bearing_speed_rpm, needle_bearing_lives, needle_ratings,
                                               reducer_life, support_bearing_lives, support_ratings)
from rvbacklash.analysis.capacity.revolution import (DEFAULT_ANGLES, CrankAngles, RevolutionLoads, load_geometry,
                                                     needle_rollers, revolution_loads)
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import ElasticModel
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem

ROOT_RTOL = 1e-9  # relative tolerance of the rated torque and the momentary maximum's root searches (in ln T)
SEARCH_LIMIT = 1e3  # at most this many times the rated torque is searched for a static limit
LOWEST_DECADES = 8  # a root search below its start by this many decades ends at T = 0 (e.g. a unit whose preload
#                     alone takes its bearings' life below the rated life: its rated torque is 0)
STATIC_ELEMENTS = ("crank needle bearings", "crank support bearings", "pins and flanks")


class StaticLimit(NamedTuple):
    """How far an element is from its static limit at a torque: its largest load (or stress) over
    the revolution against the limit (ratio 1: reached)."""

    element: str
    value: float  # P_0 [N] of the most loaded bearing, or the largest pin/flank Hertz pressure [MPa]
    limit: float  # C_0 [N], or the stated contact stress limit [MPa]
    criterion: str

    @property
    def ratio(self) -> float:
        return self.value / self.limit


class UnitCapacity:
    """A unit's capacity at K crank angles (module docstring). ``realization``: the unit's part errors
    (its crank angle is the first of the K); ``involute_backlash_rad``, ``crank_clearance_um`` as
    the elastic model's unit (``models.elastic.unit_from_realization``)."""

    def __init__(self, problem: Problem, model: ElasticModel, realization: Realization, involute_backlash_rad: float,
                 crank_clearance_um: float, angles: int = DEFAULT_ANGLES, method: str | None = None):
        self.problem, self.model = problem, model
        cap = problem.design.capacity
        self.inputs = cap
        self.method = method or cap.life_method
        if self.method not in ("iso16281", "iso281"):
            raise InputError("life_method", self.method, "allowed: iso16281, iso281")
        self.angles = CrankAngles(problem, model, realization, involute_backlash_rad, crank_clearance_um, angles)
        self.geometry = load_geometry(problem, model)
        self.needles = needle_rollers(model)
        self.needle_ratings = needle_ratings(model, self.needles.drop_um.size)
        self.support_ratings = support_ratings(model)
        self._loads: dict[float, RevolutionLoads] = {}
        self._lives: dict[tuple[float, float, str], list[BearingLife]] = {}

    @property
    def rated_torque_nm(self) -> float:
        """The design's stated rated torque T_R ([elastic] rated_torque_nm)."""
        return self.model.chain.rated_torque_nm

    def loads(self, output_torque_nm: float) -> RevolutionLoads:
        """The RevolutionLoads at an output torque [N m] (cached)."""
        t = float(output_torque_nm)
        if t not in self._loads:
            self._loads[t] = revolution_loads(self.angles, t, self.geometry, self.needles)
        return self._loads[t]

    def lives(self, output_torque_nm: float, output_speed_rpm: float, method: str | None = None) -> list[BearingLife]:
        """Every crank needle and support bearing's life at an output torque and speed."""
        key = (float(output_torque_nm), float(output_speed_rpm), method or self.method)
        if key not in self._lives:
            loads = self.loads(output_torque_nm)
            speed = bearing_speed_rpm(self.model, output_speed_rpm)
            lives = needle_bearing_lives(loads, self.needles, self.needle_ratings, key[2], speed)
            if self.support_ratings is not None:
                lives += support_bearing_lives(loads, self.support_ratings, speed)
            self._lives[key] = lives
        return self._lives[key]

    def life_h(self, output_torque_nm: float, output_speed_rpm: float, method: str | None = None) -> float:
        """The reducer's L10 [h] at an output torque and speed (its bearings as a system)."""
        return reducer_life(self.lives(output_torque_nm, output_speed_rpm, method))

    def static_limits(self, output_torque_nm: float) -> list[StaticLimit]:
        """Each element's largest static load against its limit over the revolution at a torque:
        the needle and support bearings' P_0 against C_0 (ISO 76, 4000 MPa at the most loaded
        roller contact), the pins' and flanks' Hertz pressure against the stated limit."""
        lives = self.lives(output_torque_nm, self.inputs.rated_output_speed_rpm)
        out = []
        for kind, element in (("crank_needle", STATIC_ELEMENTS[0]), ("crank_support", STATIC_ELEMENTS[1])):
            bearings = [b for b in lives if b.kind == kind]
            if bearings:
                worst = max(bearings, key=lambda b: b.static_equivalent_load_n / b.static_load_rating_n)
                out.append(StaticLimit(element, worst.static_equivalent_load_n, worst.static_load_rating_n,
                                       "ISO 76: P_0 = C_0 (4000 MPa at the most loaded roller contact)"))
        stress = float(self.loads(output_torque_nm).pin_stress_mpa.max())
        out.append(StaticLimit(STATIC_ELEMENTS[2], stress, self.inputs.contact_stress_limit_mpa,
                               "peak Hertz pressure = capacity.contact_stress_limit_mpa"))
        return out

    def rated_torque(self, rated_life_h: float | None = None, output_speed_rpm: float | None = None,
                     method: str | None = None) -> float:
        """The output torque at which the reducer's L10 equals the rated life at the rated output speed
        (defaults: the design's [capacity]) [N m]: the root of ln L(T) - ln K, solved in ln T to
        ROOT_RTOL (L falls with T)."""
        k = rated_life_h or self.inputs.rated_life_h
        n = output_speed_rpm or self.inputs.rated_output_speed_rpm

        def gap(log_t: float) -> float:
            return math.log(self.life_h(math.exp(log_t), n, method)) - math.log(k)

        t0 = self.rated_torque_nm
        # first guess by the life's cube-power law from the life at T_R, then a bracket around it
        guess = t0 * (self.life_h(t0, n, method) / k) ** 0.3
        return math.exp(_bracketed_root(gap, math.log(guess), falling=True))

    def momentary_maximum(self) -> tuple[float, str, list[StaticLimit]]:
        """(T_max [N m], the limiting element, every element's limit at T_max): the output torque at
        which the first element reaches its static limit (``static_limits``, ratio 1)."""
        def gap(log_t: float) -> float:
            return math.log(max(s.ratio for s in self.static_limits(math.exp(log_t))))

        t0 = self.rated_torque_nm
        first = max(self.static_limits(t0), key=lambda s: s.ratio)
        guess = t0 / first.ratio  # bearings' loads ~ T (pins' stress ~ sqrt(T)): a start, the bracket follows
        log_t = _bracketed_root(gap, math.log(guess), falling=False, limit=math.log(SEARCH_LIMIT * t0))
        t = math.exp(log_t)
        limits = self.static_limits(t)
        return t, max(limits, key=lambda s: s.ratio).element, limits


def _bracketed_root(f, x0: float, falling: bool, limit: float = math.inf) -> float:
    """The root of a monotone f (falling or rising in x = ln T) near x0: a bracket grown by steps of
    ln 1.5, then Brent's method to ROOT_RTOL; -inf (T = 0) when f keeps its sign LOWEST_DECADES below
    x0 (the condition already holds at no load)."""
    from scipy.optimize import brentq

    step = math.log(1.5)
    f0 = f(x0)
    if f0 == 0.0:
        return x0
    # the root lies above x0 when f is still positive on a falling curve (or negative on a rising one)
    direction = 1.0 if (f0 > 0.0) == falling else -1.0
    a, fa = x0, f0
    for _ in range(200):
        b = a + direction * step
        if direction < 0.0 and b < x0 - LOWEST_DECADES * math.log(10.0):
            return -math.inf  # no torque small enough: the condition holds unloaded (a preloaded unit): T = 0
        if b > limit:
            raise InputError("torque", math.exp(limit), "no static limit is reached below this output torque "
                                                       "(a design far outside its class?)")
        fb = f(b)
        if (fb > 0.0) != (fa > 0.0) or fb == 0.0:
            lo, hi = (a, b) if a < b else (b, a)
            return float(brentq(f, lo, hi, xtol=ROOT_RTOL, rtol=ROOT_RTOL))
        a, fa = b, fb
    raise InputError("torque", math.exp(a), "no root of the life or static-limit condition found")
