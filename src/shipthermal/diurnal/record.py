"""The weather-record run: spin-up on the record's first day, then the record as it is,
window by window, its outputs streamed to disk.

The steps: :func:`record_days` (the record's span), :func:`work_folder` (where the parts
and checkpoints go), the spin-up (:func:`spin_up_first_day`, or :func:`resumed_spin_up`
from a checkpoint), then per window :func:`window_forcing`, :func:`window_conditions`,
:func:`window_simulation` and :func:`run_window` (its days, the part of the outputs and
the checkpoint at its end), and :func:`assemble_record`.

Split over processes (``DiurnalSettings.jobs``), the record's days are cut into segments
(:func:`segment_bounds`); :func:`run_days` runs one (the first in the calling process, the
others each in a spawned one, :func:`_segment_worker`), a segment after the first spun up
:data:`~shipthermal.parameters.RECORD_SEGMENT_WARM_DAYS` before its first day; the parts
of all are assembled as one record.
"""

from __future__ import annotations

import json
import multiprocessing
import shutil
import signal
import threading
import tempfile
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numba
import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from .. import geometry
from .._threads import numba_threads
from ..checkpoint import remove_checkpoint
from ..errors import require
from ..parameters import RECORD_SEGMENT_WARM_DAYS
from ..record_stream import RecordFile, RecordParts, assemble, in_sample, sample_days
from ..results import EnergyLog, Results
from ..units import DAY
from .periodic import run_forcing, run_periodic
from .result import DiurnalResult, concat_energy, part_groups, part_mean_table
from .settings import DiurnalSettings
from .stepping import dark_intervals, night_steps, run_intervals, settle_intervals

#: Days of a weather record per window (forcing tables, checkpoint, part of the outputs).
RECORD_WINDOW_DAYS = 1


def run_record(ship, environment, settings: DiurnalSettings | None = None, *,
               absorptivity=None, emissivity=None, graph=None, traced=None,
               progress: bool = True, log=None, checkpoint=None, resume: bool = False,
               work_dir=None, window_days: int = RECORD_WINDOW_DAYS,
               end_day: int | None = None, face_dtype=np.float32) -> DiurnalResult:
    """Spin a ship up on the first day of a weather record, then run the record, window by
    window, its outputs streamed to disk.

    Parameters
    ----------
    ship, settings, absorptivity, emissivity, graph, traced, progress, log
        As :func:`~shipthermal.diurnal.run.run_diurnal`.
    environment : shipthermal.environment.Environment
        With a non-periodic weather record starting at local midnight and covering whole
        days (:meth:`Scenario.weather_record` with ``weather.day = 'record'``).
    checkpoint : path, optional
        Checkpoint file (.npz), written at the end of every window (the spin-up's own
        next to it, ``<stem>.spinup.npz``); the outputs' parts go to the folder
        ``<stem>.record`` beside it.
    resume : bool
        Continue from ``checkpoint`` if it exists (the same result as an uninterrupted
        run, bit for bit: the whole solver state is in it).
    work_dir : path, optional
        Folder of the outputs' parts and of the assembled ``record.h5`` (default: beside
        the checkpoint; without one, a temporary folder removed with the result).
    window_days : int
        Days per window (:data:`RECORD_WINDOW_DAYS`): forcing tables, checkpoint, part.
    end_day : int, optional
        Stop after this many recorded days (default: the whole record); a later call with
        ``resume`` goes on from there.
    face_dtype : numpy dtype
        Storage of the streamed face temperatures (float32: 3e-5 K at 300 K).

    Returns
    -------
    DiurnalResult
        ``part_means`` spans the recorded days (indexed by hours since local midnight of
        the first, 0 … 24·N) and ``record`` holds every output (:class:`~shipthermal.
        record_stream.RecordFile`, read lazily); ``results`` holds the final state only;
        ``days`` counts spin-up and recorded days; ``meta['record_days']`` the recorded
        days; the energy log covers spin-up and record.

    Notes
    -----
    Each window gets its own forcing tables (:func:`~shipthermal.forcing.build_ship_forcing`
    with ``window``: the rows of the whole record's tables at the same times, the ray
    tracing and view factors done once) and the simulation goes on under them with its
    whole state (:meth:`Simulation.continue_with
    <shipthermal.simulation.Simulation.continue_with>`): the result does not depend on
    the window length, nor on interruptions.
    """
    settings = settings or DiurnalSettings()
    say = log or (lambda msg: None)
    span, n_days, stop = record_days(environment, window_days, end_day)
    t_total = _time.perf_counter()
    ckpt, work_dir, temporary, parts, spin_ckpt = work_folder(checkpoint, work_dir)
    bounds = segment_bounds(stop, settings.jobs, window_days, end_day)
    if len(bounds) > 1 and multiprocessing.current_process().daemon:
        say("record: one piece (solver.jobs ignored: this process, e.g. a sweep's worker, "
            "may not start processes)")
        bounds = segment_bounds(stop, 1, window_days, end_day)
    common = dict(ship=ship, environment=environment, settings=settings,
                  absorptivity=absorptivity, emissivity=emissivity, span=span, n_days=n_days,
                  parts_folder=parts.folder, face_dtype=face_dtype, resume=resume,
                  window_days=window_days, split=len(bounds) > 1)
    try:
        rec, spun, ends = _run_segments(common, bounds, ckpt, spin_ckpt, say=say, graph=graph,
                                        traced=traced, progress=progress, log=log,
                                        end_day=end_day)
    except BaseException:
        if temporary:
            shutil.rmtree(work_dir, ignore_errors=True)
        raise
    timings = rec.timings
    for end in ends:
        for k, v in end["timings"].items():
            if k.startswith("record_"):
                timings[f"segments_{k}"] = timings.get(f"segments_{k}", 0.0) + v
    rec.stop = stop
    if ends:                       # (one window a day: a part a day)
        rec.n_parts = stop
        # the last day's tables (forcing summary) are the last segment's
        rec.forcing = window_forcing(rec, spun, stop - 1, stop, False)
    record = assemble_record(rec, work_dir, temporary)
    pm = record.part_means()
    energy = record.energy()
    final = _final_results(spun.graph, energy, settings,
                           ends[-1]["final"] if ends else _final_state(rec.sim, ckpt))
    timings["total"] = _time.perf_counter() - t_total
    w = environment.weather
    meta = {"record_days": n_days, "spinup_days": spun.days,
            "record_start": str(w.time[0]), "record_end": str(w.time[-1]),
            "weather_source": w.source, "record_window_days": int(window_days)}
    if len(bounds) > 1:
        meta["record_segments"] = [[int(a), int(b)] for a, b in bounds]
        meta["record_segment_warm_days"] = RECORD_SEGMENT_WARM_DAYS
    if stop < n_days:
        meta["record_days_done"] = stop
    return DiurnalResult(ship=ship, graph=spun.graph, forcing=rec.forcing, results=final,
                         part_means=pm, days=spun.days + stop, day_changes=spun.day_changes,
                         converged=spun.converged,
                         energy=concat_energy([spun.energy, energy]), timings=timings,
                         settings=settings, environment=environment, meta=meta,
                         record=record)


def _run_segments(common: dict, bounds, ckpt, spin_ckpt, **first):
    """The record's segments: the first in this process (``first``: its progress, log and
    prebuilt mesh and tracing), the others each in a process of its own. Returns the first
    segment's state and spin-up and the others' ends (timings, final state)."""
    pool, children = None, []
    share = max(1, numba.get_num_threads() // len(bounds))    # each process's threads
    try:
        if len(bounds) > 1:
            first["say"](f"record: {bounds[-1][1]} day(s) in {len(bounds)} segments "
                         + ", ".join(f"{a + 1}–{b}" for a, b in bounds)
                         + ", one process each")
            pool, children = _start_segments(common, bounds[1:], ckpt, share)
        with numba_threads(share):
            rec, spun = run_days(**common, **first, first_day=0, stop=bounds[0][1], ckpt=ckpt,
                                 spin_ckpt=spin_ckpt)
        if children:
            first["say"](f"record: days 1–{bounds[0][1]} done, waiting for the other "
                         "segments")
        ends = [child.get() for child in children]
    except BaseException:
        if pool is not None:       # (their checkpoints and parts are written whole or not)
            pool.terminate()
            pool.join()
            # (the traceback keeps this frame: let the pool's queues go now, not at exit)
            pool = children = None
        raise
    if pool is not None:
        pool.close()
        pool.join()
    return rec, spun, ends


def segment_bounds(stop: int, jobs: int, window_days: int, end_day) -> list[tuple[int, int]]:
    """The record's days ``0 … stop`` as ``min(jobs, stop)`` contiguous segments
    ``(first, end)`` of near-equal work: the first, without a warm-up, takes
    :data:`RECORD_SEGMENT_WARM_DAYS` more days than the others (when the record is long
    enough)."""
    jobs = max(1, min(int(jobs), int(stop)))
    if jobs > 1:
        require(int(window_days) == 1, "window_days", window_days,
                "must be 1 when a record is split over processes (settings.jobs > 1)")
        require(end_day is None, "end_day", end_day,
                "must be None when a record is split over processes (settings.jobs > 1): "
                "a segment's days are fixed by the record's length")
    extra = RECORD_SEGMENT_WARM_DAYS if stop - RECORD_SEGMENT_WARM_DAYS >= 2 * jobs else 0
    edges = extra + np.round(np.linspace(0, stop - extra, jobs + 1)).astype(int)
    edges[0] = 0
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:])]


def segment_checkpoint(ckpt: Path | None, j: int) -> tuple[Path | None, Path | None]:
    """Checkpoint and spin-up checkpoint of segment ``j`` ≥ 1 of a split record."""
    if ckpt is None:
        return None, None
    seg = ckpt.with_name(f"{ckpt.stem}.segment{j}.npz")
    return seg, seg.with_name(f"{seg.stem}.spinup.npz")


def _start_segments(common: dict, bounds, ckpt, share: int):
    """Segments ``bounds`` (all but the first) each in a process of its own (spawned: the
    solver's threads do not survive a fork) of ``share`` numba threads: the pool
    (terminated on an interrupt) and the segments' pending results."""
    ctx = multiprocessing.get_context("spawn")
    pool = ctx.Pool(len(bounds), initializer=_segment_process, initargs=(share,))
    pending = []
    for j, (first, end) in enumerate(bounds, start=1):
        seg_ckpt, seg_spin = segment_checkpoint(ckpt, j)
        pending.append(pool.apply_async(_segment_worker, (dict(
            common, first_day=first, stop=end, ckpt=seg_ckpt, spin_ckpt=seg_spin),)))
    return pool, pending


def _segment_process(threads: int) -> None:
    """A segment's process: its share of numba's threads; Ctrl-C is the caller's (which
    stops the pool), not a traceback of every process; tqdm's lock a thread lock (its
    default, a process semaphore, would be reported leaked when the pool is stopped)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    numba.set_num_threads(threads)
    tqdm.set_lock(threading.RLock())


def _segment_worker(kwargs: dict) -> dict:
    """One segment of a split record in its own process: its timings and final state."""
    rec, _ = run_days(**kwargs, say=lambda msg: None, graph=None, traced=None,
                      progress=False, log=None, end_day=None)
    return {"timings": rec.timings, "final": _final_state(rec.sim, rec.ckpt)}


def run_days(*, ship, environment, settings, absorptivity, emissivity, span, n_days,
             parts_folder, face_dtype, resume, window_days, split, first_day, stop, ckpt,
             spin_ckpt, say, graph, traced, progress, log, end_day):
    """The record's days ``first_day … stop``: spin-up (on the record's first day, or
    :data:`RECORD_SEGMENT_WARM_DAYS` before ``first_day`` and the days to it run
    unrecorded), then window by window, each window's part of the outputs written as it
    ends (``split``: other processes write the other segments' parts into the same folder).
    Returns the run's state and its spin-up."""
    timings = {"record_forcing": 0.0, "record_solve": 0.0, "record_outputs": 0.0}
    lead = max(0, int(first_day) - RECORD_SEGMENT_WARM_DAYS)
    rec = RecordRun(ship=ship, environment=environment, settings=settings, say=say,
                    span=span, n_days=n_days, stop=stop, ckpt=ckpt, spin_ckpt=spin_ckpt,
                    parts=RecordParts(parts_folder), timings=timings, face_dtype=face_dtype,
                    first_day=int(first_day), lead_day=lead, n_parts=int(first_day),
                    split=bool(split))
    if resume and ckpt is not None and ckpt.exists():
        spun = resumed_spin_up(rec, end_day, graph, absorptivity, emissivity, traced)
    else:
        spun = spin_up_first_day(rec, graph, absorptivity, emissivity, traced, progress, log,
                                 resume)
    rec.groups = part_groups(spun.graph.part_names)
    rec.sampled = sample_days(n_days)

    bar = tqdm(total=stop, initial=spun.done, unit="day", desc="record",
               disable=not progress, leave=False)
    t_loop = _time.perf_counter()
    day = spun.done
    try:
        while day < stop:
            d1 = min(day + int(window_days), stop)
            if day < rec.first_day:      # the warm-up of a segment: a window of its own
                d1 = min(d1, rec.first_day)
            t0 = _time.perf_counter()
            conditions = window_conditions(rec, window_forcing(rec, spun, day, d1, progress))
            timings["record_forcing"] += _time.perf_counter() - t0
            window_simulation(rec, spun, conditions)
            run_window(rec, spun, day, d1, bar, t_loop)
            day = d1
    finally:
        bar.close()
    return rec, spun


def record_days(environment, window_days, end_day):
    """The span of the weather record [s], its whole days and the last day to run."""
    w = environment.weather
    span = (w.time[-1] - environment.start).total_seconds()
    n_days = span / DAY
    require(n_days >= 1.0 - 1e-9 and abs(n_days - round(n_days)) < 1e-9,
            "environment.weather", f"{w.time[0]} … {w.time[-1]}",
            "a record run needs whole days from local midnight to local midnight")
    n_days = int(round(n_days))
    require(int(window_days) >= 1, "window_days", window_days, "must be ≥ 1")
    stop = n_days if end_day is None else int(end_day)
    require(1 <= stop <= n_days, "end_day", end_day, f"must lie in 1 … {n_days}")
    return span, n_days, stop


def work_folder(checkpoint, work_dir):
    """The checkpoint path, the folder of the outputs (beside the checkpoint, or a new
    temporary one), whether it is temporary, its parts and the spin-up's checkpoint."""
    ckpt = None if checkpoint is None else Path(checkpoint)
    temporary = work_dir is None and ckpt is None
    if work_dir is None and ckpt is not None:
        work_dir = ckpt.with_suffix(".record")
    elif temporary:
        work_dir = tempfile.mkdtemp(prefix="shipthermal-record-")
    parts = RecordParts(Path(work_dir) / "parts")
    spin_ckpt = None if ckpt is None else ckpt.with_name(f"{ckpt.stem}.spinup.npz")
    return ckpt, work_dir, temporary, parts, spin_ckpt


@dataclass(eq=False)
class RecordRun:
    """A record run's inputs and its state between windows: the simulation, the face
    exchange, the last window's forcing and the parts of the outputs written."""

    ship: object
    environment: object
    settings: DiurnalSettings
    say: Callable
    span: float
    n_days: int
    stop: int
    ckpt: Path | None
    spin_ckpt: Path | None
    parts: RecordParts
    timings: dict
    face_dtype: object
    first_day: int = 0      # the first recorded day (a segment's; 0 for the whole record)
    lead_day: int = 0       # the day spun up on, the simulation's start
    split: bool = False     # a segment of a record split over processes
    groups: dict = field(default_factory=dict)
    sampled: object = None
    sim: object = None
    exchange: object = None
    forcing: object = None
    n_parts: int = 0

    @property
    def parts_end(self) -> int:
        """The parts from ``first_day`` up to this one are the run's own (a segment's
        end; the whole record's when not split)."""
        return self.stop if self.split else self.n_days


@dataclass(eq=False)
class SpunUp:
    """Where the record starts: the spin-up's outcome, or a resumed run's account of it.

    ``done`` recorded days are done already; ``temp0`` is the spun-up state (None when
    ``resumed``: the checkpoint holds the state); ``traced``, ``absorptivity`` and
    ``emissivity`` are what the windows' forcing is built with."""

    done: int
    graph: object
    traced: object
    absorptivity: object
    emissivity: object
    energy: EnergyLog
    days: int
    converged: bool
    day_changes: list
    temp0: np.ndarray | None
    resumed: bool


def resumed_spin_up(rec: RecordRun, end_day, graph, absorptivity, emissivity,
                    traced) -> SpunUp:
    """The spin-up's account and the record days done from the checkpoint; the parts of
    the outputs after the checkpoint's dropped."""
    with np.load(rec.ckpt) as d:
        done = int(d["extra_record_day"])
        first = int(d["extra_record_first_day"]) if "extra_record_first_day" in d.files else 0
        spin_info = {k[len("extra_spin_"):]: d[k].copy() for k in d.files
                     if k.startswith("extra_spin_")}
    other_cut = first != rec.first_day or (rec.split and done > rec.stop)
    require(not other_cut, "checkpoint", str(rec.ckpt),
            f"holds days {first + 1}–{done} of the record, a segment of another split: this "
            f"run's segment is days {rec.first_day + 1}–{rec.stop}",
            "resume with the solver.jobs of the interrupted run, or start afresh")
    require(done <= rec.stop, "end_day", end_day,
            f"must be ≥ the {done} days the checkpoint has done already")
    spin_energy = EnergyLog(*[spin_info.pop(f"energy_{k}") for k in EnergyLog.FIELDS])
    spun = SpunUp(done=done, graph=graph, traced=traced, absorptivity=absorptivity,
                  emissivity=emissivity, energy=spin_energy, days=int(spin_info["days"]),
                  converged=bool(spin_info["converged"]),
                  day_changes=[float(x) for x in spin_info["day_changes"]], temp0=None,
                  resumed=True)
    rec.timings.update(json.loads(str(spin_info["timings"])))
    if spun.graph is None:
        spun.graph, _ = geometry.build_ship_mesh(rec.ship)
    rec.say(f"record: resumed from {rec.ckpt} after {done} of {rec.n_days} recorded day(s)")
    with np.load(rec.ckpt) as d:
        rec.n_parts = int(d["extra_record_parts"])
    rec.parts.drop_range(rec.n_parts, rec.parts_end)
    return spun


def spin_up_first_day(rec: RecordRun, graph, absorptivity, emissivity, traced, progress,
                      log, resume) -> SpunUp:
    """Spin up on the record's first day (a segment's: its lead day), repeated
    (:func:`~shipthermal.diurnal.periodic.run_periodic`); no part of the outputs kept."""
    spin_env = rec.environment.record_day(rec.lead_day)
    rec.say(f"record: spin-up on day {rec.lead_day + 1} ({spin_env.start:%Y-%m-%d}), then "
            f"days {rec.lead_day + 1}–{rec.stop} of {rec.n_days}")
    spin = run_periodic(rec.ship, spin_env, rec.settings,
                        absorptivity=absorptivity, emissivity=emissivity, graph=graph,
                        traced=traced, progress=progress, log=log, checkpoint=rec.spin_ckpt,
                        resume=resume)
    rec.timings.update(spin.timings)
    rec.timings["spinup_total"] = rec.timings.pop("total")
    rec.parts.drop_range(rec.first_day, rec.parts_end)
    return SpunUp(done=rec.lead_day, graph=spin.graph, traced=spin.forcing.traced,
                  absorptivity=spin.forcing.absorptivity, emissivity=spin.forcing.emissivity,
                  energy=spin.energy, days=spin.days, converged=spin.converged,
                  day_changes=list(spin.day_changes), temp0=spin.results.final_temperature,
                  resumed=False)


def window_forcing(rec: RecordRun, spun: SpunUp, d0: int, d1: int, progress: bool):
    """The forcing tables of the days ``d0`` … ``d1`` of the record: the window's rows of
    the record's table grid, from the settle intervals before its start (the night steps
    look back that far) to its end. The tracer's lit-fraction cache is emptied after."""
    iv = rec.settings.output_interval
    grid = np.arange(0.0, rec.span + 1.0, min(600.0, iv))
    margin = settle_intervals(rec.settings) * iv
    i0 = max(int(np.searchsorted(grid, d0 * DAY - margin, side="right")) - 1, 0)
    i1 = int(np.searchsorted(grid, d1 * DAY - 1e-6))
    f = run_forcing(rec.ship, rec.environment, spun.graph, rec.settings, spun.absorptivity,
                    spun.emissivity, times=grid[i0:i1 + 1],
                    window=(float(grid[i0]), d1 * DAY),
                    progress=progress and spun.traced is None, traced=spun.traced)
    f.traced.clear_lit_cache()
    spun.traced = f.traced
    return f


def window_conditions(rec: RecordRun, forcing) -> dict:
    """A window's boundary conditions (the face-to-face exchange is the first window's:
    it does not depend on the weather)."""
    # deferred: the solver (model, simulation, linear: 35 ms, measured) stays out of every
    # command's start-up, which loads diurnal through app.thermal
    from ..model import RadiativeExchange

    rec.forcing = forcing
    if rec.exchange is None:
        rec.exchange = RadiativeExchange(*forcing.radiative_exchange())
    return forcing.conditions(with_exchange=True)


def window_simulation(rec: RecordRun, spun: SpunUp, conditions: dict) -> None:
    """The simulation under a window's conditions: started on the first window (from the
    spun-up state, or from the checkpoint when resuming), carried on with its whole
    state after."""
    # deferred: the solver (model, simulation, linear: 35 ms, measured) stays out of every
    # command's start-up, which loads diurnal through app.thermal
    from ..model import ThermalModel
    from ..simulation import Simulation

    if rec.sim is None:
        # (resuming: the checkpoint replaces the initial state)
        model = ThermalModel(spun.graph, conditions, exchange=rec.exchange,
                             initial_temperature=300.0 if spun.temp0 is None else spun.temp0)
        rec.sim = Simulation(model, rec.settings.time_step, rec.span,
                             start_time=rec.lead_day * DAY, scheme=rec.settings.scheme,
                             output_interval=rec.settings.output_interval,
                             tolerance=rec.settings.newton_tolerance,
                             energy_tolerance=rec.settings.energy_tolerance,
                             surface_tolerance=rec.settings.surface_tolerance)
        if spun.resumed:
            rec.sim.load_checkpoint(rec.ckpt)
    else:
        rec.sim.continue_with(ThermalModel(spun.graph, conditions, exchange=rec.exchange,
                                           initial_temperature=rec.sim.temperature))


def run_window(rec: RecordRun, spun: SpunUp, day: int, d1: int, bar, t_loop: float) -> None:
    """Simulate the days ``day`` … ``d1`` of the record under the window's forcing; at the
    window's end write its part of the outputs and the checkpoint."""
    sim, settings, timings = rec.sim, rec.settings, rec.timings
    iv = settings.output_interval
    per_day = int(round(DAY / iv))
    plan = night_steps(settings, dark_intervals(settings, rec.forcing, (d1 - day) * DAY,
                                                start=day * DAY), sim.time_step)
    for d in range(day, d1):
        t0 = _time.perf_counter()
        k = (d - day) * per_day
        run_intervals(sim, plan[k:k + per_day], d * DAY, iv, f"record day {d + 1}", False)
        timings["record_solve"] += _time.perf_counter() - t0
        if d + 1 == d1 and d1 <= rec.first_day:
            sim.clear_records()      # a segment's warm-up: not recorded
        elif d + 1 == d1:
            t0 = _time.perf_counter()
            _write_part(rec.parts, rec.n_parts, sim, rec.environment, rec.groups,
                        rec.ship.n_faces, rec.sampled, rec.face_dtype)
            rec.n_parts += 1
            sim.clear_records()
            if rec.ckpt is not None:
                _save_checkpoint(rec, spun, d1)
            timings["record_outputs"] += _time.perf_counter() - t0
        bar.update(1)
        elapsed = _time.perf_counter() - t_loop
        date = (rec.environment.start + pd.Timedelta(days=d)).strftime("%Y-%m-%d")
        left = elapsed / (d + 1 - spun.done) * (rec.stop - d - 1)
        rec.say(f"record day {d + 1} of {rec.n_days} ({date}) simulated: "
                f"{elapsed:.0f} s for {d + 1 - spun.done} day(s), about {left:.0f} s left")


def _save_checkpoint(rec: RecordRun, spun: SpunUp, d1: int) -> None:
    """The checkpoint at the end of the window ending on day ``d1``, with the spin-up's
    account; the spin-up's own checkpoint is then removed."""
    extra = {"record_day": d1, "record_parts": rec.n_parts, "record_first_day": rec.first_day,
             "spin_days": spun.days, "spin_converged": spun.converged,
             "spin_day_changes": np.array(spun.day_changes, float),
             "spin_timings": json.dumps(
                 {k: v for k, v in rec.timings.items()
                  if not k.startswith("record_")}, default=float)}
    extra.update({f"spin_energy_{k}": getattr(spun.energy, k) for k in EnergyLog.FIELDS})
    rec.sim.save_checkpoint(rec.ckpt, extra=extra)
    if rec.spin_ckpt is not None:
        remove_checkpoint(rec.spin_ckpt)


def assemble_record(rec: RecordRun, work_dir, temporary: bool) -> RecordFile:
    """The parts of the outputs as one ``record.h5`` in ``work_dir``, opened lazily (a
    temporary folder removed when the file is no longer used)."""
    t0 = _time.perf_counter()
    ship, iv = rec.ship, rec.settings.output_interval
    part_columns = list(rec.parts.read(0)["part_columns"])
    path = assemble(rec.parts, rec.n_parts, Path(work_dir) / "record.h5", ship=ship,
                    part_columns=part_columns, start=str(rec.environment.start),
                    record_days=rec.n_days, days_done=rec.stop, output_interval=iv,
                    label=f"weather-record thermal run ({ship.name})",
                    face_dtype=rec.face_dtype)
    record = RecordFile(path)
    if temporary:
        record.remove_when_unused(work_dir)
    rec.timings["record_outputs"] += _time.perf_counter() - t0
    return record


def _write_part(parts, index, sim, environment, groups, n_faces, sampled, face_dtype):
    """The window's recorded outputs (and energy log) as part ``index`` of the record."""
    res = sim.results()
    pm = part_mean_table(res, groups, environment)
    keep = in_sample(res.times, sampled, DAY)
    arrays = {"times": res.times,
              "face_temperature": res.face_temperature[:, :n_faces].astype(face_dtype),
              "part_means": pm.to_numpy(), "part_columns": np.array(pm.columns, dtype=str),
              "sample_times": res.times[keep],
              "sample_cell_temperature": res.cell_temperature[keep].astype(np.float32),
              "sample_face_temperature": res.face_temperature[keep].astype(np.float32),
              "sample_face_flow": res.face_flow[keep].astype(np.float32)}
    arrays.update({f"energy_{k}": getattr(res.energy, k) for k in EnergyLog.FIELDS})
    parts.write(index, **arrays)


def _final_state(sim, ckpt) -> tuple:
    """``(time, cell temperatures, face temperatures, face flows)`` at a run's end: the
    simulation's or, when a resumed run had nothing left to do, its checkpoint's."""
    if sim is not None:
        return sim.time, sim.temperature, sim.face_temperature, sim.face_flow
    with np.load(ckpt) as d:
        return (float(d["time"]), d["temp"].copy(), d["temp_face"].copy(),
                d["flow_face"].copy())


def _final_results(graph, energy, settings, final) -> Results:
    """The record's final state ``final`` (:func:`_final_state`) as :class:`Results` (one
    time)."""
    time_, temp, face, flow = final
    return Results(graph=graph, times=np.array([time_]), cell_temperature=temp[None, :],
                   face_temperature=face[None, :], face_flow=flow[None, :], energy=energy,
                   scheme=settings.scheme, time_step=settings.time_step)
