"""The field checks of the experiment settings: each settings dataclass checks (and normalises) its own fields
in `__post_init__` with `check_types`, `require` and `within`; every mistake is a one-line `ConfigError` naming the
dotted key. The loader (`config.loader`) coerces YAML values with the same `coerce`."""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from typing import Any, Literal, Union

from kinetix_cli.errors import UserError


class ConfigError(UserError):
    """A bad experiment config: the message names the file (or `--set`), the dotted key and what was expected."""


def section_of(cls: type) -> str:
    """The YAML section a settings class is read from (its `SECTION`), '?' for others."""
    return getattr(cls, "SECTION", "?")


def check_types(obj) -> None:
    """Check (and normalise: int -> float, list -> tuple) every field of a settings dataclass in place."""
    for name, hint in field_types(type(obj)).items():
        value = getattr(obj, name)
        if dataclasses.is_dataclass(hint):
            if not isinstance(value, hint):
                raise ConfigError(f"{name}: expected {hint.__name__}, got {show(value)}")
            continue
        object.__setattr__(obj, name, coerce(value, hint, f"{section_of(type(obj))}.{name}"))


def require(obj, name: str, ok: bool, problem: str) -> None:
    if not ok:
        key = f"{section_of(type(obj))}.{name}"
        raise ConfigError(f"{key}: {problem} (got {getattr(obj, name)!r})")


def within(obj, name: str, low: float, high: float, low_excluded: bool = False) -> None:
    """Require `low <= value <= high` (`low < value` with `low_excluded`), the range in the message."""
    value = getattr(obj, name)
    ok = (low < value if low_excluded else low <= value) and value <= high
    require(obj, name, ok, f"must be {'>' if low_excluded else '>='} {_bound(low)} and <= {_bound(high)}")


def _bound(value: float) -> str:
    """A range's end as written: integers in full (2147483647, not 2.14748e+09), other numbers short (3e-4)."""
    return str(value) if isinstance(value, int) else f"{value:g}"


def coerce(value: Any, hint: Any, key: str) -> Any:
    """`value` as the field type `hint`, or a ConfigError "key: expected ..., got ..."."""
    origin = typing.get_origin(hint)
    if origin in (Union, types.UnionType):  # `X | None`
        if value is None:
            return None
        (inner,) = [a for a in typing.get_args(hint) if a is not type(None)]
        try:
            return coerce(value, inner, key)
        except ConfigError:
            raise _type_error(key, hint, value) from None
    if origin is Literal:
        if isinstance(value, str) and value in typing.get_args(hint):
            return value
        raise _type_error(key, hint, value)
    if origin is tuple:
        if not isinstance(value, list | tuple):
            raise _type_error(key, hint, value)
        item = typing.get_args(hint)[0]
        return tuple(coerce(v, item, f"{key}[{i}]") for i, v in enumerate(value))
    if not _matches(value, hint):
        raise _type_error(key, hint, value)
    if hint is float:
        return float(value)
    if hint is int:
        return int(value)
    return value


def _matches(value: Any, hint: type) -> bool:
    if hint is bool:
        return isinstance(value, bool)
    if hint is int:
        return (isinstance(value, int) and not isinstance(value, bool)) or (
            isinstance(value, float) and value.is_integer()
        )
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            return False
        try:
            return math.isfinite(value)
        except OverflowError:  # an integer beyond any float
            return False
    return isinstance(value, hint)


def _describe(hint: Any) -> str:
    origin = typing.get_origin(hint)
    if origin in (Union, types.UnionType):
        (inner,) = [a for a in typing.get_args(hint) if a is not type(None)]
        return f"{_describe(inner)} or null"
    if origin is Literal:
        return "one of " + ", ".join(map(repr, typing.get_args(hint)))
    if origin is tuple:
        return f"a list of {_describe(typing.get_args(hint)[0]).removeprefix('a ')}s"
    return {bool: "true or false", int: "an integer", float: "a finite number", str: "a string"}.get(hint, str(hint))


def _type_error(key: str, hint: Any, value: Any) -> ConfigError:
    return ConfigError(f"{key}: expected {_describe(hint)}, got {show(value)}")


_HINTS: dict[type, dict[str, Any]] = {}


def field_types(cls: type) -> dict[str, Any]:
    """Field name -> resolved type annotation, in declaration order."""
    if cls not in _HINTS:
        hints = typing.get_type_hints(cls)
        _HINTS[cls] = {f.name: hints[f.name] for f in dataclasses.fields(cls)}
    return _HINTS[cls]


def show(value: Any) -> str:
    text = repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{text} ({type(value).__name__})"
