# Two commands matter: `make run` (the demo) and `make test` (the test suite).
# Each sets everything up itself: Debian packages (when run as root), a
# virtualenv in .venv, and the Python packages of pyproject.toml.

VENV    ?= .venv
PY      := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
SETUP_LOG := $(VENV)/setup.log
APT_PKGS := xvfb xauth xdotool libegl1 libgles2 libgl1 glslang-tools chromium libnss3-tools

.PHONY: run test test-deep bench bench-sim bench-render lint system clean

run: $(STAMP)
	$(PY) -m app $(ARGS)

# Two workers (pytest-xdist): CI's machine has two cores, and half the suite waits on
# subprocesses (the window under Xvfb, the CLI), so two halve the wall time.
WORKERS ?= 2

test: $(STAMP)
	$(PY) -m pytest -n $(WORKERS) $(PYTEST_ARGS)

# The suite plus its validation runs (DLA dimension, full-screen wipe, long brute force).
test-deep: $(STAMP)
	$(PY) -m pytest -n $(WORKERS) --deep $(PYTEST_ARGS)

bench: bench-sim bench-render

bench-sim: $(STAMP)
	$(PY) -m app bench sim $(ARGS)

bench-render: $(STAMP)
	$(PY) -m app bench render $(ARGS)

lint: $(STAMP)
	$(VENV)/bin/ruff check app sim tests assets
	$(VENV)/bin/mypy app sim

system:
	@missing=""; for p in $(APT_PKGS); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	python3 -c 'import ensurepip' >/dev/null 2>&1 || missing="$$missing python3-venv"; \
	if [ -z "$$missing" ]; then exit 0; fi; \
	if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "frost: installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	else \
	  echo "frost: please install these Debian packages (as root): apt-get install$$missing"; \
	fi

# Quiet unless it fails: pip -q still prints setuptools' banner from the editable build,
# so the set-up's output goes to a log that is shown only when a step fails.
$(STAMP): pyproject.toml setup.py | system
	@echo "frost: setting up $(VENV) (the Python packages; about a minute)"
	@mkdir -p $(VENV)
	@{ python3 -m venv $(VENV) && $(PY) -m pip install -q --upgrade pip && \
	   $(PY) -m pip install -q -e '.[dev]'; } >$(SETUP_LOG) 2>&1 || { \
	  cat $(SETUP_LOG); echo "frost: setting up $(VENV) failed (log: $(SETUP_LOG))"; exit 1; }
	@touch $(STAMP)

clean:
	rm -rf $(VENV) build *.egg-info
