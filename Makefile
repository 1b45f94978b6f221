# Two entry points (see README): `make example` and `make test`.
# Both create the virtual environment in .venv/ on first use and reinstall when
# pyproject.toml changes. `make example` installs the package and what it needs to run
# (RUN_STAMP); the test and sweep extras come on top for `make test` and `make bench` (STAMP):
# a first `make example` does not wait for playwright, pandas, dask and pyarrow.

PYTHON ?= python3
VENV := .venv
RUN_STAMP := $(VENV)/.installed-run
STAMP := $(VENV)/.installed-stamp

.PHONY: example test bench screenshot clean

$(RUN_STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -e .
	touch $(RUN_STAMP)

$(STAMP): $(RUN_STAMP)
	$(VENV)/bin/python -m pip install --quiet -e '.[test,sweep]'
	touch $(STAMP)

# The main job: the HTML report of the built-in RV-80E-class example as the test bench will read it:
# a production run of 20 000 units through the elastic model (lost motion <= 1.5 arcmin, rigidity
# >= 200 N m/arcmin: the RV-80E catalogue's class), the nominal hysteresis loop, where the lost motion comes from, what to tighten
# (Sobol indices) and the cheapest grades (contact model, 2000 units per candidate). README gives the time.
example: $(RUN_STAMP)
	mkdir -p out
	$(VENV)/bin/rvbacklash report rv80e --model elastic -n 20000 --spec-arcmin 1.5 --spec-rigidity-nm-per-arcmin 200 --allocate --allocate-model contact --allocate-samples 2000 --yield 0.95 --seed 1 -o out/report.html --json out/report.json --force

test: $(STAMP)
	tools/ensure-chromium
	$(VENV)/bin/python -m pytest

# Every performance target of issue 19 in one table (minutes; BENCH_ARGS=--no-commands leaves out
# the sensitivity and allocate wall times).
bench: $(STAMP)
	$(VENV)/bin/python bench/bench_all.py $(BENCH_ARGS)

# Refresh docs/report.png (the README's picture) from the example report.
screenshot: example $(STAMP)
	$(VENV)/bin/python tools/screenshot.py out/report.html docs/report.png
	$(VENV)/bin/python tools/screenshot_workbench.py docs/workbench.png

clean:
	rm -rf $(VENV) out
