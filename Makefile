# Two commands for users (see README): `make demo` and `make test`.
# Both create or reuse the local virtual environment in .venv by themselves.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

# The ROS wheels do not set AMENT_PREFIX_PATH; DDS traffic stays on this machine.
export AMENT_PREFIX_PATH := $(abspath $(VENV))
export ROS_AUTOMATIC_DISCOVERY_RANGE := LOCALHOST
export ROS_DOMAIN_ID ?= 42

# A ROS 2 Jazzy user's environment (Ubuntu 24.04: Python 3.12, numpy 1.26.4, scipy 1.11.4) for the unit layer.
PY312  ?= $(shell for p in python3.12 $(wildcard $(HOME)/.pyenv/versions/3.12*/bin/python3.12); do \
            $$p -c 'import sys' >/dev/null 2>&1 && { command -v $$p || echo $$p; } && break; done)
NOBLE  := .venv-noble
NOBLE_STAMP := $(NOBLE)/.installed

.PHONY: demo test test-noble bench bags venv clean

venv: $(STAMP)

$(STAMP): requirements.txt setup.py setup.cfg package.xml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.txt
	$(PY) -m pip install --quiet --disable-pip-version-check --no-deps -e .
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/polyforce demo

bench: $(STAMP)
	$(PY) bench/bench_offline.py
	$(PY) bench/bench_live.py
	$(PY) bench/bench_bridge.py
	$(PY) bench/bench_chain.py

bags: $(STAMP)
	$(VENV)/bin/polyforce make-bags --out bags

test: $(STAMP)
	$(PY) -m pytest test

$(NOBLE_STAMP): requirements-noble.txt setup.py setup.cfg package.xml
	test -x $(NOBLE)/bin/python || $(PY312) -m venv $(NOBLE)
	$(NOBLE)/bin/python -m pip install --quiet --disable-pip-version-check -r requirements-noble.txt
	$(NOBLE)/bin/python -m pip install --quiet --disable-pip-version-check --no-deps -e .
	touch $(NOBLE_STAMP)

# The unit layer in the noble environment; skipped (with a message) where no Python 3.12 exists.
test-noble:
	@if [ -z "$(PY312)" ]; then echo "test-noble: no python3.12 on this machine: skipped"; else \
	  $(MAKE) --no-print-directory $(NOBLE_STAMP) && \
	  AMENT_PREFIX_PATH=$(abspath $(NOBLE)) $(NOBLE)/bin/python -m pytest -m unit test; fi

clean:
	rm -rf $(VENV) $(NOBLE) build install log .pytest_cache
