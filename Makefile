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

.PHONY: demo test bench bags venv clean

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

bags: $(STAMP)
	$(VENV)/bin/polyforce make-bags --out bags

test: $(STAMP)
	$(PY) -m pytest test

clean:
	rm -rf $(VENV) build install log .pytest_cache
