# Two commands do all set-up on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
OUT ?= out/demo
REPORT ?= out/report
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
# Headless Chromium with every request sent to a closed port and every name unresolved:
# the report must render from the file alone.
CHROMIUM := chromium --headless --no-sandbox --disable-gpu --hide-scrollbars \
	--proxy-server=127.0.0.1:9 --proxy-bypass-list='<-loopback>' \
	--host-resolver-rules='MAP * ~NOTFOUND'

.PHONY: demo test docs lint bench clean check-report fuzz

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[test]'
	$(BIN)/python -m compileall -q src
	@# The simulation kernel compiled for this CPU (once; minutes on a fresh install):
	@# else the first command that simulates builds it, and a second process started
	@# meanwhile compiles numba's kernel for itself.
	$(BIN)/python -c "from tcpmm import _compiled; print('kernel:', _compiled.status())"
	@# numba's kernel too, which runs wherever the compiled module cannot be had and which
	@# the tests hold it to: compiled once into numba's cache (a minute), not by each
	@# process that first needs it
	TCPMM_COMPILED=0 $(BIN)/python -c "from tcpmm import builtin_machine, \
		paper_circle_command, simulate; simulate(builtin_machine(), paper_circle_command())"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/tcpmm demo -o $(OUT)
	@echo "README's five steps: D=$(abspath $(OUT)) T=$(abspath $(BIN))/tcpmm"

test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples docs studies
	$(BIN)/python -m pytest -q -n 2 --dist worksteal

# The long fuzz run: 10 000 cases per target of tests/test_fuzz.py (NC programs, model files
# changed key by key, bundles with columns swapped, scaled and cut short); the normal suite
# runs 30 of each. Last result in docs/validation/fuzz.md.
fuzz: $(STAMP)
	TCPMM_FUZZ_EXAMPLES=10000 $(BIN)/python -m pytest -q -p no:xdist tests/test_fuzz.py \
		--hypothesis-show-statistics

# The demo's HTML report rendered in headless Chromium with no network; screenshots of the
# first screen and of the whole page go to $(REPORT). A finished demo in $(OUT) is reused.
check-report: $(STAMP)
	@if [ ! -f $(OUT)/report.html ]; then $(BIN)/tcpmm demo -o $(OUT); fi
	@mkdir -p $(REPORT)
	@command -v chromium >/dev/null || \
		{ $(SUDO) apt-get update -qq && $(SUDO) apt-get install -y -qq chromium; }
	$(CHROMIUM) --window-size=1280,4000 --screenshot=$(abspath $(REPORT))/report.png \
		file://$(abspath $(OUT))/report.html 2>$(REPORT)/chromium.log
	$(CHROMIUM) --window-size=1280,16000 --screenshot=$(abspath $(REPORT))/report_full.png \
		file://$(abspath $(OUT))/report.html 2>>$(REPORT)/chromium.log
	@echo "report: $(abspath $(OUT))/report.html"
	@echo "screenshots: $(REPORT)/report.png (first screen), $(REPORT)/report_full.png"

# The documentation site (site/), built strictly: a warning (a broken link, a page left
# out of the navigation, an API name that does not resolve) fails the build.
docs: $(VENV)/.docs
	$(BIN)/mkdocs build --strict

$(VENV)/.docs: $(STAMP)
	$(BIN)/python -m pip install -q -e '.[test,docs]'
	touch $(VENV)/.docs

bench: $(VENV)/.bench
	$(BIN)/python benchmarks/simulate.py
	$(BIN)/python benchmarks/fit.py
	$(BIN)/python benchmarks/interpolate.py
	$(BIN)/python benchmarks/gcode.py
	$(BIN)/python benchmarks/identify.py
	$(BIN)/python benchmarks/memory.py
	$(BIN)/python benchmarks/frf_fit.py

$(VENV)/.bench: $(STAMP)
	$(BIN)/python -m pip install -q -e '.[test,bench]'
	touch $(VENV)/.bench

clean:
	rm -rf $(VENV) out build site *.egg-info src/*.egg-info
