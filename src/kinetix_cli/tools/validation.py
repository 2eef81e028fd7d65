"""The evaluation protocol's validation suite: every choice (recipe, seed, checkpoint, blend, temperature, what ships)
is made on it, by a rule written down before the runs; the paper's 74 levels (the `test` suite) are read once per
shipped agent, after the choice.

- `build_heldout(root)`: the held-out generated levels, `HELDOUT_COUNT` per size, as level files in
  `root/<size>/` (shipped in `levels/validation/`): the first levels `kinetix generate` keeps (no-op and random-play
  filters) from the generator seeds `VALIDATION_SEED + i`, which no training run and no `kinetix generate` draws.
  The same call writes the same files.
- `validate_agent(source)`: the agent on the validation suite: zero-shot on the held-out levels and on our
  `levels/s`, `levels/m`, `levels/l` (`levels.suites`, "validation"), and fine-tuned on `FINETUNE_LEVELS` (the demo's
  level included) with `make demo`'s settings, `FINETUNE_SEEDS` seeds each. Its record (`VALIDATION_FORMAT`) gives
  each part's mean solve rate, each level's and each seed's.
"""

from __future__ import annotations

import dataclasses
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from engine import SIZES
from kinetix_cli.constants import VALIDATION_FORMAT, VALIDATION_SEED
from kinetix_cli.errors import UserError
from kinetix_cli.generator.filters import FilterConfig, chunk_source, make_config
from kinetix_cli.io import atomic_folder, atomic_write_json, read_format
from kinetix_cli.levels.export import export_level
from kinetix_cli.levels.files import level_paths
from kinetix_cli.levels.format import format_level_json
from kinetix_cli.levels.levelset import generate_levelset, level_at, load_levelset
from kinetix_cli.levels.suites import SUITES, named_suite, shown_path, suite_folder
from kinetix_cli.provenance import environment_info
from kinetix_cli.rl.agents import load_policy
from kinetix_cli.rl.evaluate import evaluate, suite_summary
from kinetix_cli.rl.train import finetune_config, train

HELDOUT_COUNT = 40
"""Held-out generated levels per size."""
FINETUNE_LEVELS = (("m", "two-link-reach.json"), ("s", "rocket-car-jump.json"))
"""The two of our levels the validation fine-tunes on (suite, file): `make demo`'s level and the one it used before."""
FINETUNE_SEEDS = (0, 1, 2)
"""Training seeds of each fine-tuning run."""
FINETUNE_SETTINGS = (
    "ppo.total_timesteps=200000",
    "ppo.ent_coef=0.05",
    "ppo.ent_coef_end=0.01",
    "run.eval_every=0",
    "run.checkpoint_every=0",
)
"""`make demo`'s fine-tuning settings on `experiments/cpu-small.yaml` (200K env steps, the entropy recipe); the run
evaluates only at its end, with the validation's attempts."""
VALIDATION_ATTEMPTS = 50
VALIDATION_EVAL_SEED = 1000


def heldout_seed(size: str) -> int:
    """The generator seed of the held-out levels of `size`."""
    return VALIDATION_SEED + list(SUITES).index(size)


def heldout_levelset(where: str | Path, size: str, count: int = HELDOUT_COUNT) -> Path:
    """Generate the held-out levels of `size` as a level set at `where` (`kinetix levels solve` and the other
    set commands read it; `build_heldout` exports its levels as the suite's files); returns `where`."""
    config = make_config(size, 256, FilterConfig())
    seed = heldout_seed(size)
    generate_levelset(
        where, size=size, count=count, seed=seed, settings=config.settings(), chunk_fn=chunk_source(config, seed)
    )
    return Path(where)


def build_heldout(root: str | Path, sizes=SUITES, count: int = HELDOUT_COUNT, progress: Callable = print) -> list[Path]:
    """Write the held-out levels of each size as level files `root/<size>/validation-<size>-NNN.json` (each folder
    whole or not at all); returns the files."""
    root = Path(root)
    written = []
    for size in sizes:
        if size not in SIZES:
            raise UserError(f"--size: {size!r} is not one of {', '.join(SIZES)}")
        progress(f"generating {count} held-out {size} levels (seed {heldout_seed(size)}; the first compiles)...")
        with tempfile.TemporaryDirectory() as scratch:
            levelset = load_levelset(heldout_levelset(Path(scratch) / "set", size, count))
            with atomic_folder(root / size, "--out") as staging:
                for index in range(count):
                    data = export_level(
                        level_at(levelset, index),
                        SIZES[size],
                        name=f"validation {size} {index}",
                        description=(
                            f"Held-out generated level {index} of size {size} (generator seed {heldout_seed(size)}, "
                            "filtered by no-op and random play): make green touch blue"
                        ),
                    )
                    (staging / f"validation-{size}-{index:03d}.json").write_text(format_level_json(data))
        written += sorted((root / size).glob("*.json"))
    return written


@dataclasses.dataclass(frozen=True)
class ValidationSettings:
    """What `validate_agent` plays.

    Attributes:
        attempts: episodes per level, zero-shot and after fine-tuning.
        seed: the seed of the sampled actions.
        finetune_seeds: training seeds of each fine-tuning run (empty: no fine-tuning part).
        config: the fine-tuning runs' experiment file (`make demo`'s).
        overrides: `--set` values after `FINETUNE_SETTINGS` (a quick look; a record with any is not a validation
            of the protocol's fine-tuning part, and says so).
    """

    attempts: int = VALIDATION_ATTEMPTS
    seed: int = VALIDATION_EVAL_SEED
    finetune_seeds: tuple[int, ...] = FINETUNE_SEEDS
    config: str = "experiments/cpu-small.yaml"
    overrides: tuple[str, ...] = ()


def validate_agent(source: str, settings: ValidationSettings, progress: Callable = print) -> dict:
    """The validation record of the policy `source` (a run, checkpoint, agent folder or shipped agent)."""
    policy = load_policy(source)
    files = level_paths(["validation"])
    progress(f"{source}: zero-shot on the validation suite ({len(files)} levels x {settings.attempts} attempts)...")
    results = evaluate(policy.config, policy.params, files, settings.attempts, settings.seed)
    heldout = [r.solve_rate for r in results if "/validation/" in r.suite]
    ours = [r.solve_rate for r in results if "/validation/" not in r.suite]
    finetune = {}
    for suite, name in FINETUNE_LEVELS if settings.finetune_seeds else ():
        level = suite_folder(suite) / name
        rates = []
        for seed in settings.finetune_seeds:
            progress(f"{source}: fine-tuning on {shown_path(level)}, seed {seed}...")
            rates.append(_finetuned(policy, source, level, seed, settings))
        finetune[shown_path(level)] = {"seeds": list(settings.finetune_seeds), "solve_rate": rates}
    tuned = [rate for row in finetune.values() for rate in row["solve_rate"]]
    return {
        "agent": source,
        "update": policy.update,
        "attempts": settings.attempts,
        "seed": settings.seed,
        "score": {
            "heldout": float(np.mean(heldout)),
            "ours": float(np.mean(ours)),
            "zero_shot": float(np.mean(heldout + ours)),
            "finetune": float(np.mean(tuned)) if tuned else None,
        },
        "suites": suite_summary(results),
        "levels": [dataclasses.asdict(r) for r in results],
        "finetune": {
            "config": settings.config,
            "settings": [*FINETUNE_SETTINGS, *settings.overrides],
            "levels": finetune,
        },
        "versions": environment_info(),
    }


def _finetuned(policy, source: str, level: Path, seed: int, settings: ValidationSettings) -> float:
    """The solve rate on `level` of `policy` fine-tuned on it with `FINETUNE_SETTINGS` and training seed `seed`."""
    files = level_paths([level])
    overrides = [*FINETUNE_SETTINGS, *settings.overrides, f"run.seed={seed}"]
    experiment = finetune_config(Path(settings.config), files, policy.config, overrides, init_from=source)
    with tempfile.TemporaryDirectory() as scratch:
        runner = train(experiment, Path(scratch) / "run", init_params=policy.params)
    (result,) = evaluate(experiment, runner.params, files, settings.attempts, settings.seed)
    return float(result.solve_rate)


def write_validation(path: str | Path, record: dict) -> None:
    """Write a validation record (`VALIDATION_FORMAT`) atomically."""
    atomic_write_json(path, record, VALIDATION_FORMAT)


def read_validation(path: str | Path) -> dict:
    """A validation record; another format is a `UserError` naming the file."""
    record = read_format(path, VALIDATION_FORMAT, UserError)
    if not isinstance(record.get("score"), dict):
        raise UserError(f"{path}: score: missing; give a file `kinetix validation run --json` wrote")
    return record


def shipped_heldout_matches(root: str | Path) -> list[str]:
    """The held-out level files that differ between the shipped suite and `root` (a rebuild), by name."""
    differ = []
    for size in SUITES:
        shipped = {p.name: p for p in named_suite("validation")[list(SUITES).index(size)].glob("*.json")}
        rebuilt = {p.name: p for p in (Path(root) / size).glob("*.json")}
        for name in sorted(set(shipped) | set(rebuilt)):
            same = name in shipped and name in rebuilt and shipped[name].read_bytes() == rebuilt[name].read_bytes()
            if not same:
                differ.append(shown_path(shipped.get(name, rebuilt.get(name))))
    return differ
