"""Safe run directories: nothing half-written ever looks complete.

Layout of ``runs/<name>/`` (every stage writes into a hidden staging folder that is
renamed into place only when the stage has finished)::

    runs/<name>/
      manifest.json          versions, git commit, seeds, command line, start/end, timings
      scenario.toml          the scenario of a single-case run (explicit copy), or
      scenario_<case>.toml   one per case (the demo: summer and winter)
      mesh/                  `shipthermal mesh`: ship files, part picture, mesh report
      thermal/<case>/        part_means.csv/.png, surface_HHMM.png, thermal.vtkhdf,
                             thermal_summary.json, energy.csv, history.npz
      imaging/               images_*.nc, typical_*.tif, panels_*.png, scr_*.png,
                             metrics_*.csv, crossovers.csv, band_comparison.csv, summary.json
      validation/            validation table (when run)
      report.html            self-contained report (images embedded)
      checkpoints/<case>.npz thermal checkpoints while a run is unfinished
      COMPLETE               written last; its absence means "not finished"

Rules (what makes it safe):

* a stage's files are written in ``.stage-<stage>.<pid>/`` and the folder is renamed to its
  final name when the stage is done, so a stage folder that exists is complete;
* single files (manifest, report, scenario copies) go through a temporary name and
  ``os.replace``;
* ``COMPLETE`` is written after everything else and removed first when a run is reopened;
* a ``.lock`` file holds the pid of the process working in the folder; a second process
  is refused, a stale lock (dead pid) is taken over;
* reopening a run (fresh or ``--resume``) deletes stale temporaries of crashed writers;
* ``--resume`` keeps finished stages and thermal checkpoints, and refuses a scenario that
  differs from the copy in the folder;
* a user error (:class:`~shipthermal.errors.InputError`) in a fresh run removes what it
  wrote (the folder too when the run created it); a crash or Ctrl-C keeps the unfinished
  folder (manifest status ``failed`` / ``interrupted``, no marker) for ``--resume``.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import os
import platform
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

from ..errors import InputError, input_error_from_os

__all__ = ["RunDir", "MARKER", "package_versions", "git_commit", "atomic_write_text",
           "is_complete", "scenario_changes", "changes_from_copy", "stale_lock"]

MARKER = "COMPLETE"
MANIFEST = "manifest.json"
LOCK = ".lock"
STAGE_PREFIX = ".stage-"

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


def _read_lock(lock: Path) -> tuple:
    """``(pid, host)`` written in a lock file; ``(-1, "")`` when unreadable."""
    try:
        pid_s, _, host = lock.read_text().strip().partition(" ")
        return int(pid_s), host
    except (OSError, ValueError):
        return -1, ""


def stale_lock(path) -> int | None:
    """The pid of a lock in ``path`` whose process on this host is gone (else None)."""
    pid, host = _read_lock(Path(path) / LOCK)
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


def _is_temporary(name: str) -> bool:
    """Names our writers give half-written files and folders."""
    return (name.startswith(STAGE_PREFIX) or (name.startswith(".") and ".tmp" in name)
            or ".part-" in name)


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
        error; with ``resume`` its marker is removed until it completes again).
    kind : str
        What made the run (``demo``, ``run``, ``mesh``, ...), recorded in the manifest.
    log : callable, optional
        Receives notes for the user (e.g. a stale lock that was taken over).
    scenario : Scenario, optional
        The scenario about to be run, to name the differences when an unfinished run of
        another scenario is in the way.
    amend : bool
        Add stages to an existing run (``image``, ``report``, ``validate --into``): nothing
        is cleared, the manifest lists the amendment, ``COMPLETE`` is left as it is.

    Raises
    ------
    InputError
        The folder is a finished run (without ``force``), is in use by another live process,
        or is a non-empty folder that is not a run directory.
    """

    def __init__(self, path, *, command=None, resume: bool = False, force: bool = False,
                 kind: str = "run", amend: bool = False, log=None, scenario=None):
        self.path = Path(path)
        self._log = log
        self.stale_lock_pid = None
        self.resume = bool(resume)
        self.amend = bool(amend)
        self._locked = False
        self._t0 = time.perf_counter()
        p = self.path
        self._created = not p.exists()
        self._fresh = False
        if amend:
            if not (p / MANIFEST).is_file():
                raise InputError("run directory", str(p), "must be a shipthermal run directory "
                                 "(with manifest.json)", "Give the folder `shipthermal run` "
                                 "or `shipthermal demo` wrote")
            self._take_lock()
            try:
                self.clean_stale()
                self.manifest = self.read_manifest()
                self._amendment = {"kind": kind, "started": _now(), "command": list(
                    command if command is not None else sys.argv), "status": "running"}
                self.manifest.setdefault("amendments", []).append(self._amendment)
                self.save_manifest()
            except BaseException:
                self.release()
                raise
            return
        self.check_target(p, resume=resume, force=force, scenario=scenario)
        p.mkdir(parents=True, exist_ok=True)
        self._take_lock()
        try:
            if is_complete(p):
                if force:
                    self._clear()
                elif resume:
                    (p / MARKER).unlink()     # reopened: not complete until it is again
                else:
                    raise InputError("--out", str(p), "is a finished run (COMPLETE exists)",
                                     "Pass --force to replace it, or choose another --out")
            elif not resume:
                self._clear()
            self._fresh = not resume or not (p / MANIFEST).exists()
            self.clean_stale()
            old = self.read_manifest() if resume else {}
            self.manifest = {
                "kind": kind, "status": "running", "started": _now(), "finished": None,
                "command": list(command if command is not None else sys.argv),
                "cwd": os.getcwd(), "host": socket.gethostname(),
                "platform": platform.platform(), "versions": package_versions(),
                "git": git_commit(), "seeds": {}, "settings": {}, "cases": {},
                "timings_s": {}, "attempts": old.get("attempts", []),
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
    def check_target(path, resume: bool = False, force: bool = False, scenario=None) -> None:
        """Raise the :class:`InputError` that opening ``path`` would raise (a file, a
        foreign non-empty folder, a finished run without ``force`` / ``resume``, an
        unfinished run with checkpoints without ``force`` / ``resume``), without touching
        anything: call it before slow preparations. With ``scenario``, the refusal of an
        unfinished run says whether it is of the same scenario (and which keys differ)."""
        p = Path(path)
        if p.exists() and not p.is_dir():
            raise InputError("--out", str(p), "must be a folder (a file of that name exists)",
                             "Choose another run directory")
        if p.is_dir() and any(p.iterdir()) and not (p / MANIFEST).exists() \
                and not (p / LOCK).exists() and not any(_is_temporary(c.name)
                                                       for c in p.iterdir()):
            raise InputError("--out", str(p), "is a non-empty folder that is not a shipthermal "
                             "run directory (no manifest.json)", "Choose a new or empty folder")
        if is_complete(p) and not (force or resume):
            raise InputError("--out", str(p), "is a finished run (COMPLETE exists)",
                             "Pass --force to replace it, or choose another --out")
        ckpts = sorted((p / "checkpoints").glob("*.npz")) if p.is_dir() else []
        if ckpts and not (force or resume) and not is_complete(p):
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
        me = f"{os.getpid()} {socket.gethostname()}"
        for _ in range(2):
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                pid, host = _read_lock(lock)
                if pid > 0 and host == socket.gethostname() and _pid_alive(pid):
                    raise InputError("--out", str(self.path), f"is in use by process {pid} "
                                     "(its .lock file)", "Wait for it to finish, or choose "
                                     "another --out") from None
                lock.unlink(missing_ok=True)   # stale: its writer died
                self.stale_lock_pid = pid if pid > 0 else None
                self._note(f"{self.path}: took over the stale lock of process "
                           f"{pid if pid > 0 else '?'} (no longer running)")
                continue
            with os.fdopen(fd, "w") as fh:
                fh.write(me)
            self._locked = True
            return
        raise InputError("--out", str(self.path), "could not be locked", "Try again")

    def _note(self, msg: str) -> None:
        if self._log is not None:
            self._log(msg)

    def release(self) -> None:
        """Remove the lock (idempotent)."""
        if self._locked:
            (self.path / LOCK).unlink(missing_ok=True)
            self._locked = False

    def _clear(self) -> None:
        """Empty the folder (a fresh start): the marker first, so nothing looks complete."""
        (self.path / MARKER).unlink(missing_ok=True)
        for child in self.path.iterdir():
            if child.name == LOCK:
                continue
            if child.is_dir() and not child.is_symlink():
                shutil.rmtree(child)
            else:
                child.unlink()

    def clean_stale(self) -> list:
        """Delete temporaries left by crashed writers (staging folders, ``.x.tmp*`` and
        ``*.part-*`` files) anywhere in the run; returns what was removed."""
        removed = []
        for root, dirs, files in os.walk(self.path):
            for d in list(dirs):
                if _is_temporary(d):
                    shutil.rmtree(Path(root) / d, ignore_errors=True)
                    removed.append(str(Path(root) / d))
                    dirs.remove(d)
            for f in files:
                if _is_temporary(f) and f != LOCK:
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
        atomic_write_text(self.path / MANIFEST,
                          json.dumps(self.manifest, indent=2, default=str) + "\n")

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
        return (self.path / stage).is_dir()

    @contextlib.contextmanager
    def stage(self, name: str):
        """Yield a staging folder for ``name`` (e.g. ``thermal/summer``); renamed to
        ``<run>/<name>`` when the block finishes, deleted when it fails."""
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
            shutil.rmtree(final)
        os.replace(tmp, final)
        self.record(name, time.perf_counter() - t0)

    def checkpoint(self, case: str) -> Path:
        """Thermal checkpoint file of a case (kept until the run completes)."""
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
        shutil.rmtree(self.path / "checkpoints", ignore_errors=True)
        self.manifest["status"] = "complete"
        self.manifest["finished"] = self.manifest.get("finished") or _now()
        self.manifest["timings_s"]["total"] = round(time.perf_counter() - self._t0, 3)
        self.save_manifest()
        atomic_write_text(self.path / MARKER, f"{self.manifest['finished']}\n")
        self.release()

    def discard(self) -> None:
        """Remove what this fresh run wrote (the folder itself if this run created it)."""
        try:
            if self._created:
                shutil.rmtree(self.path, ignore_errors=True)
            else:
                self._clear()
        finally:
            self.release()

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
