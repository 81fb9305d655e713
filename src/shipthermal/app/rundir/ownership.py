"""Which folders and names are this tool's: the names it writes into a run folder, the
temporaries of its writers, and the signature of a folder's ``manifest.json``."""

from __future__ import annotations

import json
import os
import re
import shutil
from pathlib import Path
from typing import NamedTuple

from ...errors import InputError


MARKER = "COMPLETE"
MANIFEST = "manifest.json"
LOCK = ".lock"
STAGE_PREFIX = ".stage-"
#: The signature of a manifest this tool wrote (``"tool"``), and the word its locks end in
TOOL = "shipthermal"
#: Kinds of folders the commands write (``kind`` of the manifest)
KINDS = ("demo", "run", "mesh", "validate", "calibrate", "sweep", "ensemble", "background",
         "calendar")
#: Top-level names this tool writes into a run folder: the entries of a folder written by an
#: earlier version, whose manifest lists none (``scenario_<case>.toml`` as well)
PRODUCTS = frozenset({MANIFEST, MARKER, "scenario.toml", "mesh", "thermal", "imaging",
                      "validation", "calibration", "report.html", "checkpoints", "sweep.toml",
                      "cases", "table.csv", "table.png", "ensemble", "calendar"})
_SCENARIO_COPY = re.compile(r"scenario_[\w.+-]+\.toml")


def is_complete(path) -> bool:
    """Whether ``path`` is a finished run directory (its ``COMPLETE`` marker exists)."""
    return (Path(path) / MARKER).is_file()


def _list(keys, most: int = 6) -> str:
    keys = list(keys)
    more = f" and {len(keys) - most} more" if len(keys) > most else ""
    return ", ".join(keys[:most]) + more


# ---- temporaries ------------------------------------------------------------------------------
def _is_temporary(name: str) -> bool:
    """Names our writers give half-written files and folders (inside this tool's own
    entries, where every name is ours), and those earlier versions gave them (a run folder
    of an earlier version may still hold them)."""
    return (name.startswith(STAGE_PREFIX) or (name.startswith(".") and ".tmp" in name)
            or ".part-" in name)


#: Names of temporaries: of this tool's writers, and of earlier versions' writers, which a
#: run folder of an earlier version may still hold (``.<name>.tmp<pid>``, ``<name>.part-<pid>``)
_TEMPORARY_FORMS = (
    re.compile(r"\.stage-(?P<base>[^.]+?)(?:__.*)?\.\d+"),          # RunDir.stage
    re.compile(r"\.(?P<base>.+)\.tmp\d+(?P<ext>\.[^.]+)?"),        # earlier versions' files
    re.compile(r"\.(?P<base>.+)\.[a-z0-9_]{8}\.tmp(?P<ext>\.[^.]*)?"),   # atomic.atomic_path
    re.compile(r"\.?(?P<base>.+)\.part-\w+"),     # background's staging folder; earlier files
)


def _temporary_base(name: str) -> str | None:
    """The name a temporary of this tool's writers stands for (``.report.html.tmp123`` →
    ``report.html``, ``.stage-thermal__tiny.77`` → ``thermal``); None for other names."""
    for form in _TEMPORARY_FORMS:
        m = form.fullmatch(name)
        if m:
            return m["base"] + (m.groupdict().get("ext") or "")
    return None


def _own_temporary(name: str, entries) -> bool:
    """Whether a top-level ``name`` is a temporary of one of this tool's entries (or of one
    of its product names): debris of a crashed writer, deleted when the folder is reopened."""
    base = _temporary_base(name)
    return base is not None and (base in entries or _is_product(base))


def _is_product(name: str) -> bool:
    return name in PRODUCTS or bool(_SCENARIO_COPY.fullmatch(name))


def _remove(path: Path) -> None:
    """Delete a file, a symbolic link (never what it points to) or a folder tree."""
    if path.is_symlink() or (os.path.lexists(path) and not path.is_dir()):
        path.unlink(missing_ok=True)
    elif path.is_dir():
        shutil.rmtree(path)


# ---- signatures ---------------------------------------------------------------------------------
class Signature(NamedTuple):
    """What a folder's ``manifest.json`` says of it (:func:`read_signature`)."""

    kind: str
    #: top-level names this tool created there (the manifest itself included)
    entries: frozenset
    #: written by an earlier version (no signature; entries = its products present)
    legacy: bool
    manifest: dict


def _safe_entry(name) -> bool:
    return (isinstance(name, str) and name not in ("", ".", "..", LOCK)
            and not any(c in name for c in "/\\\0"))


def read_signature(path) -> Signature | None:
    """The signature of a folder this tool wrote, or None (no readable manifest, or one that
    this tool did not write).

    A signed manifest has ``"tool": "shipthermal"``, a ``kind`` of :data:`KINDS` and
    ``"entries"``, a list of plain names. A manifest of an earlier version (no ``tool``) is
    accepted when it has the fields those versions always wrote: a ``kind`` of
    :data:`KINDS`, ``versions`` with a ``shipthermal`` key and a ``command`` starting with
    ``shipthermal``; its entries are the names of :data:`PRODUCTS` present in the folder."""
    p = Path(path)
    f = p / MANIFEST
    try:
        if f.is_symlink() or not f.is_file():
            return None
        m = json.loads(f.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(m, dict) or m.get("kind") not in KINDS:
        return None
    if "tool" in m:
        entries = m.get("entries")
        if m["tool"] != TOOL or not isinstance(entries, list) \
                or not all(_safe_entry(e) for e in entries):
            return None
        return Signature(m["kind"], frozenset(entries) | {MANIFEST}, False, m)
    versions, command = m.get("versions"), m.get("command")
    if not (isinstance(versions, dict) and TOOL in versions and isinstance(command, list)
            and command and command[0] == TOOL):
        return None
    try:
        names = {c.name for c in p.iterdir() if _is_product(c.name)}
    except OSError:
        return None
    return Signature(m["kind"], frozenset(names) | {MANIFEST}, True, m)


def _foreign_names(path: Path, entries) -> list:
    """Top-level names in a run folder that this tool did not write."""
    return sorted(c.name for c in path.iterdir() if c.name != LOCK and c.name not in entries
                  and not _own_temporary(c.name, entries))


def _foreign_error(path, foreign) -> InputError:
    return InputError("--out", str(path), f"holds files that shipthermal did not write "
                      f"({_list(foreign, 3)})", "Move them out of the folder, or choose "
                      "another --out: a fresh start or --force deletes only what shipthermal "
                      "wrote")
