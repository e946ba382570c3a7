# Two commands matter: `make run` (the demo) and `make test` (the test suite).
# Each sets up what it needs itself, in stages: `make run` the demo's Debian packages (when
# run as root), a virtualenv in .venv and the runtime packages of pyproject.toml; `make
# test` adds the tests' Debian packages and the dev extra on top. A stamp a stage.

VENV    ?= .venv
PY      := $(VENV)/bin/python
RUN_STAMP  := $(VENV)/.installed-run
TEST_STAMP := $(VENV)/.installed-test
SETUP_LOG  := $(VENV)/setup.log
# The demo's: the GL of a headless render (EGL, GLES, GL); a window uses the display's own
# libraries, and glfw's wheel carries GLFW.
RUN_PKGS := libegl1 libgles2 libgl1
# The tests' (the demo's and): a display for the window tests, the shader compiler, the
# browser that drives the phone page, certutil for the phone's HTTPS, Node for the page's
# own JavaScript (tests/web), and WebKitWebDriver with WebKitGTK's MiniBrowser for the page
# in WebKit, the iPhone's engine (tests/test_webkit_e2e.py).
APT_PKGS := $(RUN_PKGS) xvfb xauth xdotool glslang-tools chromium libnss3-tools nodejs webkit2gtk-driver

.PHONY: run serve web test quick test-deep bench bench-sim bench-render lint system-run system-test clean

run: $(RUN_STAMP)
	$(PY) -m app $(ARGS)

serve: $(RUN_STAMP)
	$(PY) -m app serve $(ARGS)

# The phone page as a static site in site/ (docs/phone.md, Without a computer); ARGS as
# `frost web`'s (--weather-api URL, --geocoding-api URL). The Pages workflow runs the same.
web: $(RUN_STAMP)
	$(PY) -m app web site $(ARGS)

# Three workers (pytest-xdist) on CI's two cores: the suite waits on its subprocesses (the
# window under Xvfb, Chromium, frost serve) for much of its run, and two workers kept the
# cores busy only about 60 % of the time (the whole suite on the quiet two-core machine:
# two workers 463 s, three 407 s, four 430 s; as it is now, three 342-359 s and four 345 s,
# four taking more CPU, 624 s against 587: three keep the cores about 86 % busy, and a
# fourth only slows each test). The costliest
# modules go first (tests/conftest.py), and a worker left without tests takes half of
# another's (worksteal: xdist's default hands each worker a fixed share, and one sat idle
# for minutes while the other ran the browser tests).
WORKERS ?= 3
XDIST   := -n $(WORKERS) --dist worksteal

# The suite starts Python some hundreds of times (frost, frost serve, pytest in pytest), and
# where bytecode is not written (PYTHONDONTWRITEBYTECODE, which some machines set) each
# compiled the app's modules and pytest rewrote every test module again: the test targets
# write their bytecode into the virtualenv instead, out of the checkout.
PYCACHE := $(abspath $(VENV))/pycache
test quick test-deep: export PYTHONDONTWRITEBYTECODE :=
test quick test-deep: export PYTHONPYCACHEPREFIX := $(PYCACHE)

test: $(TEST_STAMP)
	$(PY) -m pytest $(XDIST) $(PYTEST_ARGS)

# A change's inner loop: the suite without what opens Chromium or a window under Xvfb,
# what starts Python in a subprocess (frost, frost serve, pytest), the slow tests and the
# validation runs, with a fifth of the property tests' examples (docs/testing.md); the
# same test stage.
QUICK := not browser and not window and not subprocess and not slow and not validation

quick: $(TEST_STAMP)
	FROST_HYPOTHESIS=frost-quick $(PY) -m pytest $(XDIST) -m "$(QUICK)" $(PYTEST_ARGS)

# The suite plus its validation runs (DLA dimension, full-screen wipe, long brute force).
test-deep: $(TEST_STAMP)
	$(PY) -m pytest $(XDIST) --deep $(PYTEST_ARGS)

bench: bench-sim bench-render

bench-sim: $(RUN_STAMP)
	$(PY) -m app bench sim $(ARGS)

bench-render: $(RUN_STAMP)
	$(PY) -m app bench render $(ARGS)

# ruff and mypy are the dev extra's, so the linters take the test stage.
lint: $(TEST_STAMP)
	$(VENV)/bin/ruff check app sim bench tests assets
	$(VENV)/bin/mypy app sim bench

# The Debian packages of $(1) that are missing (and python3-venv where Python has no
# ensurepip): installed with apt-get as root, said in one line otherwise.
define apt
	@missing=""; for p in $(1); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	python3 -c 'import ensurepip' >/dev/null 2>&1 || missing="$$missing python3-venv"; \
	if [ -z "$$missing" ]; then exit 0; fi; \
	if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "frost: installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	else \
	  echo "frost: please install these Debian packages (as root): apt-get install$$missing"; \
	fi
endef

# Quiet unless it fails: pip -q still prints setuptools' banner from the editable build,
# so a stage's output goes to a log that is shown only when a step fails.
define pip_stage
	@echo "frost: setting up $(VENV): $(1) (about a minute)"
	@mkdir -p $(VENV)
	@{ $(2); } >$(SETUP_LOG) 2>&1 || { \
	  cat $(SETUP_LOG); echo "frost: setting up $(VENV) failed (log: $(SETUP_LOG))"; exit 1; }
	@touch $@
endef

system-run:
	$(call apt,$(RUN_PKGS))

system-test:
	$(call apt,$(APT_PKGS))

$(RUN_STAMP): pyproject.toml setup.py | system-run
	$(call pip_stage,the runtime packages,python3 -m venv $(VENV) && \
	  $(PY) -m pip install -q --upgrade pip && $(PY) -m pip install -q -e .)

# The test stage also compiles the bytecode of what the suite imports (its modules, the
# app's, their libraries': a collection of the suite, 8 s) into $(PYCACHE), where nothing
# from pip's install counts: else the suite's three workers and the first `frost`s they
# start each compiled the same modules at once (a fresh clone's first `make test`: 356 s of
# tests, its second 330 s). A test module that cannot be collected is left to the run.
$(TEST_STAMP): $(RUN_STAMP) | system-test
	$(call pip_stage,the test stack,$(PY) -m pip install -q -e '.[dev]' && \
	  { PYTHONDONTWRITEBYTECODE= PYTHONPYCACHEPREFIX=$(PYCACHE) \
	    $(PY) -m pytest --collect-only -q -p no:xdist -p no:cacheprovider || true; })

clean:
	rm -rf $(VENV) build *.egg-info
