"""Safe run directories: nothing half-written ever looks complete.

Layout of ``runs/<name>/`` (every stage writes into a hidden staging folder that is
renamed into place only when the stage has finished)::

    runs/<name>/
      manifest.json          signature (tool, kind, entries written), versions, git commit,
                             seeds, command line, start/end, timings
      scenario.toml          the scenario of a single-case run (explicit copy), or
      scenario_<case>.toml   one per case (the demo: summer and winter)
      mesh/                  `shipthermal mesh`: ship files, part picture, mesh report
      thermal/<case>/        part_means.csv/.png, surface_HHMM.png, thermal.vtkhdf,
                             thermal_summary.json, energy.csv, history.npz (a weather
                             record: history.h5)
      imaging/               images_*.nc, typical_*.tif, panels_*.png, scr_*.png,
                             metrics_*.csv, crossovers.csv, band_comparison.csv, summary.json
      validation/            validation table (when run)
      report.html            self-contained report (images embedded)
      checkpoints/<case>.npz thermal checkpoints while a run is unfinished (a weather
                             record: also <case>.record/, its outputs day by day)
      COMPLETE               written last; its absence means "not finished"

Rules (what makes it safe):

* a stage's files are written in ``.stage-<stage>.<pid>/`` and the folder is renamed to its
  final name when the stage is done, so a stage folder that exists is complete;
* single files (manifest, report, scenario copies) go through a temporary name and
  ``os.replace``;
* ``COMPLETE`` is written after everything else and removed first when a run is reopened;
* a ``.lock`` file holds the pid of the process working in the folder; a second process
  is refused, a stale lock (dead pid) of this tool is taken over;
* reopening a run (fresh or ``--resume``) deletes stale temporaries of crashed writers;
* ``--resume`` keeps finished stages and thermal checkpoints, and refuses a scenario that
  differs from the copy in the folder;
* a user error (:class:`~shipthermal.errors.InputError`) in a fresh run removes what it
  wrote (the folder too when the run created it); a crash or Ctrl-C keeps the unfinished
  folder (manifest status ``failed`` / ``interrupted``, no marker) for ``--resume``.

What makes it unable to destroy a user's files:

* a folder is a run folder only when its ``manifest.json`` is signed: ``"tool":
  "shipthermal"``, the ``kind`` of command that wrote it, and ``"entries"``, the top-level
  names this tool created there (each is listed, and the manifest saved, before it is
  written). A manifest of an earlier version (no signature, but ``kind``, ``versions`` with
  a ``shipthermal`` key and a command starting with ``shipthermal``) is accepted; its
  entries are the names of this tool's products that are present (:data:`PRODUCTS`);
* a command replaces (``--force``), continues (``--resume``) or amends only a run folder
  of its own kind (amendments: ``image`` a ``run`` or ``demo`` folder, ``report`` and
  ``validate --into`` any signed folder);
* everything a command deletes is an entry of the manifest or a temporary of this tool
  (``.stage-*``, ``.<entry>.tmp<pid>``, ...); nothing else is ever deleted or written
  over. A fresh start (or ``--force``) in a run folder that holds anything else is
  refused (exit 2, naming it): the user moves it away or chooses another folder;
  ``--resume`` and amendments leave such files alone;
* any other non-empty folder (a user folder, a ``manifest.json`` of someone else's, a
  ``.lock`` that this tool did not write) is never written into, with or without
  ``--force``; a file is never turned into a folder;
* the output folder may not be, or contain, an input of the command (scenario, weather,
  mesh, raster or measurement files): refused before anything is written.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import os
import platform
import re
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import NamedTuple

from ..errors import InputError, input_error_from_os

__all__ = ["RunDir", "MARKER", "package_versions", "git_commit", "atomic_write_text",
           "is_complete", "scenario_changes", "changes_from_copy", "stale_lock", "Signature",
           "read_signature", "check_inputs", "scenario_inputs", "named_files", "new_manifest",
           "TOOL",
           "KINDS", "PRODUCTS"]

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

#: Packages whose versions go into every manifest
VERSIONED = ("shipthermal", "numpy", "scipy", "numba", "pandas", "embreex", "trimesh",
             "pyvista", "vtk", "pytetwild", "pvlib", "pykrige", "rasterio", "xarray",
             "h5py", "matplotlib", "dask", "distributed", "tqdm")


def package_versions(names=VERSIONED) -> dict:
    """Installed versions of ``names`` (``None`` when a package is missing)."""
    from importlib import metadata

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


def atomic_write_text(path, text: str) -> Path:
    """Write ``text`` to a temporary name next to ``path``, then rename it into place."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    try:
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def is_complete(path) -> bool:
    """Whether ``path`` is a finished run directory (its ``COMPLETE`` marker exists)."""
    return (Path(path) / MARKER).is_file()


def _flatten(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flatten(v, key + "."))
        else:
            out[key] = v
    return out


def scenario_changes(old, new) -> list:
    """Dotted keys whose values differ between two scenarios (e.g. ``solver.time_step``)."""
    a, b = _flatten(old.to_dict()), _flatten(new.to_dict())
    return sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))


def _list(keys, most: int = 6) -> str:
    keys = list(keys)
    more = f" and {len(keys) - most} more" if len(keys) > most else ""
    return ", ".join(keys[:most]) + more


def changes_from_copy(path, scenario) -> list:
    """Keys in which ``scenario`` differs from the single-case copy in ``path`` ([] when
    there is no scenario or no copy to compare with)."""
    copy = Path(path) / "scenario.toml"
    if scenario is None or not copy.is_file():
        return []
    from .scenario import load_scenario

    try:
        return scenario_changes(load_scenario(copy), scenario)
    except InputError:
        return ["(the run's scenario.toml no longer loads)"]


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


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


# ---- temporaries ------------------------------------------------------------------------------
def _is_temporary(name: str) -> bool:
    """Names our writers give half-written files and folders (inside this tool's own
    entries, where every name is ours)."""
    return (name.startswith(STAGE_PREFIX) or (name.startswith(".") and ".tmp" in name)
            or ".part-" in name)


_TEMPORARY_FORMS = (
    re.compile(r"\.stage-(?P<base>[^.]+?)(?:__.*)?\.\d+"),          # RunDir.stage
    re.compile(r"\.(?P<base>.+)\.tmp\d+(?P<ext>\.[^.]+)?"),        # atomic_write_text, pictures
    re.compile(r"\.(?P<base>.+)\.[a-z0-9_]{8}\.tmp(?P<ext>\.[^.]*)?"),   # results.atomic_path
    re.compile(r"\.?(?P<base>.+)\.part-\w+"),                      # *.part-<pid>
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


def named_files(node, out: list | None = None) -> list:
    """The absolute paths of existing files or folders among the strings of a nested
    dict / list (a scenario's tables: its files are stored as absolute paths)."""
    out = [] if out is None else out
    if isinstance(node, dict):
        for v in node.values():
            named_files(v, out)
    elif isinstance(node, (list, tuple)):
        for v in node:
            named_files(v, out)
    elif isinstance(node, str) and os.path.isabs(node) and os.path.exists(node):
        out.append(node)
    return out


def scenario_inputs(scenario) -> list:
    """The files a scenario reads: its TOML file (when it was loaded from one) and every
    file it names (weather, ship mesh and part maps, background rasters; these are stored
    as absolute paths), plus the folder of a Landsat band-file template below the MTL's."""
    out = []
    src = getattr(scenario, "source", None)
    if src and os.path.isfile(src):
        out.append(str(src))
    data = scenario.to_dict() if hasattr(scenario, "to_dict") else scenario
    named_files(data, out)
    bg = data.get("background", {}) if isinstance(data, dict) else {}
    if isinstance(bg, dict) and bg.get("mtl") and bg.get("band_files"):
        sub = os.path.dirname(str(bg["band_files"]))
        if sub:
            out.append(os.path.join(os.path.dirname(str(bg["mtl"])), sub))
    return out


def check_inputs(out, inputs, field: str = "--out") -> None:
    """Refuse an output folder that is, or holds, one of ``inputs`` (symbolic links
    followed); an output folder inside an input's folder is fine."""
    o = Path(os.path.realpath(out))
    for i in inputs:
        if not i:
            continue
        r = Path(os.path.realpath(i))
        if r == o or o in r.parents:
            what = "is" if r == o else "holds"
            raise InputError(field, str(out), f"{what} an input of this command ({i})",
                             "Choose an output folder that holds none of the inputs, e.g. a "
                             "new folder under runs/")


def new_manifest(kind: str, command=None) -> dict:
    """The signed head of a manifest: signature, command line, host, versions, git."""
    return {"tool": TOOL, "kind": kind, "entries": [MANIFEST], "status": "running",
            "started": _now(), "finished": None,
            "command": list(command if command is not None else sys.argv),
            "cwd": os.getcwd(), "host": socket.gethostname(),
            "platform": platform.platform(), "versions": package_versions(),
            "git": git_commit()}


def _foreign_names(path: Path, entries) -> list:
    """Top-level names in a run folder that this tool did not write."""
    return sorted(c.name for c in path.iterdir() if c.name != LOCK and c.name not in entries
                  and not _own_temporary(c.name, entries))


def _foreign_error(path, foreign) -> InputError:
    return InputError("--out", str(path), f"holds files that shipthermal did not write "
                      f"({_list(foreign, 3)})", "Move them out of the folder, or choose "
                      "another --out: a fresh start or --force deletes only what shipthermal "
                      "wrote")


def _in_use(field, path, pid) -> InputError:
    return InputError(field, str(path), f"is in use by process {pid} (its .lock file)",
                      "Wait for it to finish, or choose another --out")


def _foreign_lock(field, path) -> InputError:
    return InputError(field, str(path), "holds a .lock file that is not a lock of "
                      "shipthermal", "If no shipthermal process works in this folder, delete "
                      "its .lock file")


class RunDir:
    """One run directory, opened for writing (use as a context manager).

    Parameters
    ----------
    path : path-like
        The folder (``runs/<name>``); created.
    command : list of str, optional
        Command line recorded in the manifest (default ``sys.argv``).
    resume : bool
        Keep finished stages and checkpoints of an unfinished run.
    force : bool
        Replace a finished run (otherwise reopening one without ``resume`` is a user
        error; with ``resume`` its marker is removed until it completes again). Not with
        ``resume``.
    kind : str
        What made the run (``demo``, ``run``, ``mesh``, ...), recorded in the manifest; an
        existing folder is reopened only when it is a run folder of this kind.
    log : callable, optional
        Receives notes for the user (e.g. a stale lock that was taken over).
    scenario : Scenario, optional
        The scenario about to be run, to name the differences when an unfinished run of
        another scenario is in the way.
    amend : bool
        Add stages to an existing run (``image``, ``report``, ``validate --into``): nothing
        is cleared, the manifest lists the amendment, ``COMPLETE`` is left as it is. Any
        signed run folder (:func:`read_signature`) may be amended.
    inputs : iterable of path-like
        Files the command reads: the folder may not be or hold any of them.

    Everything the run writes at the top of the folder is listed in the manifest's
    ``entries`` before it is written (:meth:`claim`); a fresh start, ``--force`` and
    :meth:`discard` delete those entries and this tool's temporaries, nothing else. A
    fresh start or ``--force`` in a folder that holds anything else is refused;
    ``resume`` and ``amend`` leave such files alone (and refuse to write over them).

    Raises
    ------
    InputError
        See :meth:`check_target`; also a folder in use by another live process.
    """

    def __init__(self, path, *, command=None, resume: bool = False, force: bool = False,
                 kind: str = "run", amend: bool = False, log=None, scenario=None, inputs=()):
        self.path = Path(path)
        self._log = log
        self.stale_lock_pid = None
        self.resume = bool(resume)
        self.amend = bool(amend)
        self.kind = kind
        self._field = "run directory" if amend else "--out"
        self._locked = False
        self._t0 = time.perf_counter()
        p = self.path
        self._created = not os.path.lexists(p)
        self._fresh = False
        if amend:
            sig = read_signature(p) if p.is_dir() else None
            if sig is None:
                raise InputError("run directory", str(p), "must be a shipthermal run directory "
                                 "(with manifest.json)", "Give the folder `shipthermal run` "
                                 "or `shipthermal demo` wrote")
            self._entries = set(sig.entries)
            self._take_lock()
            try:
                self.clean_stale()
                self.manifest = dict(sig.manifest)
                self._amendment = {"kind": kind, "started": _now(), "command": list(
                    command if command is not None else sys.argv), "status": "running"}
                self.manifest.setdefault("amendments", []).append(self._amendment)
                self.save_manifest()
            except BaseException:
                self.release()
                raise
            return
        self.check_target(p, resume=resume, force=force, scenario=scenario, kind=kind,
                          inputs=inputs)
        p.mkdir(parents=True, exist_ok=True)
        sig = read_signature(p)
        self._entries = set(sig.entries) if sig is not None else {MANIFEST}
        self._take_lock()
        try:
            if MARKER in self._entries and is_complete(p):
                if force:
                    self._clear()
                elif resume:
                    (p / MARKER).unlink()     # reopened: not complete until it is again
                else:
                    raise InputError("--out", str(p), "is a finished run (COMPLETE exists)",
                                     "Pass --force to replace it, or choose another --out")
            elif not resume:
                self._clear()
            self._fresh = not resume or sig is None
            self.clean_stale()
            old = sig.manifest if resume and sig is not None else {}
            self.manifest = {
                **new_manifest(kind, command), "seeds": {}, "settings": {}, "cases": {},
                "timings_s": {}, "attempts": list(old.get("attempts", [])),
            }
            if old:
                # keep what earlier attempts measured for the stages they finished
                self.manifest["timings_s"].update(old.get("timings_s", {}))
                self.manifest["attempts"].append({k: old.get(k) for k in
                                                  ("started", "status", "command")})
            self.save_manifest()
        except BaseException:
            self.release()
            raise

    @staticmethod
    def check_target(path, resume: bool = False, force: bool = False, scenario=None, *,
                     kind: str = "run", inputs=()) -> None:
        """Raise the :class:`InputError` that opening ``path`` would raise, without touching
        anything: call it before slow preparations.

        Refused: ``resume`` with ``force``; a file (also with ``force``); a folder that is
        or holds one of ``inputs``; a non-empty folder that is not a signed run folder
        (:func:`read_signature`; a folder holding only a stale lock of this tool counts as
        empty); a run folder of another ``kind``; without ``resume``, a run folder that
        holds files this tool did not write; a folder locked by a live process or by a
        ``.lock`` that is not this tool's; a finished run without ``force`` / ``resume``; an
        unfinished run with checkpoints without ``force`` / ``resume`` (with ``scenario``,
        the refusal says whether it is of the same scenario and which keys differ)."""
        p = Path(path)
        if resume and force:
            raise InputError("--resume --force", "both given", "contradict each other: "
                             "--resume continues the run in --out, --force discards it and "
                             "starts afresh", "Give one of them")
        if os.path.lexists(p) and not p.is_dir():
            raise InputError("--out", str(p), "must be a folder (a file of that name exists)",
                             "Choose another --out: shipthermal never turns a file into a "
                             "folder, not even with --force")
        check_inputs(p, inputs)
        if not p.is_dir():
            return
        names = sorted(c.name for c in p.iterdir())
        if not names:
            return
        sig = read_signature(p)
        if sig is None:
            if names == [LOCK]:
                state = _lock_state(p / LOCK, signed=False)
                if state == "stale":
                    return              # our own debris: a writer died before its manifest
                if state == "live":
                    raise _in_use("--out", p, _read_lock(p / LOCK)[0])
            why = ("is not a shipthermal run directory: its manifest.json was not written by "
                   "shipthermal" if MANIFEST in names else
                   "is a non-empty folder that is not a shipthermal run directory")
            raise InputError("--out", str(p), f"{why} (it holds {_list(names, 3)})",
                             "Choose a new or empty folder: shipthermal writes into, replaces "
                             "and clears only folders it wrote itself")
        if sig.kind != kind:
            raise InputError("--out", str(p), f"is a shipthermal {sig.kind} folder, not a "
                             f"{kind} folder (the kind in its manifest.json)", "Choose another "
                             f"--out: `shipthermal {kind}` replaces or continues only its "
                             "own folders")
        foreign = _foreign_names(p, sig.entries)
        if foreign and not resume:
            raise _foreign_error(p, foreign)
        state = _lock_state(p / LOCK, signed=True)
        if state == "live":
            raise _in_use("--out", p, _read_lock(p / LOCK)[0])
        if state == "foreign":
            raise _foreign_lock("--out", p)
        complete = MARKER in sig.entries and is_complete(p)
        if complete and not (force or resume):
            raise InputError("--out", str(p), "is a finished run (COMPLETE exists)",
                             "Pass --force to replace it, or choose another --out")
        ckpts = (sorted((p / "checkpoints").glob("*.npz"))
                 if "checkpoints" in sig.entries else [])
        if ckpts and not (force or resume) and not complete:
            stale = stale_lock(p)
            who = f"; its process {stale} is gone (stale .lock)" if stale else ""
            what = (f"holds an unfinished run with checkpoints "
                    f"({', '.join(c.name for c in ckpts)}){who}")
            changed = changes_from_copy(p, scenario)
            if changed:
                raise InputError("--out", str(p), f"{what}, of a different scenario (changed: "
                                 f"{_list(changed)})", "Pass --force to discard it and start "
                                 "afresh, or choose another --out")
            raise InputError("--out", str(p), what, "Continue it with --resume, or pass --force "
                             "to discard it and start afresh")

    # ---- locking and cleaning -------------------------------------------------------------
    def _take_lock(self) -> None:
        lock = self.path / LOCK
        me = f"{os.getpid()} {socket.gethostname()} {TOOL}"
        for _ in range(2):
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                state = _lock_state(lock, signed=True)
                pid, host, _ = _read_lock(lock)
                if state == "live":
                    raise _in_use(self._field, self.path, pid) from None
                if state == "foreign":
                    raise _foreign_lock(self._field, self.path) from None
                lock.unlink(missing_ok=True)   # stale: its writer died
                self.stale_lock_pid = pid if pid > 0 else None
                where = "" if not host or host == socket.gethostname() else f" on {host}"
                self._note(f"{self.path}: took over the stale lock of process "
                           f"{pid if pid > 0 else '?'}{where} (no longer running)")
                continue
            with os.fdopen(fd, "w") as fh:
                fh.write(me)
            self._locked = True
            return
        raise InputError(self._field, str(self.path), "could not be locked", "Try again")

    def _note(self, msg: str) -> None:
        if self._log is not None:
            self._log(msg)

    def release(self) -> None:
        """Remove the lock (idempotent)."""
        if self._locked:
            (self.path / LOCK).unlink(missing_ok=True)
            self._locked = False

    def claim(self, *names) -> None:
        """List top-level ``names`` (``thermal/summer`` → ``thermal``) as written by this
        run, in the manifest, before they are written. A name that exists but is not this
        tool's is refused: nothing of the user's is ever written over."""
        new = []
        for name in names:
            top = Path(name).parts[0]
            if top in self._entries or top in new:
                continue
            if not _safe_entry(top):
                raise ValueError(f"not a top-level name of a run folder: {name!r}")
            if os.path.lexists(self.path / top):
                raise InputError(self._field, str(self.path), f"holds {top}, which shipthermal "
                                 "did not write", "Move it out of the folder, or choose "
                                 "another --out")
            new.append(top)
        if new:
            self._entries.update(new)
            self.save_manifest()

    def _foreign(self) -> list:
        return _foreign_names(self.path, self._entries)

    def _clear(self) -> None:
        """A fresh start: delete what this tool wrote here (the manifest's entries and its
        temporaries; the marker first, so nothing looks complete; the manifest itself is
        rewritten at once). Refused when the folder holds anything else."""
        foreign = self._foreign()
        if foreign:
            raise _foreign_error(self.path, foreign)
        p = self.path
        if MARKER in self._entries:
            _remove(p / MARKER)
        for name in sorted(self._entries - {MANIFEST, MARKER}):
            _remove(p / name)
        for child in list(p.iterdir()):
            if child.name != LOCK and _own_temporary(child.name, self._entries):
                _remove(child)
        self._entries = {MANIFEST}

    def clean_stale(self) -> list:
        """Delete temporaries left by crashed writers (staging folders, ``.x.tmp*`` and
        ``*.part-*`` files): at the top of the folder those of this tool's entries and
        products, and any inside its entries; returns what was removed."""
        removed = []
        for child in sorted(self.path.iterdir()):
            name = child.name
            if name == LOCK:
                continue
            if _own_temporary(name, self._entries):
                with contextlib.suppress(OSError):
                    _remove(child)
                removed.append(str(child))
            elif name in self._entries and child.is_dir() and not child.is_symlink():
                for root, dirs, files in os.walk(child):
                    for d in list(dirs):
                        if _is_temporary(d):
                            shutil.rmtree(Path(root) / d, ignore_errors=True)
                            removed.append(str(Path(root) / d))
                            dirs.remove(d)
                    for f in files:
                        if _is_temporary(f):
                            (Path(root) / f).unlink(missing_ok=True)
                            removed.append(str(Path(root) / f))
        return removed

    # ---- manifest ---------------------------------------------------------------------------
    def read_manifest(self) -> dict:
        try:
            return json.loads((self.path / MANIFEST).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {}

    def save_manifest(self) -> None:
        """Write the manifest, signed: ``tool``, ``kind`` and the ``entries`` first."""
        m = {"tool": TOOL, "kind": self.manifest.get("kind", self.kind),
             "entries": sorted(self._entries | {MANIFEST})}
        m.update((k, v) for k, v in self.manifest.items() if k not in m)
        self.manifest.update(tool=m["tool"], entries=m["entries"])
        atomic_write_text(self.path / MANIFEST, json.dumps(m, indent=2, default=str) + "\n")

    def record(self, stage: str, seconds: float) -> None:
        """Wall time of a finished stage [s] (saved at once)."""
        self.manifest["timings_s"][stage] = round(float(seconds), 3)
        self.save_manifest()

    # ---- scenarios ----------------------------------------------------------------------------
    def scenario_file(self, case: str | None = None) -> Path:
        return self.path / ("scenario.toml" if case is None else f"scenario_{case}.toml")

    def add_scenario(self, scenario, case: str | None = None) -> Path:
        """Copy a scenario into the run (on ``--resume`` it must equal the copy there)."""
        target = self.scenario_file(case)
        self.claim(target.name)
        if target.exists() and self.resume:
            from .scenario import load_scenario

            changed = scenario_changes(load_scenario(target), scenario)
            if changed:
                raise InputError("--resume", str(self.path), f"the scenario differs from the "
                                 f"run's copy {target.name} (changed: {_list(changed)})",
                                 "Start afresh with --force (or resume with the same scenario)")
        else:
            scenario.write(target)
        key = case or scenario.name
        self.manifest["cases"][key] = {"scenario": target.name, "season": scenario.time.season,
                                      "date": str(scenario.time.date)}
        self.manifest["seeds"][key] = {"solver": scenario.solver.seed,
                                       "background": scenario.background.seed}
        self.save_manifest()
        return target

    # ---- stages -------------------------------------------------------------------------------
    def has(self, stage: str) -> bool:
        """Whether a stage finished (its folder was renamed into place)."""
        return Path(stage).parts[0] in self._entries and (self.path / stage).is_dir()

    @contextlib.contextmanager
    def stage(self, name: str):
        """Yield a staging folder for ``name`` (e.g. ``thermal/summer``); renamed to
        ``<run>/<name>`` when the block finishes, deleted when it fails."""
        self.claim(name)
        final = self.path / name
        tmp = self.path / f"{STAGE_PREFIX}{name.replace('/', '__')}.{os.getpid()}"
        if tmp.exists():
            shutil.rmtree(tmp)
        tmp.mkdir(parents=True)
        t0 = time.perf_counter()
        try:
            yield tmp
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        final.parent.mkdir(parents=True, exist_ok=True)
        if final.exists():
            _remove(final)
        os.replace(tmp, final)
        self.record(name, time.perf_counter() - t0)

    def checkpoint(self, case: str) -> Path:
        """Thermal checkpoint file of a case (kept until the run completes)."""
        self.claim("checkpoints")
        d = self.path / "checkpoints"
        d.mkdir(exist_ok=True)
        return d / f"{case}.npz"

    # ---- end ----------------------------------------------------------------------------------
    def mark_finished(self) -> None:
        """Stamp the finishing time now (before the last products, e.g. the report that
        shows it, are written); :meth:`complete` keeps it."""
        self.manifest["finished"] = _now()
        self.save_manifest()

    def complete(self) -> None:
        """Finish: checkpoints removed, manifest closed, then the ``COMPLETE`` marker."""
        try:
            self.claim(MARKER)
            if "checkpoints" in self._entries:
                shutil.rmtree(self.path / "checkpoints", ignore_errors=True)
                if not os.path.lexists(self.path / "checkpoints"):
                    self._entries.discard("checkpoints")
            self.manifest["status"] = "complete"
            self.manifest["finished"] = self.manifest.get("finished") or _now()
            self.manifest["timings_s"]["total"] = round(time.perf_counter() - self._t0, 3)
            self.save_manifest()
            atomic_write_text(self.path / MARKER, f"{self.manifest['finished']}\n")
        finally:
            self.release()

    def discard(self) -> None:
        """Remove what this fresh run wrote: its entries and temporaries, the manifest last
        (then the folder, when this run created it and nothing else is left in it)."""
        p = self.path
        try:
            for name in sorted(self._entries - {MANIFEST}):
                with contextlib.suppress(OSError):
                    _remove(p / name)
            for child in list(p.iterdir()):
                if child.name != LOCK and _own_temporary(child.name, self._entries):
                    with contextlib.suppress(OSError):
                        _remove(child)
            with contextlib.suppress(OSError):
                (p / MANIFEST).unlink(missing_ok=True)
        finally:
            self.release()
        if self._created:
            with contextlib.suppress(OSError):
                p.rmdir()

    def fail(self, status: str, message: str = "") -> None:
        """Record why the run stopped (``failed`` / ``interrupted``); no marker."""
        try:
            self.manifest["status"] = status
            self.manifest["finished"] = _now()
            if message:
                self.manifest["error"] = message
            self.save_manifest()
        finally:
            self.release()

    def __enter__(self) -> "RunDir":
        return self

    def __exit__(self, exc_type, exc, tb):
        if self.amend:
            self._amendment["status"] = ("done" if exc_type is None else "interrupted"
                                         if issubclass(exc_type, KeyboardInterrupt) else
                                         f"failed: {exc_type.__name__}: {exc}")
            self._amendment["finished"] = _now()
            try:
                self.save_manifest()
            finally:
                self.release()
            return False
        if exc_type is None:
            if self._locked:
                self.complete()
        elif self._fresh and (issubclass(exc_type, InputError)
                              or input_error_from_os(exc) is not None):
            self.discard()                 # a user error in a new run: leave nothing behind
        elif issubclass(exc_type, KeyboardInterrupt):
            self.fail("interrupted", "interrupted (resume with --resume)")
        else:
            self.fail("failed", f"{exc_type.__name__}: {exc}")
        return False
