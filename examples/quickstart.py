# %% [markdown]
# # rvbacklash quick start
# Run top to bottom as a script (`python examples/quickstart.py [OUTDIR]`) or cell by cell in
# Jupyter / VS Code (the `# %%` markers). Tables need pandas (installed with the test extra).

# %%
import sys
from pathlib import Path

import rvbacklash as rb

out = Path(sys.argv[1]) if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else Path("out")
out.mkdir(parents=True, exist_ok=True)

# %% A design, prepared once: a built-in example (or rb.prepare("my_design.toml"))
problem = rb.prepare("rv80e")
print(problem)

# %% Deterministic stack-up and sensitivities (paper Tables 2-3, Eq. (1)-(7))
stack = rb.analyze(problem)
print(stack)  # a few lines; stack.to_frame() is the factor table
factors = stack.to_frame()
print(factors.sort_values("rank")[["key", "variance_share", "sensitivity_arcmin_per_um", "zone_origin"]].head(5))

# %% Monte-Carlo: how many units meet a 3 arcmin spec?
sim = rb.simulate(problem, samples=1_000_000, seed=1, spec_arcmin=3.0)
y = sim.yield_
print(f"yield {y.fraction:.4%} (95 % CI {y.ci95_low:.4%} .. {y.ci95_high:.4%}), Cpk {sim.output.cpk:.2f}")
print(sim.to_frame())

# %% Which precision grade to buy: the paper's Fig. 4 scenarios (exact distribution, no sampling)
comparison = rb.compare(problem, paper=True, method="exact", spec_arcmin=3.0)
print(comparison.to_frame()[["factors_changed", "mean_arcmin", "sigma_arcmin", "q99865_arcmin"]])

# %% The HTML report of all of the above, and the plain numbers for Excel / MATLAB
report = rb.make_report(problem, samples=200_000, seed=1, spec_arcmin=3.0, paper=True)
(out / "quickstart-report.html").write_text(rb.render_html(report), encoding="utf-8")
factors.to_csv(out / "quickstart-factors.csv")
print("wrote", out / "quickstart-report.html", "and", out / "quickstart-factors.csv")
