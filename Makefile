# satgnc: `make demo` and `make test` set everything up on a fresh Debian/Ubuntu machine.
# Idempotent: stamps under build/ and .venv/ make a second run with nothing changed take seconds.
SHELL := /bin/bash
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
BUILD := build/py
CMAKE := $(VENV)/bin/cmake
CTEST := $(VENV)/bin/ctest
GEN := -G Ninja -DCMAKE_MAKE_PROGRAM=$(abspath $(VENV))/bin/ninja
PREFIX := $(CURDIR)/build/prefix
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
# ccache, when present, makes rebuilds in a second checkout (a git worktree) nearly free; paths are
# taken relative to the checkout so that two checkouts share the cache.
CCACHE := $(shell command -v ccache 2>/dev/null)
ifneq ($(CCACHE),)
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1
LAUNCHER_PIP := -C cmake.define.CMAKE_CXX_COMPILER_LAUNCHER=$(CCACHE)
LAUNCHER := -DCMAKE_CXX_COMPILER_LAUNCHER=$(CCACHE)
endif
SOURCES := $(shell find cpp python tests/cpp examples/cpp cmake -type f \
             -not -name '*.so' -not -path '*/__pycache__/*' 2>/dev/null) CMakeLists.txt pyproject.toml

.PHONY: demo test setup install cpp-test py-test example sanitize bench lint typecheck format clean wheel \
	wheel-test docs
.DEFAULT_GOAL := test

build/.system-stamp: scripts/setup-system.sh
	@mkdir -p build
	bash scripts/setup-system.sh
	@touch $@

$(VENV)/.stamp: requirements-dev.txt build/.system-stamp
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r requirements-dev.txt
	@touch $@

setup: build/.system-stamp $(VENV)/.stamp

# One CMake build serves the Python wheel, the gtest binaries and the installed C++ package.
build/.install-stamp: $(VENV)/.stamp $(SOURCES)
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PY) -m pip install -q --no-build-isolation --no-deps \
	  -C build-dir=$(BUILD) $(LAUNCHER_PIP) -C cmake.define.SATGNC_BUILD_TESTS=ON -C cmake.define.CMAKE_INSTALL_PREFIX=$(PREFIX) .
	$(CMAKE) --install $(BUILD) --component satgnc_dev --prefix $(PREFIX) > /dev/null
	@touch $@

install: build/.install-stamp

cpp-test: install
	$(CTEST) --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# Flight-style C++ linking only the installed static library (no Python).
example: install
	$(CMAKE) -S examples/cpp -B build/examples $(GEN) $(LAUNCHER) -DCMAKE_PREFIX_PATH=$(PREFIX) > /dev/null
	$(CMAKE) --build build/examples -j $(JOBS)
	@for exe in build/examples/satgnc_example_*; do echo "== $$exe"; $$exe || exit 1; done

py-test: install
	cd tests/python && ../../$(PY) -m pytest -q -p no:cacheprovider .

test: cpp-test example py-test wheel-test docs

demo: install
	$(VENV)/bin/satgnc reproduce

sanitize: setup
	$(CMAKE) -S . -B build/asan $(GEN) $(LAUNCHER) -DCMAKE_BUILD_TYPE=Debug -DSATGNC_BUILD_PYTHON=OFF \
	  -DSATGNC_BUILD_TESTS=ON -DSATGNC_SANITIZE=ON > /dev/null
	$(CMAKE) --build build/asan -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 $(CTEST) --test-dir build/asan --output-on-failure -j $(JOBS)

$(VENV)/.bench-stamp: requirements-bench.txt $(VENV)/.stamp
	$(PY) -m pip install -q -r requirements-bench.txt
	@touch $@

bench: install $(VENV)/.bench-stamp
	@for b in propagation propagation_defaults propagation_ensemble od guidance guidance_nonlinear analysis observation force_models_scipy ephemeris_spk filter filter_update; do \
	  echo "== bench/$$b.py"; $(PY) bench/$$b.py || exit 1; done

CXX_SOURCES = $$(find cpp tests/cpp examples/cpp bench/cpp -name '*.hpp' -o -name '*.cpp')

# mypy --strict over the examples and the call-every-public-function script, against the installed stubs.
typecheck: install
	$(VENV)/bin/mypy --strict examples/python tests/python/test_api_surface.py

lint: setup typecheck
	$(VENV)/bin/ruff check python tests bench examples
	$(VENV)/bin/clang-format --dry-run --Werror $(CXX_SOURCES)

format: setup
	$(VENV)/bin/clang-format -i $(CXX_SOURCES)

# A self-contained wheel: built once against Debian's SUNDIALS/ERFA/pugixml (ccache'd, its own build
# dir), then `auditwheel repair` copies those libraries into satgnc.libs/ and tags it manylinux.
WHEELHOUSE := build/wheelhouse
$(VENV)/.wheel-stamp: requirements-wheel.txt $(VENV)/.stamp
	$(PY) -m pip install -q -r requirements-wheel.txt
	@touch $@

$(WHEELHOUSE)/.stamp: $(VENV)/.wheel-stamp $(SOURCES) README.md
	rm -rf build/wheel-raw $(WHEELHOUSE)
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PY) -m pip wheel -q --no-build-isolation --no-deps \
	  -w build/wheel-raw -C build-dir=build/wheel $(LAUNCHER_PIP) .
	PATH=$(abspath $(VENV))/bin:$$PATH $(VENV)/bin/auditwheel repair -w $(WHEELHOUSE) build/wheel-raw/satgnc-*.whl
	@touch $@

wheel: $(WHEELHOUSE)/.stamp

# Installs the wheel into a clean venv (no build tools), checks with ldd that the bundled libraries are
# used, runs the README's quick start and `satgnc reproduce --help` (scripts/check_wheel.py).
wheel-test: wheel
	$(PYTHON) scripts/check_wheel.py $(WHEELHOUSE) build/wheel-venv

# The documentation site (Sphinx, warnings are errors; the gallery's examples run at build time).
$(VENV)/.docs-stamp: requirements-docs.txt $(VENV)/.stamp
	$(PY) -m pip install -q -r requirements-docs.txt
	@touch $@

docs: install $(VENV)/.docs-stamp
	$(VENV)/bin/sphinx-build -W --keep-going -q -b html docs build/docs

clean:
	rm -rf build
