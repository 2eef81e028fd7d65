"""Agents: trained policies addressed by a run directory, a checkpoint folder, an agent folder or a shipped
agent's name (`general-s`, ...), and the shipped agents themselves.

An agent folder (`kinetix agents export`) is a policy alone, small enough to ship with the package:
- `config.yaml`: the experiment config it was trained with (`kinetix-experiment/1`), which fixes its network and
  its interface to the environment;
- `params.msgpack`: the network parameters (flax msgpack of the parameter tree);
- `agent.json` (`kinetix-agent/1`): name, version, the sha256 of both files (verified on every load), how it was
  trained (run, updates, environment steps, the commands that made it, machine and versions) and its evaluation
  (`kinetix eval --json` results per suite).

`kinetix agents blend` makes an agent folder from several policies of one network: the weighted average of their
parameters (a "model soup", Wortsman et al. 2022: policies fine-tuned from one agent average into one that keeps
much of what each learned). Its card lists the ingredients; `kinetix agents export` ships it like a run.

The shipped agents live in `kinetix_cli/rl/shipped/<name>/` (the version chosen on the validation suite, its card
saying by which rule) and `shipped/<name>@<version>/` (every other version, kept loadable) and are installed with the
package. `general-s` names the chosen version, `general-s@1` version 1. A name resolves to a shipped agent only when
no file or folder of that name exists, so a local run called `general-s` still wins. `default_agent()` is the one
`make demo` fine-tunes.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import math
import os
from pathlib import Path

import flax.linen as nn
import jax
import numpy as np
from flax import serialization

from kinetix_cli.config import CONFIG_FILENAME, ExperimentConfig, format_config, load_config
from kinetix_cli.constants import AGENT_FORMAT
from kinetix_cli.env.environment import EnvParams, KinetixEnv
from kinetix_cli.env.episode import Policy
from kinetix_cli.env.factory import make_env_for_level
from kinetix_cli.errors import UserError
from kinetix_cli.io import atomic_folder, atomic_write_json, check_output_dir, read_format
from kinetix_cli.provenance import environment_info
from kinetix_cli.rl import checkpoints
from kinetix_cli.rl.evaluate import read_evaluation
from kinetix_cli.rl.networks import make_network, params_mismatch, sampling_policy, temper
from kinetix_cli.rl.trees import tree_mismatch

SHIPPED = Path(__file__).with_name("shipped")
"""The shipped agents' folders, one per name."""
AGENT_FILE = "agent.json"
PARAMS_FILE = "params.msgpack"
NAME_CHARS = set("abcdefghijklmnopqrstuvwxyz0123456789-_.")


@dataclasses.dataclass(frozen=True)
class AgentCard:
    """What `agent.json` says of an agent folder.

    Attributes:
        folder: the agent folder.
        name: its name (a shipped agent's is how it is addressed).
        version: its version; a retrained agent of the same name gets a new one.
        files: sha256 of `config.yaml` and `params.msgpack`, by file name.
        trained: how it was made: run, update, steps, commands, date, machine and versions.
        evaluation: zero-shot results per suite (`kinetix eval --json`'s `suites`), with attempts and seed.
        validation: its validation record's scores and suites (`kinetix validation run`), what it was chosen on;
            empty for an agent folder not (yet) validated.
        test: its results on the test suite (the paper's 74 levels) per evaluation seed, read after the choice.
        rule: the rule, written before the runs, that chose it.
    """

    folder: Path
    name: str
    version: int
    files: dict
    trained: dict
    evaluation: dict
    validation: dict = dataclasses.field(default_factory=dict)
    test: dict = dataclasses.field(default_factory=dict)
    rule: str = ""

    def as_dict(self) -> dict:
        """The card as `agent.json` holds it, with the folder."""
        return {"folder": str(self.folder)} | {f.name: getattr(self, f.name) for f in dataclasses.fields(self)[1:]}


def shipped_folders() -> list[Path]:
    """Folders of the agents installed with the package, every version: by name, the chosen version first, then the
    others newest first."""
    if not SHIPPED.is_dir():
        return []
    folders = [p for p in SHIPPED.iterdir() if (p / AGENT_FILE).is_file()]

    def order(folder: Path) -> tuple[str, bool, int]:
        base, _, version = folder.name.partition("@")
        return base, bool(version), -int(version) if version.isdigit() else 0

    return sorted(folders, key=order)


def shipped_names() -> list[str]:
    """Names of the agents installed with the package (each name's chosen version; `name@version` for others)."""
    return [p.name for p in shipped_folders() if "@" not in p.name]


DEFAULT_ORDER = ("general", "general-s", "general-m", "general-l")
"""Which shipped agent wins a tie for the default (`default_agent`), first to last."""


def default_agent() -> str | None:
    """The shipped default, the agent `make demo` fine-tunes (docs/experiments/2026-11-28-protocol/PLAN.md, rule 2):
    among the chosen versions whose cards carry a validation record, the best fine-tuning mean; within 5 points of
    it the first of `DEFAULT_ORDER` wins; a mean below 50% is never the default. None when no card qualifies."""
    tuned = {}
    for name in shipped_names():
        card = read_card(SHIPPED / name)
        score = card.validation.get("score", {}).get("finetune")
        if score is not None and score >= 0.5:
            tuned[name] = score
    if not tuned:
        return None
    best = max(tuned.values())
    near = [name for name, score in tuned.items() if score >= best - 0.05]
    return min(near, key=lambda name: DEFAULT_ORDER.index(name) if name in DEFAULT_ORDER else len(DEFAULT_ORDER))


def shipped_agents() -> list[tuple[AgentCard, ExperimentConfig]]:
    """(card, config) of every shipped agent and version, by name, the chosen version first."""
    return [(read_card(folder), load_config(folder / CONFIG_FILENAME)) for folder in shipped_folders()]


def shipped_agent(name: str) -> Path | None:
    """The folder of the shipped agent `name` (its chosen version) or `name@version`, or None when none is."""
    base, _, version = name.partition("@")
    if base not in shipped_names():
        return None
    if not version:
        return SHIPPED / base
    for folder in (SHIPPED / base, SHIPPED / name):
        if (folder / AGENT_FILE).is_file() and str(read_card(folder).version) == version:
            return folder
    return None


def read_card(folder: str | Path) -> AgentCard:
    """The card of an agent folder, its fields checked; a bad card is a `UserError` naming the file and field."""
    file = Path(folder) / AGENT_FILE
    card = read_format(file, AGENT_FORMAT, UserError)
    expected = {"name": str, "version": int, "files": dict, "trained": dict, "evaluation": dict}
    for field, kind in expected.items():
        if not isinstance(card.get(field), kind) or isinstance(card.get(field), bool):
            raise UserError(f"{file}: {field}: expected {kind.__name__}, got {card.get(field)!r}")
    if set(card["files"]) != {CONFIG_FILENAME, PARAMS_FILE}:
        raise UserError(
            f"{file}: files: expected the sha256 of {CONFIG_FILENAME} and {PARAMS_FILE}, got {card['files']}"
        )
    for name in (CONFIG_FILENAME, PARAMS_FILE):
        if not isinstance(card["files"].get(name), str):
            raise UserError(f"{file}: files.{name}: expected a sha256 string, got {card['files'].get(name)!r}")
    update = card["trained"].get("update", 0)
    if not isinstance(update, int) or isinstance(update, bool) or update < 0:
        raise UserError(f"{file}: trained.update: expected an update count, got {update!r}")
    optional = {"validation": dict, "test": dict, "rule": str}
    for field, kind in optional.items():
        if field in card and not isinstance(card[field], kind):
            raise UserError(f"{file}: {field}: expected {kind.__name__}, got {card[field]!r}"[:300])
    return AgentCard(Path(folder), **{k: card[k] for k in expected}, **{k: card[k] for k in optional if k in card})


def record_choice(folder: str | Path, *, validation: dict, test: list[dict], rule: str) -> AgentCard:
    """Put on the card of the agent folder `folder` (atomically; its files untouched) what chose it: the scores and
    suites of its validation record, its test evaluations (`kinetix eval --json` records on the test suite, one per
    evaluation seed) and the rule."""
    file = Path(folder) / AGENT_FILE
    card = read_format(file, AGENT_FORMAT, UserError)
    read_card(folder)  # checked as a card first
    if not rule.strip():
        raise UserError("--rule: say the rule that chose this agent (written before its runs)")
    seeds = [record["seed"] for record in test]
    if not test or len(set(seeds)) != len(seeds):
        raise UserError(f"--test: evaluation seeds {seeds}: give each seed's evaluation once")
    for record in test:
        suites = {name for name in record["suites"] if name != "all"}
        if sorted(Path(name).name for name in suites) != ["l", "m", "s"] or any(
            "reference-levels" not in n for n in suites
        ):
            raise UserError(f"--test: {record['policy']} seed {record['seed']}: not an evaluation on the test suite")
    card["validation"] = {k: validation[k] for k in ("agent", "update", "attempts", "seed", "score", "suites")}
    card["validation"]["finetune"] = validation["finetune"]["levels"]
    card["test"] = {
        "attempts": sorted({record["attempts"] for record in test}),
        "by_seed": {str(record["seed"]): record["suites"] for record in test},
    }
    card["rule"] = rule.strip()
    atomic_write_json(file, {k: v for k, v in card.items() if k != "format"}, AGENT_FORMAT)
    return read_card(folder)


def _read_agent(folder: Path) -> tuple[ExperimentConfig, object, int]:
    """(config, params, update) of an agent folder, both files verified against the card's checksums."""
    card = read_card(folder)
    for name, digest in card.files.items():
        file = folder / name
        try:
            data = file.read_bytes()
        except OSError as exc:
            raise UserError(f"{file}: cannot read: {exc.strerror or exc}") from None
        if hashlib.sha256(data).hexdigest() != digest:
            raise UserError(f"{file}: does not match its checksum in {folder / AGENT_FILE}; the agent is damaged")
    config = load_config(folder / CONFIG_FILENAME)
    try:
        params = serialization.msgpack_restore((folder / PARAMS_FILE).read_bytes())
    except Exception as exc:  # msgpack raises several types for bad bytes (checked above, so unlikely)
        raise UserError(f"{folder / PARAMS_FILE}: not a parameter file ({type(exc).__name__})") from None
    return config, params, int(card.trained.get("update", 0))


def resolve(source: str | os.PathLike) -> Path:
    """The folder `source` names: itself when it exists, else the shipped agent of that name. Anything else is a
    `UserError` that lists the shipped names."""
    path = Path(source)
    if path.exists() or os.sep in str(source):
        return path
    folder = shipped_agent(str(source))
    if folder is not None:
        return folder
    names = ", ".join(p.name for p in shipped_folders()) or "none installed"
    raise UserError(f"{source}: no such run, checkpoint or agent folder, nor a shipped agent (shipped: {names})")


@dataclasses.dataclass(frozen=True)
class LoadedPolicy:
    """A trained policy, loaded, verified and checked against its network: the one way every command that plays
    a trained policy gets it (`eval`, `rollout`, `report`, `finetune`, the studio).

    Attributes:
        source: what named it: a run or checkpoint folder, an agent folder or a shipped agent's name.
        config: the experiment config it was trained with, which fixes its network and its environment settings.
        params: the network parameters (host arrays).
        update: the update it was saved at.
    """

    source: str
    config: ExperimentConfig
    params: object
    update: int

    @functools.cached_property
    def network(self) -> nn.Module:
        return make_network(self.config.model, self.config.env)

    @functools.cached_property
    def act(self) -> Policy:
        """The episode runner's policy: sample the network's action distribution at every step."""
        return self.acting(self.params)

    def acting(self, params) -> Policy:
        """`act` with `params` in its own parameters' place (traced inside a jit: one compile serves every
        parameter set of this network)."""
        return sampling_policy(self.network, params)

    def env_for(self, size: str, origin: str) -> tuple[KinetixEnv, EnvParams]:
        """The environment this policy plays size-`size` levels in: its run's settings (frame skip, episode cap,
        shaping, observation, action); `origin` names the level in errors."""
        return make_env_for_level(
            self.config.env, size, origin, self.config.model.reads_pairs, self.config.model.reads_attention
        )


def load_policy(source: str | os.PathLike) -> LoadedPolicy:
    """The policy of a run directory (latest checkpoint), a checkpoint folder, an agent folder or a shipped
    agent's name, verified against its checksums, its parameters checked against its config's network."""
    folder = resolve(source)
    if (folder / AGENT_FILE).is_file():
        config, params, update = _read_agent(folder)
        return _checked(str(source), config, params, update, folder / PARAMS_FILE, folder / CONFIG_FILENAME)
    config, params, where = checkpoints.read_policy(folder)
    return _checked(str(source), config, params, int(where.name), where, where.parent.parent / CONFIG_FILENAME)


def _checked(source: str, config, params, update: int, where: Path, config_file: Path) -> LoadedPolicy:
    """The policy, once its parameters (read from `where`) are seen to fit the model in `config_file`."""
    why = params_mismatch(config, params)
    if why is not None:
        raise UserError(f"{where}: its parameters do not fit the model in {config_file} ({why})")
    return LoadedPolicy(source, config, params, update)


def export_agent(
    run: str | os.PathLike,
    out: str | os.PathLike,
    *,
    name: str,
    version: int,
    commands: list[str],
    evaluation: str | os.PathLike | None = None,
    temperature: float = 1.0,
) -> AgentCard:
    """Write the policy of `run` (a run directory, a checkpoint folder, an agent folder such as a blend, or a
    shipped agent's name) as the agent folder `out`, whole or not at all (written beside it, then renamed into
    place; an existing agent folder is replaced, anything else there is refused). `evaluation`: a `kinetix eval
    --json` file of this policy, whose per-suite results go on the card. An agent folder's steps and ingredients
    carry over to the new card. `temperature`: the policy's action logits divided by it (`networks.temper`),
    recorded on the card."""
    _check_name(name)
    out = _agent_out(out)
    if not (math.isfinite(temperature) and 1e-3 <= temperature <= 1e3):
        raise UserError(f"--temperature {temperature:g}: expected a number in [0.001, 1000]")
    run = resolve(run)
    if (run / AGENT_FILE).is_file():
        config, params, update = _read_agent(run)
        made = {k: v for k, v in read_card(run).trained.items() if k in ("steps", "blend")}
        where, config_file = run / PARAMS_FILE, run / CONFIG_FILENAME
    else:
        config, params, where = checkpoints.read_policy(run)
        update, made = int(where.name), {"steps": int(where.name) * config.ppo.batch_size}
        config_file = where.parent.parent / CONFIG_FILENAME
    _checked(str(run), config, params, update, where, config_file)
    scores = _evaluation(evaluation, run) if evaluation is not None else {}
    if temperature != 1.0:
        params, made = temper(params, temperature), made | {"temperature": temperature}
    trained = {"run": str(run), "update": update, **made, "commands": list(commands), **environment_info()}
    return _write_agent(out, config, params, name=name, version=version, trained=trained, evaluation=scores)


def blend_agents(
    sources: list[str],
    out: str | os.PathLike,
    *,
    name: str,
    version: int,
    commands: list[str],
    weights: list[float] | None = None,
) -> AgentCard:
    """Write the weighted average of the parameters of `sources` (runs, checkpoints, agent folders or shipped
    agents) as the agent folder `out`; `weights` (default equal) are normalised to sum to 1. The sources must be
    one network playing one environment (their `model` and `env` settings equal but for the size) and are best
    fine-tuned from one agent: the average of unrelated networks plays like neither. The blend keeps the last
    source's config; its card lists each source with its weight, update and steps, and its steps are theirs
    summed (a run started from another agent counts only its own steps, so list that agent too)."""
    _check_name(name)
    out = _agent_out(out)
    if len(sources) < 2:
        raise UserError(f"blend: give at least two policies to average, got {len(sources)}")
    weights = [1.0] * len(sources) if not weights else [float(w) for w in weights]
    if len(weights) != len(sources):
        raise UserError(f"--weight: {len(weights)} weights for {len(sources)} policies; give one per policy or none")
    if not all(math.isfinite(w) and w > 0 for w in weights):
        raise UserError(f"--weight: {weights}: every weight must be a positive number")
    policies = [load_policy(source) for source in sources]
    first = policies[0]
    for policy in policies[1:]:
        why = _difference(first.config, policy.config) or tree_mismatch(first.params, policy.params)
        if why is not None:
            raise UserError(f"{policy.source}: not the network of {first.source} ({why}); a blend averages one network")
    total = sum(weights)
    shares = [w / total for w in weights]

    def average(*leaves):
        return np.asarray(sum(s * np.asarray(x, np.float64) for s, x in zip(shares, leaves, strict=True)), np.float32)

    params = jax.tree.map(average, *[p.params for p in policies])
    blend = [_source(p) | {"weight": share} for p, share in zip(policies, shares, strict=True)]
    trained = {
        "run": "blend",
        "update": policies[-1].update,
        "steps": sum(b["steps"] for b in blend),
        "blend": blend,
        "commands": list(commands),
        **environment_info(),
    }
    return _write_agent(out, policies[-1].config, params, name=name, version=version, trained=trained, evaluation={})


def _difference(a: ExperimentConfig, b: ExperimentConfig) -> str | None:
    """The first model or environment setting (size aside) on which two policies' configs differ, or None."""
    for section in ("model", "env"):
        for field in dataclasses.fields(getattr(a, section)):
            x, y = getattr(getattr(a, section), field.name), getattr(getattr(b, section), field.name)
            if field.name != "size" and x != y:
                return f"{section}.{field.name}: {y!r}, not {x!r}"
    return None


def _source(policy: LoadedPolicy) -> dict:
    """A blend source as its card lists it: `source` (a shipped agent as `name@version`, since a bare name moves
    on with new versions; anything else as given), `update`, and `steps` (an agent folder's card's, else the
    run's updates x batch)."""
    folder = resolve(policy.source)
    if not (folder / AGENT_FILE).is_file():
        steps = policy.update * policy.config.ppo.batch_size
        return {"source": policy.source, "update": policy.update, "steps": steps}
    card = read_card(folder)
    label = f"{card.name}@{card.version}" if folder.parent == SHIPPED else policy.source
    return {"source": label, "update": policy.update, "steps": int(card.trained.get("steps", 0))}


def _check_name(name: str) -> None:
    if not name or not set(name) <= NAME_CHARS:
        raise UserError(f"--name {name!r}: use lower-case letters, digits, '-', '_' and '.'")


def _agent_out(out: str | os.PathLike) -> Path:
    """`out` checked as a place for an agent folder: new, empty, or an agent folder to replace."""
    out = check_output_dir(out, "-o")
    if out.exists() and any(out.iterdir()) and not (out / AGENT_FILE).is_file():
        raise UserError(f"-o {out}: not empty and not an agent folder; choose a new folder")
    return out


def _write_agent(
    out: Path, config: ExperimentConfig, params, *, name: str, version: int, trained: dict, evaluation: dict
) -> AgentCard:
    """Write an agent folder whole or not at all: config, parameters and the card with both files' sha256."""
    data = {CONFIG_FILENAME: format_config(config).encode(), PARAMS_FILE: serialization.msgpack_serialize(params)}
    card = {
        "name": name,
        "version": version,
        "files": {file: hashlib.sha256(b).hexdigest() for file, b in data.items()},
        "trained": trained,
        "evaluation": evaluation,
    }
    with atomic_folder(out, "-o") as staging:
        for file, b in data.items():
            (staging / file).write_bytes(b)
        atomic_write_json(staging / AGENT_FILE, card, AGENT_FORMAT)
    return read_card(out)


def _evaluation(file: str | os.PathLike, run: Path) -> dict:
    """The per-suite results of a `kinetix eval --json` file, with its attempts and seed; it must be of `run`."""
    record = read_evaluation(file)
    if not isinstance(record.get("attempts"), int):
        raise UserError(f"{file}: attempts: missing; give the file `kinetix eval --json` wrote")
    if Path(str(record.get("policy"))).resolve() != run.resolve():
        raise UserError(f"{file}: policy: evaluates {record.get('policy')!r}, not {run}")
    return {k: record.get(k) for k in ("attempts", "seed", "update", "suites")}
