# gearsim set-up: `make run` and `make test` do everything on a fresh machine.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
OUT ?= out
# one simulation per integrator variant of spur-19-48 (argument: tables or contacts), with
# the seed's stiffness law: the kernels are the same, and the accurate model's one-time
# FE calibration of the two gears would make one process wait for the other
WARM := import sys, gearsim as gs; from gearsim.stiffness.settings import MODELS; \
  c = sys.argv[1] == "contacts"; gb = gs.example("spur-19-48").replace(stiffness=MODELS["seed"]); \
  p = dict(speed_times=[0.0, 0.2], speed_values=[180.0, 190.0]); \
  [gs.simulate(gb, duration=0.11, fs=20e3, transient=0.01, contact_mesh=c, **kw) \
   for kw in ({}, p)]

.PHONY: run test lint bench sysdeps clean
.PHONY: browser

# System libraries that the gmsh wheel links (libGLU, libX11, libXcursor, libXft,
# libXinerama, fontconfig). Installed with apt only when the import of gmsh fails.
sysdeps: $(STAMP)
	@if ! $(BIN)/python -c "import gmsh" >/dev/null 2>&1; then \
	  echo "gmsh cannot load its system libraries: installing them with apt-get"; \
	  SUDO=""; [ "$$(id -u)" = "0" ] || SUDO="sudo"; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq libglu1-mesa libx11-6 \
	    libxcursor1 libxft2 libxinerama1 fontconfig libxrender1 libxext6 libgl1 >/dev/null; \
	fi

# Headless Chromium and its driver for tests/studies/test_report_browser.py (only tests
# need a browser: `run` does not depend on this). Debian's packages, installed with apt
# only when /usr/bin/chromium or /usr/bin/chromedriver is missing; selenium is pointed at
# them, so nothing is downloaded at test time.
browser:
	@if [ ! -x /usr/bin/chromium ] || [ ! -x /usr/bin/chromedriver ]; then \
	  echo "chromium or chromedriver missing: installing them with apt-get"; \
	  SUDO=""; [ "$$(id -u)" = "0" ] || SUDO="sudo"; \
	  $$SUDO apt-get update -qq && \
	  $$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null; \
	fi

$(STAMP): pyproject.toml constraints.txt
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	@# the bytecode of every installed file, compiled on both cores (pip compiles it on
	@# one: ~55 s measured); compileall reports the few files of other Python versions
	@# that some packages ship, as pip does, without failing the install
	$(BIN)/python -m pip install -q --no-compile -c constraints.txt -e ".[test]"
	-$(BIN)/python -m compileall -q -j 0 $(VENV)/lib >/dev/null 2>&1
	@# and gearsim's own (an editable install is not compiled by pip; where the
	@# environment sets PYTHONDONTWRITEBYTECODE, every command would otherwise compile the
	@# modules it imports: 0.13-0.16 s of `gearsim simulate`'s start, measured)
	$(BIN)/python -m compileall -q -j 0 src/gearsim >/dev/null
	@# compile the numba kernels once into their cache (every integrator variant: tables
	@# or contacts, constant speed or a profile), so test workers do not each compile them;
	@# two processes, one per core (the contact variants in one, the table ones in the other)
	$(BIN)/python -c '$(WARM)' tables 2>/dev/null & \
	  $(BIN)/python -c '$(WARM)' contacts 2>/dev/null; b=$$?; wait $$! && [ $$b = 0 ]
	touch $(STAMP)

run: sysdeps
	$(BIN)/gearsim reproduce --out $(OUT)

# Every core (pytest-xdist; whole files to one worker, so an expensive module fixture such
# as the reproduction is built once, not once per worker), one BLAS thread per worker (a
# second one would only spin against the other worker); the 20 slowest
# tests are printed at the end. One numba thread per worker too (its threaded kernels, the
# tooth-compliance batches, would wait on the other worker's core).
test: sysdeps browser
	OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 NUMBA_NUM_THREADS=1 \
	  $(BIN)/python -m pytest -q -n auto --dist loadfile --durations=20 tests --doctest-modules src/gearsim

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

bench: sysdeps
	$(BIN)/python benchmarks/run_all.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
