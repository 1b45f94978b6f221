"""Rich tables of the results for the terminal."""

from __future__ import annotations

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from typing import TYPE_CHECKING

from rvbacklash.analysis.stackup import StackupResult
from rvbacklash.units import display_unit

if TYPE_CHECKING:  # the simulation pulls in the compiled kernels; only its type is needed here
    from rvbacklash.analysis.simulation import SimulationResult




def _g(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def print_stackup(result: StackupResult, console: Console) -> None:
    g = result.geometry
    console.print(
        f"[bold]{escape(result.design_name)}[/]  ratio i = {g.ratio:.6g}, K1 = {g.K1:.4f}, "
        f"r1 = {g.centre_gear_pitch_radius_mm:.4g} mm, a z_c = {g.cycloid_pitch_radius_mm:.4g} mm, "
        f"a0 = {g.crank_circle_radius_mm:.4g} mm" + (" (default: centre distance)" if g.crank_circle_radius_is_default else ""))

    t = Table(title="Factors (raw zone -> circumferential backlash -> output)", title_justify="left")
    for col, just in [("id", "right"), ("factor", "left"), ("stage", "left"), ("zone [um]", "right"),
                      ("mean [um]", "right"), ("sigma [um]", "right"), ("S [arcmin/um]", "right"),
                      ("weight g", "right"), ("var. share", "right"), ("rank", "right")]:
        t.add_column(escape(col), justify=just)
    for f in result.factors:
        t.add_row(str(f.id), f.key, f.stage, escape(f"[{_g(f.zone_lower_um)}, {_g(f.zone_upper_um)}]"),
                  f"{f.mean_um:.4f}", f"{f.sigma_um:.4f}", f"{f.sensitivity_arcmin_per_um:.4e}",
                  f"{f.weight:.4f}", f"{f.variance_share:.4f}", str(f.rank))
    console.print(t)

    s = Table(title="Stages (Eq. (1)/(2))", title_justify="left")
    for col in ["stage", "C [arcmin/um]", "mean [um]", "sigma [um]", "mean [arcmin]", "sigma [arcmin]",
                "worst case [arcmin]", "var. share"]:
        s.add_column(escape(col), justify="left" if col == "stage" else "right")
    for st in result.stages.values():
        s.add_row(st.stage, f"{st.coefficient_arcmin_per_um:.4e}", f"{st.mean_um:.4f}", f"{st.sigma_um:.4f}",
                  f"{st.mean_arcmin:.4f}", f"{st.sigma_arcmin:.4f}", f"{st.worst_case_arcmin:.4f}",
                  f"{st.variance_share:.4f}")
    console.print(s)

    tot = result.total
    tt = Table(title=escape("Total output backlash [arcmin]"), title_justify="left")
    for col in ["mean", "sigma", "mean - 3 sigma", "mean + 3 sigma", "RSS (upper)", "worst case (max)",
                "worst case (min)"]:
        tt.add_column(col, justify="right")
    tt.add_row(*(f"{v:.4f}" for v in (tot.mean_arcmin, tot.sigma_arcmin, tot.minus3sigma_arcmin,
                                       tot.plus3sigma_arcmin, tot.rss_arcmin, tot.worst_case_arcmin,
                                       tot.worst_case_min_arcmin)))
    console.print(tt)

    r = Table(title="What to tighten: factors ranked by variance share", title_justify="left")
    for col in ["rank", "id", "factor", "var. share", "cumulative", "S [arcmin/um]", "sigma [arcmin]"]:
        r.add_column(escape(col), justify="left" if col == "factor" else "right")
    cum = 0.0
    for f in sorted(result.factors, key=lambda f: f.rank):
        cum += f.variance_share
        r.add_row(str(f.rank), str(f.id), f.key, f"{f.variance_share:.4f}", f"{cum:.4f}",
                  f"{f.sensitivity_arcmin_per_um:.4e}", f"{f.sigma_arcmin:.4f}")
    console.print(r)
    console.print("[dim]S: Eq. (6), output per um of raw error. weight g: Eq. (7), |S_i|/sum|S_j| "
                  "(ignores tolerance size). var. share: S_i^2 sigma_i^2 / sigma^2 (sums to 1; "
                  "the ranking to act on).[/]")


def _f(x, fmt: str = ".4f") -> str:
    return "-" if x is None else format(x, fmt)


def _ci(lo, hi, fmt: str = ".4f") -> str:
    return "-" if lo is None or hi is None else f"[{lo:{fmt}}, {hi:{fmt}}]"


def print_simulation(r: "SimulationResult", console: Console) -> None:
    head = (f"[bold]{escape(r.design_name)}[/]  model {r.model}, method {r.method}"
            + (f", {r.samples_done:,} samples, seed {r.seed}" if r.method != "exact" else " (no sampling)"))
    if r.partial:
        head += f"  [bold red]PARTIAL: interrupted after {r.samples_done:,} of {r.samples:,} samples[/]"
    console.print(head)
    for o in r.outputs.values():
        unit = display_unit(o.unit)
        t = Table(title=escape(f"{o.description} [{unit}]"), title_justify="left")
        for c in ["statistic", "value", "95 % interval"]:
            t.add_column(c, justify="left" if c == "statistic" else "right")
        if o.samples is not None and r.samples_done is not None and o.samples != r.samples_done:
            t.add_row("units counted", f"{o.samples:,} of {r.samples_done:,}", "")
        t.add_row("mean", _f(o.mean), _ci(o.mean_ci95_low, o.mean_ci95_high))
        t.add_row("standard deviation sigma", _f(o.sigma), "")
        if o.min is not None:
            t.add_row("min / max", f"{o.min:.4f} / {o.max:.4f}", "")
        for q in o.quantiles:
            t.add_row(f"quantile {q.probability * 100:g} %", _f(q.value), escape(q.interval_text()))
        if o.yield_ is not None:
            y = o.yield_
            side = "<=" if o.spec_is_upper else ">="
            flag = " [bold red](see warning)[/]" if o.warning else ""
            t.add_row(escape(f"yield P({o.quantity} {side} {o.spec_limit:g} {unit})"), f"{y.fraction * 100:.4f} %"
                      + flag, f"[{y.ci95_low * 100:.4f} %, {y.ci95_high * 100:.4f} %]")
            t.add_row("out of spec", f"{o.ppm_out:.1f} ppm", "")
            if o.cp is not None:
                t.add_row("Cp / Cpk (LSL 0, USL spec)", f"{_f(o.cp, '.3f')} / {_f(o.cpk, '.3f')}", "")
        if r.model == "linear" and o.negative_fraction is not None:
            t.add_row("P(backlash < 0): interference", f"{o.negative_fraction * 100:.4f} %", "")
        console.print(t)
        if o.warning:
            console.print(f"[bold red]warning ({escape(o.quantity)}):[/] {escape(o.warning)}")
    if r.joint_yield is not None:
        y = r.joint_yield
        console.print(f"joint yield (every spec at once): {y.fraction * 100:.4f} % "
                      f"[{y.ci95_low * 100:.4f} %, {y.ci95_high * 100:.4f} %]")
    if r.preload_fraction is not None:
        console.print(f"cycloid stage preloaded in {r.preload_fraction * 100:.3f} % of the units")
    a = r.linear_reference
    console.print(f"linear stack-up (analyze): mean {a.mean_arcmin:.4f}, sigma {a.sigma_arcmin:.4f} arcmin")
    if r.samples_per_s:
        console.print(f"[dim]{r.elapsed_s:.2f} s, {rate_text(r.samples_per_s, 'samples')}[/]")


def rate_text(per_s: float, what: str) -> str:
    """A rate with three significant digits in the unit that fits it: the linear model draws
    millions of samples per second, the transmission model hundreds ('0.00 M samples/s' said
    nothing)."""
    for scale, prefix in ((1e6, "M "), (1e3, "k ")):
        if per_s >= scale:
            return f"{per_s / scale:.3g} {prefix}{what}/s"
    return f"{per_s:.3g} {what}/s"


def print_scenarios(results, console: Console) -> None:
    t = Table(title=escape("Scenarios: output backlash [arcmin]"), title_justify="left")
    for c in ["scenario", "factors changed", "mean", "sigma", "q 99.865 %", "yield [95 % interval]"]:
        t.add_column(c, justify="left" if c == "scenario" else "right")
    for row in results.rows():
        y = row["yield"]
        ys = "-" if y is None else (f"{y * 100:.3f} % [{row['yield_ci95_low'] * 100:.3f}, "
                                    f"{row['yield_ci95_high'] * 100:.3f}]")
        t.add_row(escape(row["name"]) + (" (partial)" if row["partial"] else ""), str(row["factors_changed"]),
                  f"{row['mean_arcmin']:.4f}", f"{row['sigma_arcmin']:.4f}", _f(row["q99865_arcmin"]), ys)
    console.print(t)
    if results.partial:
        console.print(f"[bold red]PARTIAL: interrupted; {len(results)} of {len(results.requested)} scenarios[/]")


def print_sources(result: StackupResult, console: Console) -> None:
    """Where each factor's zone came from (explicit, a standard and grade, or an assumption)."""
    t = Table(title="Where each tolerance zone came from", title_justify="left")
    t.add_column("id", justify="right")
    t.add_column("factor")
    t.add_column("origin")
    for f in result.factors:
        t.add_row(str(f.id), f.key, escape(f.zone_origin + (f"; {f.note}" if f.note else "")))
    console.print(t)


def print_contact(result, console: Console) -> None:
    """The nominal design's play from the exact contact geometry."""
    what = "nominal design" if result.unit == "nominal" else result.unit
    t = Table(title=escape(f"Contact model, {what} at crank angle {result.crank_angle_deg:g} deg"),
              title_justify="left")
    for c in ["disc", "play ccw [arcmin]", "play cw [arcmin]", "first-contact pins ccw", "first-contact pins cw"]:
        t.add_column(escape(c), justify="right")
    for disc in result.discs:
        t.add_row(str(disc.disc), f"{disc.play_ccw_arcmin:.4f}", f"{disc.play_cw_arcmin:.4f}",
                  ", ".join(map(str, disc.contact_pins_ccw)), ", ".join(map(str, disc.contact_pins_cw)))
    console.print(t)
    stage = (f"[bold red]preloaded[/] by {result.preload_um:.3f} um (no rotation frees every pin)"
             if result.cycloid_stage_preloaded else f"{result.cycloid_stage_arcmin:.4f} arcmin")
    console.print(f"cycloid stage {stage} (linear model, mean: {result.linear_cycloid_stage_mean_arcmin:.4f} arcmin); "
                  f"other stages at their means "
                  + ", ".join(f"{k} {v:.4f}" for k, v in result.other_stages_mean_arcmin.items())
                  + f" arcmin; [bold]output lost motion {result.lost_motion_arcmin:.4f} arcmin[/]")
    console.print(f"[dim]{escape(result.assumptions)}[/]")
