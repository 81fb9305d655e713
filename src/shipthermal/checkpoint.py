"""Checkpoints of a :class:`~shipthermal.simulation.Simulation`: the solver's state between
steps (:class:`SolverState`) written to and read from one ``.npz`` file, atomically.

A checkpoint holds the temperatures and the step before (BDF2's history), the surface
temperatures and their slopes, the step lengths, the energy log, the column
preconditioner's groups (so a resumed run solves with the very same ones), a signature of
the setup (step, start, scheme, mesh size: a checkpoint of another setup is refused), a
caller's own arrays (``extra_<name>``) and the list of its record files.

What was recorded since the records were last cleared (every cell and face at every output
time: 3.5 MB a record of the frigate at 0.5 m) lives in files of its own beside it, in the
folder ``<checkpoint name>.records/``: each checkpoint writes only the records taken since
the one before (:class:`RecordFiles`). Rewritten whole every time, an hourly checkpoint of
that ship's day wrote 5.9 GB and took 5.6 s of a 30 s run. The files a checkpoint lists are
never replaced (each list of records has its own random token in the names), so a run
killed at any moment leaves a checkpoint whose record files are complete; the files of an
earlier list go once a checkpoint no longer names them.
"""

from __future__ import annotations

import contextlib
import re
import uuid
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._aggregates import Aggregates
from .errors import InputError
from .results import EnergyLog, atomic_path

__all__ = ["SolverState", "RecordFiles", "write_checkpoint", "read_checkpoint",
           "remove_checkpoint"]


@dataclass
class SolverState:
    """Everything a :class:`~shipthermal.simulation.Simulation` carries from one step to the
    next, and what it recorded."""

    time: float
    step: int
    temp: np.ndarray
    temp_prev: np.ndarray | None
    temp_face: np.ndarray
    flow_face: np.ndarray          # boundary flows at ``time`` [W]
    source: np.ndarray             # volumetric heat per cell at ``time`` [W]
    cell_flow: np.ndarray          # net F(T, t) at ``time`` [W]
    face_slope: np.ndarray | None = None   # ∂T_s/∂T_cell of the last balance [-]
    dt_prev: float = 0.0           # length of the last step taken [s] (0: none yet)
    origin: tuple = (0.0, 0)       # (time, step) where the current step length began
    recorded_times: list = field(default_factory=list)
    recorded_cell: list = field(default_factory=list)
    recorded_face: list = field(default_factory=list)
    recorded_flow: list = field(default_factory=list)
    energy: dict = field(default_factory=lambda: {k: [] for k in EnergyLog.FIELDS})


_RECORDS = {"rec_times": "recorded_times", "rec_cell": "recorded_cell",
            "rec_face": "recorded_face", "rec_flow": "recorded_flow"}
"""A checkpoint's arrays of records → the :class:`SolverState` lists they hold."""

_RECORD_FILE = re.compile(r"[0-9a-f]{12}-[0-9]{5}\.npz")
"""The name of a record file (:meth:`RecordFiles.file`)."""


def records_folder(path) -> Path:
    """The folder of a checkpoint's record files."""
    path = Path(path)
    return path.with_name(f"{path.name}.records")


@dataclass(frozen=True)
class RecordFiles:
    """The record files of one list of records (``token``), one per checkpoint that had new
    records: ``counts[k]`` records in file ``k``."""

    token: str
    counts: tuple = ()

    @classmethod
    def new(cls) -> "RecordFiles":
        return cls(uuid.uuid4().hex[:12])

    @property
    def total(self) -> int:
        return int(sum(self.counts))

    def file(self, path, k: int) -> Path:
        return records_folder(path) / f"{self.token}-{k:05d}.npz"

    def files(self, path) -> list:
        return [self.file(path, k) for k in range(len(self.counts))]


def write_checkpoint(path, st: SolverState, dt_now: float, signature: np.ndarray,
                     groups: Aggregates | None = None, extra: dict | None = None,
                     records: RecordFiles | None = None,
                     continued: bool = False) -> RecordFiles:
    """Write ``st`` (the next step's length ``dt_now``, the setup's ``signature``, the column
    preconditioner's ``groups`` and a caller's ``extra`` arrays) to ``path`` atomically.

    ``records``: the record files of the last checkpoint written to ``path`` (None: none),
    ``continued``: whether ``st``'s records continue them (False after the records were
    cleared). Only the records after those go into a new file; a fresh list starts
    otherwise. Returns the record files this checkpoint lists; the files of ``records`` it
    no longer lists are removed once it is in place."""
    path = Path(path)
    n = len(st.recorded_times)
    keep = (records if continued and records is not None and records.total <= n
            else RecordFiles.new())
    written = None
    if n > keep.total:
        lo = keep.total
        written = keep.file(path, len(keep.counts))
        with atomic_path(written) as tmp:
            np.savez(tmp, **{key: np.array(getattr(st, name)[lo:])
                             for key, name in _RECORDS.items()})
        keep = RecordFiles(keep.token, keep.counts + (n - lo,))
    arrays = dict(
        time=st.time, step=st.step, temp=st.temp,
        temp_prev=st.temp_prev if st.temp_prev is not None else np.zeros(0),
        has_prev=st.temp_prev is not None, temp_face=st.temp_face, flow_face=st.flow_face,
        source=st.source,
        face_slope=st.face_slope if st.face_slope is not None else np.zeros(0),
        cell_flow=st.cell_flow, dt_now=dt_now, dt_prev=st.dt_prev,
        origin=np.array(st.origin, dtype=float),
        records_token=np.array(keep.token), records_counts=np.array(keep.counts, np.int64),
        **({f"groups_{k}": v for k, v in groups.arrays().items()} if groups is not None else {}),
        signature=np.asarray(signature, dtype=float),
        **{f"energy_{k}": np.array(v) for k, v in st.energy.items()},
        **{f"extra_{k}": np.asarray(v) for k, v in (extra or {}).items()})
    try:
        with atomic_path(path) as tmp:      # an error names the checkpoint, not tmp
            np.savez(tmp, **arrays)
    except BaseException:
        if written is not None:             # listed by no checkpoint
            written.unlink(missing_ok=True)
        raise
    if records is not None and records.token != keep.token:
        _remove_files(path, records)
    return keep


def _remove_files(path, records: RecordFiles) -> None:
    for f in records.files(path):
        f.unlink(missing_ok=True)
    with contextlib.suppress(OSError):      # not empty: another list's files are still there
        records_folder(path).rmdir()


def _read_records(path, d, st: SolverState) -> RecordFiles | None:
    """The records of the checkpoint ``d`` (open ``np.load`` of ``path``) into ``st``, and
    its record files (None: an older checkpoint that held them itself)."""
    if "records_token" not in d.files:
        for key, name in _RECORDS.items():
            setattr(st, name, list(d[key]))
        return None
    files = RecordFiles(str(d["records_token"]),
                        tuple(int(c) for c in d["records_counts"]))
    for k, f in enumerate(files.files(path)):
        if not f.is_file():
            raise InputError("checkpoint", str(path),
                             f"lists the record file {f.name} in {f.parent}, which is missing",
                             "Start afresh without --resume")
        with np.load(f) as r:
            got = len(r["rec_times"])
            if got != files.counts[k]:
                raise InputError("checkpoint", str(f), f"holds {got} records, not the "
                                 f"{files.counts[k]} its checkpoint lists",
                                 "Start afresh without --resume")
            for key, name in _RECORDS.items():
                getattr(st, name).extend(r[key])
    return files


def remove_checkpoint(path) -> None:
    """Remove a checkpoint and its record files (every file of the record files' name
    pattern in its records folder, then the folder when that leaves it empty)."""
    path = Path(path)
    path.unlink(missing_ok=True)
    folder = records_folder(path)
    if folder.is_dir():
        for f in folder.iterdir():
            if _RECORD_FILE.fullmatch(f.name):
                f.unlink(missing_ok=True)
        with contextlib.suppress(OSError):      # not empty: files this tool did not write
            folder.rmdir()


def read_checkpoint(path, signature: np.ndarray, dt: float, start_time: float):
    """``(state, next step length, column groups or None, extra arrays, record files or
    None)`` of a checkpoint written for the setup ``signature`` (another setup's is
    refused); ``dt`` and ``start_time`` stand in for what older checkpoints did not
    store."""
    groups = None
    with np.load(path) as d:
        if not np.allclose(d["signature"], signature):
            raise InputError("checkpoint", str(path),
                             "was written by a different setup (time step, start, scheme or "
                             "mesh size differ)", "Start afresh without --resume")
        st = SolverState(float(d["time"]), int(d["step"]), d["temp"].copy(),
                         d["temp_prev"].copy() if bool(d["has_prev"]) else None,
                         d["temp_face"].copy(), d["flow_face"].copy(), d["source"].copy(),
                         d["cell_flow"].copy())
        # (older checkpoints: the first step then starts its balances unmoved)
        if "face_slope" in d.files and d["face_slope"].size:
            st.face_slope = d["face_slope"].copy()
        if "dt_now" in d.files:     # (older checkpoints: uniform steps of time_step)
            st.dt_prev = float(d["dt_prev"])
            st.origin = (float(d["origin"][0]), int(d["origin"][1]))
            dt_now = float(d["dt_now"])
        else:
            st.dt_prev = dt if st.temp_prev is not None else 0.0
            st.origin = (start_time, 0)
            dt_now = dt
        records = _read_records(path, d, st)
        st.energy = {k: list(d[f"energy_{k}"]) for k in EnergyLog.FIELDS}
        extra = {k[6:]: d[k].copy() for k in d.files if k.startswith("extra_")}
        if "groups_ptr" in d.files:
            groups = Aggregates.from_arrays({k: d[f"groups_{k}"] for k in Aggregates.FIELDS})
    return st, dt_now, groups, extra, records
