"""Rich tables of a stack-up result for the terminal."""

from __future__ import annotations

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from rvbacklash.analysis.stackup import StackupResult


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
