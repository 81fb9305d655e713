"""Benchmark of a sweep on dask.distributed against the same cases run one by one.

    python benchmarks/bench_sweep.py [--cases 8] [--edge 3.0] [--workers N] [--thermal-only]
                                     [--rounds 1]

The sweep: the built-in patrol boat (56 m) at ``--edge`` m surface edges, summer design
day, default solver settings (300 s steps, BDF2, spin-up to 0.01 K, 256 rays per face),
axes heading x wind offset (``--cases`` cases, even), thermal + imaging (3-5 and 8-14 um
every 10 min on the 10 km synthetic port) unless ``--thermal-only``. The defaults take
about 3 minutes on two free cores.

1. serial: ``run_sweep(serial=True)`` — every case in this process, one after the other
   (the peer), each case pinned to one thread like a worker's;
2. dask: ``run_sweep`` on the sweep's LocalCluster (``shipthermal.app.sweep.local_cluster``)
   of ``--workers`` single-threaded worker processes (default: the usable cores; start-up
   included in the wall time).

Prints both wall times and the speed-up; per case the mean wall and CPU time (user + system;
CPU well below wall means the case waited for a core that other processes held); the threads
of each worker process; each worker process's whole CPU time; the load average around each
phase; and whether the two tables agree (same values: the cases are deterministic). Then
why: a case's time alone and next to another one, each worker's first-case set-up, and the
limit that slow-down sets. Last, a projection that other jobs on the machine cannot spoil:
the serial run's CPU time over the busiest worker's CPU time plus the cluster start-up, i.e.
the speed-up with a free core per worker. With 2 workers on 2 free cores the ideal is 2x,
less the cluster start-up and each worker's first-case set-up (imports, cached numba
kernels, the port background): the serial run pays that set-up once, the sweep once per
worker (in parallel), so the speed-up grows with the number and the size of the cases.
Because other jobs may share the machine, it first measures the ceiling: how much faster
``--workers`` concurrent single-threaded numpy matmul processes get through their work than
one (2.0 on two free cores). Timings are wall clock: compare the speed-up with that ceiling.
Matmul is compute-bound; the sweep's sparse solves and ray tracing also share the memory bus
and the last-level cache, so a third run measures the ceiling of this very workload without
any scheduler:

3. split: ``--workers`` plain processes started at once, each running its share of the
   cases serially (``run_sweep(serial=True)`` on cases k, k + n, ...; start-up, imports and
   cached numba kernels included, as a worker pays them). serial wall / slowest process
   wall is the best any scheduler could do for these cases on this machine now.

The dask / split ratio compares two runs minutes apart, and this machine's speed drifts by
more than the ratio's last tenth within minutes: ``--rounds N`` (N > 1) runs dask and split
N - 1 more times, alternating which goes first (dask, split, split, dask, dask, ...), prints
each round's ratio and their median.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "src"))

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from shipthermal.app.sweep import (default_workers, load_sweep, local_cluster,  # noqa: E402
                                   pin_workers, run_sweep)

HEADINGS = (0, 45, 90, 135, 180, 225, 270, 315, 30, 60, 120, 150, 210, 240, 300, 330)
WINDS = (-1.0, 1.0)


def sweep_text(n_cases: int, edge: float, thermal_only: bool) -> str:
    """Headings x two wind offsets: ``2 * (n_cases // 2)`` cases (at least 2)."""
    headings = HEADINGS[: max(1, min(len(HEADINGS), n_cases // 2))]
    stages = '["thermal"]' if thermal_only else '["thermal", "imaging"]'
    return (f'name = "bench"\nbase = "summer"\nstages = {stages}\n[set]\n'
            f'"ship.builtin" = "patrol_boat"\n"ship.edge_length" = {edge}\n'
            f'"ship.mooring_position" = [300.0, 100.0]\n'
            f'[axes]\n"ship.heading" = {list(headings)}\n'
            f'"weather.wind_speed_offset" = {list(WINDS)}\n')


_MATMUL = ("import os, time; os.environ['OPENBLAS_NUM_THREADS'] = '1'; import numpy as np; "
           "a = np.random.default_rng(0).random((500, 500)); t = time.perf_counter(); "
           "[a @ a for _ in range(60)]; print(time.perf_counter() - t)")


def machine_ceiling(n: int) -> float:
    """Throughput of ``n`` concurrent single-threaded numeric processes relative to one
    (2.0 on two free cores; less when other jobs share them): the best a sweep can do."""
    import subprocess

    def run(k):
        procs = [subprocess.Popen([sys.executable, "-c", _MATMUL], stdout=subprocess.PIPE,
                                  text=True) for _ in range(k)]
        return [float(p.communicate()[0]) for p in procs]

    alone = min(run(1)[0] for _ in range(2))
    together = max(run(n))
    return n * alone / together


def run_part(path: str, out: str, part: int, parts: int) -> None:
    """Run cases ``part, part + parts, ...`` of the sweep at ``path`` serially into ``out``
    and print the clock when done [s since the epoch] (the ``split`` run; a process of its
    own)."""
    import dataclasses

    spec = load_sweep(path)
    spec = dataclasses.replace(spec, cases=spec.cases[part::parts])
    run_sweep(spec, out, serial=True, progress=False)
    print(time.time())


def split_walls(path: str, tmp: str, parts: int) -> list:
    """Wall times of ``parts`` concurrent plain processes sharing the cases (see run_part),
    each from its start (before the interpreter starts and imports what it needs: a dask
    worker's start-up is in the sweep's wall time too) to its last case's table written."""
    import subprocess

    start = time.time()
    procs = [subprocess.Popen([sys.executable, __file__, "--part", f"{k}/{parts}", path,
                               os.path.join(tmp, f"split{k}")], stdout=subprocess.PIPE,
                              text=True) for k in range(parts)]
    return [float(p.communicate()[0].split()[-1]) - start for p in procs]


def process_cpu() -> float:
    """User + system CPU time of this process so far [s]."""
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def load() -> str:
    return "load " + "/".join(f"{x:.1f}" for x in os.getloadavg()) + f" on {os.cpu_count()} cores"


def case_files(folder) -> list:
    return [json.loads(p.read_text()) for p in sorted(Path(folder, "cases").glob("*.json"))]


def case_means(cases: list) -> str:
    """Mean wall, CPU, thermal and imaging time of ``cases`` (case files) without each
    process's slowest case (its first: imports, cached kernels, the port background), as
    text."""
    slowest = {}
    for c in cases:
        w = str(c.get("worker", ""))
        if w not in slowest or c["seconds"] > slowest[w]["seconds"]:
            slowest[w] = c
    rest = [c for c in cases if all(c is not f for f in slowest.values())]

    def mean(get):
        return float(np.mean([float(get(c)) for c in rest])) if rest else float("nan")
    return (f"{mean(lambda c: c['seconds']):.2f} s wall, {mean(lambda c: c['cpu_s']):.2f} s "
            f"CPU (thermal {mean(lambda c: c['values'].get('thermal_s', 0.0)):.2f} s, imaging "
            f"{mean(lambda c: c['values'].get('imaging_s', 0.0)):.2f} s)")


def describe(name: str, folder, table: pd.DataFrame, wall: float) -> None:
    cases = case_files(folder)
    cpu = pd.to_numeric(table["cpu_s"]).to_numpy()
    sec = pd.to_numeric(table["seconds"]).to_numpy()
    threads = {}
    for c in cases:
        for w in str(c.get("worker", "")).split(" + "):
            threads[w] = max(threads.get(w, 0), int(c.get("threads", 0)))
    parts = [f"{c}: {pd.to_numeric(table[c]).mean():.1f} s" for c in ("thermal_s", "imaging_s")
             if c in table]
    print(f"  {name}: {wall:.1f} s wall; per case {sec.mean():.1f} s wall, {cpu.mean():.1f} s "
          f"CPU (first {cpu[0]:.1f} s, then mean {cpu[1:].mean() if len(cpu) > 1 else 0:.1f} s; "
          f"{', '.join(parts)}); threads per process {sorted(set(threads.values()))} "
          f"in {len(threads)} process(es); retries {int(table['retries'].sum())}", flush=True)


def setup_and_steady(table: pd.DataFrame) -> tuple[float, float]:
    """``(set-up, steady)``: how much longer each process's first case took than its others
    (imports, cached numba kernels, the port background; mean over the processes), and the
    median wall time of the other cases [s]. Cases run in table order, so a process's first
    row is the first case it ran."""
    sec = pd.to_numeric(table["seconds"]).to_numpy()
    worker = table["worker"].astype(str).to_numpy()
    _, first_rows = np.unique(worker, return_index=True)
    rest = np.delete(sec, first_rows)
    if not len(rest):
        return float("nan"), float("nan")
    steady = float(np.median(rest))
    return float(np.mean(sec[first_rows]) - steady), steady


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=8, help="number of cases (even, >= 2)")
    ap.add_argument("--edge", type=float, default=3.0, help="ship surface edge [m]")
    ap.add_argument("--workers", type=int, default=None,
                    help="LocalCluster workers (default: the usable cores, as a sweep does)")
    ap.add_argument("--thermal-only", action="store_true")
    ap.add_argument("--rounds", type=int, default=1,
                    help="dask and split runs, alternating which goes first (see above)")
    ap.add_argument("--part", nargs=3, metavar=("K/N", "SWEEP", "OUT"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.part:
        k, n = (int(v) for v in args.part[0].split("/"))
        run_part(args.part[1], args.part[2], k, n)
        return
    with tempfile.TemporaryDirectory(prefix="bench_sweep_") as tmp:
        path = os.path.join(tmp, "sweep.toml")
        with open(path, "w") as fh:
            fh.write(sweep_text(args.cases, args.edge, args.thermal_only))
        spec = load_sweep(path)
        workers = args.workers or default_workers(len(spec.cases))
        print(f"sweep: {len(spec.cases)} cases (patrol boat, edge {args.edge} m, "
              f"{'thermal' if args.thermal_only else 'thermal + imaging'}), "
              f"{workers} workers; {load()}", flush=True)
        ceiling = machine_ceiling(workers)
        print(f"machine: {workers} concurrent single-threaded matmul processes give "
              f"{ceiling:.2f}x the throughput of one (the ceiling of any speed-up now)",
              flush=True)

        print(f"serial (one by one in this process), {load()}", flush=True)
        t0, c0 = time.perf_counter(), process_cpu()
        ser = run_sweep(spec, os.path.join(tmp, "serial"), serial=True, progress=False)
        t_ser, c_ser = time.perf_counter() - t0, process_cpu() - c0
        describe("serial", os.path.join(tmp, "serial"), ser.table, t_ser)

        print(f"dask, {load()}", flush=True)
        from dask.distributed import Client

        t0, c0 = time.perf_counter(), process_cpu()
        # the sweep's own LocalCluster, started here so that the workers' whole CPU time
        # (imports, the port background, the cases, dask itself) can be read before it stops
        with local_cluster(workers) as cluster, Client(cluster) as client:
            pin_workers(client)              # as a sweep does on its own LocalCluster
            startup = time.perf_counter() - t0
            par = run_sweep(spec, os.path.join(tmp, "dask"),
                            scheduler=cluster.scheduler_address, progress=False,
                            log=lambda m: print("  " + m, flush=True))
            t_par, c_par = time.perf_counter() - t0, process_cpu() - c0
            busy = client.run(process_cpu)
        describe(f"dask ({par.workers} workers)", os.path.join(tmp, "dask"), par.table, t_par)
        print(f"  cluster start {startup:.1f} s; whole CPU time of each worker process: "
              + ", ".join(f"{v:.1f} s" for v in busy.values())
              + f"; of this process meanwhile: {c_par:.1f} s", flush=True)
        print(f"after: {load()}", flush=True)

        print(f"split ({workers} plain processes, no scheduler), {load()}", flush=True)
        walls = split_walls(path, tmp, workers)
        print("  split: process walls " + ", ".join(f"{w:.1f} s" for w in walls)
              + f"; workload ceiling serial / slowest = {t_ser / max(walls):.2f}x", flush=True)
        split_cases = [c for k in range(workers)
                       for c in case_files(os.path.join(tmp, f"split{k}"))]
        print("  per case, each process's slowest left out: split "
              + case_means(split_cases) + "; dask "
              + case_means(case_files(os.path.join(tmp, "dask"))), flush=True)

        drop = ["seconds", "cpu_s", "thermal_s", "imaging_s", "worker"]
        a = par.table.drop(columns=[c for c in drop if c in par.table])
        b = ser.table.drop(columns=[c for c in drop if c in ser.table])
        try:
            pd.testing.assert_frame_equal(a, b, check_exact=True)
            same = "identical"
        except AssertionError as exc:
            same = f"DIFFERENT: {str(exc).splitlines()[0]}"
        failed = f"{ser.failed} / {par.failed} failed"
        print(f"tables {same} ({failed})")
        print(f"speed-up dask / serial: {t_ser / t_par:.2f}x on {par.workers} workers "
              f"(serial {t_ser:.1f} s, dask {t_par:.1f} s; ideal "
              f"{min(par.workers, os.cpu_count() or 1)}x on free cores; measured machine "
              f"ceiling now {ceiling:.2f}x, this workload's {t_ser / max(walls):.2f}x; "
              f"dask / split {max(walls) / t_par:.2f})")
        # Why the speed-up is what it is: the set-up every worker pays (the serial run once)
        # and how much slower a case runs next to another one than alone.
        f_ser, c_one = setup_and_steady(ser.table)
        f_par, c_side = setup_and_steady(par.table)
        k = c_side / c_one
        print(f"why: a case takes {c_one:.2f} s alone and {c_side:.2f} s next to another "
              f"({k:.2f}x); each worker's first case takes {f_par:.1f} s more (imports, "
              f"cached kernels, the port background), which the serial run pays once "
              f"({f_ser:.1f} s). At this slow-down no number of cases gets past "
              f"{par.workers / k:.2f}x.")
        # the wall times with a free core per process: their CPU time, plus the cluster
        # start-up, plus (pessimistically, as if it never overlapped) this process's share
        projected = c_ser / (startup + max(busy.values()) + c_par)
        print(f"CPU-bound projection (a free core per worker): serial {c_ser:.1f} s CPU / "
              f"(start {startup:.1f} s + busiest worker {max(busy.values()):.1f} s CPU + "
              f"this process {c_par:.1f} s CPU) = {projected:.2f}x")
        if args.rounds > 1:
            ratios = [max(walls) / t_par] + more_rounds(spec, path, tmp, workers, args.rounds)
            print(f"dask / split over {len(ratios)} rounds: "
                  + ", ".join(f"{r:.2f}" for r in ratios)
                  + f"; median {float(np.median(ratios)):.2f}")


def dask_wall(spec, out: str, workers: int) -> float:
    """Wall time of the sweep ``spec`` on its own LocalCluster of ``workers`` (start-up
    included) [s]."""
    t0 = time.perf_counter()
    run_sweep(spec, out, n_workers=workers, progress=False)
    return time.perf_counter() - t0


def more_rounds(spec, path: str, tmp: str, workers: int, rounds: int) -> list:
    """dask / split of rounds 2 … ``rounds``, split first in the even rounds (the first
    round, run above, took dask first)."""
    ratios = []
    for r in range(1, rounds):
        first_split = r % 2 == 1
        if first_split:
            split = max(split_walls(path, os.path.join(tmp, f"r{r}"), workers))
        dask = dask_wall(spec, os.path.join(tmp, f"r{r}", "dask"), workers)
        if not first_split:
            split = max(split_walls(path, os.path.join(tmp, f"r{r}"), workers))
        ratios.append(split / dask)
        print(f"round {r + 1} ({'split' if first_split else 'dask'} first; {load()}): "
              f"dask {dask:.1f} s, split {split:.1f} s (slowest process): "
              f"dask / split {split / dask:.2f}", flush=True)
    return ratios


if __name__ == "__main__":
    main()
