"""Measured hysteresis loops and transmission-error curves (``rvbacklash bench``; docs/bench-data.md):
from a bench file's samples to the test bench's figures, read by the same functions as the
model's loops (``analysis.loop_reading``), with an uncertainty from the data's noise.

A hysteresis file (torque, output angle, maybe time; design/bench_files.py) goes through:

1. turning points: the zig-zag of the torque with a hysteresis threshold (TURN_FRACTION of the
   torque's range): an extreme counts once the torque has moved back from it by more than the
   threshold, so noise smaller than that never makes a branch (the smoothed sign change of dT);
2. branches: a falling stretch (+peak to -peak) is unload+ while T >= 0 and load- below; a rising
   one unload- below 0 and load+ from 0; several cycles, a start anywhere, partial stretches at
   both ends all land in their branch;
3. drift: the angle read at one torque near each peak (0.95 of the smallest peak of that sign, a
   line through the arriving stretch's samples there) against time: a common slope for both
   signs (least squares), removed from every sample; needs two such readings of one sign;
4. averaging: each branch on a common torque grid (GRID_POINTS plus the definitions' torques):
   at each node a local cubic fit of angle against torque of the k nearest samples of every
   cycle, k growing by sqrt 2 while the wider fit agrees with the narrower ones and its form
   error (the quadratic's value less the cubic's) is not significant, up to +-WINDOW_FRACTION T_R
   (the data choose the window: narrow where the branch bends hardest, at the dead band's ends,
   wide where it is straight). A turning point belongs to both branches it joins (a loop sampled
   at the definitions' torques reaches T_R on its loading branch), a sample at zero torque to
   both branches it joins. Load branches keep only their nodes beyond the dead band (|T| >= x T_R)
   and start at the branch they continue (load+(0) = unload-(0)): the jump through the dead bands
   is no function of torque; the unloading branch's end at T = 0 is fitted centred, with the
   samples its stretch takes past zero before the jump (not one-sided);
5. centring: the middle of the zero-torque width is 0 (as the model's loops);
6. uncertainty: each figure is, linearised, a weighted sum of the samples (the reader's response
   to each node times the node's fit weights); its noise part is that sum's standard deviation
   with each sample's own noise (from differences of neighbouring samples, Gasser et al. 1986:
   no fit enters), its reading part the fits' own bias - the form error and the change to the
   next window, each counted where it stands out of its noise - added in quadrature
   (``uncertainty_noise_k2``, ``uncertainty_reading_k2``; both k = 2).

A TE file (output angle and TE, or output and input angle with the ratio) is averaged onto
TE_POSITIONS equal steps of an output revolution (samples binned by position, the bins' means at
their centres, periodic interpolation of empty bins), its peak-to-peak and its spectrum by order
read as the model's (``analysis.transmission.amplitude_spectrum``; each order divided by the
bins' own averaging, sinc(m / N)).

A TE file of two runs (the forward and backward runs of one unit side by side, or marked by a
direction column) is one unit: each run read as above on the same positions (from the forward
run's first sample), and its lost motion at every output position the gap between the runs, by
the transmission model's definition (``models.kinematics.lost_motion_arcmin``, the upper run as
its ccw flank), its mean, least and largest reported.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from rvbacklash.analysis.hysteresis import HysteresisBranch, RigiditySecant
from rvbacklash.analysis.loop_reading import BRANCHES, SECANT_INTERVALS, loop_figures, secant_key
from rvbacklash.analysis.transmission import SPECTRUM_FLOOR_ARCSEC, SpectralLine, amplitude_spectrum
from rvbacklash.design.bench_files import BenchTable, FileFormat, read_bench_table
from rvbacklash.errors import InputError
from rvbacklash.models.kinematics import ARCSEC_PER_RAD, lost_motion_arcmin
from rvbacklash.sampling.seeds import check_seed
from rvbacklash.results import EXPORT, Result

TURN_FRACTION = 0.2  # hysteresis threshold of the turning points, of the torque's range
GRID_POINTS = 41  # nodes per branch (the definitions' torques are added)
WINDOW_FRACTION = 0.05  # the widest half-width of a node's local fit, of T_R (the data choose the width)
AGREEMENT = 3.0  # sigmas: a wider fit is taken while it agrees with the narrower ones (its form error not significant)
JUMP_MARGIN = 0.25  # an unloading branch's end is fitted with its stretch's samples this share of the way to the jump
LOCAL_NOISE = 41  # samples around each one whose differences give its own noise
MIN_FIT_POINTS = 8  # samples a branch needs
REACH_TOLERANCE = 0.02  # a branch reaches a torque if it comes within this fraction of T_R of it (fit extrapolates)
TE_POSITIONS = 1024
LEADING_ORDERS = 8
FIGURES = ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin", "hysteresis_loss_j")


@dataclass(frozen=True, repr=False)
class Placement(Result):
    """A measured figure in the design's predicted production run."""

    figure: str  # the JSON field name of the figure
    measured: float
    percentile: float  # [%] of the predicted units at or below the measured value
    outside: bool  # beyond the 0.135-99.865 % band
    predicted_q00135: float
    predicted_q05: float
    predicted_median: float
    predicted_q95: float
    predicted_q99865: float
    explaining_factors: tuple[str, ...]  # the factor groups whose total Sobol index dominates (flagged units only)
    beyond_every_predicted_unit: bool  # no tolerance reaches it: a model input is off (calibrate), or the unit


@dataclass(frozen=True, repr=False)
class BenchLoop(Result):
    """One unit's measured hysteresis loop read by the test bench's definitions."""

    source: str
    kind: str  # "hysteresis"
    rated_torque_nm: float
    rated_torque_from: str  # given | design | loop peaks
    measuring_torque_fraction: float
    rigidity_interval_fraction: tuple[float, float]
    lost_motion_arcmin: float
    backlash_arcmin: float
    torsional_rigidity_nm_per_arcmin: float
    rigidity_secants: tuple[RigiditySecant, ...]
    hysteresis_loss_j: float
    uncertainty_k2: dict[str, float]  # expanded uncertainty (k = 2, ~95 %) of each figure from the data's noise
    samples: int
    cycles: int  # peaks of each sign (the fewer): cycles whose turning points the file holds
    branch_stretches: dict[str, int]  # stretches found per branch, partial ones included
    noise_arcmin: float  # sigma of the samples about the loop (from differences of neighbouring samples)
    drift_arcmin_per_s: float | None  # removed; per sample when the file has no time column; None: not estimated
    drift_per: str  # s | sample
    centring_offset_arcmin: float  # the angle subtracted: the middle of the zero-torque width
    torque_peaks_nm: tuple[float, float]  # mean of the positive and negative peaks
    notes: tuple[str, ...]
    loop: tuple[HysteresisBranch, ...]  # the cycles averaged on the grid, centred
    placement: tuple[Placement, ...] = ()
    torque_nm: np.ndarray = field(default=None, metadata={EXPORT: False})  # samples, drift removed, centred
    angle_arcmin: np.ndarray = field(default=None, metadata={EXPORT: False})
    branch_index: np.ndarray = field(default=None, metadata={EXPORT: False})  # into BRANCHES
    node_sigma_arcmin: dict = field(default=None, metadata={EXPORT: False})
    metadata: tuple[str, ...] = ()  # the file's lines above its header (a rig's metadata), as written
    uncertainty_noise_k2: dict[str, float] = field(default_factory=dict)  # the part of uncertainty_k2 from the noise
    uncertainty_reading_k2: dict[str, float] = field(default_factory=dict)  # and from the reader's own fits (bias)
    sample_sigma_arcmin: np.ndarray = field(default=None, metadata={EXPORT: False})  # each sample's own noise

    def figures(self) -> dict[str, float]:
        return {k: getattr(self, k) for k in FIGURES}

    def rows(self) -> list[dict]:
        return [{"source": self.source, "branch": b.branch, "torque_nm": t, "angle_arcmin": a}
                for b in self.loop for t, a in zip(b.torque_nm, b.angle_arcmin)]

    def summary(self) -> list[str]:
        u = self.uncertainty_k2
        return [f"{self.source}: lost motion {self.lost_motion_arcmin:.4f} ± {u['lost_motion_arcmin']:.4f} arcmin, "
                f"backlash {self.backlash_arcmin:.4f} ± {u['backlash_arcmin']:.4f} arcmin, rigidity "
                f"{self.torsional_rigidity_nm_per_arcmin:.1f} ± {u['torsional_rigidity_nm_per_arcmin']:.1f} "
                f"N m/arcmin",
                f"{self.cycles} cycles, {self.samples} samples, noise {self.noise_arcmin:.4f} arcmin"]


@dataclass(frozen=True, repr=False)
class BenchTransmissionError(Result):
    """One unit's measured transmission-error curve over an output revolution."""

    source: str
    kind: str  # "transmission_error"
    samples: int
    revolutions: float  # output revolutions the samples span
    positions: int
    te_peak_to_peak_arcsec: float
    te_min_arcsec: float
    te_max_arcsec: float
    noise_arcsec: float  # sigma of the samples about the averaged curve
    spectrum_floor_arcsec: float  # lines below are not listed (noise floor: 5 x the spectrum's median line)
    leading_orders: tuple[SpectralLine, ...]
    notes: tuple[str, ...]
    placement: tuple[Placement, ...] = ()
    output_angle_deg: np.ndarray = field(default=None, metadata={EXPORT: True})
    te_arcsec: np.ndarray = field(default=None, metadata={EXPORT: True})
    spectrum_amplitude_arcsec: np.ndarray = field(default=None, metadata={EXPORT: True})
    metadata: tuple[str, ...] = ()  # the file's lines above its header (a rig's metadata), as written

    def figures(self) -> dict[str, float]:
        return {"te_peak_to_peak_arcsec": self.te_peak_to_peak_arcsec}

    def rows(self) -> list[dict]:
        return [{"source": self.source, "output_angle_deg": float(a), "te_arcsec": float(t)}
                for a, t in zip(self.output_angle_deg, self.te_arcsec)]

    def summary(self) -> list[str]:
        lines = ", ".join(f"{s.order}: {s.amplitude_arcsec:.2f}" for s in self.leading_orders[:5])
        return [f"{self.source}: TE peak-to-peak {self.te_peak_to_peak_arcsec:.2f} arcsec over {self.revolutions:.2f} "
                f"revolutions, noise {self.noise_arcsec:.2f} arcsec", f"leading orders [arcsec]: {lines or 'none'}"]


@dataclass(frozen=True, repr=False)
class BenchTwoRunTE(Result):
    """One unit's measured TE in both directions (the forward and backward runs of one file) and
    its lost motion against output position: the gap between the runs."""

    source: str
    kind: str  # "transmission_error_two_runs"
    forward: BenchTransmissionError  # each run read as a TE file, on the same output positions
    backward: BenchTransmissionError
    te_peak_to_peak_arcsec: float  # the forward run's
    te_peak_to_peak_backward_arcsec: float
    ccw_run: str  # forward | backward: the upper curve, read as the model's ccw flank
    lost_motion_mean_arcmin: float  # the gap between the runs, averaged over the output revolution
    lost_motion_min_arcmin: float
    lost_motion_max_arcmin: float
    notes: tuple[str, ...]
    placement: tuple[Placement, ...] = ()
    metadata: tuple[str, ...] = ()  # the file's lines above its header (a rig's metadata), as written
    output_angle_deg: np.ndarray = field(default=None, metadata={EXPORT: True})
    lost_motion_arcmin: np.ndarray = field(default=None, metadata={EXPORT: True})  # at each output position

    def figures(self) -> dict[str, float]:
        return {"te_peak_to_peak_arcsec": self.te_peak_to_peak_arcsec,
                "te_peak_to_peak_backward_arcsec": self.te_peak_to_peak_backward_arcsec,
                "lost_motion_mean_arcmin": self.lost_motion_mean_arcmin}

    def rows(self) -> list[dict]:
        return [{"source": self.source, "output_angle_deg": float(a), "te_forward_arcsec": float(f),
                 "te_backward_arcsec": float(b), "lost_motion_arcmin": float(g)}
                for a, f, b, g in zip(self.output_angle_deg, self.forward.te_arcsec, self.backward.te_arcsec,
                                      self.lost_motion_arcmin)]

    def summary(self) -> list[str]:
        def lines(u):
            return ", ".join(f"{s.order}: {s.amplitude_arcsec:.2f}" for s in u.leading_orders[:5]) or "none"
        return [f"{self.source}: TE peak-to-peak {self.te_peak_to_peak_arcsec:.2f} arcsec forward, "
                f"{self.te_peak_to_peak_backward_arcsec:.2f} backward; lost motion {self.lost_motion_mean_arcmin:.4f} "
                f"arcmin mean ({self.lost_motion_min_arcmin:.4f} .. {self.lost_motion_max_arcmin:.4f})",
                f"leading orders [arcsec]: forward {lines(self.forward)}; backward {lines(self.backward)}"]


@dataclass(frozen=True, repr=False)
class BenchResult(Result):
    """A batch of measured units (one file each), and with a design their place in its production run."""

    design_name: str | None
    samples_predicted: int  # units of the predicted production run (0: no design)
    seed: int
    units: tuple[BenchLoop | BenchTransmissionError | BenchTwoRunTE, ...]
    spread: dict[str, dict[str, float]]  # figure -> {"measured_sigma": .., "predicted_sigma": .. | None, "units": n}
    warnings: tuple[str, ...] = ()  # of the design's predictions, e.g. its lost motion read in a stick band

    def rows(self) -> list[dict]:
        out = []
        for u in self.units:
            row = {"source": u.source, "kind": u.kind, **u.figures()}
            if isinstance(u, BenchLoop):
                row.update({f"{k}_u95": v for k, v in u.uncertainty_k2.items()})
            for p in u.placement:
                row[f"{p.figure}_percentile"] = p.percentile
            out.append(row)
        return out

    def summary(self) -> list[str]:
        return [line for u in self.units for line in u.summary()]


# --- hysteresis loops ---------------------------------------------------------------------------

def turning_points(torque: np.ndarray, threshold: float) -> list[int]:
    """Indices of the torque's alternating extremes (zig-zag): an extreme is confirmed once the
    torque has moved back from it by more than ``threshold`` [N m]; the first and last samples
    are not turning points, nor is a first extreme within a quarter of the threshold of the first
    sample (a record starting at zero torque: the sensor's noise before the first real stretch)."""
    ext: list[int] = []
    mode, hi, lo = 0, 0, 0
    for i in range(1, torque.size):
        if mode >= 0 and torque[i] > torque[hi]:
            hi = i
        if mode <= 0 and torque[i] < torque[lo]:
            lo = i
        if mode >= 0 and torque[hi] - torque[i] > threshold:
            ext.append(hi)
            mode, lo = -1, i
        elif mode <= 0 and torque[i] - torque[lo] > threshold:
            ext.append(lo)
            mode, hi = 1, i
    ext = [k for k in ext if 0 < k < torque.size - 1]
    if ext and abs(torque[ext[0]] - torque[0]) < 0.25 * threshold:
        ext = ext[1:]
    return ext


def _stretches(torque: np.ndarray, turns: list[int]) -> list[tuple[int, int, int, bool]]:
    """(start, stop, direction +1 rising / -1 falling, complete: between two turning points); a
    turning point ends one stretch and starts the next (both hold it)."""
    bounds = [0, *turns, torque.size - 1]
    out = []
    for k, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
        if b <= a:
            continue
        direction = 1 if torque[b] > torque[a] else -1
        out.append((a, b, direction, 0 < k < len(bounds) - 2))
    return out


def _label(torque: np.ndarray, stretches) -> np.ndarray:
    """Branch index of every sample (BRANCHES order): rising -> unload- below 0, load+ from 0;
    falling -> unload+ from 0, load- below. A turning point is labelled by the stretch it starts
    (the branches it belongs to: ``_members``)."""
    idx = np.empty(torque.size, int)
    for a, b, d, _ in stretches:
        t = torque[a:b + 1]
        idx[a:b + 1] = np.where(t >= 0, 0, 3) if d > 0 else np.where(t >= 0, 1, 2)
    return idx


def _members(torque: np.ndarray, stretches) -> np.ndarray:
    """(4, samples) which branches each sample belongs to (BRANCHES order): a rising stretch's
    samples at T <= 0 to unload-, at T >= 0 to load+; a falling one's at T >= 0 to unload+, at
    T <= 0 to load-. A turning point belongs to the branch that arrives at it and to the one that
    leaves it, a sample at exactly zero torque to both branches it joins: each branch holds its
    own ends (a loop sampled at the definitions' torques, as the model writes it, reaches T_R)."""
    out = np.zeros((len(BRANCHES), torque.size), bool)
    for a, b, d, _ in stretches:
        t = torque[a:b + 1]
        up, down = (0, 3) if d > 0 else (1, 2)
        out[up, a:b + 1] |= t >= 0
        out[down, a:b + 1] |= t <= 0
    return out


def _drift(time: np.ndarray, angle: np.ndarray, torque: np.ndarray, stretches, span: float) -> float | None:
    """Common slope [arcmin per time unit] of the angle read at one torque near each peak, on the
    stretch arriving at it (a line through its samples within +-3 % of the torque range of
    0.95 x the smallest peak of that sign), against time: pooled least squares over both signs;
    None with fewer than two such readings of one sign."""
    groups: dict[int, list[tuple[float, float]]] = {1: [], -1: []}
    arriving = [(a, b, d) for a, b, d, complete in stretches if b < torque.size - 1]  # ends at a turning point
    for sign in (1, -1):
        ends = [sign * torque[b] for a, b, d in arriving if d == sign]
        if not ends:
            continue
        level = 0.95 * min(ends)
        for a, b, d in arriving:
            if d != sign:
                continue
            t, y, s = torque[a:b + 1] * sign, angle[a:b + 1], time[a:b + 1]
            near = np.abs(t - level) <= 0.03 * span
            if near.sum() < 3:
                continue
            slope, icpt = np.polyfit(t[near] - level, y[near], 1)
            groups[sign].append((float(np.mean(s[near])), float(icpt)))
    num = den = 0.0
    for pts in groups.values():
        if len(pts) < 2:
            continue
        t, a = np.array(pts).T
        num += float(np.sum((t - t.mean()) * (a - a.mean())))
        den += float(np.sum((t - t.mean()) ** 2))
    return num / den if den > 0 else None


def _middle_guess(torque: np.ndarray, angle: np.ndarray, stretches) -> float:
    """The loop's middle angle before it is read: the mean of the median angles at which the
    rising and the falling stretches cross zero torque (interpolated between the two samples
    around the crossing); without a crossing of each kind, the middle of the angles at the torque's
    extremes."""
    at_zero: dict[int, list[float]] = {1: [], -1: []}
    for a, b, d, _ in stretches:
        t, y = torque[a:b + 1] * d, angle[a:b + 1]  # rising in t
        cross = np.nonzero((t[:-1] < 0) & (t[1:] >= 0))[0]
        if cross.size:
            i = int(cross[0])
            w = -t[i] / (t[i + 1] - t[i])
            at_zero[d].append(float(y[i] + w * (y[i + 1] - y[i])))
    if at_zero[1] and at_zero[-1]:
        return 0.5 * (float(np.median(at_zero[1])) + float(np.median(at_zero[-1])))
    return 0.5 * (float(angle[np.argmax(torque)]) + float(angle[np.argmin(torque)]))


def _before_the_jump(torque: np.ndarray, angle: np.ndarray, stretches, members: np.ndarray,
                     middle: float) -> tuple[np.ndarray, dict[str, float]]:
    """Samples of the loading branches taken before the angle has crossed the loop's middle (the
    jump through the dead bands at T = +-T_f: there the angle is still the stretch's unloading
    branch, continued past zero torque), and for each loading branch the median |torque| of the
    first sample past the jump (0 when no stretch crosses)."""
    out = np.zeros(torque.size, bool)
    where: dict[str, list[float]] = {"load+": [], "load-": []}
    for a, b, d, _ in stretches:
        k = 0 if d > 0 else 2  # load+ on a rising stretch, load- on a falling one
        on = np.arange(a, b + 1)[members[k, a:b + 1]]
        crossed = d * (angle[on] - middle) >= 0
        first = int(np.argmax(crossed)) if crossed.any() else on.size
        out[on[:first]] = True
        if 0 < first < on.size:
            where[BRANCHES[k]].append(abs(float(torque[on[first]])))
    return out, {k: float(np.median(v)) if v else 0.0 for k, v in where.items()}


def _noise(torque: np.ndarray, angle: np.ndarray, fit: np.ndarray) -> tuple[float, np.ndarray]:
    """The noise of the samples about the loop [arcmin]: sigma, and each sample's own (the larger of
    sigma and the noise of the LOCAL_NOISE samples around it on its branch: a torque sensor's noise
    moves the angle by the branch's slope times it, most where the branch is steepest). From
    differences (Gasser, Sroka & Jennen-Steinmetz, Biometrika 73, 1986): each sample against the
    line through its neighbours in torque on its branch, e_i = [a_i - (1 - w) a_i-1 - w a_i+1] /
    sqrt(1 + (1 - w)^2 + w^2), robust (1.4826 x the median absolute deviation; locally 1.4826 x
    the median |e|). No fit enters: a noiseless loop reads about 0 (its curvature over two sample
    steps), not a fit's misfit."""
    parts, local = [], []
    for k in range(fit.shape[0]):
        sel = np.nonzero(fit[k])[0]
        o = sel[np.argsort(torque[sel], kind="stable")]
        t, a = torque[o], angle[o]
        if t.size < 3:
            continue
        span = t[2:] - t[:-2]
        ok = span > 0
        w = np.where(ok, (t[1:-1] - t[:-2]) / np.where(ok, span, 1.0), 0.5)
        e = (a[1:-1] - ((1 - w) * a[:-2] + w * a[2:])) / np.sqrt(1 + (1 - w) ** 2 + w ** 2)
        e = np.abs(e[ok])
        parts.append(e)
        if e.size:
            m = min(LOCAL_NOISE, e.size)
            padded = np.pad(e, (m // 2, m - 1 - m // 2), mode="edge")
            around = 1.4826 * np.median(np.lib.stride_tricks.sliding_window_view(padded, m), axis=1)
            local.append((o[1:-1][ok], around))
    r = np.concatenate(parts) if parts else np.zeros(0)
    sigma = float(1.4826 * np.median(r)) if r.size else 0.0
    each = np.full(torque.size, sigma)
    for idx, around in local:
        np.maximum.at(each, idx, around)
    return sigma, each


def _beyond_noise(kernel: np.ndarray, angle: np.ndarray, sigma: np.ndarray) -> float:
    """|D| less its noise, sqrt(max(0, D^2 - sum (kernel_i sigma_i)^2)), of a difference D =
    kernel . angle (the kernel sums to 0: a systematic departure, read where it stands out of the noise)."""
    dv = float(kernel @ angle)
    return math.sqrt(max(dv * dv - float(np.sum((kernel * sigma) ** 2)), 0.0))


@dataclass(frozen=True)
class NodeFit:
    """One node of a branch averaged from its samples: value = weights . angle[samples]; the fit's
    form error read as form_weights . angle[samples] (the quadratic's value less the cubic's over the
    same samples) and its window's as shift_weights . angle[samples] (the next narrower fit's value
    less this one's; the next wider one's for the narrowest)."""

    value: float  # [arcmin]
    samples: np.ndarray  # indices into the loop's samples
    weights: np.ndarray  # the fit's equivalent kernel at the node (they sum to 1)
    form_weights: np.ndarray  # (they sum to 0)
    shift_weights: np.ndarray  # (they sum to 0)
    window_nm: float  # the largest |T - node| of the samples fitted


def _fit_sizes(first: int, count: int) -> list[int]:
    """Numbers of nearest samples tried at a node: ``first``, then by a factor sqrt 2 to ``count``."""
    out, k = [first], float(first)
    while True:
        k *= math.sqrt(2.0)
        if int(round(k)) >= count:
            break
        if int(round(k)) > out[-1]:
            out.append(int(round(k)))
    return out + [count] if count > out[-1] else out


def _padded(w: np.ndarray, n: int) -> np.ndarray:
    out = np.zeros(n)
    out[:w.size] = w
    return out


def _distinct_prefix(t_sorted: np.ndarray, count: int) -> int | None:
    """The fewest leading samples holding ``count`` distinct torques (None: the branch has fewer)."""
    scale = max(float(np.max(np.abs(t_sorted))), 1.0) if t_sorted.size else 1.0
    new = np.ones(t_sorted.size, bool)
    seen: list[float] = []
    for i, v in enumerate(t_sorted):
        new[i] = all(abs(v - s) > 1e-9 * scale for s in seen)
        if new[i]:
            seen.append(float(v))
            if len(seen) == count:
                return i + 1
    return None


def _local_fit(t: np.ndarray, a: np.ndarray, sigma: np.ndarray, at: float, half: float) -> NodeFit | None:
    """The angle at torque ``at`` from a cubic least-squares fit of the k nearest samples, k growing
    by sqrt 2 from the fewest holding 4 distinct torques to every sample within +-``half`` (Lepski's
    balance of bias and noise): a wider fit is taken while it agrees with every narrower one taken,
    |f_k - f_j| <= AGREEMENT |(w_k - w_j) sigma|, and while its form error d - the quadratic's value
    less the cubic's over the same samples - is not both significant (d^2 > AGREEMENT^2 var d) and
    above the fit's own noise (d^2 - var d > |w_k sigma|^2). With 3 distinct torques only, the
    quadratic through them. ``sigma``: each sample's noise. None: fewer than 3 distinct torques."""
    d = t - at
    order = np.argsort(np.abs(d), kind="stable")
    first = _distinct_prefix(d[order], 4)
    if first is None:
        first = _distinct_prefix(d[order], 3)
        if first is None:
            return None
        idx = order[:first]
        quad = _poly_weights(d[idx], 2)
        zero = np.zeros(first)
        return NodeFit(float(quad @ a[idx]), idx, quad, zero, zero, float(np.max(np.abs(d[idx]))))
    within = int(np.count_nonzero(np.abs(d) <= half))
    taken: list[tuple[int, float, np.ndarray, np.ndarray]] = []  # (k, value, weights, form weights)
    rejected = None
    for k in _fit_sizes(first, max(within, first)):
        idx = order[:k]
        s = sigma[idx]
        cubic, quad = _poly_weights(d[idx], 3), _poly_weights(d[idx], 2)
        value, form = float(cubic @ a[idx]), quad - cubic
        fit = (k, value, cubic, form)
        if taken:
            dv, var = float(form @ a[idx]), float(np.sum((form * s) ** 2))
            bent = dv * dv > AGREEMENT ** 2 * var and dv * dv - var > float(np.sum((cubic * s) ** 2))
            apart = any(abs(value - fj) > AGREEMENT * float(np.linalg.norm((cubic - _padded(wj, k)) * s))
                        for _, fj, wj, _ in taken)
            if bent or apart:
                rejected = fit
                break
        taken.append(fit)
    k, value, w, form = taken[-1]
    other = taken[-2] if len(taken) > 1 else rejected
    n = max(k, other[0]) if other is not None else k
    shift = _padded(other[2], n) - _padded(w, n) if other is not None else np.zeros(n)
    return NodeFit(value, order[:n], _padded(w, n), _padded(form, n), shift, float(np.max(np.abs(d[order[:k]]))))


def _poly_weights(d: np.ndarray, degree: int) -> np.ndarray | None:
    """The equivalent kernel at d = 0 of a least-squares polynomial of ``degree`` in d: value = w . a;
    None: fewer distinct d than coefficients."""
    scale = float(np.max(np.abs(d))) if d.size else 0.0
    if scale <= 0 or d.size <= degree:
        return None
    basis = np.vander(d / scale, degree + 1, increasing=True)
    u, s, vt = np.linalg.svd(basis, full_matrices=False)
    if s[-1] <= 1e-9 * s[0]:
        return None
    return (vt.T[0] / s) @ u.T


def _grid(start: float, end: float, extra: Sequence[float]) -> np.ndarray:
    grid = np.linspace(start, end, GRID_POINTS)
    lo, hi = min(start, end), max(start, end)
    t = np.unique(np.concatenate([grid, [x for x in extra if lo <= x <= hi]]))
    return t if end >= start else t[::-1]


def read_loop(table: BenchTable, rated_torque_nm: float | None = None, measuring_fraction: float = 0.03,
              interval: Sequence[float] = (0.5, 1.0), rated_from: str = "given") -> BenchLoop:
    """The figures of one measured loop (module docstring); ``rated_torque_nm`` None: the mean of
    the loop's smaller peak magnitudes (said in ``rated_torque_from``)."""
    where = table.path
    col_t = f"{where}: column '{table.headers['torque']}'"
    torque, angle = table.columns["torque"].copy(), table.columns["angle"].copy()
    has_time = "time" in table.columns
    time = table.columns["time"] if has_time else np.arange(torque.size, dtype=float)
    if torque.size < 4 * MIN_FIT_POINTS:
        raise InputError(where, torque.size, f"samples; allowed: at least {4 * MIN_FIT_POINTS} (a loop of four "
                                             f"branches)")
    span = float(torque.max() - torque.min())
    turns = turning_points(torque, TURN_FRACTION * span) if span > 0 else []
    stretches = _stretches(torque, turns)
    idx = _label(torque, stretches)
    members = _members(torque, stretches)
    counts = {b: sum(int(np.count_nonzero(members[k, a:e + 1]) >= 2) for a, e, _, _ in stretches)
              for k, b in enumerate(BRANCHES)}
    missing = [b for k, b in enumerate(BRANCHES)
               if counts[b] == 0 or np.count_nonzero(members[k]) < MIN_FIT_POINTS]
    if missing:
        found = [b for b in BRANCHES if b not in missing]
        raise InputError(col_t, allowed=f"found {', '.join(found) or 'no branch'} only (missing {', '.join(missing)}); "
                                        f"allowed: a loop 0 -> +T -> 0 -> -T -> 0 with all four branches")
    peaks_p = [torque[k] for k in turns if torque[k] > 0] or [torque.max()]
    peaks_m = [torque[k] for k in turns if torque[k] < 0] or [torque.min()]
    peaks = (float(np.mean(peaks_p)), float(np.mean(peaks_m)))
    if rated_torque_nm is None:
        rated_torque_nm, rated_from = min(peaks[0], -peaks[1]), "loop peaks"
    tr = float(rated_torque_nm)
    x = measuring_fraction * tr
    lo, hi = interval
    need = max(hi, *(h for _, h in SECANT_INTERVALS)) * tr
    for b, sign in (("load+", 1), ("load-", -1)):
        reach = float(np.max(sign * torque[members[BRANCHES.index(b)]]))
        if reach < need - REACH_TOLERANCE * tr:
            raise InputError(col_t, allowed=f"{b} reaches {sign * reach:g} N m only; allowed: a loop reaching "
                                            f"{'+' if sign > 0 else '-'}{need:g} N m ({max(hi, 1.0):g} T_R, "
                                            f"T_R = {tr:g} N m)")
    notes = list(table.notes)
    drift = _drift(time, angle, torque, stretches, span)
    if drift is None:
        notes.append("drift not estimated (fewer than two torque peaks of one sign)")
    else:
        angle = angle - drift * (time - time[0])
    cycles = min(sum(torque[k] > 0 for k in turns), sum(torque[k] < 0 for k in turns))  # a peak of each sign
    fit = members.copy()
    jump, jump_nm = _before_the_jump(torque, angle, stretches, members, _middle_guess(torque, angle, stretches))
    for load, end in (("load+", "unload-"), ("load-", "unload+")):
        k = BRANCHES.index(load)
        before = members[k] & jump
        fit[k] &= ~(before & (np.abs(torque) < x))  # the loading branch is read from x T_R on, past its jump
        # an unloading branch's end at zero torque is its stretch's angle there: read with the
        # stretch's samples on both sides of zero, short of the jump (a fit centred at T = 0)
        fit[BRANCHES.index(end)] |= before & (np.abs(torque) < JUMP_MARGIN * jump_nm[load])
    noise, sigma = _noise(torque, angle, fit)
    half = WINDOW_FRACTION * tr
    secant_torques = tuple(f * tr for iv in SECANT_INTERVALS for f in iv)
    specs = (("load+", 0.0, tr, (x, lo * tr, hi * tr, *secant_torques)), ("unload+", tr, 0.0, (x,)),
             ("load-", 0.0, -tr, (-x, -lo * tr, -hi * tr, *(-s for s in secant_torques))), ("unload-", -tr, 0.0, (-x,)))
    fitted = _average(torque, angle, sigma, fit, specs, x, half, col_t)
    branches, offset = _centred(fitted)
    figs = loop_figures(branches, tr, measuring_fraction, interval)
    kernel, form, shift = _responses(branches, fitted, angle.size, noise, tr, measuring_fraction, interval, figs)
    u_noise = {k: float(np.linalg.norm(w * sigma)) for k, w in kernel.items()}
    u_reading = {k: math.hypot(_beyond_noise(form[k], angle, sigma), _beyond_noise(shift[k], angle, sigma))
                 for k in form}
    loop = tuple(HysteresisBranch(k, tuple(float(v) for v in branches[k][0]), tuple(float(v) for v in branches[k][1]))
                 for k in BRANCHES)
    secants = tuple(RigiditySecant(a, b, figs[secant_key(a, b)]) for a, b in SECANT_INTERVALS)
    sigmas = {k: np.array([float(np.linalg.norm(f.weights * sigma[f.samples])) for f in fs])
              for k, (_, fs) in fitted.items()}
    unc = {k: 2.0 * math.hypot(u_noise[k], u_reading[k]) for k in FIGURES}
    return BenchLoop(
        where, "hysteresis", tr, rated_from, measuring_fraction, (float(lo), float(hi)), figs["lost_motion_arcmin"],
        figs["backlash_arcmin"], figs["torsional_rigidity_nm_per_arcmin"], secants, figs["hysteresis_loss_j"],
        unc, int(torque.size), int(cycles), counts, noise, drift,
        "s" if has_time else "sample", float(offset), peaks, tuple(notes), loop, (), torque, angle - offset, idx,
        sigmas, uncertainty_noise_k2={k: 2.0 * u_noise[k] for k in FIGURES},
        uncertainty_reading_k2={k: 2.0 * u_reading[k] for k in FIGURES}, sample_sigma_arcmin=sigma)


def _average(torque, angle, sigma, fit, specs, x, half, col_t) -> dict[str, tuple[np.ndarray, list[NodeFit]]]:
    """Each branch's nodes and their fits from the samples ``fit`` marks (step 4)."""
    fitted: dict[str, tuple[np.ndarray, list[NodeFit]]] = {}
    for name, start, end, extra in specs:
        sel = np.nonzero(fit[BRANCHES.index(name)])[0]
        t, a, s = torque[sel], angle[sel], sigma[sel]
        nodes = _grid(start, end, extra)
        if name.startswith("load"):
            nodes = nodes[np.abs(nodes) >= x * (1 - 1e-12)]  # beyond the dead band's jump
        fits = []
        for node in nodes:
            f = _local_fit(t, a, s, float(node), half)
            if f is None:
                raise InputError(col_t, allowed=f"{name} has fewer than 3 distinct torques; allowed: a loop whose "
                                                f"branches are sampled at 3 torques or more")
            fits.append(dataclasses.replace(f, samples=sel[f.samples]))
        fitted[name] = (nodes, fits)
    # load branches start where the branch they continue ends (the jump is no function of torque)
    for load, before in (("load+", "unload-"), ("load-", "unload+")):
        n, f = fitted[load]
        fitted[load] = (np.concatenate([[0.0], n]), [fitted[before][1][-1], *f])
    return fitted


def _centred(fitted) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], float]:
    """The branches with the middle of the zero-torque width at 0 (step 5), and that offset."""
    values = {k: (n, np.array([f.value for f in fs])) for k, (n, fs) in fitted.items()}
    offset = 0.5 * (values["unload+"][1][-1] + values["unload-"][1][-1])
    return {k: (n, v - offset) for k, (n, v) in values.items()}, float(offset)


def _responses(branches, fitted, samples, noise, tr, x, interval, figs) -> tuple[dict, dict]:
    """Each figure as a weighted sum of the samples, linearised: kernel = sum_nodes g_node w_node
    (g the reader's response to the node's angle, a finite step; w the node's fit), and its form
    error's kernel = sum_nodes g_node (quadratic - cubic)_node. Nodes whose fits share samples are
    correlated through them: counted exactly."""
    kernel = {k: np.zeros(samples) for k in figs}
    form = {k: np.zeros(samples) for k in figs}
    shift = {k: np.zeros(samples) for k in figs}
    for name, (nodes, values) in branches.items():
        for i, f in enumerate(fitted[name][1]):
            if name.startswith("load") and i == 0:
                continue  # that node is the unload branch's end, counted there
            step = max(1e-6, 1e-3 * noise)
            moved = dict(branches)
            v = values.copy()
            v[i] += step
            moved[name] = (nodes, v)
            if name.startswith("unload") and i == len(v) - 1:  # the load branch starts at this node too
                load = "load+" if name == "unload-" else "load-"
                lv = branches[load][1].copy()
                lv[0] += step
                moved[load] = (branches[load][0], lv)
            after = loop_figures(moved, tr, x, interval)
            for k in kernel:
                g = (after[k] - figs[k]) / step
                if not math.isfinite(g) or g == 0.0:
                    continue
                np.add.at(kernel[k], f.samples, g * f.weights)
                np.add.at(form[k], f.samples, g * f.form_weights)
                np.add.at(shift[k], f.samples, g * f.shift_weights)
    return kernel, form, shift


# --- transmission error -------------------------------------------------------------------------

def read_te(table: BenchTable, ratio: float | None = None, positions: int = TE_POSITIONS) -> BenchTransmissionError:
    """The TE curve of one measured unit over an output revolution (module docstring)."""
    out_arcmin, te = _run_te(table, ratio, "")
    deg = out_arcmin / 60.0
    return _te_reading(table.path, f"{table.path}: column '{table.headers['angle']}'", deg, te, positions,
                       float(deg[0]), list(table.notes))[0]


def _run_te(table: BenchTable, ratio: float | None, run: str) -> tuple[np.ndarray, np.ndarray]:
    """(output angle [arcmin], TE [arcsec]) of one run (``run`` "" forward, "_bw" backward)."""
    out_arcmin = table.columns["angle" + run]
    if "te" + run in table.columns:
        return out_arcmin, table.columns["te" + run]
    if ratio is None or not (isinstance(ratio, (int, float)) and math.isfinite(ratio) and ratio != 0):
        raise InputError("ratio", ratio, f"{table.path} gives input and output angles: allowed: the reduction ratio "
                                         f"(input turns per output turn, non-zero)")
    te = (out_arcmin - table.columns["input_angle" + run] / ratio) * 60.0
    if not np.all(np.isfinite(te)):
        raise InputError("ratio", ratio, f"{table.path}: the TE from these angles overflows; allowed: the reduction "
                                         f"ratio (input turns per output turn)")
    return out_arcmin, te


def _te_reading(where: str, col: str, deg: np.ndarray, te: np.ndarray, positions: int, origin_deg: float,
                notes: list[str], label: str = "") -> tuple[BenchTransmissionError, np.ndarray]:
    """One run's reading on ``positions`` equal steps of the revolution from ``origin_deg``, and
    its bins' means before centring [arcsec] (the runs' gap is read from them)."""
    revolutions = float((deg.max() - deg.min()) / 360.0)
    pos = np.mod(deg - origin_deg, 360.0)
    bins = np.floor(pos / 360.0 * positions).astype(int) % positions
    counts = np.bincount(bins, minlength=positions)
    widest = _widest_empty(counts > 0)
    if widest * 360.0 / positions > 5.0 or revolutions < 1.0 - 5.0 / 360.0:
        raise InputError(col, allowed=f"{label}the samples span {revolutions * 360:.1f} deg with a gap of "
                                      f"{widest * 360.0 / positions:.1f} deg; allowed: a full output revolution "
                                      f"without gaps wider than 5 deg")
    sums = np.bincount(bins, weights=te, minlength=positions)
    centre = (np.arange(positions) + 0.5) * 360.0 / positions
    have = counts > 0
    mean = np.interp(centre, centre[have], sums[have] / counts[have], period=360.0)
    noise = float(np.std(te - mean[bins]))
    # the curve on the equal steps of the revolution: the bins' centres
    grid = centre
    curve = mean - mean.mean()
    # a bin's mean of cos(m theta) is sinc(m / N) times its value at the centre: undone per order
    spec = amplitude_spectrum(curve) / np.sinc(np.arange(positions // 2 + 1) / positions)
    floor = max(SPECTRUM_FLOOR_ARCSEC, 5.0 * float(np.median(spec[1:])))
    lead = [int(k) for k in np.argsort(spec[1:])[::-1][:LEADING_ORDERS] + 1 if spec[k] > floor]
    if revolutions > 1.05:
        notes.append(f"{revolutions:.2f} revolutions averaged by output position")
    if te.size < 2 * np.count_nonzero(have):
        notes.append(f"{te.size / np.count_nonzero(have):.1f} samples per position of {positions}: the noise about "
                     f"the averaged curve is not resolved (noise_arcsec is a lower bound)")
    start = float(np.mod(origin_deg, 360.0))
    return BenchTransmissionError(where, "transmission_error", int(te.size), revolutions, positions,
                                  float(np.ptp(curve)), float(curve.min()), float(curve.max()), noise, floor,
                                  tuple(SpectralLine(k, float(spec[k])) for k in lead), tuple(notes), (),
                                  np.mod(grid + start, 360.0), curve, spec), mean


def read_te_two_runs(table: BenchTable, ratio: float | None = None, positions: int = TE_POSITIONS) -> BenchTwoRunTE:
    """One unit's forward and backward runs (module docstring): each run's TE curve, orders and
    peak-to-peak on the same output positions (from the forward run's first sample), and the lost
    motion at each position, the gap between the runs by ``models.kinematics.lost_motion_arcmin``
    with the upper run as the ccw flank (a rig whose TE is output minus input / ratio and whose
    output lags in the forward run has the backward run above; ``ccw_run`` says which it was)."""
    where = table.path
    (fwd_arcmin, fwd_te), (bwd_arcmin, bwd_te) = _run_te(table, ratio, ""), _run_te(table, ratio, "_bw")
    origin = float(fwd_arcmin[0] / 60.0)
    readings = []
    for name, run, (arcmin, te) in (("forward", "", (fwd_arcmin, fwd_te)), ("backward", "_bw", (bwd_arcmin, bwd_te))):
        col = f"{where}: column '{table.headers['angle' + run]}'"
        u, mean = _te_reading(f"{where} ({name})", col, arcmin / 60.0, te, positions, origin, [], f"{name} run: ")
        readings.append((u, mean))
    (fwd, fwd_mean), (bwd, bwd_mean) = readings
    gap = lost_motion_arcmin(bwd_mean / ARCSEC_PER_RAD, fwd_mean / ARCSEC_PER_RAD)
    ccw = "backward"
    notes = list(table.notes) + [f"{name} run: {n}" for name, u in (("forward", fwd), ("backward", bwd))
                                 for n in u.notes]
    if gap.mean() < 0:
        gap, ccw = -gap, "forward"
        notes.append("the forward run's TE lies above the backward's: read as the ccw flank (the file's TE or "
                     "position sign is the other way round)")
    if gap.min() < 0:
        notes.append(f"the runs cross at {int(np.count_nonzero(gap < 0))} of {positions} positions (a gap below "
                     f"0: noise, or runs measured from different zeros)")
    return BenchTwoRunTE(where, "transmission_error_two_runs", fwd, bwd, fwd.te_peak_to_peak_arcsec,
                         bwd.te_peak_to_peak_arcsec, ccw, float(gap.mean()), float(gap.min()), float(gap.max()),
                         tuple(notes), (), table.metadata, fwd.output_angle_deg, gap)


def _widest_empty(filled: np.ndarray) -> int:
    """Longest run of empty bins, around the revolution's end too."""
    if filled.all():
        return 0
    if not filled.any():
        return filled.size
    k = int(np.argmax(filled))
    rolled = np.roll(filled, -k)
    best = run = 0
    for f in rolled:
        run = 0 if f else run + 1
        best = max(best, run)
    return best


# --- files, a batch, the design's production run ----------------------------------------------------

def read_bench_file(path: str | Path, *, rated_torque_nm: float | None = None, measuring_fraction: float = 0.03,
                    interval: Sequence[float] = (0.5, 1.0), units: Mapping[str, str | None] | FileFormat | None = None,
                    ratio: float | None = None,
                    rated_from: str = "given") -> BenchLoop | BenchTransmissionError | BenchTwoRunTE:
    """One bench file: a hysteresis loop (a torque column), a TE curve, or a unit's two TE runs.
    ``units``: the unit flags, or a FileFormat (design.bench_files.file_format: a column map, units,
    decimal mark, separator, sheet)."""
    table = read_bench_table(path, units)
    if table.kind == "hysteresis":
        u = read_loop(table, rated_torque_nm, measuring_fraction, interval, rated_from)
    elif table.two_runs:
        return read_te_two_runs(table, ratio)
    else:
        u = read_te(table, ratio)
    return dataclasses.replace(u, metadata=table.metadata) if table.metadata else u


def check_rated_torque(value) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise InputError("rated_torque_nm", value, "allowed: a torque > 0 [N m]")
    return float(value)


def read_bench(paths: Sequence[str | Path], problem=None, *, rated_torque_nm: float | None = None,
               units: Mapping[str, str | None] | FileFormat | None = None, ratio: float | None = None,
               samples: int = 2000, seed: int = 0, sobol_samples: int = 256) -> BenchResult:
    """Every file of a batch (one unit each); with ``problem`` (a design with [elastic]) each
    figure placed in the design's predicted production run of ``samples`` units (``place``).
    ``units``: the unit flags, or a FileFormat (a column map, units, decimal mark, ...)."""
    if isinstance(paths, (str, Path)):
        paths = [paths]
    if not paths:
        raise InputError("files", [], "allowed: one or more bench files")
    seed = check_seed(seed)
    rated_torque_nm = check_rated_torque(rated_torque_nm)
    x, interval, rated_from = 0.03, (0.5, 1.0), "given"
    if problem is not None and problem.design.elastic is not None:
        e = problem.design.elastic
        x, interval = e.measuring_torque_fraction, tuple(e.rigidity_interval_fraction)
        if rated_torque_nm is None:
            rated_torque_nm, rated_from = e.rated_torque_nm, "design"
    if ratio is None and problem is not None:
        ratio = float(problem.geometry.ratio)
    units_read = [read_bench_file(p, rated_torque_nm=rated_torque_nm, measuring_fraction=x, interval=interval,
                                  units=units, ratio=ratio, rated_from=rated_from) for p in paths]
    predicted: dict[str, np.ndarray] = {}
    warnings: tuple[str, ...] = ()
    if problem is not None:
        units_read, predicted = place(problem, units_read, samples=samples, seed=seed, sobol_samples=sobol_samples)
        if "lost_motion_arcmin" in predicted:
            from rvbacklash.models.elastic import elastic_model
            from rvbacklash.models.elastic.chain import stick_band_warning

            w = stick_band_warning(elastic_model(problem).chain)
            warnings = (f"the design's predicted lost motion: {w}",) if w else ()
    spread = {}
    for kind_figs in (("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin"),
                      ("te_peak_to_peak_arcsec", "te_peak_to_peak_backward_arcsec", "lost_motion_mean_arcmin")):
        for f in kind_figs:
            vals = [u.figures()[f] for u in units_read if f in u.figures()]
            if len(vals) >= 2:
                p = predicted.get(f)
                spread[f] = {"units": len(vals), "measured_mean": float(np.mean(vals)),
                             "measured_sigma": float(np.std(vals, ddof=1)),
                             "predicted_sigma": float(np.std(p)) if p is not None else None}
    return BenchResult(problem.name if problem is not None else None, samples if problem is not None else 0, seed,
                       tuple(units_read), spread, warnings)


ELASTIC_OUTPUTS = {"lost_motion_arcmin": (0, "lost_motion"), "backlash_arcmin": (1, "backlash"),
                   "torsional_rigidity_nm_per_arcmin": (2, "rigidity")}


def predicted_elastic(problem, samples: int, seed: int) -> dict[str, np.ndarray]:
    """Lost motion, backlash and rigidity of ``samples`` units of the design's production run
    (the elastic model's units, drawn as the Monte-Carlo draws them)."""
    from rvbacklash.models.elastic import elastic_model, loop_design
    from rvbacklash.sampling.elastic_source import design_pin_laws, evaluate_batch, sample_units

    model = elastic_model(problem)
    out = evaluate_batch(loop_design(model, design_pin_laws(model)), sample_units(problem, int(seed), int(samples)))
    return {k: out[i] for k, (i, _) in ELASTIC_OUTPUTS.items()}


def predicted_te(problem, samples: int, seed: int) -> dict[str, np.ndarray]:
    """TE peak-to-peak (the ccw flank's, and the cw flank's as ``..._other_flank``) and the mean of
    the lost motion over the revolution of ``samples`` units of the transmission model's production
    run (exact curves)."""
    from rvbacklash.analysis.transmission import transmission_error
    from rvbacklash.sampling.te_source import sample_units

    units = sample_units(problem, int(seed), int(samples))
    curves = [transmission_error(problem, u, "", 1024, shares=False) for u in units]
    return {"te_peak_to_peak_arcsec": np.array([c.te_peak_to_peak_arcsec for c in curves]),
            "te_peak_to_peak_other_flank_arcsec": np.array([c.te_peak_to_peak_other_flank_arcsec for c in curves]),
            "lost_motion_mean_arcmin": np.array([float(np.mean(c.lost_motion_arcmin)) for c in curves])}


def _predicted_key(u, figure: str) -> str:
    """The predicted figure a measured one is placed among: a unit's two runs by flank (the run
    read as ccw against the ccw flank's TE, the other against the cw flank's)."""
    if isinstance(u, BenchTwoRunTE) and figure.startswith("te_peak_to_peak"):
        run = "backward" if figure.endswith("_backward_arcsec") else "forward"
        return "te_peak_to_peak_arcsec" if run == u.ccw_run else "te_peak_to_peak_other_flank_arcsec"
    return figure


def _explaining(problem, model: str, output: str, samples: int, seed: int) -> tuple[str, ...]:
    """The factor groups whose total Sobol index is at least a third of the largest (at most 3)."""
    from rvbacklash.analysis.sensitivity_global import global_sensitivity

    s = global_sensitivity(problem, model=model, output=output, samples=samples, seed=seed, resamples=100)
    ranked = sorted(s.groups, key=lambda g: -g.total)
    top = ranked[0].total if ranked else 0.0
    return tuple(g.input for g in ranked[:3] if top > 0 and g.total >= top / 3)


def place(problem, units: Sequence, *, samples: int = 2000, seed: int = 0, sobol_samples: int = 256):
    """Each unit's figures as percentiles of the design's predicted production run; a unit outside
    0.135-99.865 % names the factor groups that dominate that figure's variance (Sobol)."""
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 100 <= samples <= 10**6:
        raise InputError("samples", samples, "allowed: 100 to 1e6 predicted units")
    loops = any(isinstance(u, BenchLoop) for u in units)
    tes = any(isinstance(u, (BenchTransmissionError, BenchTwoRunTE)) for u in units)
    predicted: dict[str, np.ndarray] = {}
    if loops:
        if problem.design.elastic is None:
            raise InputError("elastic", allowed="the design has no [elastic] table; allowed: a design with one to "
                                                "place hysteresis loops")
        predicted.update(predicted_elastic(problem, samples, seed))
    if tes:
        predicted.update(predicted_te(problem, min(samples, 200), seed))
    sobol_cache: dict[tuple[str, str], tuple[str, ...]] = {}
    out = []
    for u in units:
        rows = []
        for fig, value in u.figures().items():
            p = predicted.get(_predicted_key(u, fig))
            if p is None or not math.isfinite(value):
                continue
            pct = 100.0 * (np.count_nonzero(p < value) + 0.5 * np.count_nonzero(p == value)) / p.size
            q = np.quantile(p, [0.00135, 0.05, 0.5, 0.95, 0.99865])
            outside = not 0.135 <= pct <= 99.865
            factors: tuple[str, ...] = ()
            if outside:
                model, output = (("elastic", ELASTIC_OUTPUTS[fig][1]) if fig in ELASTIC_OUTPUTS
                                 else ("transmission", "lost_motion_max") if fig == "lost_motion_mean_arcmin"
                                 else ("transmission", "transmission_error"))
                if (model, output) not in sobol_cache:  # one Sobol run per model output (both runs' TE share it)
                    sobol_cache[model, output] = _explaining(problem, model, output, sobol_samples, seed)
                factors = sobol_cache[model, output]
            beyond = bool(value < p.min() or value > p.max())
            rows.append(Placement(fig, float(value), float(pct), outside, *(float(v) for v in q), factors, beyond))
        out.append(_with_placement(u, tuple(rows)))
    return out, predicted


def _with_placement(u, rows):
    return dataclasses.replace(u, placement=rows)
