# rvcoax: two commands set up everything on a fresh Debian 12 machine.
#   make run    create .venv, install, run the published-table check on the reference rig
#   make test   create .venv, install with test extras, run the test suite (make test-fast: the quick half)
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= rvcoax_out

.PHONY: run test test-fast lint bench system-deps test-deps clean

# System packages a bare Debian 12 lacks: python3-venv; the shared libraries gmsh loads at run time
# (libGLU, libGL, X client libraries, OpenMP); EGL + Mesa for off-screen VTK rendering. Only the
# missing ones are installed, and only when we are root (CI, fresh machines); otherwise a message.
DEBIAN_PACKAGES := python3-venv libglu1-mesa libgl1 libxcursor1 libxft2 libxinerama1 libgomp1 \
                   libegl1 libegl-mesa0 libgl1-mesa-dri
# $(call debian-install,PACKAGES,WHEN-IT-CANNOT): install the missing PACKAGES when root, else run WHEN-IT-CANNOT
define debian-install
	@missing=""; for p in $(1); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ] && command -v dpkg-query >/dev/null; then \
	  if [ "$$(id -u)" = "0" ] && command -v apt-get >/dev/null; then \
	    echo "installing Debian packages:$$missing"; \
	    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing; } \
	      || { $(2); }; \
	  else echo "missing Debian packages:$$missing (run: sudo apt-get install$$missing)"; $(2); fi; \
	fi
endef

system-deps:
	$(call debian-install,$(DEBIAN_PACKAGES),exit 1)

# The tests open the HTML report in headless Chromium (Debian package chromium) and compare modes with CalculiX
# (calculix-ccx). Installed for `make test`
# when missing and we are root; without it the one browser test is skipped and says why.
TEST_PACKAGES := chromium calculix-ccx
test-deps:
	$(call debian-install,$(TEST_PACKAGES),echo "the report's browser test and the CalculiX modal comparison will be skipped")

$(BIN)/rvcoax: pyproject.toml | system-deps
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip "setuptools>=77"
	$(BIN)/python -m pip install --quiet -e ".[test]"
	@touch $@

# `check` exits 0 (within tolerance), 1 (outside tolerance) or 3 (within tolerance only with an
# implausible fitted parameter: the reference rig's case): each is a finished run whose verdict is
# printed and written to $(OUT)/check_verdict.json. Exit 2 (a user error) or any other fails `make run`.
run: $(BIN)/rvcoax
	@$(BIN)/rvcoax check --out $(OUT); status=$$?; \
	case $$status in 0|1|3) echo "make run: check finished with verdict exit status $$status (see $(OUT)/check_verdict.json)";; \
	  *) exit $$status;; esac

# The suite runs in parallel (pytest-xdist): one worker per core this process may use (its CPU affinity; not
# `nproc`, which follows OMP_NUM_THREADS), at most 4 (each worker holds its own meshes and module fixtures,
# about 1 GB); on one core, no workers. `--dist loadfile` keeps each test file on one worker: its module
# fixtures are built once and the Dask cluster's tests keep their order. TEST_WORKERS=0 runs it serially.
TEST_WORKERS ?= $(shell $(PYTHON) -c "import os; n = len(os.sched_getaffinity(0)); print(min(n, 4) if n > 1 else 0)" 2>/dev/null || echo 0)
PYTEST_PARALLEL = -n $(TEST_WORKERS) --dist loadfile

test: $(BIN)/rvcoax test-deps
	$(BIN)/python -m pytest -q $(PYTEST_PARALLEL)

# The quick half: everything but the tests marked slow, dask or render.
test-fast: $(BIN)/rvcoax
	$(BIN)/python -m pytest -q $(PYTEST_PARALLEL) -m "not slow and not dask and not render"

lint: $(BIN)/rvcoax
	$(BIN)/ruff check .

# Benchmarks print their figures and append them to benchmarks/RESULTS.md. CalculiX (the peer of
# bench_calculix.py) is installed from Debian when missing and we are root.
bench: $(BIN)/rvcoax
	@command -v ccx >/dev/null || { [ "$$(id -u)" = "0" ] && apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends calculix-ccx; } || true
	$(BIN)/python benchmarks/bench_sweep.py
	$(BIN)/python benchmarks/bench_startup.py
	$(BIN)/python benchmarks/bench_convergence.py
	$(BIN)/python benchmarks/bench_fidelity.py
	$(BIN)/python benchmarks/bench_calculix.py
	$(BIN)/python benchmarks/bench_housing_calculix.py
	$(BIN)/python benchmarks/bench_solid_scaling.py

clean:
	rm -rf $(VENV) $(OUT) build *.egg-info
