"""Sweeps on dask.distributed: an 8-case sweep on a 2-worker LocalCluster gives the same
table as the cases run one by one; so does a sweep sent to an external scheduler and two
worker processes; a worker killed in the middle of a case is named in the log and the case
is run again; re-running skips finished cases; a failing case is reported with its error
and the others still finish."""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cli_helpers import write_tiny
from distributed.diagnostics.plugin import WorkerPlugin

from shipthermal.app.cli import main
from shipthermal.app.sweep import load_sweep, run_case, run_sweep

# columns that legitimately differ between runs (wall times, which process ran the case)
VOLATILE = ("seconds", "cpu_s", "thermal_s", "imaging_s", "worker")

SWEEP = """\
name = "eight"
base = "tiny.toml"
stages = ["thermal"]
[set]
"solver.spinup_max_days" = 1
[axes]
"ship.heading" = [0, 90, 180, 270]
"weather.wind_speed_offset" = [-1.0, 1.0]
"""


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("sweep")
    write_tiny(d)
    path = d / "eight.toml"
    path.write_text(SWEEP)
    return path


@pytest.fixture(scope="module")
def serial(sweep_file, tmp_path_factory):
    """The 8 cases run one by one in this process (the reference)."""
    out = tmp_path_factory.mktemp("serial")
    return run_sweep(load_sweep(sweep_file), out, serial=True, progress=False), out


def _stable(table):
    return table.drop(columns=[c for c in VOLATILE if c in table]).reset_index(drop=True)


def test_sweep_on_two_workers_equals_serial(sweep_file, serial, tmp_path):
    spec = load_sweep(sweep_file)
    assert len(spec.cases) == 8
    assert len({c.id for c in spec.cases}) == 8
    par = run_sweep(spec, tmp_path / "par", n_workers=2, progress=False)
    assert par.workers == 2 and par.ran == 8 and par.failed == 0
    assert (par.table["status"] == "ok").all()
    # the cases really ran on two worker processes, not here
    assert par.table["worker"].nunique() == 2
    ser = serial[0]
    # same code, inputs and seeds, single-threaded steps: bit-identical results
    pd.testing.assert_frame_equal(_stable(par.table), _stable(ser.table), check_exact=True)
    # the axes matter (the table is not 8 copies of one case): heading moves the deck mean
    # and more wind cools it at noon
    t = par.table
    assert t["deck_12h_K"].nunique() == 8
    for h in (0, 90, 180, 270):
        rows = t[t["ship.heading"] == h].set_index("weather.wind_speed_offset")
        assert rows.loc[1.0, "deck_12h_K"] < rows.loc[-1.0, "deck_12h_K"]
    # the CSV holds the same table
    csv = pd.read_csv(tmp_path / "par" / "table.csv")
    np.testing.assert_allclose(csv["deck_12h_K"], t["deck_12h_K"], atol=1e-6)
    assert (tmp_path / "par" / "table.png").stat().st_size > 10_000


def test_rerun_skips_finished_cases_and_one_case_equals_a_single_run(sweep_file, serial):
    spec = load_sweep(sweep_file)
    first, out = serial
    again = run_sweep(spec, out, serial=True, progress=False)
    assert again.ran == 0 and again.skipped == 8
    pd.testing.assert_frame_equal(first.table, again.table)
    # a case = the scenario run on its own (the case TOML is a complete scenario)
    from shipthermal.app.thermal import run_scenario_thermal
    from shipthermal.app.scenario import loads_scenario

    case = spec.cases[3]
    res = run_scenario_thermal(loads_scenario(case.toml), progress=False)
    row = first.table.set_index("case").loc[case.id]
    assert row["deck_12h_K"] == res.part_mean_at("deck", 12.0)
    assert row["days"] == res.days == 1


def test_failed_case_is_reported_not_lost(tmp_path, capsys):
    """One case reads a weather file whose content is bad (found only when it runs): the
    table keeps its error, the other case finishes, the exit code says 'failure' (1), and a
    re-run retries only the failed case."""
    write_tiny(tmp_path)
    (tmp_path / "broken.csv").write_text("time,temp_air\n2023-07-15T00:00+08:00,20\n")
    (tmp_path / "s.toml").write_text(
        'base = "tiny.toml"\nstages = ["thermal"]\n[set]\n"solver.spinup_max_days" = 1\n'
        '[[axes.weather]]\n"weather.source" = "builtin"\n'
        '[[axes.weather]]\n"weather.source" = "broken.csv"\n"weather.temp_sea" = 295.0\n')
    out = tmp_path / "out"
    assert main(["-q", "sweep", str(tmp_path / "s.toml"), "--serial", "--out", str(out)]) == 1
    text = capsys.readouterr().out
    table = pd.read_csv(out / "table.csv")
    assert list(table["status"]) == ["ok", "failed"]
    err = table.loc[1, "error"]
    assert err.startswith("InputError") and "missing required column" in err
    assert f"failed: {err}" in text
    case = json.loads(next((out / "cases").glob("0001-*.json")).read_text())
    assert "Traceback" in case["traceback"] and case["status"] == "failed"
    # retry: the ok case is skipped, the failed one runs (and fails) again
    assert main(["-q", "sweep", str(tmp_path / "s.toml"), "--serial", "--out", str(out)]) == 1
    assert "1 ran, 1 skipped" in capsys.readouterr().out
    assert (out / "COMPLETE").is_file()
    assert "missing required column" in (out / "report.html").read_text()


def test_season_axis_moves_the_season_defaults(tmp_path):
    """time.season on the built-in base also moves date, image times and compartment air to
    the winter defaults (changes go to the raw scenario before validation)."""
    (tmp_path / "s.toml").write_text('base = "summer"\n[axes]\n"time.season" = '
                                     '["summer", "winter"]\n')
    spec = load_sweep(tmp_path / "s.toml")
    from shipthermal.app.scenario import default_scenario, loads_scenario

    for case, season in zip(spec.cases, ("summer", "winter")):
        assert loads_scenario(case.toml) == default_scenario(season)


def test_base_scenario_with_a_date(tmp_path):
    """A base scenario with a TOML date (``date = 2024-07-15``, not a string) is swept like
    any other: the date reaches every case."""
    base = write_tiny(tmp_path)
    base.write_text(base.read_text().replace("[time]\n", "[time]\ndate = 2024-07-15\n"))
    (tmp_path / "s.toml").write_text('base = "tiny.toml"\n[axes]\n"ship.heading" = [0, 90]\n')
    spec = load_sweep(tmp_path / "s.toml")
    from shipthermal.app.scenario import loads_scenario

    assert [str(loads_scenario(c.toml).time.date) for c in spec.cases] == ["2024-07-15"] * 2


def test_run_case_never_raises():
    r = run_case({"id": "x", "index": 0, "changes": {}, "labels": {}, "toml": "not = [toml",
                  "stages": ["thermal"]})
    assert r["status"] == "failed" and "must be valid TOML" in r["error"]


def test_sweep_with_imaging_columns(tmp_path):
    """Thermal + imaging cases (8-14 um only, 10-min frames, 100-pixel port): per-band
    crossover times and SCR range land in the table, and both headings cross over twice a
    day (the moored ship is warmer than the water by day, colder by night)."""
    write_tiny(tmp_path)
    (tmp_path / "s.toml").write_text(
        'base = "tiny.toml"\n[set]\n"solver.spinup_max_days" = 1\n"imaging.bands" = ["8-14"]\n'
        '[axes]\n"ship.heading" = [0, 90]\n')
    res = run_sweep(load_sweep(tmp_path / "s.toml"), tmp_path / "out", serial=True,
                    progress=False)
    t = res.table
    assert list(t["status"]) == ["ok", "ok"], list(t["error"])
    for col in ("crossovers_8-14", "n_crossovers_8-14", "scr_min_8-14", "scr_max_8-14"):
        assert col in t
    assert not [c for c in t.columns if c.endswith("3-5")]
    assert (t["scr_max_8-14"] > t["scr_min_8-14"]).all()
    assert (t["scr_min_8-14"] >= 0).all()
    assert (t["n_crossovers_8-14"] == 2).all()


# ---------------------------------------------------------------------------------------
# An external cluster: `dask scheduler` and two `dask worker` processes on 127.0.0.1
# ---------------------------------------------------------------------------------------
TWO = SWEEP.replace('name = "eight"', 'name = "two"').replace(
    '"ship.heading" = [0, 90, 180, 270]', '"ship.heading" = [90]')


class _Cluster:
    """A scheduler and ``n`` single-threaded workers, each its own process (no nanny, so
    a killed worker stays dead and its process id is the one started here)."""

    def __init__(self, folder: Path, n: int = 2):
        self.folder = folder
        self.procs = []
        src = Path(__file__).resolve().parents[2] / "src"
        # the workers import the package and this module (for the plugin below)
        path = [str(src), str(Path(__file__).resolve().parent), os.environ.get("PYTHONPATH")]
        self.env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in path if p))
        self.file = folder / "scheduler.json"
        dask = [sys.executable, "-m", "dask"]
        self._start(dask + ["scheduler", "--host", "127.0.0.1", "--port", "0",
                            "--no-dashboard", "--scheduler-file", str(self.file),
                            "--idle-timeout", "600"])
        self.workers = [self._start(dask + ["worker", "--scheduler-file", str(self.file),
                                            "--nthreads", "1", "--no-nanny",
                                            "--host", "127.0.0.1", "--no-dashboard",
                                            "--death-timeout", "120"])
                        for _ in range(n)]

    def _start(self, cmd):
        with open(self.folder / f"proc{len(self.procs)}.log", "w") as log:
            p = subprocess.Popen(cmd, env=self.env, stdout=log, stderr=subprocess.STDOUT)
        self.procs.append(p)
        return p

    def client(self):
        """A client once every worker has joined (the client waits for the scheduler's
        file, then for the workers, each with a time limit)."""
        from dask.distributed import Client

        c = Client(scheduler_file=str(self.file), timeout="60s")
        c.wait_for_workers(len(self.workers), timeout=120)
        return c

    def close(self):
        for p in self.procs[::-1]:
            if p.poll() is None:
                p.terminate()
        for p in self.procs:
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def _csv_rows(path, **axes):
    t = pd.read_csv(path)
    for k, v in axes.items():
        t = t[t[k] == v]
    return t.drop(columns=[c for c in VOLATILE + ("case", "index") if c in t]
                  ).reset_index(drop=True)


@pytest.mark.slow
def test_external_scheduler_and_worker_processes(sweep_file, serial, tmp_path, capsys):
    """`sweep --scheduler ADDRESS` sends the cases to a running cluster (a `dask scheduler`
    and two `dask worker` processes started here) instead of starting one; the table equals
    the serial one, and both worker processes ran cases. (Slow: 65 s, two fresh worker
    processes each importing the stack; the default run keeps the two-worker local cluster
    against serial, `test_sweep_on_two_workers_equals_serial`.)"""
    (sweep_file.parent / "two.toml").write_text(TWO)
    cluster = _Cluster(tmp_path)
    try:
        with cluster.client() as c:
            address = c.scheduler.address
            pids = set(c.run(os.getpid).values())
        assert pids == {p.pid for p in cluster.workers}
        code = main(["sweep", str(sweep_file.parent / "two.toml"), "--scheduler", address,
                     "--out", str(tmp_path / "o")])
        assert code == 0
        assert f"dask: 2 workers at {address}" in capsys.readouterr().err
    finally:
        cluster.close()
    t = _csv_rows(tmp_path / "o" / "table.csv")
    ref = _csv_rows(serial[1] / "table.csv", **{"ship.heading": 90})
    assert len(t) == 2 and (t["retries"] == 0).all()
    pd.testing.assert_frame_equal(t, ref, check_exact=True)
    ran_on = {int(w.rsplit(":", 1)[1]) for w in pd.read_csv(tmp_path / "o" / "table.csv")["worker"]}
    assert ran_on == pids
    manifest = json.loads((tmp_path / "o" / "manifest.json").read_text())
    assert manifest["settings"]["scheduler"] == address
    # signed: every top-level entry is listed as written by the tool
    assert (manifest["tool"], manifest["kind"]) == ("shipthermal", "sweep")
    assert manifest["entries"] == sorted(p.name for p in (tmp_path / "o").iterdir())


class StallFirstStart(WorkerPlugin):
    """A worker plugin: the first worker to start the task ``key`` (a case) writes
    its process id to ``flag`` and stalls there (until it is killed); any later attempt
    finds the flag and runs normally."""

    name = "stall-first-start"

    def __init__(self, key: str, flag: str):
        self.key, self.flag = key, flag

    def transition(self, key, start, finish, **kwargs):
        if key != self.key or finish != "executing" or os.path.exists(self.flag):
            return
        tmp = self.flag + ".tmp"
        with open(tmp, "w") as fh:
            fh.write(str(os.getpid()))
        os.replace(tmp, self.flag)
        threading.Event().wait(600)       # the test kills this process meanwhile


def test_lost_worker_is_logged_and_its_case_retried(sweep_file, serial, tmp_path, capsys):
    """A worker process dies in the middle of a case (killed once the case has signalled
    that it started): the log names the worker and the case, dask runs the case again on
    the other worker, the row counts one retry, and the table still equals the serial one."""
    (sweep_file.parent / "two.toml").write_text(TWO)
    spec = load_sweep(sweep_file.parent / "two.toml")
    target = spec.cases[0]
    flag = tmp_path / "started"
    cluster = _Cluster(tmp_path)
    killed = {}

    def kill_when_started():
        deadline = time.monotonic() + 300
        while not flag.exists() and time.monotonic() < deadline:
            time.sleep(0.02)                 # waits on the file, not for a fixed time
        if flag.exists():
            killed["pid"] = int(flag.read_text())
            os.kill(killed["pid"], signal.SIGKILL)

    try:
        with cluster.client() as c:
            address = c.scheduler.address
            c.register_plugin(StallFirstStart(f"case-{target.id}", str(flag)))
        watcher = threading.Thread(target=kill_when_started, daemon=True)
        watcher.start()
        code = main(["sweep", str(sweep_file.parent / "two.toml"), "--scheduler", address,
                     "--out", str(tmp_path / "o")])
        watcher.join(timeout=60)
        assert code == 0
        err = capsys.readouterr().err
    finally:
        cluster.close()
    assert killed["pid"] in {p.pid for p in cluster.workers}
    lost = [line for line in err.splitlines() if "was lost while running case" in line]
    assert any(f"case {target.id}" in line and "retry 1" in line for line in lost), err
    raw = pd.read_csv(tmp_path / "o" / "table.csv").set_index("case")
    assert raw.loc[target.id, "retries"] == 1
    # the case finished on the surviving worker, not on the killed one
    assert not raw.loc[target.id, "worker"].endswith(f":{killed['pid']}")
    # a case queued on the killed worker is retried too; every retry is in the log
    assert raw["retries"].sum() == len(lost)
    case_file = json.loads(next((tmp_path / "o" / "cases").glob(f"{target.id}.json"))
                           .read_text())
    assert case_file["retries"] == 1 and case_file["status"] == "ok"
    pd.testing.assert_frame_equal(_csv_rows(tmp_path / "o" / "table.csv").drop(
        columns="retries"), _csv_rows(serial[1] / "table.csv", **{"ship.heading": 90}).drop(
        columns="retries"), check_exact=True)


def test_default_workers_follow_the_usable_cores():
    """At most one worker per usable core (CPU affinity) and per case."""
    from shipthermal.app.sweep import default_workers

    cores = len(os.sched_getaffinity(0))
    assert default_workers(1) == 1
    assert default_workers(100) == cores
    assert default_workers(2) == min(2, cores)


def test_cases_are_pinned():
    """Inside a case numba, BLAS and OpenMP use the threads given (one by default); after
    it, the process's own settings come back."""
    import numba
    from threadpoolctl import threadpool_info

    from shipthermal.app.sweep import _pinned

    before = numba.get_num_threads(), [p["num_threads"] for p in threadpool_info()]
    with _pinned(1):
        assert numba.get_num_threads() == 1
        assert all(p["num_threads"] == 1 for p in threadpool_info())
    assert (numba.get_num_threads(), [p["num_threads"] for p in threadpool_info()]) == before


def _worker_environment():
    import dask

    return ({k: os.environ.get(k) for k in ("MALLOC_TRIM_THRESHOLD_", "MALLOC_ARENA_MAX",
                                            "NUMBA_NUM_THREADS", "OMP_NUM_THREADS",
                                            "OPENBLAS_NUM_THREADS")},
            dask.config.get("distributed.worker.profile.enabled"))


def test_local_cluster_workers_start_pinned_with_adaptive_malloc():
    """A sweep's LocalCluster workers start with one-thread pools, without the malloc
    trim threshold dask's nanny sets by default (it turned every large temporary array
    into page faults) and with one malloc arena (the task thread's own arena faulted its
    arrays in again and again), and without the profiler; the environment of this process is left
    as it was (dask's nanny sets its pre-spawn variables in it). ``pin_workers`` then holds
    each worker to a core of its own."""
    from dask.distributed import Client

    from shipthermal.app.sweep import local_cluster, pin_workers

    here = dict(os.environ)
    with local_cluster(2, threads=1) as cluster, Client(cluster) as c:
        found = list(c.run(_worker_environment).values())
        # each worker on a core of its own when the workers fill the cores, else left to
        # the system
        cores = os.sched_getaffinity(0)
        pinned = pin_workers(c)
        held = [frozenset(a) for a in c.run(os.sched_getaffinity, 0).values()]
    assert pinned == (len(cores) == 2)
    if pinned:
        assert all(len(a) == 1 for a in held) and len(set(held)) == 2
        assert set().union(*held) <= cores
    else:
        assert held == [frozenset(cores)] * 2
    # ... while this process keeps its own environment (numba refuses to compile once its
    # thread count and NUMBA_NUM_THREADS disagree; later child processes inherit it)
    assert dict(os.environ) == here
    assert len(found) == 2
    for env, profile in found:
        assert env == {"MALLOC_TRIM_THRESHOLD_": None, "MALLOC_ARENA_MAX": "1",
                       "NUMBA_NUM_THREADS": "1",
                       "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
        assert profile is False


def test_a_worker_keeps_one_background_per_world_not_per_port(tmp_path, monkeypatch):
    """A kept port background is reused only by cases of the same location, time, weather
    and [background]: the background's every pixel runs under the case's weather, so a
    wind-offset axis gets one background per offset, a heading axis shares one."""
    from shipthermal.app import pipeline, sweep
    from shipthermal.app.scenario import load_scenario

    built = []
    monkeypatch.setattr(pipeline, "build_background", lambda sc: built.append(sc) or len(built))
    monkeypatch.setattr(sweep, "_BACKGROUNDS", {})
    base = load_scenario(write_tiny(tmp_path))
    heading = base.updated({"ship.heading": 90.0})
    windy = base.updated({"weather.wind_speed_offset": 2.0})
    assert [sweep._background(s) for s in (base, heading, windy, base)] == [1, 1, 2, 1]
