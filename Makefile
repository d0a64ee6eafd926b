# Two commands for a fresh machine with Python 3 and make:
#   make demo   create .venv, install flexcal, calibrate the shipped sample experiment
#   make test   create .venv, install flexcal with its test extra, run the whole test suite
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.flexcal-installed
OUT ?= out/sample

.PHONY: demo test venv clean

venv: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/calibrate --trials datasets/sample --pressure datasets/sample/pressure.csv --out $(OUT)
	@echo "open the report: $(OUT)/report.html"

test: $(STAMP)
	$(BIN)/python -m pytest

clean:
	rm -rf $(VENV) out
