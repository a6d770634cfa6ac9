# One-word entry points. `make test` and `make demo` set everything up on a fresh machine.
PY ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
WARM := $(VENV)/.warm

.PHONY: setup test lint docs demo pilots bench clean package-check

$(STAMP): pyproject.toml constraints.txt
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -c constraints.txt -e ".[dev]"
	touch $(STAMP)

# the physics kernels compiled ahead (minutes, once; again after a source change, when only
# what changed compiles): the demo's first step then starts at once. The tests compile only
# what they use, so `make test` does not wait on it.
$(WARM): $(STAMP) $(shell find fluidsim_envs -name '*.py')
	$(BIN)/python -m fluidsim_envs.warmup
	touch $(WARM)

setup: $(WARM)

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m pytest -n 2 fluidsim_envs tests

# pip install into a fresh virtualenv outside the checkout, then train there (CI runs it)
package-check:
	.ci/package_check

# the docs site (mkdocs.yml: docs/ and the API reference from the docstrings) into site/;
# strict: a broken link, a page outside the nav or a docstring griffe cannot read fails it
docs: $(STAMP)
	$(BIN)/mkdocs build --strict --site-dir site

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

# the main job: a PPO pilot for PaperAirplane-v1 trained briefly (the shipped config, cut to
# 1M PPO steps after its warm start, which fits the policy to the tuned pilot first),
# evaluated against the scripted pilots and random (not the planner: minutes more;
# docs/results.md has it), its episodes written to a Rerun recording
DEMO_RUN ?= runs/demo
demo: $(WARM)
	$(BIN)/fluidsim-train paper_airplane_v1_ppo \
		--set total_timesteps=1000000 --run-dir $(DEMO_RUN) --no-progress-bar
	$(BIN)/fluidsim-evaluate $(DEMO_RUN) --episodes 256 --no-planner \
		--rerun $(DEMO_RUN)/episodes.rrd

# the physics demo and the scripted pilots of the three envs, side by side
pilots: $(STAMP)
	$(BIN)/python -m fluidsim_envs.demo

bench: $(STAMP)
	$(BIN)/python -m benchmarks.bench_kernel

clean:
	rm -rf $(VENV) .pytest_cache build site *.egg-info
