"""Pictures and the HTML page of a design sweep, drawn from its rows (a ``SweepResult``).

- ``heatmap_svg``: a figure (e.g. the yield) over two parameters; on a grid, one cell per pair
  of values (the mean over any other parameters), the best cell outlined; for a sampled design
  (Latin hypercube, Sobol), the points coloured by the figure.
- ``line_svg``: a figure over one parameter, with its 95 % interval when it has one.
- ``plot_svg``: the one that fits (line for one parameter, heat map for more).
- ``render_sweep_html``: a self-contained page (inline CSS and SVG, no network) with the figures
  and the table; ``section_context`` gives what the partial template
  ``templates/_sweep_section.html.j2`` needs, to include the sweep in another page.
"""

from __future__ import annotations

import math
from typing import Any

from rvbacklash.analysis.sweep import SweepResult
from rvbacklash.errors import InputError
from rvbacklash.report import plots
from rvbacklash.report.templating import environment

MAX_TABLE_ROWS = 2000  # rows shown in the HTML table (the CSV and Parquet files hold all)
UNITLESS = ("_yield", "_yield_ci95_low", "_yield_ci95_high", "_cp", "_cpk", "_ppm_out", "_negative_fraction",
            "_samples", "_bounded")


# --- choosing what to draw -----------------------------------------------------------------------

def check_parameter(result: SweepResult, name: str | None, parameter: str) -> str | None:
    """A parameter by its path or label; None stays None."""
    if name is None:
        return None
    if name in result.parameters:
        return name
    if name in result.labels:
        return result.parameters[result.labels.index(name)]
    raise InputError(parameter, name, f"allowed: a parameter of the sweep: {', '.join(result.parameters)}")


def check_figure(result: SweepResult, figure: str | None) -> str:
    figure = figure or result.default_figure()
    cols = result.figure_columns()
    if figure not in cols:
        raise InputError("figure", figure, f"allowed: a column of the results: {', '.join(cols)}")
    return figure


def label_of(result: SweepResult, path: str) -> str:
    return result.labels[result.parameters.index(path)] if path in result.parameters else path


def figure_unit(result: SweepResult, figure: str) -> str:
    if figure.endswith(UNITLESS) or figure.startswith("joint_yield") or figure == "preload_fraction":
        return ""
    if figure.startswith("linear_"):
        return "arcmin"
    for o in sorted(result.outputs, key=len, reverse=True):
        if figure.startswith(o + "_"):
            return result.output_units.get(o, "")
    return ""


def is_fraction(figure: str) -> bool:
    base = figure.removesuffix("_ci95_low").removesuffix("_ci95_high")
    return base.endswith(("yield", "_negative_fraction")) or base == "preload_fraction"


def figure_title(result: SweepResult, figure: str) -> str:
    unit = figure_unit(result, figure)
    if is_fraction(figure):
        unit = "%"
    return f"{figure} [{unit}]" if unit else figure


def format_value(figure: str, value: Any) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    if isinstance(value, bool) or isinstance(value, str):
        return str(value)
    if isinstance(value, int):
        return f"{value:,}" if abs(value) >= 10000 else str(value)
    if is_fraction(figure):
        return f"{100 * value:.3g} %" if value < 0.999 else f"{100 * value:.4g} %"
    return f"{value:.4g}"


def defaults(result: SweepResult, x: str | None = None, y: str | None = None,
             figure: str | None = None) -> tuple[str, str | None, str]:
    """(x, y or None for a line plot, figure) with the defaults filled in and checked."""
    x = check_parameter(result, x, "x_parameter") or result.parameters[0]
    y = check_parameter(result, y, "y_parameter")
    if y is None and len(result.parameters) > 1:
        y = next(p for p in result.parameters if p != x)
    if y is not None and y == x:
        raise InputError("y_parameter", y, "is also the x parameter; allowed: another parameter")
    return x, y, check_figure(result, figure)


def _ordered(values: list) -> list:
    unique = list(dict.fromkeys(v for v in values if v is not None))
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in unique):
        return sorted(unique)
    return unique


def _tick(v: Any) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def _finite(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _scale(figure: str) -> float:
    return 100.0 if is_fraction(figure) else 1.0


# --- figures -----------------------------------------------------------------------------------

def heatmap_figure(result: SweepResult, x: str, y: str, figure: str):
    import matplotlib.pyplot as plt
    import numpy as np

    rows = [r for r in result.table if _finite(r.get(figure))]
    scale = _scale(figure)
    fig, ax = plt.subplots(figsize=(7.8, 5.6))
    best = result.best(figure)
    title = f"{result.name}: {figure_title(result, figure)}"
    others = [label_of(result, p) for p in result.parameters if p not in (x, y)]
    if result.sampling == "grid":
        xs, ys = _ordered([r.get(x) for r in result.table]), _ordered([r.get(y) for r in result.table])
        total = np.zeros((len(ys), len(xs)))
        count = np.zeros((len(ys), len(xs)))
        for r in rows:
            i, j = ys.index(r[y]), xs.index(r[x])
            total[i, j] += r[figure] * scale
            count[i, j] += 1
        with np.errstate(invalid="ignore"):
            grid = np.where(count > 0, total / np.maximum(count, 1), np.nan)
        im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis", interpolation="nearest")
        ax.set_xticks(range(len(xs)))
        ax.set_xticklabels([_tick(v) for v in xs], rotation=45 if len(xs) > 10 else 0, fontsize=8)
        ax.set_yticks(range(len(ys)))
        ax.set_yticklabels([_tick(v) for v in ys], fontsize=8)
        if len(xs) * len(ys) <= 225:
            finite = grid[np.isfinite(grid)]
            mid = 0.5 * (finite.min() + finite.max()) if finite.size else 0.0
            for i in range(len(ys)):
                for j in range(len(xs)):
                    if math.isfinite(grid[i, j]):
                        ax.text(j, i, f"{grid[i, j]:.3g}", ha="center", va="center", fontsize=7,
                                color="black" if grid[i, j] > mid else "white")
        if best is not None and not others:
            from matplotlib.patches import Rectangle

            j, i = xs.index(best[x]), ys.index(best[y])
            ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec=plots.RED, lw=2.2))
        if others:
            title += f" (mean over {', '.join(others)})"
    else:
        im = ax.scatter([r[x] for r in rows], [r[y] for r in rows], c=[r[figure] * scale for r in rows],
                        cmap="viridis", s=36, edgecolors="k", linewidths=0.3)
        if best is not None:
            ax.scatter([best[x]], [best[y]], s=160, facecolors="none", edgecolors=plots.RED, linewidths=2)
        ax.grid(alpha=0.3)
    bar = fig.colorbar(im, ax=ax)
    bar.set_label(figure_title(result, figure))
    ax.set_xlabel(label_of(result, x))
    ax.set_ylabel(label_of(result, y))
    if best is not None:
        shown = result.parameters if others else (x, y)
        title += f"\nbest point {format_value(figure, best[figure])} at " + \
                 ", ".join(f"{label_of(result, p)} = {_tick(best[p])}" for p in shown)
    if result.partial:
        title += f"  [PARTIAL: {result.points_done} of {result.points_total} points]"
    ax.set_title(title, fontsize=10)
    return fig


def line_figure(result: SweepResult, x: str, figure: str):
    import matplotlib.pyplot as plt

    scale = _scale(figure)
    rows = sorted((r for r in result.table if _finite(r.get(figure)) and r.get(x) is not None),
                  key=lambda r: _ordered([q.get(x) for q in result.table]).index(r[x]))
    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    numeric = all(_finite(r[x]) for r in rows)
    xs = [r[x] for r in rows] if numeric else list(range(len(rows)))
    ys = [r[figure] * scale for r in rows]
    lo, hi = f"{figure}_ci95_low", f"{figure}_ci95_high"
    if rows and all(_finite(r.get(lo)) and _finite(r.get(hi)) for r in rows):
        ax.fill_between(xs, [r[lo] * scale for r in rows], [r[hi] * scale for r in rows], color=plots.BLUE,
                        alpha=0.2, lw=0, label="95 % interval")
    ax.plot(xs, ys, marker="o", ms=4, color=plots.BLUE, label=figure)
    if not numeric:
        ax.set_xticks(xs)
        ax.set_xticklabels([_tick(r[x]) for r in rows])
    best = result.best(figure)
    if best is not None and best in rows:
        bx = best[x] if numeric else rows.index(best)
        ax.plot([bx], [best[figure] * scale], marker="*", ms=14, color=plots.RED, ls="none",
                label=f"best: {format_value(figure, best[figure])}")
    ax.set_xlabel(label_of(result, x))
    ax.set_ylabel(figure_title(result, figure))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    title = f"{result.name}: {figure_title(result, figure)}"
    if result.partial:
        title += f"  [PARTIAL: {result.points_done} of {result.points_total} points]"
    ax.set_title(title, fontsize=10)
    return fig


def heatmap_svg(result: SweepResult, x: str | None = None, y: str | None = None, figure: str | None = None) -> str:
    x, y, figure = defaults(result, x, y, figure)
    if y is None:
        raise InputError("y_parameter", None, "a heat map needs two parameters; this sweep has one (a line plot)")
    return plots._svg(heatmap_figure(result, x, y, figure))


def line_svg(result: SweepResult, x: str | None = None, figure: str | None = None) -> str:
    x = check_parameter(result, x, "x_parameter") or result.parameters[0]
    return plots._svg(line_figure(result, x, check_figure(result, figure)))


def plot_svg(result: SweepResult, x: str | None = None, y: str | None = None, figure: str | None = None) -> str:
    """A line plot for a one-parameter sweep, else a heat map over x and y (default: the first
    two parameters) of ``figure`` (default: ``result.default_figure()``)."""
    _check_rows(result)
    x, y, figure = defaults(result, x, y, figure)
    if y is None:
        return plots._svg(line_figure(result, x, figure))
    return plots._svg(heatmap_figure(result, x, y, figure))


def _check_rows(result: SweepResult) -> None:
    if not result.table:
        raise InputError("out", result.out, "holds no finished point yet; allowed: a sweep with results")


# --- the page ----------------------------------------------------------------------------------

def table_columns(result: SweepResult) -> list[str]:
    """The columns the HTML table shows: index, parameters, and per output its mean, 99.865 %
    quantile and yield; the joint yield and the model's own figures. The files hold them all."""
    cols = ["point", *result.parameters]
    have = set(result.columns)
    for o in result.outputs:
        cols += [c for c in (f"{o}_mean", f"{o}_sigma", f"{o}_q99865", f"{o}_yield") if c in have]
    cols += [c for c in ("joint_yield", "preload_fraction") if c in have]
    return cols


def section_context(result: SweepResult, figures: list[tuple[str, str]] | None = None) -> dict:
    """What ``_sweep_section.html.j2`` needs: ``sweep`` (the result), ``sweep_figures`` (caption,
    inline SVG), ``sweep_header`` (column, heading), ``sweep_rows`` (formatted cells),
    ``sweep_best`` (label of the best point, or None), ``sweep_facts`` (label, value)."""
    if figures is None:
        figures = default_figures(result)
    cols = table_columns(result)
    header = [(c, label_of(result, c) + (" [%]" if is_fraction(c) else
                                         (f" [{figure_unit(result, c)}]" if figure_unit(result, c) else "")))
              for c in cols]
    rows = [[_cell(r.get(c), c) for c in cols] for r in result.table[:MAX_TABLE_ROWS]]
    fig = result.default_figure()
    b = result.best(fig) if result.table else None
    best = None
    if b is not None:
        where = ", ".join(f"{label_of(result, p)} = {_tick(b.get(p))}" for p in result.parameters)
        best = f"{fig} = {format_value(fig, b[fig])} at point {b['point']}: {where}"
    limits = ", ".join(f"{k} {'≤' if result.output_upper.get(k, True) else '≥'} {v:g} "
                       f"{result.output_units.get(k, '')}".rstrip() for k, v in result.limits.items()) or "none"
    facts = [("design", result.design_name), ("model", result.model),
             ("points", f"{result.points_done} of {result.points_total} ({result.sampling})"),
             ("samples per point", f"{result.samples:,}"), ("seed", str(result.seed)),
             ("method", result.method), ("specs", limits),
             ("parameters", ", ".join(result.parameters)), ("fingerprint", result.fingerprint[:16])]
    return {"sweep": result, "sweep_figures": [(c, plots.inline_svg(s)) for c, s in figures], "sweep_header": header,
            "sweep_rows": rows, "sweep_best": best, "sweep_facts": facts,
            "sweep_truncated": max(0, len(result.table) - MAX_TABLE_ROWS)}


def _cell(value: Any, column: str) -> str:
    if is_fraction(column) and _finite(value):
        return f"{100 * value:.3f}"
    return format_value(column, value) if not isinstance(value, float) else f"{value:.5g}"


def default_figures(result: SweepResult) -> list[tuple[str, str]]:
    """(caption, SVG) of the page: the default figure, then the primary output's 99.865 %
    quantile and the preloaded fraction where they differ from it."""
    if not result.table:
        return []
    out = []
    shown = []
    primary = result.outputs[0] if result.outputs else None
    for fig in (result.default_figure(), f"{primary}_q99865", "preload_fraction"):
        if fig in result.figure_columns() and fig not in shown and any(_finite(v) for v in result.column(fig)):
            shown.append(fig)
            kind = "line plot" if len(result.parameters) == 1 else "heat map"
            over = ", ".join(label_of(result, p) for p in result.parameters[:2])
            caption = f"{figure_title(result, fig)} over {over}" \
                      f" ({kind}; best point {'highest' if result.maximise(fig) else 'lowest'}, outlined)"
            out.append((caption, plot_svg(result, figure=fig)))
    return out


def render_sweep_html(result: SweepResult, figures: list[tuple[str, str]] | None = None) -> str:
    """The sweep as one self-contained HTML page (inline CSS and SVG, no network)."""
    return environment().get_template("sweep.html.j2").render(**section_context(result, figures))
