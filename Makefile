# facet: two commands on a fresh clone.
#   make render     create .venv, install facet from uv.lock, render the bundled model to
#                   out/default.png
#   make test       install the dev set from uv.lock too and run the fast tier of the tests
#                   (JOBS processes side by side; JOBS=1 for one)
#   make test-all   every test: the fast tier and the slow one (soaks, browsers, Ray, the
#                   wheel, 4096-spp references); what .ci/run runs, with make docs
#   make bench      run the benchmarks (prints tables; asserts nothing)
#   make docs       run the examples and build the documentation site into build/site
#   make lint       ruff, and mypy on the public modules
#   make lock       resolve uv.lock anew (newest versions within pyproject.toml's ranges)
#   make test-latest  the whole suite against the newest versions, in .venv-latest (drift
#                   found on purpose; .venv and uv.lock are left as they are)
# Every target installs exactly what uv.lock names (uv sync --frozen); pyproject.toml keeps
# the ranges a user's pip install gets. How to add a dependency: docs/development.md.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
UV     := $(VENV)/.uv/bin/uv
# uv never downloads a Python of its own: .venv's (made from $(PYTHON)) is the one.
export UV_PYTHON_DOWNLOADS := never
# Mesa's compiled shaders are kept in the environment, not the home folder (a warm cache
# halves the suite's time on llvmpipe; tests/conftest.py sets the same for pytest alone).
export MESA_SHADER_CACHE_DIR ?= $(CURDIR)/$(VENV)/cache/mesa-shader-cache
SYNC   := $(UV) sync --frozen --quiet
# Test processes side by side: one per core, at most 4 (llvmpipe renders on every core).
JOBS   ?= $(shell n=$$(nproc 2>/dev/null || echo 1); [ $$n -gt 4 ] && n=4; echo $$n)
PYTEST := $(BIN)/python -m pytest -n $(JOBS) --dist worksteal

.PHONY: render test test-all test-latest tiers bench lint docs lock lock-uv check-gl sync-dev \
        clean

check-gl:
	@sh tools/check-gl.sh
	@mkdir -p $(MESA_SHADER_CACHE_DIR)

# uv itself, pinned by hash, beside the environment it manages (uv sync removes what the
# lock does not name from site-packages; .venv/.uv is outside it).
$(UV): tools/uv-bootstrap.txt
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip --disable-pip-version-check -q install --require-hashes \
	    --no-deps --upgrade --target $(VENV)/.uv -r tools/uv-bootstrap.txt
	@touch $@

# render needs facet's own dependencies only; it leaves anything else installed in place.
render: check-gl $(UV)
	@$(SYNC) --inexact
	@$(BIN)/facet render -o out/default.png

sync-dev: $(UV)
	@$(SYNC) --extra dev

test: check-gl sync-dev
	$(PYTEST) -m "not slow"

test-all: check-gl sync-dev
	$(PYTEST)

# The tiers anew from measured durations: the whole suite with --durations=0, then
# tests/slow_tests.txt from it (tools/tiers.py).
tiers: check-gl sync-dev
	@mkdir -p build
	$(PYTEST) --durations=0 -q | tee build/durations.txt
	$(BIN)/python tools/tiers.py build/durations.txt

bench: check-gl $(UV)
	@$(SYNC) --extra dev --extra bench
	$(BIN)/python benchmarks/run.py

lint: sync-dev
	$(BIN)/ruff check app tests benchmarks models tools examples
	$(BIN)/mypy

# The documentation site: run the gallery's examples (each picture checked against the stored
# one), then build with warnings as errors into build/site.
docs: check-gl sync-dev
	$(BIN)/python tools/gallery.py build/examples
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

lock: $(UV)
	$(UV) lock --upgrade

lock-uv: $(UV)
	echo "uv" | $(UV) pip compile --generate-hashes --no-header --upgrade - \
	    -o tools/uv-bootstrap.txt.new
	{ sed -n '/^#/p' tools/uv-bootstrap.txt; cat tools/uv-bootstrap.txt.new; } \
	    > tools/uv-bootstrap.txt.tmp && rm tools/uv-bootstrap.txt.new && \
	    mv tools/uv-bootstrap.txt.tmp tools/uv-bootstrap.txt

# The newest versions pyproject.toml's ranges allow, in an environment of their own.
test-latest: check-gl $(UV)
	@test -x .venv-latest/bin/python || $(PYTHON) -m venv .venv-latest
	$(UV) pip install --quiet --python .venv-latest/bin/python --upgrade --refresh -e '.[dev]'
	.venv-latest/bin/python -m pytest -n $(JOBS) --dist worksteal

clean:
	rm -rf $(VENV) .venv-latest out dist build
