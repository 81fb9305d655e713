"""Writing a scenario as TOML (``tomllib`` only reads).
"""

from __future__ import annotations

import json
import re
from typing import Any

# ---------------------------------------------------------------------------------------
# TOML writing (tomllib only reads)
# ---------------------------------------------------------------------------------------
_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _dump_toml(d: dict, prefix: str = "") -> str:
    lines = []
    scalars = {k: v for k, v in d.items() if not isinstance(v, dict) or _inline(v)}
    tables = {k: v for k, v in d.items() if k not in scalars}
    if prefix and (scalars or not tables):
        lines.append(f"\n[{prefix}]")
    for k, v in scalars.items():
        lines.append(f"{_key(k)} = {_value(v)}")
    text = "\n".join(lines)
    for k, v in tables.items():
        text += "\n" + _dump_toml(v, f"{prefix}.{_key(k)}" if prefix else _key(k))
    return text.strip("\n") + "\n" if not prefix else text


def _inline(d: dict) -> bool:
    """Tables written inline: none (every dict becomes a [section])."""
    return False
