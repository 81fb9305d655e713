"""RunDir: one run directory opened for writing (staged stages, lock, manifest, marker)."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import socket
import sys
import time
from pathlib import Path

from ...atomic import atomic_write_text
from ...errors import InputError, input_error_from_os
from ..scenario import load_scenario
from .inputs import changes_from_copy, check_inputs, scenario_changes
from .locks import _foreign_lock, _in_use, _lock_state, _read_lock, stale_lock
from .manifest import _now, new_manifest
from .ownership import (LOCK, MANIFEST, MARKER, STAGE_PREFIX, TOOL, _foreign_error,
                        _foreign_names, _is_temporary, _list, _own_temporary, _remove,
                        _safe_entry, is_complete, read_signature)


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
