"""Checkpoints of a :class:`~shipthermal.simulation.Simulation`: the solver's state between
steps (:class:`SolverState`) written to and read from one ``.npz`` file, atomically.

A checkpoint holds the temperatures and the step before (BDF2's history), the surface
temperatures and their slopes, the step lengths, what was recorded, the energy log, the
column preconditioner's groups (so a resumed run solves with the very same ones), a
signature of the setup (step, start, scheme, mesh size: a checkpoint of another setup is
refused) and a caller's own arrays (``extra_<name>``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._aggregates import Aggregates
from .errors import InputError
from .results import EnergyLog, atomic_path

__all__ = ["SolverState", "write_checkpoint", "read_checkpoint"]


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


def write_checkpoint(path, st: SolverState, dt_now: float, signature: np.ndarray,
                     groups: Aggregates | None = None, extra: dict | None = None) -> Path:
    """Write ``st`` (the next step's length ``dt_now``, the setup's ``signature``, the column
    preconditioner's ``groups`` and a caller's ``extra`` arrays) to ``path`` atomically."""
    path = Path(path)
    arrays = dict(
        time=st.time, step=st.step, temp=st.temp,
        temp_prev=st.temp_prev if st.temp_prev is not None else np.zeros(0),
        has_prev=st.temp_prev is not None, temp_face=st.temp_face, flow_face=st.flow_face,
        source=st.source,
        face_slope=st.face_slope if st.face_slope is not None else np.zeros(0),
        cell_flow=st.cell_flow, dt_now=dt_now, dt_prev=st.dt_prev,
        origin=np.array(st.origin, dtype=float), rec_times=np.array(st.recorded_times),
        rec_cell=np.array(st.recorded_cell), rec_face=np.array(st.recorded_face),
        rec_flow=np.array(st.recorded_flow),
        **({f"groups_{k}": v for k, v in groups.arrays().items()} if groups is not None else {}),
        signature=np.asarray(signature, dtype=float),
        **{f"energy_{k}": np.array(v) for k, v in st.energy.items()},
        **{f"extra_{k}": np.asarray(v) for k, v in (extra or {}).items()})
    with atomic_path(path) as tmp:      # an error names the checkpoint, not tmp
        np.savez(tmp, **arrays)
    return path


def read_checkpoint(path, signature: np.ndarray, dt: float, start_time: float):
    """``(state, next step length, column groups or None, extra arrays)`` of a checkpoint
    written for the setup ``signature`` (another setup's is refused); ``dt`` and
    ``start_time`` stand in for what older checkpoints did not store."""
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
        st.recorded_times = list(d["rec_times"])
        st.recorded_cell = list(d["rec_cell"])
        st.recorded_face = list(d["rec_face"])
        st.recorded_flow = list(d["rec_flow"])
        st.energy = {k: list(d[f"energy_{k}"]) for k in EnergyLog.FIELDS}
        extra = {k[6:]: d[k].copy() for k in d.files if k.startswith("extra_")}
        if "groups_ptr" in d.files:
            groups = Aggregates.from_arrays({k: d[f"groups_{k}"] for k in Aggregates.FIELDS})
    return st, dt_now, groups, extra
