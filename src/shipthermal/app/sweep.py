"""Parameter sweeps on dask.distributed: the Cartesian product of scenario changes.

The sweep file (a base scenario, changes for every case, and the axes whose product makes
the cases) and its checks: :mod:`.sweep_file`. Every case is validated before anything
runs: a bad value is a user error listing all problems.

Each case runs pinned to one thread (numba, BLAS, OpenMP: :data:`CASE_THREADS`), as one
dask task (its thermal stage, then its imaging stage; the worker builds each port
background once and keeps it for its later cases) on a LocalCluster (one single-threaded
worker process per usable core, at most one per case; no dashboard) or on an existing scheduler
(``scheduler=ADDRESS``, see ``docs/CLUSTER.md``). With one usable core the cases run one
by one in this process. Results come back to the client, which writes ``cases/<id>.json``
at once (so a remote cluster needs no shared disk for results; input files named in
scenarios must exist on the workers at the same paths). A worker lost in the middle of a
case is named in the log with the cases dask runs again; the row counts the retries. A
case's id is a hash of its full scenario and stages, so re-running skips the cases that
finished (status ``ok``); failed cases keep their error and traceback and are retried.
The table (``table.csv``, ``table.png``) has one row per case: the axis values,
status, error, spin-up days and convergence, deck / hull / superstructure means at 12:00,
and per band the crossover times, their count and the min / max SCR; and per case its wall
and CPU seconds, retries and worker.
"""

from __future__ import annotations

import json
import os
import socket
import time as _time
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..atomic import atomic_path, atomic_write_text
from ..errors import InputError
from ..figures import OKABE_ITO, band_label
from ..results import save_png
from ..units import HOUR
from . import pipeline
from .pipeline import frame_times, imaging_scenario
from .scenario import loads_scenario
from .sweep_file import SweepCase, SweepSpec, load_sweep, sweep_inputs
from .thermal import run_scenario_thermal, ship_thermal_history

__all__ = ["SweepSpec", "SweepCase", "load_sweep", "run_case", "run_sweep", "SweepResult",
           "plot_table", "default_workers", "CASE_THREADS", "sweep_inputs"]


# ---------------------------------------------------------------------------------------
# One case (runs on a worker)
# ---------------------------------------------------------------------------------------
_BACKGROUNDS: dict = {}
"""Per-process cache of port backgrounds (a worker builds each port once: it costs seconds).
A background depends on [location], [time], [weather] (the run's one environment drives
every pixel's energy balance) and [background]: cases that differ in any of them get their
own."""

#: The scenario sections a port background is built from (:func:`.pipeline.background_inputs`)
BACKGROUND_SECTIONS = ("location", "time", "weather", "background")


def _background_key(sc) -> str:
    d = sc.to_dict()
    return json.dumps([d[k] for k in BACKGROUND_SECTIONS], sort_keys=True, default=str)


def _background(sc):
    key = _background_key(sc)
    if key not in _BACKGROUNDS:
        if len(_BACKGROUNDS) >= 4:
            _BACKGROUNDS.pop(next(iter(_BACKGROUNDS)))
        _BACKGROUNDS[key] = pipeline.build_background(sc)   # through the module: tests replace it
    return _BACKGROUNDS[key]


def _hhmm(seconds: float) -> str:
    m = int(round(seconds / 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}"


CASE_THREADS = 1
"""Threads one case may use (numba ``prange`` kernels, BLAS, OpenMP). One: a case keeps
about one core busy anyway (CPU / wall time 0.83 to 0.95 for the patrol boat at 2 m edges,
measured alone), so threads inside a case gain little, while cases side by side with
several threads each oversubscribe the cores. Serial runs are pinned the same way, so the
two are compared fairly."""

WORKER_TICK = "1s"
"""Interval of a sweep worker's event-loop health tick (dask's default 20 ms; see
:func:`local_cluster`)."""

WORKER_MALLOC = {"MALLOC_TRIM_THRESHOLD_": None, "MALLOC_ARENA_MAX": "1"}
"""glibc's malloc in a sweep worker (set before the worker process starts; see
:func:`local_cluster`): dask's default ``MALLOC_TRIM_THRESHOLD_`` removed, and one arena.
A case runs on a worker's task thread, not its main thread, so by default its arrays come
from a thread arena of its own, not the main arena a plain process's main thread uses; four
patrol-boat cases at 3 m (thermal + imaging) one after the other in a one-worker cluster
took 300 000 - 400 000 page faults and 0.7 - 0.8 s of system time each from the third
on, and 6 000 - 8 000 faults and 0.04 - 0.07 s with one arena, as in a
plain process's main thread (large arrays given back to the system and faulted in again:
glibc trims a thread arena's heaps as they shrink)."""

WORKER_MONITORS = {"distributed.worker.memory.monitor-interval": "1s",
                   "distributed.admin.system-monitor.interval": "2s",
                   "distributed.admin.system-monitor.disk": False}
"""A sweep worker's memory monitor (and its nanny's) every second instead of every 100 ms,
its system monitor every 2 s instead of 0.5 s and without disk counters (dask's defaults;
see :func:`local_cluster`)."""

_PIN_ENV = ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""Environment variables that size the thread pools of a fresh worker process (read once,
when numba / BLAS load)."""


class _pinned:
    """numba, BLAS and OpenMP limited to ``threads`` inside the block (restored after)."""

    def __init__(self, threads: int):
        self.threads = int(threads)

    def __enter__(self):
        # lazy: numba takes over a second to import (measured); a sweep imports it on
        # its first case
        import numba
        from threadpoolctl import threadpool_limits

        self._numba = numba.get_num_threads()
        numba.set_num_threads(max(1, min(self.threads, numba.config.NUMBA_NUM_THREADS)))
        self._pools = threadpool_limits(limits=self.threads)
        return self

    def __exit__(self, *exc):
        import numba                            # lazy: as in __enter__

        self._pools.restore_original_limits()
        numba.set_num_threads(self._numba)
        return False


def _threads_now() -> int:
    """Threads of this process (Linux ``/proc``; 0 where unavailable)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Threads:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def _new_result(spec: dict) -> dict:
    return {"id": spec["id"], "index": spec["index"], "changes": spec["changes"],
            "labels": spec["labels"], "worker": f"{socket.gethostname()}:{os.getpid()}",
            "status": "failed", "error": "", "traceback": "", "values": {},
            "seconds": 0.0, "cpu_s": 0.0, "retries": 0}


def _fail(out: dict, exc: BaseException) -> None:
    out["error"] = f"{type(exc).__name__}: {exc}"
    out["traceback"] = "".join(traceback.format_exception(exc))


def _thermal_part(spec: dict, threads: int = CASE_THREADS):
    """The thermal stage of a case: ``(result, history)``; ``history`` (the imaging
    stage's input) is ``None`` when the case failed or has no imaging stage."""
    t0, c0 = _time.perf_counter(), _time.process_time()
    out = _new_result(spec)
    history = None
    try:
        with _pinned(threads):
            sc = loads_scenario(spec["toml"])
            res = run_scenario_thermal(sc, progress=False)
            v = out["values"]
            v["days"] = int(res.days)
            v["converged"] = bool(res.converged)
            v["surface_faces"] = int(res.ship.n_faces)
            for part in ("deck", "hull", "superstructure"):
                if part in res.part_means.columns:
                    v[f"{part}_12h_K"] = res.part_mean_at(part, 12.0)
            v["energy_relative_imbalance"] = float(res.energy.relative_imbalance)
            v["thermal_s"] = _time.perf_counter() - t0
            if "imaging" in spec["stages"]:
                history = ship_thermal_history(res)
            else:
                out["status"] = "ok"
    except Exception as exc:                       # reported with the case, not lost
        _fail(out, exc)
    out["seconds"] = _time.perf_counter() - t0
    out["cpu_s"] = _time.process_time() - c0
    out["threads"] = _threads_now()
    return out, history


def _imaging_part(part, spec: dict, threads: int = CASE_THREADS) -> dict:
    """Finish a case after :func:`_thermal_part`: the imaging stage on its port background
    (built in this process the first time, then kept: :func:`_background`)."""
    out, history = part
    if history is None:            # thermal only, or the thermal stage failed
        return out
    # deferred: the renderer and the atmosphere add 75 ms to the sweep's import (measured); a
    # thermal-only sweep needs neither
    from imaging.experiment import render_series

    t1, c1 = _time.perf_counter(), _time.process_time()
    try:
        with _pinned(threads):
            sc = loads_scenario(spec["toml"])
            scen = imaging_scenario(sc, _background(sc), history)
            series = render_series(history, scen, sc.bands, frame_times(sc), progress=False)
            v = out["values"]
            curves = out["curves"] = {}
            for band, sr in series.items():
                scr = sr.metrics["scr"].to_numpy(float)
                # the SCR curve itself (in the case file, not the table): ensemble bands
                curves[band] = {"time_h": [float(t) for t in sr.metrics["time_h"]],
                                "scr": [float(x) for x in scr]}
                out.setdefault("crossovers", {})[band] = [[c.time / HOUR, c.direction]
                                                          for c in sr.crossovers]
                v[f"crossovers_{band}"] = "; ".join(f"{_hhmm(c.time)} {c.direction}"
                                                    for c in sr.crossovers)
                v[f"n_crossovers_{band}"] = len(sr.crossovers)
                v[f"first_crossover_h_{band}"] = (sr.crossovers[0].time / HOUR
                                                  if sr.crossovers else float("nan"))
                v[f"scr_min_{band}"] = float(np.nanmin(scr))
                v[f"scr_max_{band}"] = float(np.nanmax(scr))
            v["imaging_s"] = _time.perf_counter() - t1
        out["status"] = "ok"
    except Exception as exc:
        _fail(out, exc)
    out["seconds"] += _time.perf_counter() - t1
    out["cpu_s"] += _time.process_time() - c1
    out["threads"] = max(out.get("threads", 0), _threads_now())
    return out


def run_case(spec: dict, threads: int = CASE_THREADS) -> dict:
    """Run one case; never raises for a failure of the case itself (it is returned as
    ``status = 'failed'`` with the error and traceback).

    ``threads``: the threads the case may use (:data:`CASE_THREADS`). The port background
    is built in this process the first time a case needs it and kept (:func:`_background`).
    """
    return _imaging_part(_thermal_part(spec, threads), spec, threads)


# ---------------------------------------------------------------------------------------
# The sweep
# ---------------------------------------------------------------------------------------
@dataclass(eq=False)
class SweepResult:
    """What :func:`run_sweep` produced."""

    table: pd.DataFrame
    ran: int
    skipped: int
    failed: int
    seconds: float
    files: dict
    workers: int = 0


def _table(spec: SweepSpec, results: dict) -> pd.DataFrame:
    rows = []
    for case in spec.cases:
        r = results.get(case.id)
        row = {"case": case.id, "index": case.index}
        row.update(case.labels)
        if r is None:
            row.update(status="missing", error="not run")
        else:
            row.update(status=r["status"], error=r.get("error", ""))
            row.update(r.get("values", {}))
            row["seconds"] = r.get("seconds")
            row["cpu_s"] = r.get("cpu_s")
            row["retries"] = r.get("retries", 0)
            row["worker"] = r.get("worker")
        rows.append(row)
    df = pd.DataFrame(rows)
    front = ["case", "index"] + spec.axis_names + ["status", "error"]
    return df[front + [c for c in df.columns if c not in front]]


def plot_table(table: pd.DataFrame, axis_names, path) -> Path:
    """PNG: deck mean at 12:00, spin-up days, and per band the SCR range and crossover
    times, one point per case."""
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = [" | ".join(str(r[a]) for a in axis_names) for _, r in table.iterrows()]
    x = np.arange(len(table))
    bands = sorted({c[len("scr_min_"):] for c in table.columns if c.startswith("scr_min_")})
    n = 2 + 2 * len(bands)
    fig, axes = plt.subplots(n, 1, figsize=(max(8, 0.35 * len(x) + 3), 2.2 * n), sharex=True)
    ok = (table["status"] == "ok").to_numpy()

    def col(name):
        return pd.to_numeric(table[name], errors="coerce").to_numpy(float) if name in table \
            else np.full(len(table), np.nan)

    # a temperature is a point, not a bar: its axis need not start at 0 K (bars must)
    axes[0].plot(x[ok], col("deck_12h_K")[ok], "o", color=OKABE_ITO["black"], ms=5)
    lo = np.nanmin(col("deck_12h_K")) if ok.any() else 0
    hi = np.nanmax(col("deck_12h_K")) if ok.any() else 1
    if np.isfinite(lo) and np.isfinite(hi):
        axes[0].set_ylim(lo - 2, hi + 2)
    axes[0].set_ylabel("deck 12:00 [K]")
    axes[1].bar(x[ok], col("days")[ok], color=OKABE_ITO["sky_blue"])
    axes[1].set_ylim(bottom=0)                                   # bars from zero
    axes[1].set_ylabel("spin-up days")
    for i in np.flatnonzero(~ok):
        for a in axes[:2]:
            a.axvline(i, color=OKABE_ITO["vermillion"], ls=":", lw=1)
        axes[0].text(i, axes[0].get_ylim()[0], " failed", color=OKABE_ITO["vermillion"],
                     rotation=90,
                     va="bottom", fontsize=7)
    for k, band in enumerate(bands):
        a = axes[2 + 2 * k]
        smin, smax = (np.clip(col(f"scr_{k}_{band}"), 1e-3, None) for k in ("min", "max"))
        a.vlines(x, smin, smax, color=OKABE_ITO["blue"], lw=3)
        a.set_yscale("log")
        a.axhline(1.0, color=OKABE_ITO["black"], lw=0.8, ls=(0, (1, 2)))
        a.set_ylabel(f"SCR {band_label(band)}\nmin–max (log)")
        b = axes[3 + 2 * k]
        for i, txt in enumerate(table.get(f"crossovers_{band}", pd.Series([""] * len(x)))):
            if isinstance(txt, str) and txt:
                for item in txt.split("; "):
                    hh, mm = item.split()[0].split(":")
                    b.plot(i, int(hh) + int(mm) / 60, "o", color=OKABE_ITO["orange"], ms=4)
        b.set_ylim(0, 24)
        b.set_yticks(range(0, 25, 6))
        b.set_ylabel(f"crossovers {band_label(band)}\n[local h]")
    for a in axes:
        a.grid(alpha=0.3)
    axes[-1].set_xticks(x)
    axes[-1].set_xticklabels(labels, rotation=60, ha="right", fontsize=7)
    axes[-1].set_xlabel(" | ".join(axis_names), fontsize=8)
    fig.suptitle(f"sweep: {len(x)} cases ({int(ok.sum())} ok)", fontsize=10)
    fig.tight_layout()
    return save_png(fig, path, dpi=100)


def _write_case(cases_dir: Path, result: dict) -> None:
    atomic_write_text(cases_dir / f"{result['id']}.json",
                      json.dumps(result, indent=1, default=str) + "\n")


def _read_cases(cases_dir: Path, spec: SweepSpec) -> dict:
    done = {}
    for case in spec.cases:
        f = cases_dir / f"{case.id}.json"
        if f.is_file():
            try:
                done[case.id] = json.loads(f.read_text(encoding="utf-8"))
            except ValueError:
                f.unlink()     # unreadable (never half-written, but be safe): rerun it
    return done


def _allowed_cores() -> list[int] | None:
    """The cores this process may run on (its CPU affinity, not the machine's count), or
    None where the system does not say (not on Linux)."""
    try:
        return sorted(os.sched_getaffinity(0))
    except AttributeError:
        return None


def default_workers(n_cases: int) -> int:
    """LocalCluster workers when none are asked for: the cores this process may run on
    (its CPU affinity, not the machine's count), at most one per case."""
    cores = _allowed_cores()
    return max(1, min(len(cores) if cores is not None else (os.cpu_count() or 1), n_cases))


def local_cluster(n_workers: int, threads: int = CASE_THREADS):
    """A dask LocalCluster for sweep cases: ``n_workers`` processes of one thread each.

    Worker processes start with the thread pools of numba, BLAS and OpenMP sized to
    ``threads``, without the statistical profiler (it feeds a dashboard the sweep does
    not start), with the event loop's health tick every second instead of every 20 ms
    (each tick takes the GIL from the case's thread: a case took 5.2 s of CPU in a worker
    against 4.2 s with the slower tick, and the sweep went from 0.74 to 0.86 of two plain
    processes, ``benchmarks/bench_sweep.py``, 8 patrol-boat cases at 3 m; 0.98 with 16; the
    tick only times the loop for the "unresponsive" warning), with the memory and system
    monitors woken less often (:data:`WORKER_MONITORS`; a case's CPU time in each worker of
    a two-worker cluster, six patrol-boat cases, two paired runs: 3.99 → 3.68 s and 3.75 →
    3.57 s; the memory limit is still enforced, up to a second later), and without the
    ``MALLOC_TRIM_THRESHOLD_`` that dask's nanny sets by default: setting it switches off
    glibc's adaptive mmap threshold, so every large temporary array became a fresh mmap,
    zeroed page by page.
    That doubled the CPU time of a case's imaging stage (9.4 s instead of 4.0 s, 5.5 s of
    it in the kernel, 2.3 million page faults instead of a hundred: measured on the
    patrol boat at 3 m edges). For the same reason each worker keeps a single malloc arena
    (:data:`WORKER_MALLOC`).
    """
    # lazy: dask.distributed takes about a second to import (measured)
    import dask
    from dask.distributed import LocalCluster

    # Pre-spawn variables are set in this process too (dask's nanny docs: "poisoning the
    # process running the Nanny": dask's defaults add OMP_NUM_THREADS=1 and others, which
    # later child processes of this one would inherit); only the malloc setting needs that
    # (glibc reads it when a process starts), so this process gets its own environment
    # back once the workers are up (a nanny restarting a lost worker sets them again).
    # The thread pools are sized through the worker's own environment, set before it
    # imports numba: a NUMBA_NUM_THREADS left in this process would make numba refuse to
    # compile here later.
    before = dict(os.environ)
    try:
        with dask.config.set({"distributed.worker.profile.enabled": False,
                              "distributed.admin.tick.interval": WORKER_TICK,
                              **{f"distributed.nanny.pre-spawn-environ.{k}": v
                                 for k, v in WORKER_MALLOC.items()},
                              **WORKER_MONITORS}):
            return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                dashboard_address=None, silence_logs=40,
                                env={k: str(threads) for k in _PIN_ENV})
    finally:
        for k in set(os.environ) - set(before):
            del os.environ[k]
        os.environ.update({k: v for k, v in before.items() if os.environ.get(k) != v})


def pin_workers(client) -> bool:
    """Each worker of ``client``'s cluster held to a core of its own, when there are as
    many workers as cores this process may run on (its CPU affinity): a worker is then
    not moved between cores when the cluster's own process (scheduler, nannies, client)
    wakes up beside it. Returns whether the workers were pinned. Measured on the patrol
    boat at 3 m (thermal + imaging, 8 cases on two workers, each worker's first case left
    out): 4.29 - 4.70 s a case pinned, 4.26 - 5.14 s not, with 75 - 204 involuntary
    context switches a case against 295 - 478; ``benchmarks/bench_sweep.py``: a case next
    to another took 0.98 - 1.05x its time alone pinned (three runs), 1.30 - 1.31x in two
    of three runs unpinned. A worker the nanny restarts runs unpinned. Fewer workers than
    cores (``--workers``, e.g. on a host other jobs keep busy) are left to the system, which
    moves them off busy cores.
    """
    cores = _allowed_cores()
    workers = sorted(client.scheduler_info().get("workers", {}))
    if cores is None or len(workers) < 2 or len(workers) != len(cores):
        return False
    for core, w in zip(cores, workers):
        client.run(os.sched_setaffinity, 0, {core}, workers=[w])
    return True


class _RetryLog:
    """Follows the scheduler's ``remove-worker`` events: which worker was lost, which
    cases it was running (or held results of) and must run again; counts the retries of
    each case. Events arrive on the client's event loop before the retried case's result."""

    _PREFIXES = ("case-",)

    def __init__(self, cases: dict, say):
        self.cases = cases
        self.say = say
        self.retries: dict = {}
        self.events: list = []

    def __call__(self, event) -> None:
        _, msg = event
        if not isinstance(msg, dict) or msg.get("action") != "remove-worker":
            return
        keys = set(msg.get("processing-tasks", ())) | set(msg.get("lost-computed-tasks", ()))
        ids = sorted({str(k).split("-", 1)[1] for k in keys
                      if str(k).startswith(self._PREFIXES)} & set(self.cases))
        if not ids:
            return
        worker = msg.get("worker", "?")
        how = "left" if msg.get("expected") else "was lost"
        self.events.append({"worker": worker, "cases": ids, "expected": msg.get("expected")})
        for cid in ids:
            self.retries[cid] = self.retries.get(cid, 0) + 1
            c = self.cases[cid]
            where = ", ".join(f"{a}={v}" for a, v in c.labels.items())
            self.say(f"dask: worker {worker} {how} while running case {cid} ({where}): "
                     f"the case runs again on another worker (retry {self.retries[cid]})")


def run_sweep(spec: SweepSpec, out_dir, *, scheduler: str | None = None,
              n_workers: int | None = None, serial: bool = False, retry_failed: bool = True,
              progress: bool = True, log=None, run=None,
              threads: int = CASE_THREADS) -> SweepResult:
    """Run every unfinished case of ``spec`` and write the table.

    Parameters
    ----------
    spec : SweepSpec
    out_dir : path-like
        The sweep folder (``cases/``, ``table.csv``, ``table.png``).
    scheduler : str, optional
        Address of an existing dask scheduler (``tcp://host:8786``); default a LocalCluster.
    n_workers : int, optional
        LocalCluster workers, one thread each (default :func:`default_workers`: the usable
        cores, at most one per case; when that is one, the cases run one by one in this
        process, which a one-worker cluster could only slow down).
    serial : bool
        Run the cases one by one in this process (no dask): the reference of the tests.
    retry_failed : bool
        Re-run cases that failed before (finished ``ok`` cases are always skipped).
    run : RunDir, optional
        Record timings and settings in its manifest.
    threads : int
        Threads each case may use (numba, BLAS, OpenMP); :data:`CASE_THREADS`.

    On dask each case is one task, thermal then imaging stage, the cases in order; each
    worker builds a port background the first time one of its cases needs it. A worker
    lost in the middle of a case is named in the log with the case, which dask runs again
    elsewhere; the case's row counts the retries (``retries``).
    """
    say = log or (lambda m: None)
    out = Path(out_dir)
    if run is not None:
        run.claim("cases", "table.csv", "table.png")
    cases_dir = out / "cases"
    cases_dir.mkdir(parents=True, exist_ok=True)
    t0 = _time.perf_counter()
    results = _read_cases(cases_dir, spec)
    todo = [c for c in spec.cases if c.id not in results
            or (retry_failed and results[c.id]["status"] != "ok")]
    skipped = len(spec.cases) - len(todo)
    if skipped:
        say(f"{skipped} of {len(spec.cases)} cases already finished: skipped")
    if todo and not serial and not scheduler and n_workers is None \
            and default_workers(len(todo)) == 1:
        say("one usable core (or one case): the cases run one by one in this process")
        serial = True
    # lazy: tqdm.auto takes a tenth of a second to import (measured)
    from tqdm.auto import tqdm

    bar = tqdm(total=len(todo), unit="case", desc="sweep", disable=not progress)
    workers = 0
    try:
        if todo and serial:
            workers = 1
            for c in todo:
                r = run_case(c.spec(), threads=threads)
                results[c.id] = r
                _write_case(cases_dir, r)
                bar.update(1)
        elif todo:
            workers = _run_on_dask(todo, results, cases_dir, bar, scheduler=scheduler,
                                   n_workers=n_workers, threads=threads, say=say)
    finally:
        bar.close()
    table, files = _write_table(spec, results, out)
    failed = int((table["status"] != "ok").sum())
    seconds = _time.perf_counter() - t0
    if run is not None:
        run.manifest["settings"].update({"cases": len(spec.cases), "ran": len(todo),
                                         "skipped": skipped, "failed": failed,
                                         "workers": workers, "serial": serial,
                                         "threads_per_case": threads,
                                         "scheduler": scheduler or ("none (serial)" if serial
                                                                    else "LocalCluster")})
        run.record("sweep", seconds)
    return SweepResult(table, len(todo), skipped, failed, seconds, files, workers)


def _run_on_dask(todo: list, results: dict, cases_dir: Path, bar, *, scheduler, n_workers,
                 threads: int, say) -> int:
    """Run the ``todo`` cases on a dask cluster (the scheduler at ``scheduler``, else a
    LocalCluster of ``n_workers``), one task per case; each result is written into
    ``cases_dir`` and ``results`` as it arrives. Returns the number of workers."""
    # lazy: dask.distributed takes about a second to import (measured)
    from dask.distributed import Client, as_completed

    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="15s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError("--scheduler", scheduler, "must be the address of a "
                             f"running dask scheduler ({type(exc).__name__}: {exc})",
                             "e.g. tcp://host:8786 (start one with `dask scheduler`)"
                             ) from None
    else:
        cluster = local_cluster(int(n_workers or default_workers(len(todo))), threads)
        client = Client(cluster)
    try:
        workers = len(client.scheduler_info().get("workers", {}))
        pinned = cluster is not None and pin_workers(client)
        say(f"dask: {workers} workers at {client.scheduler.address}"
            + (", each on a core of its own" if pinned else ""))
        retry_log = _RetryLog({c.id: c for c in todo}, say)
        client.subscribe_topic("all", retry_log)
        # One task per case, submitted in order (dask runs the highest priority
        # first, so cases finish one after the other and the last ones run side by
        # side). A worker builds a port background the first time one of its cases
        # needs it and keeps it for its later cases (``_BACKGROUNDS``): each worker
        # pays one build (~1 s warm) instead of receiving 43 MB from a worker whose
        # compute thread holds the GIL, and a case's history never leaves the worker
        # that computed it.
        futures = {client.submit(run_case, c.spec(), threads,
                                 priority=len(todo) - i, key=f"case-{c.id}",
                                 pure=False): c
                   for i, c in enumerate(todo)}
        for fut in as_completed(futures):
            c = futures[fut]
            try:
                r = fut.result()
            except Exception as exc:   # dask gave up (the case killed its workers)
                r = {"id": c.id, "index": c.index, "changes": c.changes,
                     "labels": c.labels, "status": "failed",
                     "error": f"{type(exc).__name__}: {exc}",
                     "traceback": traceback.format_exc(), "values": {}}
            r["retries"] = retry_log.retries.get(c.id, 0)
            fut.release()
            results[c.id] = r
            _write_case(cases_dir, r)
            bar.update(1)
    finally:
        client.unsubscribe_topic("all")
        client.close()
        if cluster is not None:
            cluster.close()
    return workers


def _write_table(spec: SweepSpec, results: dict, out: Path) -> tuple:
    """``(table, files)``: the sweep's table of every case, written as ``table.csv`` and
    pictured in ``table.png``."""
    table = _table(spec, results)
    files = {}
    with atomic_path(out / "table.csv") as tmp:
        table.to_csv(tmp, index=False, float_format="%.6f")
    files["csv"] = out / "table.csv"
    files["png"] = plot_table(table, spec.axis_names, out / "table.png")
    return table, files
