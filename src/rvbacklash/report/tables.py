"""Rich tables of the results for the terminal."""

from __future__ import annotations

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from typing import TYPE_CHECKING

from rvbacklash.analysis.stackup import StackupResult

if TYPE_CHECKING:  # the simulation pulls in the compiled kernels; only its type is needed here
    from rvbacklash.analysis.simulation import SimulationResult


def _g(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def print_stackup(result: StackupResult, console: Console) -> None:
    g = result.geometry
    console.print(
        f"[bold]{result.design_name}[/]  ratio i = {g.ratio:.6g}, K1 = {g.K1:.4f}, "
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


def _ci(ci) -> str:
    return "-" if ci is None or None in ci else f"[{ci[0]:.4f}, {ci[1]:.4f}]"


def print_simulation(r: "SimulationResult", console: Console) -> None:
    s = r.stats
    head = (f"[bold]{r.design_name}[/]  model {r.model}, method {r.method}"
            + (f", {s['samples_done']:,} samples, seed {r.seed}" if r.method != "exact" else " (no sampling)"))
    if r.partial:
        head += f"  [bold red]PARTIAL: interrupted after {s['samples_done']:,} of {r.samples:,} samples[/]"
    console.print(head)

    t = Table(title=escape("Output backlash [arcmin]"), title_justify="left")
    for c in ["statistic", "value", "95 % interval"]:
        t.add_column(c, justify="left" if c == "statistic" else "right")
    t.add_row("mean", _f(s["mean_arcmin"]), _ci(s["mean_ci95"]))
    t.add_row("standard deviation", _f(s["std_arcmin"]), "")
    if s.get("min_arcmin") is not None:
        t.add_row("min / max", f"{s['min_arcmin']:.4f} / {s['max_arcmin']:.4f}", "")
    for p, q in s["quantiles"].items():
        t.add_row(f"quantile {float(p) * 100:g} %", _f(q["value"]), _ci(q["ci95"]))
    if s.get("yield") is not None:
        y = s["yield"]
        t.add_row(f"yield P(backlash <= {s['spec_arcmin']:g})", f"{y['fraction'] * 100:.4f} %",
                  f"[{y['ci95'][0] * 100:.4f} %, {y['ci95'][1] * 100:.4f} %]")
        t.add_row("out of spec", f"{s['ppm_out']:.1f} ppm", "")
        t.add_row("Cp / Cpk (LSL 0, USL spec)", f"{_f(s['cp'], '.3f')} / {_f(s['cpk'], '.3f')}", "")
    label = "cycloid stage preloaded" if r.model == "contact" else "P(backlash < 0): interference"
    t.add_row(label, f"{s['interference_fraction'] * 100:.4f} %", "")
    console.print(t)
    a = r.analytic
    console.print(f"linear stack-up (analyze): mean {a['mean_arcmin']:.4f}, sigma {a['sigma_arcmin']:.4f} arcmin")
    if r.elapsed_s > 0 and s.get("samples_done"):
        console.print(f"[dim]{r.elapsed_s:.2f} s, {s['samples_done'] / r.elapsed_s / 1e6:.1f} M samples/s[/]")


def print_scenarios(results, console: Console) -> None:
    t = Table(title=escape("Scenarios: output backlash [arcmin]"), title_justify="left")
    for c in ["scenario", "factors changed", "mean", "sigma", "q 99.865 %", "yield [95 % interval]"]:
        t.add_column(c, justify="left" if c == "scenario" else "right")
    for r in results:
        d = r.to_dict()
        y = d["yield"]
        ys = "-" if y is None else f"{y['fraction'] * 100:.3f} % [{y['ci95'][0] * 100:.3f}, {y['ci95'][1] * 100:.3f}]"
        t.add_row(r.name, str(r.tightened), f"{d['mean_arcmin']:.4f}", f"{d['sigma_arcmin']:.4f}",
                  f"{d['q99865_arcmin']:.4f}", ys)
    console.print(t)


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
    d = result.to_dict()
    t = Table(title=escape(f"Contact model, nominal design at crank angle {d['crank_angle_deg']:g} deg"),
              title_justify="left")
    for c in ["disc", "play ccw [rad]", "play cw [rad]", "first-contact pins ccw", "first-contact pins cw"]:
        t.add_column(c, justify="right")
    for i, disc in enumerate(d["discs"]):
        t.add_row(str(i), f"{disc['play_ccw_rad']:.4e}", f"{disc['play_cw_rad']:.4e}",
                  ", ".join(map(str, disc["contact_pins_ccw"])), ", ".join(map(str, disc["contact_pins_cw"])))
    console.print(t)
    console.print(f"cycloid stage {d['cycloid_stage_arcmin']:.4f} arcmin (linear model, mean: "
                  f"{d['linear_cycloid_stage_mean_arcmin']:.4f}); other stages at their means "
                  + ", ".join(f"{k} {v:.4f}" for k, v in d["other_stages_mean_arcmin"].items())
                  + f"; [bold]output lost motion {d['lost_motion_arcmin']:.4f} arcmin[/]")
    console.print(f"[dim]{d['assumptions']}[/]")
