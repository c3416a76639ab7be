# Every target creates .venv on first use; a fresh machine needs only python3.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
UV := $(VENV)/bin/uv
OUT ?= out

.PHONY: install browser-deps urdf-tools test test-fast demo urdf bench timings lint clean answers floor-springs docs-figures walking-map walking-map-3d designs designs-3d lateral-mass

# uv installs (PyPI's uv, put in the venv by its pip): one parallel resolve and download, no byte code compiled ahead
# (each module compiles as it is first imported). On this project's extras: 23 s on a cold cache and about 3 s on a
# warm one, where pip took 55 s with its cache warm.
$(UV):
	[ -x $(PY) ] || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet "uv>=0.5,<1"

# the plain install (what `pasibot analyze` needs: make demo), then the extras the tests need (make test)
$(VENV)/.installed-base: pyproject.toml | $(UV)
	$(UV) pip install --python $(PY) --quiet -e .
	touch $@

# On a fresh clone one call installs the package with its extras (one resolve, one build of the package).
$(VENV)/.installed: pyproject.toml | $(UV)
	$(UV) pip install --python $(PY) --quiet -e ".[dev,mujoco,sweep]"
	touch $(VENV)/.installed-base $@

install: $(VENV)/.installed

# Debian's chromium for tests/test_browser.py (a no-op when installed; sudo only when not root).
# If apt-get is unavailable this fails, and so does the browser test: it never skips.
browser-deps:
	@command -v chromium >/dev/null 2>&1 || { \
	  SUDO=$$([ "$$(id -u)" = 0 ] || echo sudo); \
	  $$SUDO apt-get update && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y --no-install-recommends chromium; }

# Debian's urdfdom tools (check_urdf) for tests/test_urdf_tools.py, the same way: it never skips.
urdf-tools:
	@command -v check_urdf >/dev/null 2>&1 || [ -x /usr/bin/check_urdf ] || { \
	  SUDO=$$([ "$$(id -u)" = 0 ] || echo sudo); \
	  $$SUDO apt-get update && \
	  DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y --no-install-recommends liburdfdom-tools; }

test: install browser-deps urdf-tools
	$(PY) -m pytest -q

# the fast tier: everything not marked slow, integration, browser, mujoco or network (pyproject's markers)
test-fast: install
	$(PY) -m pytest -q -m "not slow and not integration and not browser and not mujoco and not network"

demo: $(VENV)/.installed-base
	$(VENV)/bin/pasibot analyze --out $(OUT) --force

urdf: install
	$(VENV)/bin/pasibot build-urdf --defaults --force

# the design-exploration answers quoted in the README (docs/results/): three NSGA-II runs, about 2 minutes for
# question 1 and 3 minutes of CPU for question 2 (the spring designs walked 6 steps on the floor)
answers: install
	$(PY) tools/answers.py

# the walking map (docs/results/walking_map.csv, docs/walking_map.png): 108 designs walked 20 steps on 2 workers
# (about 30 minutes of CPU; tools/walking_answer.py); then the picture, the found designs (designs/) and the quoted
# answer (docs/walking.md, README.md) from the saved map
walking-map: install
	$(PY) tools/walking_answer.py --compute --workers 2

# designs/: the found designs (the walking sweep's fastest walker and the walking map's picks) from the committed
# tables, each with its picture (about 20 s); `$(PY) tools/designs_catalog.py --check` re-simulates them
designs: install
	$(PY) tools/designs_catalog.py

# the 3-D walking map (docs/results/walking_map3d.csv, docs/walking_map3d.png): comb reach and leg spacing x crank
# speed, 6 steps each, ours and the MuJoCo twin (about 40 minutes of CPU); then the upright walkers (designs/3d/)
walking-map-3d: install
	$(PY) tools/walking_map3d.py --compute --workers 2
	$(PY) tools/designs3d.py

designs-3d: install
	$(PY) tools/designs3d.py

# does a mass the crank moves sideways keep the centred-sole walker upright? (48 walks in 3-D, about 4 minutes)
lateral-mass: install
	$(PY) tools/lateral_mass.py

# docs/floor_springs.{md,csv,png}: weld against floor for runs 1-4 and the four springs (about a minute);
# docs/floor_quasi_static.{csv,png}: the quasi-static K_e x beta0 sweep, weld beside floor
floor-springs: install
	$(VENV)/bin/pasibot simulate --ground floor --study --scenario all --out docs --force

# the ratio benchmarks (about 2 min; bench_stability: walk --stability on the fastest walker over bench_demo's
# reference workload); the demo's own time is `make timings`, compare_outputs.py a tool
BENCHMARKS := bench_dynamics bench_floor bench_floor3d bench_studies bench_floor_section bench_sweep bench_stability bench_start
bench: install
	@set -e; for name in $(BENCHMARKS); do echo "== benchmarks/$$name.py"; $(PY) benchmarks/$$name.py; done

# the README's pictures (docs/variants.png, gait.gif, kinematics.png, torques.png, simulation.png) drawn by
# the library, about 3 s (the other docs pictures: make floor-springs, make answers)
docs-figures: install
	$(PY) tools/docs_figures.py

# docs/timings.md: the demo's wall and CPU time, measured here, and `make demo` from a fresh clone (install
# included, about 3 minutes), with the machine named
timings: install
	$(PY) benchmarks/bench_demo.py --fresh --write docs/timings.md

# ruff, and mypy on the package with pyproject.toml's [tool.mypy] settings (zero errors; tests/test_typecheck.py too)
lint: install
	$(VENV)/bin/ruff check pasibot_pin tests benchmarks tools
	$(VENV)/bin/mypy

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
