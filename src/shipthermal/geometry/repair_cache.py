"""Repaired surfaces computed once and reused: the same input gives the same mesh.

fTetWild (pytetwild) is not deterministic: two repairs of the same file differ in their
triangles (a cargo ship at pytetwild's default size: 1148 and 1108 triangles in two
calls). A ship that ``shipthermal mesh`` showed must be the ship that ``shipthermal run``
solves, and two runs of one scenario must agree to the byte. So a repair is computed once
per input and written to a cache; every later read of the same input with the same repair
settings loads it.

The key is a SHA-256 of the surface as read (vertices, triangles, part labels, after
unit conversion and welding), the repair method and its settings, and
:data:`CACHE_VERSION`. The cache folder is ``$SHIPTHERMAL_CACHE`` when set (``off``
disables the cache), else ``$XDG_CACHE_HOME/shipthermal``, else
``~/.cache/shipthermal``; repaired surfaces go to ``repaired/<key>.npz`` (compressed
NumPy arrays and the repair report as JSON). A cache that cannot be written (read-only
home, disk full) only costs the reuse: the repair is returned and the report says the
surface was not cached.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np

from ..atomic import atomic_path

__all__ = ["CACHE_VERSION", "cache_folder", "repair_key", "load_repaired", "save_repaired"]

CACHE_VERSION = 2
"""Changes whenever a repair's algorithm or its cached fields change (old entries are
then never found). 2: a tetwild repair with pinched edges is run again (a version-1 entry
may hold such a surface, which every read then refused)."""


def cache_folder() -> Path | None:
    """The cache folder (not created), or None when ``SHIPTHERMAL_CACHE=off``."""
    env = os.environ.get("SHIPTHERMAL_CACHE")
    if env is not None:
        return None if env.strip().lower() in ("off", "0", "none", "") else Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg) if xdg else Path.home() / ".cache"
    return base / "shipthermal"


def repair_key(vertices, faces, labels, method: str, **settings) -> str:
    """SHA-256 (hex) of a surface and the settings of its repair."""
    h = hashlib.sha256()
    h.update(f"shipthermal-repair-v{CACHE_VERSION}:{method}:".encode())
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    for a, dtype in ((vertices, "<f8"), (faces, "<i8"), (labels, "<i8")):
        arr = np.ascontiguousarray(np.asarray(a), dtype=dtype)
        h.update(str(arr.shape).encode())
        h.update(arr.tobytes())
    return h.hexdigest()


def _path(key: str) -> Path | None:
    folder = cache_folder()
    return None if folder is None else folder / "repaired" / f"{key}.npz"


def load_repaired(key: str):
    """``(vertices, faces, labels, report, path)`` of a cached repair, or None."""
    path = _path(key)
    if path is None or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as d:
            report = json.loads(str(d["report"]))
            return (np.asarray(d["vertices"], float), np.asarray(d["faces"], np.int64),
                    np.asarray(d["labels"], np.int64), report, path)
    except (OSError, ValueError, KeyError):      # a damaged entry: repair again
        return None


def save_repaired(key: str, vertices, faces, labels, report: dict) -> tuple[Path | None, str]:
    """Write a repair to the cache atomically. Returns ``(path, "")`` or ``(None, why)``."""
    path = _path(key)
    if path is None:
        return None, "the cache is off (SHIPTHERMAL_CACHE=off)"
    try:
        with atomic_path(path) as tmp, open(tmp, "wb") as fh:
            np.savez_compressed(fh, vertices=np.asarray(vertices, float),
                                faces=np.asarray(faces, np.int64),
                                labels=np.asarray(labels, np.int64),
                                report=np.array(json.dumps(report, default=float)))
        return path, ""
    except OSError as exc:
        return None, f"{exc.strerror or exc} ({path.parent})"
