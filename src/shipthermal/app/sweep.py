"""Parameter sweeps on dask.distributed: the Cartesian product of scenario changes.

A sweep file (TOML)::

    name = "heading-wind"                 # optional; names the sweep folder
    base = "my_scenario.toml"             # a scenario file (relative to the sweep file),
                                          # or "summer" / "winter" (the built-in defaults)
    stages = ["thermal", "imaging"]       # or ["thermal"] (default: both)

    [set]                                 # changes applied to every case (dotted keys)
    "ship.edge_length" = 3.0

    [axes]                                # one list of values per dotted scenario key
    "time.season" = ["summer", "winter"]
    "ship.heading" = [0, 90, 180, 270]
    "weather.wind_speed_offset" = [-1.0, 0.0, 1.0]
    "imaging.bands" = [["3-5"], ["8-14"]]

    [[axes.site]]                         # a grouped axis: keys that change together
    "weather.source" = "a.csv"
    "weather.temp_sea" = 290.0
    [[axes.site]]
    "weather.source" = "builtin"

Keys may also be written as nested tables (``ship.heading = [...]`` without quotes). The
changes are applied to the *raw* base scenario before validation, so season-dependent
defaults follow (``time.season = "winter"`` on the built-in base also moves the date, the
map and image times and the compartment temperatures to the winter defaults). Every case
is validated before anything runs: a bad value is a user error listing all problems.

Each case is one task (``run_case``) on a LocalCluster (``n_workers`` = cores,
``threads_per_worker=1``, no dashboard) or on an existing scheduler (``scheduler=ADDRESS``).
Results come back to the client, which writes ``cases/<id>.json`` at once (so a remote
cluster needs no shared disk for results; input files named in scenarios must exist on the
workers). A case's id is a hash of its full scenario and stages, so re-running skips the
cases that finished (status ``ok``); failed cases keep their error and traceback and are
retried. The table (``table.csv``, ``table.png``) has one row per case: the axis values,
status, error, spin-up days and convergence, deck / hull / superstructure means at 12:00,
and per band the crossover times, their count and the min / max SCR.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import socket
import time as _time
import tomllib
import traceback
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError
from ..units import HOUR

__all__ = ["SweepSpec", "SweepCase", "load_sweep", "run_case", "run_sweep", "SweepResult",
           "plot_table"]

STAGES = ("thermal", "imaging")
_TOP_KEYS = ("name", "description", "base", "stages", "set", "axes")


@dataclass(frozen=True)
class SweepCase:
    """One case: its id, position in the product, changes and scenario (TOML text)."""

    id: str
    index: int
    changes: dict
    labels: dict
    toml: str
    stages: tuple

    def spec(self) -> dict:
        """What a worker needs (plain data: pickles and serialises everywhere)."""
        return {"id": self.id, "index": self.index, "changes": self.changes,
                "labels": self.labels, "toml": self.toml, "stages": list(self.stages)}


@dataclass(frozen=True)
class SweepSpec:
    """A loaded and validated sweep file."""

    name: str
    source: str
    text: str
    base: str
    stages: tuple
    fixed: dict
    axes: dict
    cases: tuple = field(repr=False)

    @property
    def axis_names(self) -> list:
        return list(self.axes)


def _flatten(node, prefix: str, out: dict, leaf_lists: bool) -> None:
    """Nested tables → dotted keys. With ``leaf_lists`` (axes), a list ends a key."""
    for k, v in node.items():
        key = f"{prefix}.{k}" if prefix else str(k)
        if isinstance(v, dict):
            _flatten(v, key, out, leaf_lists)
        else:
            out[key] = v


def _set_dotted(raw: dict, key: str, value, where: str) -> None:
    node = raw
    parts = key.split(".")
    for p in parts[:-1]:
        nxt = node.setdefault(p, {})
        if not isinstance(nxt, dict):
            raise InputError(where, key, f"cannot set below {p!r}: it is a value, not a table")
        node = nxt
    node[parts[-1]] = value


def _show(v) -> str:
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, (list, tuple)):
        return "+".join(_show(x) for x in v)
    return str(v)


def _digest(text: str) -> str:
    return hashlib.sha1(text.encode("utf-8")).hexdigest()[:12]


def load_sweep(path) -> SweepSpec:
    """Read and validate a sweep file (every case's scenario is validated here).

    Raises
    ------
    InputError
        A malformed file, an unknown top-level key, an empty axis, a base that cannot be
        read; or a :class:`~shipthermal.app.scenario.ScenarioError` naming the case and every
        problem of its scenario.
    """
    from .scenario import SEASONS, ScenarioError, load_scenario

    path = Path(path)
    if not path.is_file():
        raise InputError("sweep", str(path), "must be an existing TOML file", "Check the path")
    text = path.read_text(encoding="utf-8")
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("sweep", str(path), f"must be valid TOML ({exc})") from None
    for k in raw:
        if k not in _TOP_KEYS:
            raise InputError(f"sweep.{k}", raw[k], f"unknown key; allowed: {', '.join(_TOP_KEYS)}")
    name = raw.get("name", path.stem)
    if (not isinstance(name, str) or not name or any(c in name for c in "/\\")
            or name.startswith(".")):
        raise InputError("sweep.name", name, "must be a non-empty name without slashes")
    stages = raw.get("stages", list(STAGES))
    if (not isinstance(stages, list) or not stages or any(s not in STAGES for s in stages)
            or "thermal" not in stages):
        raise InputError("sweep.stages", stages, "must be ['thermal'] or ['thermal', 'imaging']")
    base = raw.get("base", "summer")
    if not isinstance(base, str) or not base:
        raise InputError("sweep.base", base, "must be 'summer', 'winter' or a scenario file path")
    base_dir = path.parent.resolve()
    if base in SEASONS:
        base_raw = {"time": {"season": base}}
    else:
        bp = Path(os.path.expanduser(base))
        bp = bp if bp.is_absolute() else base_dir / bp
        if not bp.is_file():
            raise InputError("sweep.base", base, "must be 'summer', 'winter' or an existing "
                             "scenario file", f"Not found: {bp} (relative to the sweep file)")
        try:
            base_raw = tomllib.loads(bp.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError("sweep.base", base, f"must be valid TOML ({exc})") from None
        base_dir = bp.parent.resolve()
    fixed: dict = {}
    if "set" in raw:
        if not isinstance(raw["set"], dict):
            raise InputError("sweep.set", raw["set"], "must be a table of dotted scenario keys")
        _flatten(raw["set"], "", fixed, False)
    axes_raw = raw.get("axes")
    if not isinstance(axes_raw, dict) or not axes_raw:
        raise InputError("sweep.axes", axes_raw, "must be a non-empty table: one list of "
                         "values per dotted scenario key", 'e.g. "ship.heading" = [0, 90]')
    axes: dict = {}
    flat: dict = {}
    _flatten(axes_raw, "", flat, True)
    for key, values in flat.items():
        if not isinstance(values, list) or not values:
            raise InputError(f"sweep.axes.{key}", values, "must be a non-empty list of values")
        if all(isinstance(v, dict) for v in values):
            groups = []
            for v in values:
                g: dict = {}
                _flatten(v, "", g, False)
                if not g:
                    raise InputError(f"sweep.axes.{key}", v, "each entry must change at least "
                                     "one key")
                groups.append(g)
            axes[key] = groups
        elif any(isinstance(v, dict) for v in values):
            raise InputError(f"sweep.axes.{key}", values, "must hold plain values or only "
                             "tables (a grouped axis), not both")
        else:
            axes[key] = [{key: v} for v in values]
    n = math.prod(len(v) for v in axes.values())
    if n > 10000:
        raise InputError("sweep.axes", f"{n} cases", "must give at most 10000 cases")
    cases, problems = [], []
    for index, combo in enumerate(itertools.product(*axes.values())):
        case_raw = json.loads(json.dumps(base_raw))
        changes: dict = {}
        for k, v in fixed.items():
            _set_dotted(case_raw, k, v, "sweep.set")
        labels = {}
        for axis, group in zip(axes, combo):
            for k, v in group.items():
                _set_dotted(case_raw, k, v, f"sweep.axes.{axis}")
                changes[k] = v
            only = next(iter(group.values()))
            if len(group) == 1:     # the value itself (numbers stay numbers in the table)
                labels[axis] = only if isinstance(only, (int, float, str, bool)) else _show(only)
            else:
                labels[axis] = ", ".join(f"{k}={_show(v)}" for k, v in group.items())
        try:
            sc = load_scenario(case_raw, base_dir=base_dir)
        except ScenarioError as exc:
            where = ", ".join(f"{a}={labels[a]}" for a in labels)
            problems.extend(InputError(f"case {index} ({where}): {e.field}", e.value, e.allowed,
                                       e.fix) for e in exc.errors)
            continue
        if "imaging" in stages:
            from .pipeline import check_imaging_bands

            try:
                check_imaging_bands(sc)
            except InputError as e:
                where = ", ".join(f"{a}={labels[a]}" for a in labels)
                problems.append(InputError(f"case {index} ({where}): {e.field}", e.value,
                                           e.allowed, e.fix))
                continue
        toml = sc.to_toml().split("\n", 1)[1]   # without the 'written by' comment
        cid = f"{index:04d}-{_digest(toml + '|'.join(stages))}"
        cases.append(SweepCase(cid, index, changes, labels, toml, tuple(stages)))
    if problems:
        raise ScenarioError(problems, f"sweep {path}")
    return SweepSpec(name, str(path), text, base, tuple(stages), fixed, axes, tuple(cases))


# ---------------------------------------------------------------------------------------
# One case (runs on a worker)
# ---------------------------------------------------------------------------------------
_BACKGROUNDS: dict = {}
"""Per-process cache of port backgrounds (a worker builds each port once; it depends only
on the season, date, location and [background], and costs seconds)."""


def _background_key(sc) -> str:
    d = sc.to_dict()
    return json.dumps([d["time"]["season"], d["time"]["date"], d["location"], d["background"]],
                      sort_keys=True, default=str)


def _background(sc):
    from .pipeline import build_background

    key = _background_key(sc)
    if key not in _BACKGROUNDS:
        if len(_BACKGROUNDS) >= 4:
            _BACKGROUNDS.pop(next(iter(_BACKGROUNDS)))
        _BACKGROUNDS[key] = build_background(sc)
    return _BACKGROUNDS[key]


def _hhmm(seconds: float) -> str:
    m = int(round(seconds / 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}"


def run_case(spec: dict, backgrounds: dict | None = None) -> dict:
    """Run one case; never raises for a failure of the case itself (it is returned as
    ``status = 'failed'`` with the error and traceback).

    ``backgrounds``: port backgrounds built once by the client and broadcast to the workers
    (key → background), so that each worker does not rebuild the same port.
    """
    from .scenario import loads_scenario
    from .thermal import run_scenario_thermal

    for key, bg in (backgrounds or {}).items():
        _BACKGROUNDS.setdefault(key, bg)

    t0 = _time.perf_counter()
    out = {"id": spec["id"], "index": spec["index"], "changes": spec["changes"],
           "labels": spec["labels"], "worker": f"{socket.gethostname()}:{os.getpid()}",
           "status": "failed", "error": "", "traceback": "", "values": {}}
    try:
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
            from imaging.experiment import render_series

            from .pipeline import frame_times, imaging_scenario
            from .thermal import ship_thermal_history

            t1 = _time.perf_counter()
            hist = ship_thermal_history(res)
            scen = imaging_scenario(sc, _background(sc), hist)
            series = render_series(hist, scen, sc.bands, frame_times(sc),
                                   progress=False)
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
    except Exception as exc:                       # reported with the case, not lost
        out["error"] = f"{type(exc).__name__}: {exc}"
        out["traceback"] = traceback.format_exc()
    out["seconds"] = _time.perf_counter() - t0
    return out


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
            row["worker"] = r.get("worker")
        rows.append(row)
    df = pd.DataFrame(rows)
    front = ["case", "index"] + spec.axis_names + ["status", "error"]
    return df[front + [c for c in df.columns if c not in front]]


def plot_table(table: pd.DataFrame, axis_names, path) -> Path:
    """PNG: deck mean at 12:00, spin-up days, and per band the SCR range and crossover
    times, one point per case."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..results import atomic_path

    labels = [" | ".join(str(r[a]) for a in axis_names) for _, r in table.iterrows()]
    x = np.arange(len(table))
    bands = sorted({c[len("scr_min_"):] for c in table.columns if c.startswith("scr_min_")})
    n = 2 + 2 * len(bands)
    fig, axes = plt.subplots(n, 1, figsize=(max(8, 0.35 * len(x) + 3), 2.2 * n), sharex=True)
    ok = (table["status"] == "ok").to_numpy()

    def col(name):
        return pd.to_numeric(table[name], errors="coerce").to_numpy(float) if name in table \
            else np.full(len(table), np.nan)

    axes[0].bar(x[ok], col("deck_12h_K")[ok], color="#3c4247")
    lo = np.nanmin(col("deck_12h_K")) if ok.any() else 0
    hi = np.nanmax(col("deck_12h_K")) if ok.any() else 1
    if np.isfinite(lo) and np.isfinite(hi):
        axes[0].set_ylim(lo - 2, hi + 2)
    axes[0].set_ylabel("deck 12:00 [K]")
    axes[1].bar(x[ok], col("days")[ok], color="#7a8590")
    axes[1].set_ylabel("spin-up days")
    for i in np.flatnonzero(~ok):
        for a in axes[:2]:
            a.axvline(i, color="#c0392b", ls=":", lw=1)
        axes[0].text(i, axes[0].get_ylim()[0], " failed", color="#c0392b", rotation=90,
                     va="bottom", fontsize=7)
    for k, band in enumerate(bands):
        a = axes[2 + 2 * k]
        smin, smax = col(f"scr_min_{band}"), col(f"scr_max_{band}")
        a.vlines(x, smin, smax, color="#2b7bba", lw=3)
        a.set_ylabel(f"SCR {band} um\nmin-max")
        b = axes[3 + 2 * k]
        for i, txt in enumerate(table.get(f"crossovers_{band}", pd.Series([""] * len(x)))):
            if isinstance(txt, str) and txt:
                for item in txt.split("; "):
                    hh, mm = item.split()[0].split(":")
                    b.plot(i, int(hh) + int(mm) / 60, "o", color="#d9a441", ms=4)
        b.set_ylim(0, 24)
        b.set_yticks(range(0, 25, 6))
        b.set_ylabel(f"crossovers {band} um\n[local h]")
    for a in axes:
        a.grid(alpha=0.3)
    axes[-1].set_xticks(x)
    axes[-1].set_xticklabels(labels, rotation=60, ha="right", fontsize=7)
    axes[-1].set_xlabel(" | ".join(axis_names), fontsize=8)
    fig.suptitle(f"sweep: {len(x)} cases ({int(ok.sum())} ok)", fontsize=10)
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=100)
    plt.close(fig)
    return path


def _write_case(cases_dir: Path, result: dict) -> None:
    from .rundir import atomic_write_text

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


def run_sweep(spec: SweepSpec, out_dir, *, scheduler: str | None = None,
              n_workers: int | None = None, serial: bool = False, retry_failed: bool = True,
              progress: bool = True, log=None, run=None) -> SweepResult:
    """Run every unfinished case of ``spec`` and write the table.

    Parameters
    ----------
    spec : SweepSpec
    out_dir : path-like
        The sweep folder (``cases/``, ``table.csv``, ``table.png``).
    scheduler : str, optional
        Address of an existing dask scheduler (``tcp://host:8786``); default a LocalCluster.
    n_workers : int, optional
        LocalCluster workers (default: the machine's cores), one thread each.
    serial : bool
        Run the cases one by one in this process (no dask): the reference of the tests.
    retry_failed : bool
        Re-run cases that failed before (finished ``ok`` cases are always skipped).
    run : RunDir, optional
        Record timings and settings in its manifest.
    """
    say = log or (lambda m: None)
    out = Path(out_dir)
    cases_dir = out / "cases"
    cases_dir.mkdir(parents=True, exist_ok=True)
    t0 = _time.perf_counter()
    results = _read_cases(cases_dir, spec)
    todo = [c for c in spec.cases if c.id not in results
            or (retry_failed and results[c.id]["status"] != "ok")]
    skipped = len(spec.cases) - len(todo)
    if skipped:
        say(f"{skipped} of {len(spec.cases)} cases already finished: skipped")
    from tqdm.auto import tqdm

    bar = tqdm(total=len(todo), unit="case", desc="sweep", disable=not progress)
    workers = 0
    try:
        if todo and serial:
            workers = 1
            for c in todo:
                r = run_case(c.spec())
                results[c.id] = r
                _write_case(cases_dir, r)
                bar.update(1)
        elif todo:
            from dask.distributed import Client, LocalCluster, as_completed

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
                n = int(n_workers or os.cpu_count() or 1)
                cluster = LocalCluster(n_workers=n, threads_per_worker=1,
                                       dashboard_address=None, processes=True,
                                       silence_logs=40)
                client = Client(cluster)
            try:
                workers = len(client.scheduler_info().get("workers", {}))
                say(f"dask: {workers} workers at {client.scheduler.address}")
                backgrounds = None
                if "imaging" in spec.stages:
                    # Build each distinct port once here and broadcast it: a worker would
                    # otherwise spend seconds rebuilding the same background.
                    from .scenario import loads_scenario

                    built = {}
                    for c in todo:
                        sc = loads_scenario(c.spec()["toml"])
                        k = _background_key(sc)
                        if k not in built:
                            built[k] = _background(sc)
                    backgrounds = client.scatter(built, broadcast=True, hash=False)
                futures = {client.submit(run_case, c.spec(), backgrounds, key=f"case-{c.id}",
                                         pure=False): c
                           for c in todo}
                for fut in as_completed(futures):
                    c = futures[fut]
                    try:
                        r = fut.result()
                    except Exception as exc:   # the worker died (e.g. out of memory)
                        r = {"id": c.id, "index": c.index, "changes": c.changes,
                             "labels": c.labels, "status": "failed",
                             "error": f"{type(exc).__name__}: {exc}",
                             "traceback": traceback.format_exc(), "values": {}}
                    results[c.id] = r
                    _write_case(cases_dir, r)
                    bar.update(1)
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
    finally:
        bar.close()
    table = _table(spec, results)
    from ..results import atomic_path

    files = {}
    with atomic_path(out / "table.csv") as tmp:
        table.to_csv(tmp, index=False, float_format="%.6f")
    files["csv"] = out / "table.csv"
    files["png"] = plot_table(table, spec.axis_names, out / "table.png")
    failed = int((table["status"] != "ok").sum())
    seconds = _time.perf_counter() - t0
    if run is not None:
        run.manifest["settings"].update({"cases": len(spec.cases), "ran": len(todo),
                                         "skipped": skipped, "failed": failed,
                                         "workers": workers, "serial": serial,
                                         "scheduler": scheduler or "LocalCluster"})
        run.record("sweep", seconds)
    return SweepResult(table, len(todo), skipped, failed, seconds, files, workers)
