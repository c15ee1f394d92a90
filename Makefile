# facet: two commands on a fresh clone.
#   make render   create .venv, install facet, render the bundled model to out/default.png
#   make test     install the dev dependencies too and run the whole test suite
#                 (JOBS processes side by side; JOBS=1 for one)
#   make bench    run the benchmarks (prints tables; asserts nothing)
#   make docs     run the examples and build the documentation site into build/site
#   make lint     ruff, and mypy on the public modules
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
PIP    := $(BIN)/python -m pip --disable-pip-version-check -q
# Test processes side by side: one per core, at most 4 (llvmpipe renders on every core).
JOBS   ?= $(shell n=$$(nproc 2>/dev/null || echo 1); [ $$n -gt 4 ] && n=4; echo $$n)

.PHONY: render test bench lint docs check-gl clean

check-gl:
	@sh tools/check-gl.sh

$(VENV)/.installed: pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(PIP) install -e .
	@touch $@

$(VENV)/.installed-dev: $(VENV)/.installed
	$(PIP) install -e '.[dev]'
	@touch $@

render: check-gl $(VENV)/.installed
	@$(BIN)/facet render -o out/default.png

test: check-gl $(VENV)/.installed-dev
	$(BIN)/python -m pytest -n $(JOBS) --dist worksteal

bench: check-gl $(VENV)/.installed-dev
	@$(PIP) install -e '.[bench]' || echo "(embreex or pyrender not installable here: their columns are skipped)"
	$(BIN)/python benchmarks/run.py

lint: $(VENV)/.installed-dev
	$(BIN)/ruff check app tests benchmarks models tools examples
	$(BIN)/mypy

# The documentation site: run the gallery's examples (each picture checked against the stored
# one), then build with warnings as errors into build/site.
docs: check-gl $(VENV)/.installed-dev
	$(BIN)/python tools/gallery.py build/examples
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

clean:
	rm -rf $(VENV) out dist build
