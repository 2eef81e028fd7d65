"""Reading and writing experiment files: `load_config(path, ["ppo.lr=3e-4"])` reads a YAML file, applies `--set`
overrides and returns a validated `ExperimentConfig`; `save_config` writes the resolved config (every field, with a
`format: kinetix-experiment/1` line) that `load_config` reads back to an equal config.

Numbers may be written `5e-5` or `1e6` (PyYAML alone reads those as strings); an integral float such as `5e9` is
accepted for an integer field; only true/false are booleans. Unknown keys get a "did you mean" suggestion."""

from __future__ import annotations

import dataclasses
import difflib
import os
import re
from pathlib import Path
from typing import Any

import yaml

from kinetix_cli.config.fields import ConfigError, coerce, field_types, section_of, show
from kinetix_cli.config.settings import CONFIG_FORMAT, SECTIONS, ExperimentConfig
from kinetix_cli.io import atomic_write_text


def load_config(path: str | os.PathLike, overrides: list[str] | tuple[str, ...] = ()) -> ExperimentConfig:
    """Read an experiment YAML file, apply `--set` overrides ("ppo.lr=3e-4"; the value is parsed as YAML, so
    numbers, booleans, null and lists work) and return the validated config. Raises `ConfigError`."""
    source = str(path)
    raw = _read_yaml(Path(path))
    if not isinstance(raw, dict):
        raise ConfigError(f"{source}: expected a mapping of sections ({', '.join(SECTIONS)}), got {show(raw)}")
    fmt = raw.pop("format", CONFIG_FORMAT)
    if fmt != CONFIG_FORMAT:
        raise ConfigError(f"{source}: format: expected {CONFIG_FORMAT!r}, got {fmt!r}")

    values: dict[str, dict[str, Any]] = {}
    for section, body in raw.items():
        if section not in SECTIONS:
            raise ConfigError(f"{source}: unknown key {_quote(section)}{_suggest(str(section))}")
        if body is None:
            body = {}
        if not isinstance(body, dict):
            raise ConfigError(f"{source}: {section}: expected a mapping of its fields, got {show(body)}")
        values[section] = {}
        for name, value in body.items():
            key = f"{section}.{name}"
            if name not in field_types(SECTIONS[section]):
                raise ConfigError(f"{source}: unknown key {_quote(key)}{_suggest(key)}")
            values[section][name] = _coerce_or_raise(value, SECTIONS[section], name, source)

    for text in overrides:
        key, sep, value_text = text.partition("=")
        key = key.strip()
        if not sep:
            raise ConfigError(f"--set {text}: expected KEY=VALUE, such as ppo.lr=3e-4")
        section, _, name = key.partition(".")
        if section not in SECTIONS or name not in field_types(SECTIONS[section]):
            raise ConfigError(f"--set: unknown key {_quote(key)}{_suggest(key)}")
        try:
            value = yaml.load(value_text, Loader=_Loader)
        except yaml.YAMLError as exc:
            raise ConfigError(f"--set {key}: the value is not valid YAML ({_one_line(exc)})") from None
        values.setdefault(section, {})[name] = _coerce_or_raise(value, SECTIONS[section], name, "--set")

    where = source + (f" with --set {' '.join(overrides)}" if overrides else "")
    sections = {}
    for section, cls in SECTIONS.items():
        given = values.get(section, {})
        for field in dataclasses.fields(cls):
            if _is_required(field) and field.name not in given:
                raise ConfigError(f"{where}: missing required key '{section}.{field.name}'")
        try:
            sections[section] = cls(**given)
        except ConfigError as exc:
            raise ConfigError(f"{where}: {exc}") from None
    try:
        return ExperimentConfig(**sections)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def config_to_dict(config: ExperimentConfig) -> dict[str, dict[str, Any]]:
    """Plain nested dict of every field (tuples as lists), as written by `save_config`."""
    out = {}
    for section in SECTIONS:
        settings = getattr(config, section)
        out[section] = {
            f.name: list(v) if isinstance(v := getattr(settings, f.name), tuple) else v
            for f in dataclasses.fields(settings)
        }
    return out


def format_config(config: ExperimentConfig) -> str:
    """The resolved config as YAML text, `format` line first; `load_config` reads it back to an equal config."""
    body = yaml.safe_dump(config_to_dict(config), sort_keys=False, default_flow_style=False)
    return f"# Resolved experiment config: every field, defaults included.\nformat: {CONFIG_FORMAT}\n{body}"


def save_config(config: ExperimentConfig, path: str | os.PathLike) -> Path:
    """Write the resolved config atomically to `path` (usually `run_dir / CONFIG_FILENAME`) and return the path."""
    path = Path(path)
    atomic_write_text(path, format_config(config))
    return path


def _coerce_or_raise(value: Any, cls: type, name: str, source: str) -> Any:
    try:
        return coerce(value, field_types(cls)[name], f"{section_of(cls)}.{name}")
    except ConfigError as exc:
        raise ConfigError(f"{source}: {exc}") from None


def _is_required(field: dataclasses.Field) -> bool:
    return field.default is dataclasses.MISSING and field.default_factory is dataclasses.MISSING


# Names people bring from other PPO code bases -> our field names.


# Names people bring from other PPO code bases -> our field names.
_ALIASES = {
    "learning_rate": "lr",
    "epochs": "update_epochs",
    "num_epochs": "update_epochs",
    "lambda": "gae_lambda",
    "entropy_coef": "ent_coef",
    "value_coef": "vf_coef",
    "clip": "clip_eps",
    "timesteps": "total_timesteps",
    "grad_norm": "max_grad_norm",
}


def _suggest(key: str) -> str:
    """ "; did you mean 'ppo.lr'?" for the closest valid dotted key, or a list of the sections."""
    head, _, leaf = key.rpartition(".")
    leaf = _ALIASES.get(leaf, leaf)
    field_keys = [f"{s}.{n}" for s, cls in SECTIONS.items() for n in field_types(cls)]
    close = [k for k in field_keys if k.rpartition(".")[2] == leaf and k != key]  # right field, wrong section
    if not close and head in SECTIONS:  # a misspelt field of a real section
        close = [f"{head}.{m}" for m in difflib.get_close_matches(leaf, field_types(SECTIONS[head]), n=1, cutoff=0.5)]
    if not close and not head:  # a misspelt section
        close = difflib.get_close_matches(key, SECTIONS, n=1, cutoff=0.4)
    if not close:
        close = difflib.get_close_matches(key, list(SECTIONS) + field_keys, n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else f"; valid sections: {', '.join(SECTIONS)}"


def _quote(key: Any) -> str:
    return repr(str(key)) if isinstance(key, str) else repr(key)


def _one_line(exc: Exception) -> str:
    return " ".join(str(exc).split())


# ----------------------------------------------------------------------------------------------------- YAML


class _Loader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 scalars: floats without a dot (`5e-5`, `1e6`) are numbers and only true/false are
    booleans (so `wandb: off` is the string 'off', not false). Duplicate keys are an error."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            if key in seen:
                raise yaml.constructor.ConstructorError(None, None, f"duplicate key {key!r}", key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


_Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:bool"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool", re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF")
)
_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$"),
    list("-+.0123456789"),
)


def _read_yaml(path: Path) -> Any:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such experiment file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: cannot read ({_one_line(exc)})") from None
    try:
        data = yaml.load(text, Loader=_Loader)
    except yaml.YAMLError as exc:
        raise ConfigError(f"{path}: invalid YAML ({_one_line(exc)})") from None
    return {} if data is None else data
