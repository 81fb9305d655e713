"""Errors a user can cause, with messages that say what to change.

Every check at the edge of the library raises :class:`InputError` naming the field
(a dotted path such as ``layup.deck[0].thickness``), the value it got, what is allowed
and, where useful, how to fix it. Inside the library inputs are trusted.
:class:`SimulationError` is the other kind: a solve that failed on valid inputs.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["InputError", "require", "check_positive", "check_finite", "check_range",
           "input_error_from_os", "SimulationError"]


class InputError(ValueError):
    """A user input is invalid.

    Attributes
    ----------
    field : str
        Dotted path of the offending input.
    value : Any
        The value received (shortened in the message for large arrays).
    allowed : str
        What would have been accepted.
    fix : str
        A hint on how to fix it (may be empty).
    """

    def __init__(self, field: str, value: Any, allowed: str, fix: str = ""):
        self.field = field
        self.value = value
        self.allowed = allowed
        self.fix = fix
        msg = f"{field} = {_short(value)}: {allowed}"
        if fix:
            msg += f". {fix}"
        super().__init__(msg)

    def __reduce__(self):
        # (from a worker process to the caller whole: fields, not the message alone)
        return (type(self), (self.field, self.value, self.allowed, self.fix))


class SimulationError(RuntimeError):
    """The solve failed (NaN, no convergence): not a user input error."""


def _short(value: Any) -> str:
    if isinstance(value, np.ndarray):
        if value.size <= 6:
            return np.array2string(value, precision=6)
        return f"array(shape={value.shape}, dtype={value.dtype})"
    text = repr(value)
    return text if len(text) <= 120 else text[:117] + "..."


def require(condition: bool, field: str, value: Any, allowed: str, fix: str = "") -> None:
    """Raise :class:`InputError` unless ``condition`` holds."""
    if not condition:
        raise InputError(field, value, allowed, fix)


def check_finite(field: str, value: Any) -> None:
    """Reject NaN or infinite numbers (scalars or arrays), naming the first bad entry."""
    arr = np.asarray(value, dtype=float)
    bad = ~np.isfinite(arr)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0]) if arr.ndim else ()
        shown = arr[where] if arr.ndim else float(arr)
        loc = f"{field}{list(where) if where else ''}"
        raise InputError(loc, float(shown), "must be a finite number (no NaN or inf)",
                         "Check the input data for missing values")


def check_positive(field: str, value: Any, unit: str = "") -> None:
    """Reject non-finite or non-positive numbers (scalars or arrays)."""
    check_finite(field, value)
    arr = np.asarray(value, dtype=float)
    bad = arr <= 0
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0]) if arr.ndim else ()
        shown = arr[where] if arr.ndim else float(arr)
        loc = f"{field}{list(where) if where else ''}"
        raise InputError(loc, float(shown), f"must be > 0{(' ' + unit) if unit else ''}")


def check_range(field: str, value: Any, low: float, high: float, unit: str = "",
                low_open: bool = False, high_open: bool = False) -> None:
    """Reject numbers outside ``[low, high]`` (ends open where requested)."""
    check_finite(field, value)
    arr = np.asarray(value, dtype=float)
    bad = (arr <= low if low_open else arr < low) | (arr >= high if high_open else arr > high)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0]) if arr.ndim else ()
        shown = arr[where] if arr.ndim else float(arr)
        lo = "(" if low_open else "["
        hi = ")" if high_open else "]"
        loc = f"{field}{list(where) if where else ''}"
        u = f" {unit}" if unit else ""
        lo_s = "-inf" if math.isinf(low) else f"{low:g}"
        hi_s = "inf" if math.isinf(high) else f"{high:g}"
        raise InputError(loc, float(shown), f"must lie in {lo}{lo_s}, {hi_s}{hi}{u}")


#: What an operating-system error on a user's path means, and how to fix it
_OS_ERRORS = {
    "EACCES": ("permission denied for this user", "Choose a path you may read and write "
               "(e.g. --out in your home folder), or change its permissions"),
    "EPERM": ("operation not permitted for this user", "Choose a path you may read and write, "
              "or change its permissions"),
    "EROFS": ("is on a read-only file system", "Choose a writable location (e.g. --out)"),
    "ENOSPC": ("no space left on the device", "Free disk space, or choose --out on another "
               "disk"),
    "EDQUOT": ("disk quota exceeded", "Free space in your quota, or choose --out elsewhere"),
    "ENAMETOOLONG": ("a file or folder name is longer than the file system allows (255 bytes "
                     "per name)", "Use shorter names"),
    "ENOTDIR": ("a part of the path is a file, not a folder", "Check the path"),
    "EISDIR": ("is a folder where a file is expected", "Name the file inside the folder"),
    "ENOENT": ("does not exist", "Check the path"),
    "ELOOP": ("has too many symbolic links", "Check the path"),
}


def input_error_from_os(exc: BaseException) -> InputError | None:
    """The :class:`InputError` that an :class:`OSError` on a user path amounts to (permission,
    disk full, name too long, ...), or None when it is not one a user can fix.

    Only errors that name a file are converted; a file inside this installation is never the
    user's.
    """
    import errno
    from pathlib import Path

    if not isinstance(exc, OSError) or exc.errno is None:
        return None
    name = errno.errorcode.get(exc.errno, "")
    if name not in _OS_ERRORS or exc.filename is None:
        return None
    path = str(exc.filename)
    try:
        package = Path(__file__).resolve().parents[1]
        if Path(path).resolve().is_relative_to(package):
            return None
    except (OSError, ValueError):
        pass
    allowed, fix = _OS_ERRORS[name]
    return InputError("path", path, f"{allowed} ({name})", fix)
