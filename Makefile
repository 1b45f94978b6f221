# Two entry points (see README): `make example` and `make test`.
# Both create the virtual environment in .venv/ on first use and reinstall when
# pyproject.toml changes.

PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed-stamp

.PHONY: example test bench screenshot clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -e '.[test,sweep]'
	touch $(STAMP)

# The main job: the HTML report of the built-in RV-80E-class example: the paper's scenarios and
# the cheapest grades that keep 99 % of the units within 3 arcmin.
example: $(STAMP)
	mkdir -p out
	$(VENV)/bin/rvbacklash report rv80e --paper --spec-arcmin 3 --allocate --yield 0.99 --seed 1 -o out/report.html --json out/report.json --force

test: $(STAMP)
	tools/ensure-chromium
	$(VENV)/bin/python -m pytest

# Every performance target of issue 19 in one table (minutes; BENCH_ARGS=--no-commands leaves out
# the sensitivity and allocate wall times).
bench: $(STAMP)
	$(VENV)/bin/python bench/bench_all.py $(BENCH_ARGS)

# Refresh docs/report.png (the README's picture) from the example report.
screenshot: example
	$(VENV)/bin/python tools/screenshot.py out/report.html docs/report.png

clean:
	rm -rf $(VENV) out
