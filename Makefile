# Two commands on a fresh machine: `make demo` and `make test`. Both create .venv with python3.11.
PYTHON ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-dev
CMP_STAMP := $(VENV)/.installed-compare
ALL_STAMP := $(VENV)/.installed-all
UV := $(BIN)/uv
INSTALL := $(UV) pip install -q --python $(BIN)/python -c constraints.txt
DOCS_STAMP := $(VENV)/.installed-docs
PYTEST_FLAGS ?=
TEST_WORKERS ?= 2  # pytest-xdist processes for `make test`, one per core of CI's 2: alternating in-place suites here,
                   # 2 workers took 420 and 436 s (756 and 792 s of CPU time), 3 took 461 and 457 s (854 and 850 s)

.PHONY: demo test test-all lint format bench clean reference-levels docs

$(BIN)/python:
	$(PYTHON) -m venv --without-pip $(VENV)

# uv installs the packages: make test's in 10 s on a fresh clone here, against 40 s with pip (plus 14 s for the
# venv's own pip), as it downloads in parallel and installs without compiling bytecode (Python compiles a module's
# bytecode when it is first imported). uv comes from PyPI by the system's pip, or where the system Python has none,
# by a pip the venv makes itself (ensurepip). The venv gets pip too, for `.venv/bin/pip install`.
$(UV): | $(BIN)/python
	if $(PYTHON) -m pip --version >/dev/null 2>&1; then pip="$(PYTHON) -m pip --python $(BIN)/python"; \
	else $(BIN)/python -m ensurepip >/dev/null || exit 1; pip="$(BIN)/python -m pip"; fi; \
	$$pip install -q -c constraints.txt uv
	$(INSTALL) pip

$(STAMP): pyproject.toml constraints.txt | $(UV)
	$(INSTALL) -e ".[dev]"
	touch $@

# One install for what make test needs (the dev tools and the reference engine), not one per extra.
$(CMP_STAMP): pyproject.toml constraints.txt | $(UV)
	$(INSTALL) -e ".[dev,compare]"
	touch $(STAMP) $@

# make test-all also logs a run to wandb (offline).
$(ALL_STAMP): $(CMP_STAMP)
	$(INSTALL) -e ".[dev,compare,wandb]"
	touch $@

# Every command make runs writes the bytecode of what it imports (jax, flax, optax, orbax, ...) into .venv and
# __pycache__, as Python does by default. Where PYTHONDONTWRITEBYTECODE is set (as on this machine) Python never
# writes it, so every process compiled those modules from source again: 8 s to import the training code instead of
# 4 here, in each of the ~20 `kinetix` processes of `make demo` and the many that `make test` starts.
unexport PYTHONDONTWRITEBYTECODE

$(DOCS_STAMP): $(STAMP)
	$(INSTALL) -e ".[dev,docs]"
	touch $@

# The reference's 74 hand-made levels (JSON, its own format), from the kinetix-env wheel on PyPI; the wheel is only
# unzipped, never installed (it pins an older jax).
REFERENCE_LEVELS := .cache/reference-levels
REFERENCE_WHEEL := kinetix-env==3.0.2

$(REFERENCE_LEVELS)/.fetched: | $(UV)
	rm -rf $(REFERENCE_LEVELS) .cache/wheels && mkdir -p $(REFERENCE_LEVELS) .cache/wheels
	$(BIN)/pip download -q --no-deps $(REFERENCE_WHEEL) -d .cache/wheels
	$(BIN)/python -c "import glob, pathlib, zipfile; \
	z = zipfile.ZipFile(glob.glob('.cache/wheels/*.whl')[0]); \
	names = [n for n in z.namelist() if n.startswith('kinetix/levels/') and n.endswith('.json')]; \
	[pathlib.Path('$(REFERENCE_LEVELS)', n.removeprefix('kinetix/levels/')).parent.mkdir(parents=True, exist_ok=True) \
	 or pathlib.Path('$(REFERENCE_LEVELS)', n.removeprefix('kinetix/levels/')).write_bytes(z.read(n)) for n in names]; \
	print(f'unzipped {len(names)} reference levels into $(REFERENCE_LEVELS)/{{s,m,l}}')"
	touch $@

reference-levels: $(REFERENCE_LEVELS)/.fetched

DEMO_LEVEL := levels/s/rocket-car-jump.json
# What pretraining buys: fine-tune the shipped default agent (`kinetix_cli.rl.agents.default_agent`: the best
# fine-tuner of the validation suite, docs/experiments/2026-11-28-protocol; a test keeps DEMO_AGENT equal to it) on a
# level of ours, and train the same network from scratch for the same 200K steps. The validation's fine-tuning part
# runs these settings on this level, training seeds 0-2: `general` 100% / 100% / 98%; scratch 0% on seeds 0-2
# (BENCHMARKS.md, "What make demo fine-tunes").
TUNE_LEVEL := levels/m/two-link-reach.json
DEMO_AGENT := general
TUNE := --config experiments/cpu-small.yaml --set ppo.total_timesteps=200000 --set ppo.ent_coef=0.05 \
	--set ppo.ent_coef_end=0.01
SCRATCH_NETWORK := --set model.name=rel-mlp --set model.width=64 --set model.mask_unused_actions=true  # the agents'


demo: $(STAMP)
	rm -rf demo-out/levels-s demo-out/pretrain demo-out/finetune demo-out/scratch
	$(BIN)/kinetix demo
	$(BIN)/kinetix validate --play $(DEMO_LEVEL)
	$(BIN)/kinetix render $(DEMO_LEVEL) -o demo-out/level.png
	$(BIN)/kinetix rollout $(DEMO_LEVEL) --policy solution -o demo-out/rollout.gif
	$(BIN)/kinetix generate --size s --count 1024 --seed 0 --out demo-out/levels-s
	$(BIN)/kinetix levels show demo-out/levels-s --grid 16 -o demo-out/levels-s.png
	$(BIN)/kinetix pretrain --config experiments/cpu-small.yaml --run-dir demo-out/pretrain --levels demo-out/levels-s
	$(BIN)/kinetix eval demo-out/pretrain --levels levels/s --json demo-out/eval-pretrain.json
	$(BIN)/kinetix agents
	$(BIN)/kinetix eval $(DEMO_AGENT) --levels $(TUNE_LEVEL) --json demo-out/eval-agent.json
	$(BIN)/kinetix finetune $(TUNE_LEVEL) --from $(DEMO_AGENT) --run-dir demo-out/finetune $(TUNE)
	$(BIN)/kinetix finetune $(TUNE_LEVEL) --from none --run-dir demo-out/scratch $(TUNE) $(SCRATCH_NETWORK)
	$(BIN)/kinetix eval demo-out/finetune --levels $(TUNE_LEVEL) --json demo-out/eval-finetune.json
	$(BIN)/kinetix eval demo-out/scratch --levels $(TUNE_LEVEL) --json demo-out/eval-scratch.json
	$(BIN)/kinetix compare demo-out/eval-agent.json demo-out/eval-scratch.json demo-out/eval-finetune.json \
		-o demo-out/compare.png
	$(BIN)/kinetix rollout $(TUNE_LEVEL) --policy demo-out/finetune -o demo-out/finetuned.gif
	$(BIN)/kinetix report demo-out/finetune demo-out/scratch -o demo-out/report
	@echo "demo outputs in demo-out/: level.png and rollout.gif (a hand-made level and its solution),"
	@echo "  levels-s/ and levels-s.png (1024 generated levels), pretrain/ (a run: config, metrics, checkpoints),"
	@echo "  eval-pretrain.json; on $(TUNE_LEVEL): eval-agent.json (the shipped agent zero-shot),"
	@echo "  finetune/ and scratch/ (the agent fine-tuned, the same network from scratch, equal steps),"
	@echo "  eval-finetune.json, eval-scratch.json and compare.png (all three side by side), finetuned.gif,"
	@echo "  report/index.html (both runs' curves, evaluations and the agents playing; open it in a browser)"

lint: $(STAMP)
	$(BIN)/ruff check src tests examples docs
	$(BIN)/ruff format --check src tests examples docs
	$(BIN)/lint-imports

format: $(STAMP)
	$(BIN)/ruff format src tests examples docs
	$(BIN)/ruff check --fix src tests examples docs

# The documentation site (mkdocs.yml): guides, README, benchmarks and the API from the docstrings, into .cache/site;
# any warning (a broken link, a docstring that names a missing parameter) fails it.
docs: $(DOCS_STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

# `make test KINETIX_TEST_CODEGEN=release`: compiled as `kinetix` compiles (tests/conftest.py), to check tolerances.
test: $(CMP_STAMP) lint reference-levels
	$(BIN)/pytest -m "not slow" -n $(TEST_WORKERS) --dist loadgroup --durations=15 $(PYTEST_FLAGS)

test-all: lint reference-levels $(ALL_STAMP)
	$(BIN)/pytest $(PYTEST_FLAGS)

bench: $(CMP_STAMP)
	$(BIN)/kinetix bench engine --size s --envs 1,64,1024,4096 --against jax2d --json bench-s.json
	$(BIN)/kinetix bench engine --size m --envs 1,64,1024,4096 --against jax2d --json bench-m.json
	$(BIN)/kinetix bench engine --size l --envs 1,64,1024,4096 --against jax2d --json bench-l.json

clean:
	rm -rf $(VENV) .pytest_cache .ruff_cache .cache
