"""A run folder's ``.lock``: which process works in it, and whether a lock is live, stale
(taken over) or not this tool's (never touched)."""

from __future__ import annotations

import os
import socket
from pathlib import Path

from ...errors import InputError
from .ownership import LOCK, TOOL


# ---- locks ----------------------------------------------------------------------------------
def _read_lock(lock: Path) -> tuple:
    """``(pid, host, tagged)`` written in a lock file (``<pid> <host> shipthermal``; earlier
    versions wrote ``<pid> <host>``, untagged); pid ``0`` for an empty file (a writer that
    died between creating and filling it), ``-1`` when unreadable or in another form."""
    try:
        text = lock.read_text(encoding="utf-8")
    except (OSError, ValueError):
        return -1, "", False
    words = text.split()
    if not words:
        return 0, "", False
    if len(words) not in (2, 3) or (len(words) == 3 and words[2] != TOOL):
        return -1, "", False
    try:
        pid = int(words[0])
    except ValueError:
        return -1, "", False
    return (pid, words[1], len(words) == 3) if pid > 0 else (-1, "", False)


def _lock_state(lock: Path, signed: bool) -> str:
    """``free``, ``live`` (its process runs on this host), ``stale`` (a lock of this tool
    that may be taken over) or ``foreign`` (not a lock of this tool: never touched).

    In a signed run folder a lock in this tool's form (tagged or not) whose process is gone,
    or that was written on another host (which cannot be checked), is stale, and so is an
    empty one. Outside one, only a tagged lock of a dead process on this host is."""
    if not os.path.lexists(lock):
        return "free"
    if lock.is_symlink() or not lock.is_file():
        return "foreign"
    pid, host, tagged = _read_lock(lock)
    if pid < 0 or (not signed and (pid == 0 or not tagged)):
        return "foreign"
    if pid == 0:
        return "stale"
    if host == socket.gethostname():
        return "live" if _pid_alive(pid) else "stale"
    return "stale" if signed else "foreign"


def stale_lock(path) -> int | None:
    """The pid of a lock in ``path`` whose process on this host is gone (else None)."""
    pid, host, _ = _read_lock(Path(path) / LOCK)
    if host == socket.gethostname() and pid > 0 and not _pid_alive(pid):
        return pid
    return None


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _in_use(field, path, pid) -> InputError:
    return InputError(field, str(path), f"is in use by process {pid} (its .lock file)",
                      "Wait for it to finish, or choose another --out")


def _foreign_lock(field, path) -> InputError:
    return InputError(field, str(path), "holds a .lock file that is not a lock of "
                      "shipthermal", "If no shipthermal process works in this folder, delete "
                      "its .lock file")
