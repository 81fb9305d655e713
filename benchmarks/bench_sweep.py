"""Benchmark of a sweep on dask.distributed against the same cases run one by one.

    python benchmarks/bench_sweep.py [--cases 8] [--edge 2.0] [--workers 2] [--thermal-only]

The sweep: the built-in patrol boat (56 m) at ``--edge`` m surface edges, summer design
day, default solver settings (300 s steps, BDF2, spin-up to 0.01 K, 256 rays per face),
axes heading x wind offset (``--cases`` cases), thermal + imaging (3-5 and 8-14 um every
10 min on the 10 km synthetic port) unless ``--thermal-only``.

1. serial: ``run_sweep(serial=True)`` — every case in this process, one after the other
   (the peer);
2. dask: ``run_sweep`` on a LocalCluster of ``--workers`` single-threaded worker processes
   (start-up included in the wall time).

Prints both wall times, the speed-up, the cluster start-up, and checks that the two tables
agree (same values: the cases are deterministic). With 2 workers on 2 cores the ideal is 2x;
imports and the port background are paid once per worker process. Because other jobs share
the machine, it first measures the ceiling: how much faster two concurrent single-threaded
numpy matmul processes get through their work than one. Timings are wall clock on a shared
2-core machine (other agents run too): expect +-30 %.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "src"))

import pandas as pd  # noqa: E402

from shipthermal.app.sweep import load_sweep, run_sweep  # noqa: E402

HEADINGS = (0, 45, 90, 135, 180, 225, 270, 315)
WINDS = (-1.0, 1.0)


def sweep_text(n_cases: int, edge: float, thermal_only: bool) -> str:
    """Headings x two wind offsets: ``2 * (n_cases // 2)`` cases (at least 2)."""
    headings = HEADINGS[: max(1, min(len(HEADINGS), n_cases // 2))]
    winds = WINDS
    stages = '["thermal"]' if thermal_only else '["thermal", "imaging"]'
    return (f'name = "bench"\nbase = "summer"\nstages = {stages}\n[set]\n'
            f'"ship.builtin" = "patrol_boat"\n"ship.edge_length" = {edge}\n'
            f'"ship.mooring_position" = [300.0, 100.0]\n'
            f'[axes]\n"ship.heading" = {list(headings)}\n'
            f'"weather.wind_speed_offset" = {list(winds)}\n')


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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=8)
    ap.add_argument("--edge", type=float, default=2.0, help="ship surface edge [m]")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--thermal-only", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench_sweep_") as tmp:
        path = os.path.join(tmp, "sweep.toml")
        with open(path, "w") as fh:
            fh.write(sweep_text(args.cases, args.edge, args.thermal_only))
        spec = load_sweep(path)
        print(f"sweep: {len(spec.cases)} cases (patrol boat, edge {args.edge} m, "
              f"{'thermal' if args.thermal_only else 'thermal + imaging'}), axes "
              f"{ {k: len(v) for k, v in spec.axes.items()} }", flush=True)

        ceiling = machine_ceiling(args.workers)
        print(f"machine: {args.workers} concurrent single-threaded matmul processes give "
              f"{ceiling:.2f}x the throughput of one (the ceiling of any speed-up now)",
              flush=True)

        from dask.distributed import Client, LocalCluster

        t0 = time.perf_counter()
        with LocalCluster(n_workers=args.workers, threads_per_worker=1,
                          dashboard_address=None, silence_logs=40) as cluster, Client(cluster):
            startup = time.perf_counter() - t0
        print(f"LocalCluster({args.workers} workers) start + stop alone: {startup:.1f} s",
              flush=True)

        print(f"load average before: {os.getloadavg()[0]:.2f} (other processes on "
              f"{os.cpu_count()} cores)", flush=True)
        t0 = time.perf_counter()
        par = run_sweep(spec, os.path.join(tmp, "dask"), n_workers=args.workers,
                        progress=False)
        t_par = time.perf_counter() - t0
        print(f"dask ({par.workers} workers): {t_par:.1f} s wall, {par.failed} failed",
              flush=True)

        t0, c0 = time.perf_counter(), time.process_time()
        ser = run_sweep(spec, os.path.join(tmp, "serial"), serial=True, progress=False)
        t_ser, c_ser = time.perf_counter() - t0, time.process_time() - c0
        print(f"serial (one by one, this process): {t_ser:.1f} s wall, {c_ser:.1f} s CPU "
              f"({c_ser / t_ser:.2f} cores busy on average), {ser.failed} failed", flush=True)

        drop = ["seconds", "thermal_s", "imaging_s", "worker"]
        a = par.table.drop(columns=[c for c in drop if c in par.table])
        b = ser.table.drop(columns=[c for c in drop if c in ser.table])
        try:
            pd.testing.assert_frame_equal(a, b, check_exact=True)
            same = "identical"
        except AssertionError as exc:
            same = f"DIFFERENT: {str(exc).splitlines()[0]}"
        per_case = ser.table["seconds"].mean()
        cols = [c for c in ("seconds", "thermal_s", "imaging_s") if c in par.table]
        print(f"mean case {per_case:.1f} s (serial), "
              + ", ".join(f"{c} dask {par.table[c].mean():.1f} / serial {ser.table[c].mean():.1f}"
                          for c in cols) + f"; tables {same}")
        print(f"load average after: {os.getloadavg()[0]:.2f}")
        print(f"speed-up dask / serial: {t_ser / t_par:.2f}x on {args.workers} workers "
              f"(ideal {min(args.workers, os.cpu_count() or 1)}x when the cores are free; "
              f"measured machine ceiling {ceiling:.2f}x; shared machine, +-30 %)")


if __name__ == "__main__":
    main()
