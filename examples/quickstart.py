# %% [markdown]
# # rvbacklash quick start
# Run top to bottom as a script (`python examples/quickstart.py [OUTDIR]`) or cell by cell in
# Jupyter / VS Code (the `# %%` markers). Needs `pip install -e '.[pandas]'` for the tables.

# %%
import sys
from pathlib import Path

import rvbacklash as rb

out = Path(sys.argv[1]) if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else Path("out")
out.mkdir(parents=True, exist_ok=True)

# %% A design: a built-in example (or rb.load_design("my_design.toml"))
design = rb.load_design("rv80e")
print(design.name, "-", design.description)

# %% Deterministic stack-up and sensitivities (paper Tables 2-3, Eq. (1)-(7))
stack = rb.analyze(design)
t = stack.total
print(f"mean {t.mean_arcmin:.3f} arcmin, sigma {t.sigma_arcmin:.3f}, mean+3sigma {t.plus3sigma_arcmin:.3f}, "
      f"worst case {t.worst_case_arcmin:.3f}")
factors = stack.to_frame()
print(factors.sort_values("rank")[["key", "variance_share", "sensitivity_arcmin_per_um", "zone_origin"]].head(5))

# %% Monte-Carlo: how many units meet a 3 arcmin spec?
sim = rb.simulate(design, samples=1_000_000, seed=1, spec_arcmin=3.0)
y = sim.stats["yield"]
print(f"yield {y['fraction']:.4%} (95 % CI {y['ci95'][0]:.4%} .. {y['ci95'][1]:.4%}), Cpk {sim.stats['cpk']:.2f}")
print(sim.to_frame())

# %% Which precision grade to buy: the paper's Fig. 4 scenarios
comparison = rb.compare(design, rb.paper_scenarios(design), samples=None, seed=None, method="exact",
                        spec_arcmin=3.0)
print(comparison.to_frame()[["factors_changed", "mean_arcmin", "sigma_arcmin", "q99865_arcmin"]])

# %% The HTML report of all of the above, and the plain numbers for Excel / MATLAB
report = rb.make_report("rv80e", samples=200_000, seed=1, spec_arcmin=3.0, paper=True)
(out / "quickstart-report.html").write_text(rb.render_html(report), encoding="utf-8")
factors.to_csv(out / "quickstart-factors.csv")
print("wrote", out / "quickstart-report.html", "and", out / "quickstart-factors.csv")
