"""The elastic model's solver: the monotone solves of a set of contacts, and the warm starts that
make a unit's loop cheap (docs/elastic.md, "Solving the chain").

A set of contacts (``ContactSet``: the pins of a unit referred to the output, the rollers of a
needle bearing, the rollers of a support bearing) closes as one coordinate x moves: contact j by
delta_j = lever_j x - gap_j, pushing back with its law's force F_j(delta_j) (``law_step``). The
set's load, scale sum F_j lever_j, rises monotonically with x, so the x that carries a given load
is one bracketed root (``solve_set``). The pins add the discs' sideways translations on their
needle bearings (``solve_pins``). A loop solves the same sets at ten torques: each solve starts
from the last one under a load of the same sign (``SOLVE_STATE``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.models import compliance as cm
from rvbacklash.models.elastic.rollers import SlicedRoller

TINY_LEVER = 1e-3  # of the largest lever: a contact that cannot bound a rotation (set_bounds)
SETTLE = 1e-4  # set_load: a force is stepped again while its relative error bound is above this
#                 (steps s/F > ~0.07: below, the (s/F)^2 bound holds well within solve_set's factor-2
#                 margin; 1e-3 let a bracket move wrongly)
LN_FORCE_GUESS = 6.0  # ln(400 N): start of the inversion of Johnson's law (pin and roller loads 10 N - 10 kN)
FIRST_STEPS = 2  # solve_set: law steps of every contact at a solve's first evaluation (its forces are the last
#                   solve's): a fixed count, not a test on each step's error bound, which the CPU cannot predict
#                   (~1 us per unit of mispredicted branches; issue 28)
SOLVE_RTOL = 1e-11  # solve_set stops when the load's residual and its error bound are below this share of it
WALK_RATIO = 1.5  # solve_set: a load this many times the last one's is started from closure_prediction
TRANSLATION_STEP_UM = 1e-6  # solve_pins: a Newton step on the translations below this ends the rounds
TINY_TORQUE = 1e-12  # of T_R: the torque at which a translating disc's dead-band edge is read
POSITIVE, NEGATIVE = 0, 1  # a warm start's side: the last solve under a positive or a negative load


class ContactLaw(NamedTuple):
    """The law of every contact of a set, delta = F^n (a_j - b ln F) [um, N] (a_j: ContactSet.law_a),
    and the scale from sum F_j lever_j to the set's load (1e-6 N um -> N m for the pins referred to
    the output; 1 for a bearing's rollers, whose load is a force [N])."""

    b: float
    n: float
    scale: float


class Bounds(NamedTuple):
    """The free band of a set (set_bounds): the first contact turning positive is at hi, the first
    turning negative at lo (hi < lo: preloaded); ``tiny``: a contact too small a lever to bound a
    rotation interferes (the solver then checks its brackets)."""

    hi: float
    lo: float
    tiny: bool


class ContactSet(NamedTuple):
    """A set of contacts closing with one coordinate x: gap_j and lever_j [um, um per unit of x],
    each contact's law coefficient a_j, the set's Bounds, each contact's force at the last
    evaluation (law_step's start) [N], and, when the contacts are in ``closure_order``, its runs
    (npos with levers > 0, then nneg with levers < 0; npos = -1: no order)."""

    gaps: np.ndarray
    levers: np.ndarray
    law_a: np.ndarray
    bounds: Bounds
    forces: np.ndarray
    npos: int
    nneg: int


class SetSolution(NamedTuple):
    """solve_set's answer: the coordinate x, and the set's stiffness dload/dx there when the solve
    converged under a load (NaN otherwise: no tangent to start the next solve from)."""

    x: float
    stiffness: float


class DiscTranslation(NamedTuple):
    """The discs' translations along their eccentrics and solve_pins' work (docs/elastic.md): the
    per-disc rows (``per_disc`` (7, discs), rows by name: Y, the translations [um]; a round's sums
    RADIAL_FORCE [N], STIFFNESS_YY (dF/dy), STIFFNESS_XY (dF/dx), FORCE_SCALE (sum |F radial|);
    LAST_POSITIVE, LAST_NEGATIVE, the last translations under a positive and a negative load [um],
    the next solve's start), the pins' gaps shifted by the translations (one per pin), the
    translations' Newton system and step. One array for the rows: each array in a record costs
    every call that passes it (separate rows made a unit's evaluation ~1 % slower)."""

    per_disc: np.ndarray
    shifted_gaps_um: np.ndarray
    jacobian: np.ndarray
    step_um: np.ndarray


Y, RADIAL_FORCE, STIFFNESS_YY, STIFFNESS_XY, FORCE_SCALE, LAST_POSITIVE, LAST_NEGATIVE = range(7)  # DiscTranslation rows
N_TRANSLATION_ROWS = 7


class PinSet(NamedTuple):
    """A unit's pin contacts referred to the output (``chain.prepare_pins``): the ContactSet, each
    pin's closure per um of its disc's translation along the eccentric (0 when the discs do not
    translate), its disc, and the translations' state."""

    contacts: ContactSet
    radial: np.ndarray
    disc: np.ndarray
    translation: DiscTranslation


class SupportMemo(NamedTuple):
    """The support bearings' deflections solved so far (support_deflection_um): chain torque [N m],
    the side of a solve at zero torque (0 under a load), deflection [um]; NaN torque: a free slot."""

    torque_nm: np.ndarray
    side: np.ndarray
    deflection_um: np.ndarray


class SupportSet(NamedTuple):
    """One crank support (tapered-roller) bearing's rollers, the memo of its solves, and its rollers'
    slices (``rollers.SlicedRoller``; none: straight rollers, Palmgren's law per roller as before)."""

    contacts: ContactSet
    memo: SupportMemo
    roller: SlicedRoller


# A unit's warm starts through its loop (new_state; chain_angles): per side (POSITIVE, NEGATIVE)
# the last solution of the pins, of the crank bearings' rollers and of the support bearings (the
# next solve's start; NaN: none), the load and stiffness of the pins' last solve (solve_set's
# tangent); the last |load| and |deflection| of the rollers and of the support bearings (an even
# number of rollers, one on the load line, deflects alike under a load and its mirror: no solve).
SOLVE_STATE = np.dtype([("pins_start", np.float64, (2,)), ("rollers_start", np.float64, (2,)),
                        ("support_start", np.float64, (2,)), ("pins_tangent_load_nm", np.float64, (2,)),
                        ("pins_tangent_stiffness", np.float64, (2,)), ("rollers_tangent_load_n", np.float64, (2,)),
                        ("rollers_tangent_stiffness", np.float64, (2,)), ("rollers_last_load_n", np.float64),
                        ("rollers_last_um", np.float64), ("support_last_load_n", np.float64),
                        ("support_last_um", np.float64)])


@njit(nogil=True, cache=True)
def new_state():
    """A unit's SOLVE_STATE before its first solve (one record in an array: pass the array, read
    its record [0] where it is used): no starts yet."""
    state = np.empty(1, dtype=SOLVE_STATE)
    st = state[0]
    for i in range(2):
        st.pins_start[i] = np.nan
        st.rollers_start[i] = np.nan
        st.support_start[i] = np.nan
        st.pins_tangent_load_nm[i] = np.nan
        st.pins_tangent_stiffness[i] = np.nan
        st.rollers_tangent_load_n[i] = np.nan
        st.rollers_tangent_stiffness[i] = np.nan
    st.rollers_last_load_n = np.nan
    st.rollers_last_um = np.nan
    st.support_last_load_n = np.nan
    st.support_last_um = np.nan
    return state


@njit(nogil=True, cache=True)
def law_step(delta_um, a, b, n, f0):
    """One step towards the force of a contact closed by delta > 0 under delta = F^n (a - b ln F):
    (F [N], dF/ddelta [N/um], bound of F's relative error after the step).

    Palmgren (b = 0): the closed form, error 0. Johnson (n = 1): one Newton step on
    phi(F) = F (a - b ln F) - delta from f0 (e.g. the contact's force at the previous evaluation),
    or from the estimate delta / (a - b LN_FORCE_GUESS) when f0 is not positive or not below
    delta / (2 b). phi is concave (phi'' = -b/F): from the left the iterates rise monotonically to
    the root; from the right they land left of it, and stay positive for starts below delta / b.
    After a step s the relative error is b / (2 (g - b)) (s/F)^2 (g = a - b ln F), the bound
    returned. Johnson's formula stops increasing at ln F = a/b - 1 (half-width ~ radius: far
    outside its validity); beyond ln F_lim = a/b - 2, where d(delta)/dF = b, it is continued by
    that tangent so that every closure has one force (only brackets get there)."""
    if b == 0.0:
        f = (delta_um / a) ** (1.0 / n)
        return f, f / (n * delta_um), 0.0
    if 0.0 < f0 < 0.5 * delta_um / b:
        f = f0
    else:
        f = delta_um / max(a - b * LN_FORCE_GUESS, 2.0 * b)
    g = a - b * math.log(f)
    if g < 2.5 * b:  # near the end of the formula's range
        flim = math.exp(a / b - 2.0)
        dlim = 2.0 * b * flim
        if delta_um >= dlim:
            return flim + (delta_um - dlim) / b, 1.0 / b, 0.0
        f = min(f, 0.75 * flim)
        g = a - b * math.log(f)
    inv = 1.0 / (g - b)
    step = (f * g - delta_um) * inv
    if step >= f:  # keep the iterate positive (cannot happen from the starts above; a guard)
        step = 0.5 * f
    r = step / f
    return f - step, inv, 0.5 * b * inv * r * r


@njit(nogil=True, cache=True)
def law_force(delta_um, a, b, n, f0):
    """(F [N], dF/ddelta [N/um]) of a contact closed by delta > 0: ``law_step`` to convergence."""
    f, df, err = law_step(delta_um, a, b, n, f0)
    for _ in range(60):
        if err < 1e-15:
            break
        f, df, err = law_step(delta_um, a, b, n, f)
    return f, df


@njit(nogil=True, cache=True, inline="always")
def _settled_force(d, a, b, n, f0, steps):
    """law_step from f0, ``steps`` times, then repeated while its error bound is above SETTLE
    (set_load). A branch on each step's error is hard to predict; a count is not."""
    f, df, e = law_step(d, a, b, n, f0)
    for _ in range(steps - 1):
        f, df, e = law_step(d, a, b, n, f)
    for _ in range(30):  # settle: quadratic once close, 1-3 steps from a warm start
        if e <= SETTLE:
            break
        f, df, e = law_step(d, a, b, n, f)
    return f, df, e


@njit(nogil=True, cache=True, inline="always")
def set_load(x, cs, law, steps):
    """(load, dload/dx, bound of the load's error, scale sum |F_j levers_j|) of ContactSet ``cs``
    at x: contact j closes by delta_j = levers_j x - gaps_j and pushes back with F_j(delta_j)
    (``law_step`` with ``law`` (ContactLaw) from cs.forces[j], its force at the previous
    evaluation, ``steps`` times, then repeated while the error bound is above SETTLE; 0 when
    open); load = scale sum F_j levers_j. Below SETTLE the forces are refined
    along with x (``solve_set``), which stops only once the bound is below 1e-11 of the load.
    ``cs.npos`` >= 0: the contacts are in closure order (``closure_order``): npos with levers > 0
    by gap / lever rising, then nneg with levers < 0 by gap / lever falling, then the rest; the
    closed ones of each run are a prefix, so each run stops at its first open contact (whose
    force is then left as it was: only a start for law_step)."""
    gaps, levers, law_a, work, npos, nneg = cs.gaps, cs.levers, cs.law_a, cs.forces, cs.npos, cs.nneg
    b, n, scale = law.b, law.n, law.scale
    m = gaps.size
    g = 0.0
    dg = 0.0
    err = 0.0
    gabs = 0.0
    pos_end = max(npos, 0)
    sorted_end = pos_end + nneg if npos >= 0 else 0
    for run in range(3):  # the two sorted runs, then the contacts in no order
        lo_j = 0 if run == 0 else (pos_end if run == 1 else sorted_end)
        hi_j = pos_end if run == 0 else (sorted_end if run == 1 else m)
        for j in range(lo_j, hi_j):
            d = levers[j] * x - gaps[j]
            if d <= 0.0:
                if run < 2:
                    break  # a sorted run: every contact after it is open too
                work[j] = 0.0
                continue
            f, df, e = _settled_force(d, law_a[j], b, n, work[j], steps)
            work[j] = f
            fl = f * abs(levers[j])
            g += f * levers[j]
            dg += df * levers[j] * levers[j]
            err += e * fl
            gabs += fl
    return g * scale, dg * scale, err * scale, gabs * scale


@njit(nogil=True, cache=True)
def closure_order(gaps, levers, m):
    """(order, npos, nneg): the contacts with levers > 0 by gap / lever rising, then those with
    levers < 0 by gap / lever falling, then those without a lever (set_load's runs). Insertion
    sorts (stable): a unit keeps a few dozen contacts."""
    order = np.empty(m, dtype=np.int64)
    key = np.empty(m)
    npos = nneg = 0
    for j in range(m):  # count the runs, so that each is sorted in place
        if levers[j] > 0.0:
            npos += 1
        elif levers[j] < 0.0:
            nneg += 1
    ip, ineg, irest = 0, npos, npos + nneg
    for j in range(m):
        if levers[j] > 0.0:
            k, v, lo = ip, gaps[j] / levers[j], 0
            ip += 1
        elif levers[j] < 0.0:
            k, v, lo = ineg, -gaps[j] / levers[j], npos  # falling gap / lever: rising -gap / lever
            ineg += 1
        else:
            order[irest] = j
            irest += 1
            continue
        while k > lo and key[k - 1] > v:
            key[k] = key[k - 1]
            order[k] = order[k - 1]
            k -= 1
        key[k] = v
        order[k] = j
    return order, npos, nneg


@njit(nogil=True, cache=True)
def set_bounds(gaps, levers, m):
    """The Bounds of the first m contacts: the first contact turning positive (smallest gap/lever
    over lever > 0) and negative (largest over lever < 0). hi >= lo: free between them; hi < lo:
    preloaded (no coordinate frees every contact). Contacts whose lever is below TINY_LEVER of the
    largest (pins facing a tooth tip or root) cannot bound a rotation: left out; tiny when one of
    them interferes (it pushes at every rotation, with a torque too small to matter, and the
    solver then checks its brackets)."""
    big = 0.0
    for j in range(m):
        big = max(big, abs(levers[j]))
    small = TINY_LEVER * big
    hi = np.inf
    lo = -np.inf
    tiny = False
    for j in range(m):
        if abs(levers[j]) <= small:
            if gaps[j] < 0.0:
                tiny = True
            continue
        r = gaps[j] / levers[j]
        if levers[j] > 0.0:
            if r < hi:
                hi = r
        elif r > lo:
            lo = r
    return Bounds(hi, lo, tiny)


@njit(nogil=True, cache=True, inline="always")
def closure_prediction(cs, law, load, x0):
    """A start for ``solve_set`` far from its last solution: the x at which ContactSet ``cs`` (in
    closure order) would carry ``load``, from x0, the last solution under a smaller load of the same
    sign, if each contact closed at x0 kept its tangent stiffness k_j there (its force
    F_j + k_j (delta_j(x) - delta_j(x0)), F_j from cs.forces) and each contact closing beyond x0 that
    of the last one closed: a piecewise-linear load whose root is found by walking the loaded run
    in closure order (no logarithm). Tangents: Johnson (n = 1) dF/ddelta = F / (delta - b F),
    Palmgren F / (n delta). NaN when there is no prediction: no closure order, a contact of the
    other run closed at x0 (a preloaded set), nothing closed at x0, or a tangent that is not
    positive (forces not of x0)."""
    if cs.npos < 0 or load == 0.0:
        return np.nan
    gaps, levers, forces = cs.gaps, cs.levers, cs.forces
    b, n = law.b, law.n
    first, end = (0, cs.npos) if load > 0.0 else (cs.npos, cs.npos + cs.nneg)
    other, other_end = (cs.npos, cs.npos + cs.nneg) if load > 0.0 else (0, cs.npos)
    if other < other_end and levers[other] * x0 - gaps[other] > 0.0:
        return np.nan
    stiffness = 0.0  # sum k_j L_j^2: the model's dload/dx (unscaled)
    offset = 0.0  # the model's load at x = 0 (unscaled)
    k = 0.0
    j = first
    while j < end:
        lever = levers[j]
        d = lever * x0 - gaps[j]
        if d <= 0.0:
            break
        f = forces[j]
        k = f / (d - b * f) if b > 0.0 else f / (n * d)
        if not (f > 0.0 and k > 0.0 and k < np.inf):
            return np.nan
        stiffness += k * lever * lever
        offset += lever * (f - k * lever * x0)
        j += 1
    if stiffness <= 0.0:
        return np.nan
    target = load / law.scale
    x = (target - offset) / stiffness
    while j < end and levers[j] * x - gaps[j] > 0.0:  # the next contact closes before x: it carries too
        lever = levers[j]
        stiffness += k * lever * lever
        offset -= k * lever * gaps[j]
        x = (target - offset) / stiffness
        j += 1
    return x


@njit(nogil=True, cache=True)
def solve_set(cs, law, load, side, guess, tangent):
    """The SetSolution of ContactSet ``cs`` (ContactLaw ``law``) carrying ``load`` (its sign: the
    direction): its coordinate x and its stiffness there. load = 0: the edge of the free band on
    ``side`` (+1: the positive edge), or the preloaded equilibrium. ``guess``: a start inside the
    bracket (NaN: none).

    Bracket (load > 0; mirrored for load < 0): at the first contact hi the loaded side is still
    free, so load(hi) <= 0. The contact with the largest lever L alone carries the load once it
    has closed by delta(load / (scale L)), at x_t; beyond lo nothing pulls back; so
    load(max(lo, x_t)) >= load. Newton inside the bracket, bisection when a step leaves it. The
    contacts' forces are refined along (FIRST_STEPS ``law_step`` at the first evaluation, then one
    per evaluation while within SETTLE); the bracket moves only
    where the load's error bound cannot flip the sign of the residual, else the forces settle in
    place. Stops when the residual and its error bound are below 1e-11 of the load (or of the
    contacts' loads, at a preloaded equilibrium: SOLVE_RTOL).
    ``tangent``: (load_0, K_0), the load at which ``guess`` was solved and the set's stiffness
    dload/dx there (K_0 NaN: unknown); the solve then starts from the tangent's prediction guess +
    (load - load_0) / K_0 when it lies in the bracket, or from the bracket's loaded end when the
    prediction passes it (saving the evaluation at the guess). Two better starts from it: power-law
    contacts (b = 0, n < 1) under a larger load stiffen at least as one contact does, load ~
    (x - x_e)^(1/n), and a set in closure order under a load more than WALK_RATIO times the last
    is walked (``closure_prediction``); both cut the evaluations of a unit's loop (the crank
    bearings' rollers 27 -> 19, the pins' 53 -> 51 per unit; issue 28)."""
    gaps, levers, law_a, npos, nneg = cs.gaps, cs.levers, cs.law_a, cs.npos, cs.nneg
    b, n, scale = law.b, law.n, law.scale
    m = gaps.size
    hi, lo = cs.bounds.hi, cs.bounds.lo
    if load == 0.0:
        if lo <= hi:
            return SetSolution(hi if side > 0 else lo, np.nan)
        xl, xh = hi, lo
    else:
        jm = 0
        for j in range(m):  # the largest lever on the loaded side
            if levers[j] * load > levers[jm] * load:
                jm = j
        lev = abs(levers[jm])
        dx = cm.law_approach_um(abs(load) / (scale * lev), law_a[jm], b, n) / lev
        xt = gaps[jm] / levers[jm] + (dx if load > 0.0 else -dx)
        if npos >= 0:  # closure order: the first contacts to close, each alone, bound it too (tighter
            # for a small load, where the set is only beginning to close); only levers near the
            # largest: a small lever would need a force beyond the law's range
            first, count = (0, npos) if load > 0.0 else (npos, nneg)
            for j in range(first, first + min(count, 3)):
                lv = abs(levers[j])
                if lv < 0.5 * lev:
                    continue
                dxj = cm.law_approach_um(abs(load) / (scale * lv), law_a[j], b, n) / lv
                xj = gaps[j] / levers[j] + (dxj if load > 0.0 else -dxj)
                xt = min(xt, xj) if load > 0.0 else max(xt, xj)
        if load > 0.0:
            xl = hi
            xh = max(lo, xt)
        else:
            xh = lo
            xl = min(hi, xt)
        if not math.isfinite(guess) and xl < xt < xh:  # preloaded: try the tighter end first
            guess = xt
    if cs.bounds.tiny:  # interfering tip/root contacts: make sure the bracket holds the root
        width = max(xh - xl, 1e-12)
        for _ in range(80):
            if set_load(xl, cs, law, 1)[0] <= load:
                break
            xl -= width
            width *= 2.0
        width = max(xh - xl, 1e-12)
        for _ in range(80):
            if set_load(xh, cs, law, 1)[0] >= load:
                break
            xh += width
            width *= 2.0
    if math.isfinite(guess) and xl < guess < xh:
        x = guess
        if load != 0.0 and tangent[1] > 0.0:
            pred = guess + (load - tangent[0]) / tangent[1]
            if b == 0.0 and n < 1.0 and load * tangent[0] > 0.0 and abs(load) > abs(tangent[0]):
                # a set of power-law contacts stiffens at least as one contact does, load ~ (x - x_e)^(1/n):
                # from the tangent (load_0, K_0), x - x_e = load_0 / (n K_0) there
                pred = guess + tangent[0] / (n * tangent[1]) * ((load / tangent[0]) ** n - 1.0)
            if abs(load) > WALK_RATIO * abs(tangent[0]) and load * tangent[0] > 0.0:  # far: walk the contacts
                walked = closure_prediction(cs, law, load, guess)
                if math.isfinite(walked):
                    pred = walked
            if xl < pred < xh:
                x = pred
            elif (pred >= xh) if load > 0.0 else (pred <= xl):  # past the loaded end: that end is closer
                x = xh if load > 0.0 else xl
    else:
        x = xh if load > 0.0 else (xl if load < 0.0 else 0.5 * (xl + xh))
    tol = 1e-13 * (abs(xl) + abs(xh)) + 1e-300
    steps = FIRST_STEPS if law.b > 0.0 else 1  # (Palmgren's closed form is exact in one)
    for _ in range(300):
        g, dg, err, gabs = set_load(x, cs, law, steps)
        steps = 1
        f = g - load
        ftol = SOLVE_RTOL * max(abs(load), gabs)
        if err <= ftol and abs(f) <= ftol:
            return SetSolution(x, dg if load != 0.0 else np.nan)
        trusted = abs(f) > 2.0 * err  # the sign of f is right: the bracket may move
        if trusted:
            if f > 0.0:
                xh = x
            else:
                xl = x
        xn = x - f / dg if dg > 0.0 else xl - 1.0
        if not (xl < xn < xh):  # bisect on trusted loads; else settle the forces where we are
            xn = 0.5 * (xl + xh) if trusted else x
        if err <= ftol and abs(xn - x) <= tol:
            return SetSolution(xn, dg if load != 0.0 else np.nan)
        x = xn
    return SetSolution(x, np.nan)


@njit(nogil=True, cache=True)
def solve_in_place(a, b):
    """b <- x solving a x = b (n x n, a overwritten): Gaussian elimination with partial pivoting
    (Golub & Van Loan, Matrix Computations, 4th ed., Algorithm 3.4.1). For the discs' translations
    (n = discs): no allocation, so that the loop's kernel runs without numba's runtime."""
    n = b.size
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(a[i, k]) > abs(a[p, k]):
                p = i
        if p != k:
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
            b[k], b[p] = b[p], b[k]
        for i in range(k + 1, n):
            f = a[i, k] / a[k, k]
            for j in range(k + 1, n):
                a[i, j] -= f * a[k, j]
            b[i] -= f * b[k]
    for k in range(n - 1, -1, -1):
        t = b[k]
        for j in range(k + 1, n):
            t -= a[k, j] * b[j]
        b[k] = t / a[k, k]


@njit(nogil=True, cache=True)
def solve_pins(pins, load, side, guess, c, tangent):
    """The SetSolution of the pins (PinSet): their output angle x [rad] at chain torque ``load``
    (``solve_set``; at 0 the dead band's edge on ``side``) for the design's Chain ``c``. With the
    discs translating (docs/elastic.md): each disc q also moves by y_q
    [um] along its eccentric, which closes pin j by radial_j y_q, until its pins' radial resultant
    balances its bearings: r_q = sum_j F_j radial_j + K_y y_q = 0. Solved by turns: x exactly for
    the y's held (the pins' gaps shifted by radial_j y_q: the bracketed solver unchanged), then a
    Newton step on the y's with x re-solved (J = diag(K_yy,q + K_y) - K_xy K_xy^T / K_xx), from the
    last y's, until the residuals are below 1e-10 of the forces. The dead band's edge of a
    translating disc is read at TINY_TORQUE (its radial balance needs a direction). ``tangent``:
    solve_set's (fixed discs only)."""
    cs = pins.contacts
    law = ContactLaw(c.law_b, c.law_n, 1e-6)
    ky = c.radial_stiffness_n_per_um
    if not ky < np.inf:
        return solve_set(cs, law, load, side, guess, tangent)
    pg, pl, pa, pw = cs.gaps, cs.levers, cs.law_a, cs.forces
    pm = pg.size
    pr, pd, tr = pins.radial, pins.disc, pins.translation
    rows = tr.per_disc
    y, ge, jac, res = rows[Y], tr.shifted_gaps_um, tr.jacobian, tr.step_um
    t = side * TINY_TORQUE * c.rated_torque_nm if load == 0.0 else load
    discs = y.size
    last = rows[LAST_POSITIVE] if t > 0.0 else rows[LAST_NEGATIVE]
    for q in range(discs):  # start from the last solution under a load of the same sign (loops: no temporary)
        y[q] = last[q]
    x = guess
    no_tangent = (np.nan, np.nan)
    for _ in range(c.translation_rounds):
        for j in range(pm):
            ge[j] = pg[j] - pr[j] * y[pd[j]]
        shifted = ContactSet(ge, pl, pa, set_bounds(ge, pl, pm), pw, -1, 0)
        x = solve_set(shifted, law, t, side, x, no_tangent).x
        for q in range(discs):  # this round's sums start from zero; so do both signs' last translations
            # (the one of this solve's sign is written back below: a solve starts from the last one's
            # translations only when that one had the same sign)
            rows[RADIAL_FORCE, q] = 0.0
            rows[STIFFNESS_YY, q] = 0.0
            rows[STIFFNESS_XY, q] = 0.0
            rows[FORCE_SCALE, q] = 0.0
            rows[LAST_POSITIVE, q] = 0.0
            rows[LAST_NEGATIVE, q] = 0.0
        kxx = 0.0
        for j in range(pm):
            if pw[j] > 0.0:
                d = pl[j] * x - ge[j]
                f, df, _e = law_step(d, pa[j], c.law_b, c.law_n, pw[j]) if d > 0.0 else (0.0, 0.0, 0.0)
                q = pd[j]
                rows[RADIAL_FORCE, q] += f * pr[j]
                rows[STIFFNESS_YY, q] += df * pr[j] * pr[j]
                rows[STIFFNESS_XY, q] += df * pr[j] * pl[j]
                rows[FORCE_SCALE, q] += f * abs(pr[j])
                kxx += df * pl[j] * pl[j]
        done = True
        for q in range(discs):
            res[q] = rows[RADIAL_FORCE, q] + ky * y[q]
            if abs(res[q]) > 1e-9 * (rows[FORCE_SCALE, q] + ky * abs(y[q])) + 1e-9:
                done = False
        if done:
            break
        for q in range(discs):
            for r in range(discs):
                jac[q, r] = -rows[STIFFNESS_XY, q] * rows[STIFFNESS_XY, r] / kxx if kxx > 0.0 else 0.0
            jac[q, q] += rows[STIFFNESS_YY, q] + ky
        solve_in_place(jac, res)  # res <- the Newton step
        small = True
        for q in range(discs):
            y[q] -= res[q]
            small = small and abs(res[q]) <= TRANSLATION_STEP_UM
        if small:  # a last step this small is taken without re-solving x (its effect is below the figures' digits)
            break
    for q in range(discs):
        last[q] = y[q]
    return SetSolution(x, np.nan)


@njit(nogil=True, cache=True)
def support_deflection_um(t_el, s, support, c, state):
    """Radial deflection of the support bearings [um] (SupportSet ``support``) when the chain
    carries t_el [N m] (side s at 0): from the support set's memo when this torque was solved
    before, else solved from the last solution under a load of the same sign (``state``: the
    unit's SOLVE_STATE; a symmetric set's mirrored load from its last solve) and remembered."""
    memo = support.memo
    st = state[0]
    side = s if t_el == 0.0 else 0.0
    free = -1
    for i in range(memo.torque_nm.size):
        if memo.torque_nm[i] == t_el and memo.side[i] == side:
            return memo.deflection_um[i]
        if free < 0 and np.isnan(memo.torque_nm[i]):
            free = i
    sload = t_el * c.support_force_n_per_nm
    if c.support_symmetric and sload != 0.0 and abs(sload) == st.support_last_load_n:
        ds = s * st.support_last_um
    else:
        k = POSITIVE if s > 0.0 else NEGATIVE
        if support.roller.x_mm.size > 0:  # profiled rollers: by slices, with the crank's tilt
            ds = solve_sliced_set(support.contacts, support.roller, c.support_a, 0.0, cm.PALMGREN_EXPONENT,
                                  c.support_cos_alpha, sload, s)
        else:
            ds = solve_set(support.contacts, ContactLaw(0.0, cm.PALMGREN_EXPONENT, 1.0), sload, s,
                           st.support_start[k], (np.nan, np.nan)).x
        if sload != 0.0:
            st.support_start[k] = ds
        st.support_last_load_n = abs(sload)
        st.support_last_um = abs(ds)
    if free >= 0:
        memo.torque_nm[free] = t_el
        memo.side[free] = side
        memo.deflection_um[free] = ds
    return ds


@njit(nogil=True, cache=True)
def sliced_set_load(x, cs, roller, a, b, n, cos_alpha, tilt_rad):
    """(load sum Q_j levers_j [N], scale sum |Q_j levers_j| [N]) of a bearing's sliced rollers
    (ContactSet ``cs``: roller j closes by levers_j x - gaps_j at its middle) at x: each roller's
    load by slices (``compliance.sliced_roller_load_n``, the straight roller's law a, b, n: the
    support bearings' is Palmgren's for two contacts) with the raceways' misalignment
    tilt cos(psi_j) in its plane (levers_j = cos(alpha) cos(psi_j)): a tilt of the inner ring about
    the bearing's pressure centre moves no roller's middle along its normal, it turns the raceway
    along each roller by the tilt's component in the roller's plane (ISO/TS 16281: psi_j = psi
    cos(phi_j))."""
    load = 0.0
    scale = 0.0
    for j in range(cs.gaps.size):
        lv = cs.levers[j]
        q = cm.sliced_roller_load_n(lv * x - cs.gaps[j], tilt_rad * lv / cos_alpha, roller.x_mm, roller.drop_um, a, b,
                                    n)
        load += q * lv
        scale += q * abs(lv)
    return load, scale


@njit(nogil=True, cache=True)
def solve_sliced_set(cs, roller, a, b, n, cos_alpha, load, side):
    """The coordinate x [um] at which a bearing's sliced rollers (``sliced_set_load``) carry ``load``
    [N] (its sign: the direction; the straight roller's law a, b, n; levers cos(alpha) cos(psi_j)),
    the tilt being roller.tilt_rad_per_n |load|; at load 0 the edge
    of the free band on ``side`` (where the first slice touches), or the preloaded equilibrium.
    The load rises monotonically with x: bracketed by steps doubling from the edges, then Illinois
    regula falsi with bisection, to 1e-12 of the load (or of the rollers' loads at a preloaded
    equilibrium) or 1e-14 of x. Once per design and torque (``support_deflection_um``)."""
    tilt = roller.tilt_rad_per_n * abs(load)
    lowest = np.inf  # the profile's smallest opening (both contacts)
    lift = 0.0  # and the slices' largest distance from the roller's middle [um]
    for k in range(roller.x_mm.size):
        lowest = min(lowest, 2.0 * roller.drop_um[k])
        lift = max(lift, abs(roller.x_mm[k]) * 1e3)
    hi_edge, lo_edge = np.inf, -np.inf
    for j in range(cs.gaps.size):  # the first roller to touch on either side, without the tilt
        lv = cs.levers[j]
        if lv > 0.0:
            hi_edge = min(hi_edge, (cs.gaps[j] + lowest) / lv)
        elif lv < 0.0:
            lo_edge = max(lo_edge, (cs.gaps[j] + lowest) / lv)
    if load == 0.0 and lo_edge <= hi_edge:
        return hi_edge if side > 0.0 else lo_edge
    reach = tilt * lift / cos_alpha  # a tilted roller touches this much earlier [um of x at most]
    xl = min(hi_edge, lo_edge) - reach
    xh = max(hi_edge, lo_edge) + reach
    step = max(1.0, xh - xl)
    fl = sliced_set_load(xl, cs, roller, a, b, n, cos_alpha, tilt)[0] - load
    for _ in range(200):
        if fl <= 0.0:
            break
        xl -= step
        step *= 2.0
        fl = sliced_set_load(xl, cs, roller, a, b, n, cos_alpha, tilt)[0] - load
    step = max(1.0, xh - xl)
    fh = sliced_set_load(xh, cs, roller, a, b, n, cos_alpha, tilt)[0] - load
    for _ in range(200):
        if fh >= 0.0:
            break
        xh += step
        step *= 2.0
        fh = sliced_set_load(xh, cs, roller, a, b, n, cos_alpha, tilt)[0] - load
    x = xh
    last = 0
    for _ in range(400):
        x = cm.illinois_point(xl, fl, xh, fh)
        f, scale = sliced_set_load(x, cs, roller, a, b, n, cos_alpha, tilt)
        f -= load
        if abs(f) <= 1e-12 * max(abs(load), scale) or xh - xl <= 1e-14 * (abs(xl) + abs(xh)):
            return x
        xl, fl, xh, fh, last = cm.illinois_bracket(x, f, xl, fl, xh, fh, last)
    return x
