"""One source of truth for bake options: frozen dataclasses whose fields carry help, choices and bounds.

The CLI flags (``--<bake>-<option>``), recipe files and the Python API are all generated from, or checked against,
these dataclasses; nothing re-declares an option.
"""
from __future__ import annotations

import dataclasses
import typing
from dataclasses import field


def opt(default, help: str, *, choices=None, min=None, max=None):
    """A dataclass field with its documentation and bounds attached as metadata."""
    return field(default=default, metadata={"help": help, "choices": choices, "min": min, "max": max})


def _base_type(cls, f):
    hint = typing.get_type_hints(cls)[f.name]
    args = [a for a in typing.get_args(hint) if a is not type(None)]
    return args[0] if args else hint


def coerce(cls, name: str, value):
    """Convert ``value`` (from a flag string or a recipe) to the type of ``cls.name`` and check its bounds."""
    fields = {f.name: f for f in dataclasses.fields(cls)}
    if name not in fields:
        raise ValueError(f"unknown option '{name}' (known: {', '.join(fields)})")
    f = fields[name]
    base = _base_type(cls, f)
    if value is None:
        return None
    if base is bool:
        if isinstance(value, str):
            low = value.lower()
            if low not in ("1", "0", "true", "false", "yes", "no", "on", "off"):
                raise ValueError(f"option '{name}' expects true or false, got {value!r}")
            value = low in ("1", "true", "yes", "on")
        value = bool(value)
    elif base is tuple:
        parts = value.split(",") if isinstance(value, str) else list(value)
        value = tuple(float(p) for p in parts)
        if len(value) != len(f.default):
            raise ValueError(f"option '{name}' expects {len(f.default)} comma-separated numbers")
    elif base in (int, float):
        try:
            value = base(value)
        except (TypeError, ValueError):
            raise ValueError(f"option '{name}' expects a number, got {value!r}") from None
    elif base is str:
        value = str(value)
    meta = f.metadata
    if meta.get("choices") and value not in meta["choices"]:
        raise ValueError(f"option '{name}' must be one of {', '.join(map(str, meta['choices']))}, got {value!r}")
    for item in value if isinstance(value, tuple) else (value,):  # bounds apply to each component of a tuple
        if meta.get("min") is not None and item < meta["min"]:
            raise ValueError(f"option '{name}' must be >= {meta['min']}, got {value}")
        if meta.get("max") is not None and item > meta["max"]:
            raise ValueError(f"option '{name}' must be <= {meta['max']}, got {value}")
    return value


def from_mapping(cls, values: dict):
    """Build options of ``cls`` from a mapping (e.g. a recipe table); unknown keys are errors."""
    return cls(**{k.replace("-", "_"): coerce(cls, k.replace("-", "_"), v) for k, v in values.items()})


def add_arguments(parser, cls, prefix: str, *, prefixed_flags: bool = True, skip=()) -> None:
    """Add one ``--<prefix>-<name>`` flag per field of ``cls`` to an argparse parser (default: unset).

    ``prefixed_flags=False`` gives plain ``--<name>`` flags, for commands with a single option set (``baker hair``,
    ``baker glyphs``); values land in ``<prefix>__<name>`` either way, so :func:`from_args` reads both. Fields in
    ``skip`` get no flag."""
    group = parser.add_argument_group(f"{prefix} options", (cls.__doc__ or "").strip())
    for f in dataclasses.fields(cls):
        if f.name in skip:
            continue
        flag = f"--{prefix + '-' if prefixed_flags else ''}{f.name.replace('_', '-')}"
        meta = f.metadata
        default = f.default
        shown = ",".join(map(str, default)) if isinstance(default, tuple) else default
        text = meta.get("help", "")
        if shown is not None:  # None defaults are explained in the help text itself ("default: ...")
            text += f" (default: {shown})"
        text = text.replace("%", "%%")  # argparse formats help strings with %
        metavar = "{" + ",".join(map(str, meta["choices"])) + "}" if meta.get("choices") else f.name.upper()
        group.add_argument(flag, dest=f"{prefix}__{f.name}", default=None, metavar=metavar, help=text)


def from_args(cls, prefix: str, namespace) -> object:
    values = {}
    for f in dataclasses.fields(cls):
        raw = getattr(namespace, f"{prefix}__{f.name}", None)
        if raw is not None:
            values[f.name] = coerce(cls, f.name, raw)
    return cls(**values)
