"""The signed head of a run folder's manifest (command, host, package versions, git
commit); single files are written with :func:`shipthermal.atomic.atomic_write_text`."""

from __future__ import annotations

import datetime as _dt
import os
import platform
import socket
import subprocess
import sys
from importlib import metadata
from pathlib import Path

from .ownership import MANIFEST, TOOL


#: Packages whose versions go into every manifest
VERSIONED = ("shipthermal", "numpy", "scipy", "numba", "pandas", "embreex", "trimesh",
             "pyvista", "vtk", "pytetwild", "pvlib", "pykrige", "rasterio", "xarray",
             "h5py", "matplotlib", "dask", "distributed", "tqdm")


def package_versions(names=VERSIONED) -> dict:
    """Installed versions of ``names`` (``None`` when a package is missing)."""
    out = {"python": platform.python_version()}
    for n in names:
        try:
            out[n] = metadata.version(n)
        except metadata.PackageNotFoundError:
            out[n] = None
    return out


def git_commit(path=None) -> dict | None:
    """Commit (and whether the tree has local changes) of the git checkout holding
    ``path`` (default: this package); None outside a checkout or without git."""
    where = Path(path) if path is not None else Path(__file__).resolve().parent
    try:
        head = subprocess.run(["git", "-C", str(where), "rev-parse", "HEAD"], capture_output=True,
                              text=True, timeout=5)
        if head.returncode != 0:
            return None
        dirty = subprocess.run(["git", "-C", str(where), "status", "--porcelain",
                                "--untracked-files=no"], capture_output=True, text=True,
                               timeout=10)
        return {"commit": head.stdout.strip(),
                "local_changes": bool(dirty.stdout.strip()) if dirty.returncode == 0 else None}
    except (OSError, subprocess.SubprocessError):
        return None


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")


def new_manifest(kind: str, command=None) -> dict:
    """The signed head of a manifest: signature, command line, host, versions, git."""
    return {"tool": TOOL, "kind": kind, "entries": [MANIFEST], "status": "running",
            "started": _now(), "finished": None,
            "command": list(command if command is not None else sys.argv),
            "cwd": os.getcwd(), "host": socket.gethostname(),
            "platform": platform.platform(), "versions": package_versions(),
            "git": git_commit()}
