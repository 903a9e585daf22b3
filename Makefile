# Two commands do all set-up on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
OUT ?= out/demo

.PHONY: demo test docs lint bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[test]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/tcpmm demo -o $(OUT)

test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples docs
	$(BIN)/python -m pytest -q -n 2

# The documentation site (site/), built strictly: a warning (a broken link, a page left
# out of the navigation, an API name that does not resolve) fails the build.
docs: $(VENV)/.docs
	$(BIN)/mkdocs build --strict

$(VENV)/.docs: $(STAMP)
	$(BIN)/python -m pip install -q -e '.[test,docs]'
	touch $(VENV)/.docs

bench: $(STAMP)
	$(BIN)/python benchmarks/simulate.py
	$(BIN)/python benchmarks/fit.py
	$(BIN)/python benchmarks/interpolate.py
	$(BIN)/python benchmarks/identify.py

clean:
	rm -rf $(VENV) out build site *.egg-info src/*.egg-info
