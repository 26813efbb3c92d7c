# rvcoax: two commands set up everything on a fresh Debian 12 machine.
#   make run    create .venv, install, run the published-table check on the reference rig
#   make test   create .venv, install with test extras, run the test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= rvcoax_out

.PHONY: run test lint bench system-deps clean

# System packages: only what a bare Debian 12 lacks for a Python venv (python3-venv). Installed
# when missing and when we are root (CI, fresh machines); otherwise a clear message.
system-deps:
	@if ! $(PYTHON) -c "import venv, ensurepip" >/dev/null 2>&1; then \
	  if [ "$$(id -u)" = "0" ] && command -v apt-get >/dev/null; then \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-venv; \
	  else echo "python3-venv is missing: run 'sudo apt-get install python3-venv'"; exit 1; fi; \
	fi

$(BIN)/rvcoax: pyproject.toml | system-deps
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	@touch $@

run: $(BIN)/rvcoax
	$(BIN)/rvcoax check --out $(OUT)

test: $(BIN)/rvcoax
	$(BIN)/python -m pytest -q

lint: $(BIN)/rvcoax
	$(BIN)/ruff check .

bench: $(BIN)/rvcoax
	$(BIN)/python benchmarks/bench_sweep.py

clean:
	rm -rf $(VENV) $(OUT) build *.egg-info
