# roughdiffuse: the two commands of the README.
#   make figures   set up .venv, install the package, write the lecture's figures to figures/
#   make test      the same set-up plus test extras and system packages, then the test suite
#   make docs      the same set-up plus docs extras and system packages, then the documentation
#                  site into docs/_build/html (warnings are errors)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip
# libLLVM for Mitsuba's llvm variants (Debian's libllvm19; see scripts/system-deps.sh), looked
# up by the shell when `test` and `docs` run, after system-deps has installed it (make's own
# $(wildcard) caches the folder as it was before), unless DRJIT_LIBLLVM_PATH is set
WITH_LLVM = DRJIT_LIBLLVM_PATH="$${DRJIT_LIBLLVM_PATH:-$$(ls /usr/lib/x86_64-linux-gnu/libLLVM.so.19* /usr/lib/*/libLLVM-19.so /usr/lib/*/libLLVM.so.1* 2>/dev/null | head -n 1)}"

.PHONY: figures test docs install install-test install-js test-all install-docs install-blender system-deps lint bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip

$(VENV)/.installed: pyproject.toml | $(PY)
	$(PIP) install -q -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml $(VENV)/.installed
	@# PyTorch: the CPU wheel shipped with this machine image when present (the PyPI
	@# default pulls several GB of CUDA packages); tests of the torch backend skip without it
	if ls /opt/wheels/torch-2.13.0* >/dev/null 2>&1; then $(PIP) install -q torch==2.13.0; fi
	$(PIP) install -q -e ".[test,docs]"
	touch $@

$(VENV)/.installed-docs: pyproject.toml $(VENV)/.installed
	$(PIP) install -q -e ".[docs]"
	touch $@

# Blender as a Python module (the bpy wheel, about 375 MB to download) for the Blender check
# and the .blend export. It pins its own NumPy (1.26) and Python (3.11), so it gets a virtual
# environment of its own, which roughdiffuse runs as a subprocess (roughdiffuse.exporters.
# blender_run finds it here, or through ROUGHDIFFUSE_BLENDER_PYTHON)
BLENDER_VENV ?= .venv-blender
BLENDER_PYTHON ?= python3.11
BPY_VERSION ?= 5.0.1
$(BLENDER_VENV)/.installed:
	$(BLENDER_PYTHON) -m venv $(BLENDER_VENV)
	$(BLENDER_VENV)/bin/python -m pip install -q --upgrade pip
	$(BLENDER_VENV)/bin/python -m pip install -q bpy==$(BPY_VERSION)
	touch $@

install-blender: $(BLENDER_VENV)/.installed

# three.js (npm) for the test that renders `roughdiffuse export --to glsl` in a ShaderMaterial:
# the versions of tests/js/package-lock.json, installed by `npm ci` into tests/js/node_modules
tests/js/node_modules/.installed: tests/js/package-lock.json
	npm ci --prefix tests/js --no-audit --no-fund --loglevel=error
	touch $@

install-js: tests/js/node_modules/.installed

install: $(VENV)/.installed

install-test: $(VENV)/.installed-test

install-docs: $(VENV)/.installed-docs

system-deps:
	bash scripts/system-deps.sh

figures: install
	$(VENV)/bin/roughdiffuse figures

# pytest-xdist: one worker per core (WORKERS=0: one process); a test file runs on one worker,
# so module- and session-scoped fixtures are made once, and the files go out heaviest first
# (tests/conftest.py FILE_SECONDS; docs/developer/testing.md). A worker that crashes is not
# replaced (--max-worker-restart=0): the run ends, naming the test it crashed in (under
# --dist loadfile, xdist 3.8 hangs after replacing a crashed worker: pytest-xdist issue 784)
WORKERS ?= $(shell nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
# `make test` leaves out the tests marked slow (pyproject.toml); `make test SLOW=1` (CI) and
# `make test-all` run every one
SLOW ?=
test: install-test system-deps install-js
	$(PY) -m ruff check src tests $(wildcard bench examples)
	$(WITH_LLVM) $(PY) -m pytest -n $(WORKERS) --dist loadfile --no-loadscope-reorder --max-worker-restart=0 $(if $(SLOW),,-m "not slow")

test-all:
	$(MAKE) test SLOW=1

# Sphinx runs the gallery and the notebooks; nothing is downloaded (see docs/conf.py). The
# system packages are those of the tests: the Mitsuba example needs libLLVM 19 (with an older
# one it renders with scalar_rgb, roughdiffuse.integrations.drjit_llvm)
docs: install-docs system-deps
	$(WITH_LLVM) $(PY) -m sphinx -b html -W --keep-going docs docs/_build/html

bench: install
	$(PY) bench/run.py

clean:
	rm -rf $(VENV) $(BLENDER_VENV) tests/js/node_modules figures .pytest_cache docs/_build docs/models docs/api docs/auto_gallery docs/jupyter_execute
