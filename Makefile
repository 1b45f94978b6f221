# Two entry points (see README): `make example` and `make test`.
# Both create the virtual environment in .venv/ on first use and reinstall when
# pyproject.toml changes.

PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed-stamp

.PHONY: example test clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

example: $(STAMP)
	mkdir -p out
	$(VENV)/bin/rvbacklash analyze sun2014 --json out/sun2014.json --csv out/sun2014.csv

test: $(STAMP)
	$(VENV)/bin/python -m pytest

clean:
	rm -rf $(VENV) out
