"""Writing a file atomically: the writer fills a temporary file next to the target, which is
renamed into place once complete, so an interrupted write never leaves a file that looks
complete.

The temporary is ``.<stem>.<8 random characters>.tmp<suffix>`` in the target's folder: it
keeps the target's suffix at the end, so writers that choose the format by the name still
recognise it. On success it gets the permissions a plain ``open()`` would give and replaces
the target; on failure it is removed, and an operating-system error of the write names the
user's file rather than the temporary.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from .errors import InputError

__all__ = ["atomic_path", "atomic_write_text", "check_room"]


class atomic_path:
    """Context manager giving a temporary path next to ``path``; renamed on success,
    removed on failure."""

    def __init__(self, path, suffix: str | None = None):
        self.path = Path(path)
        self.suffix = suffix if suffix is not None else self.path.suffix

    def __enter__(self) -> Path:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=self.path.parent, prefix=f".{self.path.stem}.",
                                   suffix=".tmp" + self.suffix)
        os.close(fd)
        self.tmp = Path(tmp)
        return self.tmp

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            # mkstemp creates 0600; give the file the permissions a plain open() would
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(self.tmp, 0o666 & ~umask)
            os.replace(self.tmp, self.path)
        else:
            if self.tmp.exists():
                self.tmp.unlink()
            if isinstance(exc, OSError) and exc.errno is not None and (
                    exc.filename is None or str(exc.filename) == str(self.tmp)):
                # the user's file, not the temporary name (disk full, quota, ...)
                raise OSError(exc.errno, exc.strerror or str(exc), str(self.path)) from exc
        return False


def atomic_write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` through :class:`atomic_path`; returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


#: Room asked for besides the data's own bytes before an HDF5 file is written: a fraction
#: of them and a fixed amount [bytes] (HDF5's headers and chunk indexes: a few kB in the
#: product's files).
HDF5_ROOM_MARGIN = (0.01, 2 ** 20)


def check_room(path, needed: int, what: str) -> None:
    """Refuse to write ``needed`` bytes (and :data:`HDF5_ROOM_MARGIN`) at ``path`` where the
    disk has not the room. For the HDF5 writers: HDF5 fails part-way on a full disk, its
    file then closes with an error of its own that hides the disk's, and the objects left
    behind crashed the interpreter when collected (segmentation fault after the error
    message, measured on a full 60 MB file system)."""
    path = Path(path)
    folder = next((p for p in (path.parent, *path.parent.parents) if p.exists()), Path("."))
    free = shutil.disk_usage(folder).free
    total = int(needed * (1.0 + HDF5_ROOM_MARGIN[0])) + HDF5_ROOM_MARGIN[1]
    if free < total:
        raise InputError(str(path), f"{total / 2 ** 20:.0f} MiB needed, "
                         f"{free / 2 ** 20:.0f} MiB free",
                         f"no space left on the device for {what}",
                         "Free disk space, or choose --out on another disk")
