"""The names and numbers the rest of `kinetix_cli` agrees on, each stated once.

Size names and capacities are the engine's (`engine.SIZES`); everything the task, the agent and the files add on
top is here: roles, action bindings, the action, observation and model choices (and which model reads which
observation), and the format tags of every file the toolkit writes.
"""

from __future__ import annotations

# --- roles ---------------------------------------------------------------------------------------------------
NEUTRAL, GREEN, BLUE, RED = 0, 1, 2, 3
"""Role ids stored per body (`engine.Bodies.role`): the task is green touching blue, never green touching red."""
ROLE_NAMES = ("neutral", "green", "blue", "red")
"""Role names by id, as level files write them."""

# --- actions -------------------------------------------------------------------------------------------------
NUM_MOTOR_BINDINGS = 4
"""Motor bindings at every size: each motor reads one of these action entries (or runs as an auto motor)."""
NUM_THRUSTER_BINDINGS = 2
"""Thruster bindings at every size."""
ACTION_WIDTH = NUM_MOTOR_BINDINGS + NUM_THRUSTER_BINDINGS
"""Entries of a multi-discrete or continuous action (motor bindings first, then thruster bindings)."""
ACTION_TYPES = ("multi-discrete", "discrete", "continuous")
"""Action encodings (see `kinetix_cli.env.actions`)."""

# --- observations and models ---------------------------------------------------------------------------------
OBSERVATION_TYPES = ("symbolic-flat", "symbolic-entity", "pixels")
"""Observation types (see `kinetix_cli.env.observations` and `kinetix_cli.env.pixels`)."""
SIZE_INDEPENDENT_OBSERVATIONS = ("symbolic-entity", "pixels")
"""Observations with the same shape at every size: a policy reading one plays levels of any size. A
`symbolic-flat` vector's length depends on the size, so such a policy plays its own size only."""
MODEL_OBSERVATIONS = {
    "transformer": ("symbolic-entity",),
    "pi-mlp": ("symbolic-entity",),
    "rel-mlp": ("symbolic-entity",),
    "flat-mlp": ("symbolic-flat", "pixels"),
}
"""The observation types each model reads (`flat-mlp` flattens the pixel image); any other pair is refused."""
MODEL_NAMES = tuple(MODEL_OBSERVATIONS)
NUM_ATTENTION_CHANNELS = 4
"""Attention-mask channels of the `symbolic-entity` observation (all shapes, joint-linked, directly joined, in
contact); the transformer drives `heads / NUM_ATTENTION_CHANNELS` heads with each."""

# --- numbers ------------------------------------------------------------------------------------------------
INT32_MAX = 2**31 - 1
"""Largest value of the integer settings JAX keeps as int32 (seeds, episode caps, counts)."""
VALIDATION_SEED = 2**31 - 1024
"""Generator seeds from here up to `INT32_MAX` are the validation suite's (`levels.suites`): no training run and no
`kinetix generate` draws them (`run.seed` and `--seed` stop below, a generated pool's later rounds skip them), so its
held-out levels are never trained on."""

# --- file formats --------------------------------------------------------------------------------------------
VALIDATION_FORMAT = "kinetix-validation/1"
"""A `kinetix validation run` result: zero-shot on the validation suite and fine-tuning on two of our levels."""
LEVEL_FORMAT = "kinetix-level/1"
"""Hand-made level files (JSON, `docs/level-format.md`)."""
LEVELSET_FORMAT = "kinetix-levelset/1"
"""The manifest of a generated level set."""
LEVELSET_PROGRESS_FORMAT = "kinetix-levelset-progress/1"
"""Where an unfinished level set resumes."""
EXPERIMENT_FORMAT = "kinetix-experiment/1"
"""Experiment configs (YAML), and the resolved config saved in every run."""
VERSIONS_FORMAT = "kinetix-versions/1"
"""A run's library versions and machine (`versions.json`)."""
AGENT_FORMAT = "kinetix-agent/1"
"""The card (`agent.json`) of an agent folder: a policy with its config, checksums, training and evaluation."""
EVAL_FORMAT = "kinetix-eval/1"
"""`kinetix eval --json` results."""
BENCH_FORMAT = "kinetix-bench/1"
"""`kinetix bench ... --json` results."""
IMPORT_REPORT_FORMAT = "kinetix-import-report/1"
"""`kinetix import --report` notes."""
CURVES_FORMAT = "kinetix-curves/1"
"""`kinetix plot --json` numbers (and a report's `curves.json`)."""
COMPARE_FORMAT = "kinetix-compare/1"
"""`kinetix compare --json` tables."""
REPORT_FORMAT = "kinetix-report/1"
"""A run report's `report.json`: what its page shows, as numbers."""

COMPUTE_TYPES = ("float32", "bfloat16")
"""Number types a network can compute in (`model.compute`); parameters and optimiser state are float32 either way."""
