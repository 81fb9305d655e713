"""Benchmark: the land surface-energy solver on a port-sized batch of columns.

10 000 columns (half paving, 30 % roofs, 20 % grass: 19, 13 and 18 cells), 4 days of 300 s
steps (forcing on the 300 s grid, a diurnal sun, sky, air and wind, per-column albedo), backward
Euler: the spin-up loop forced to run exactly 4 days (``tolerance`` tiny, ``min_days`` =
``max_days`` = 4) after the steady start. Timed in the same run:

- **ours, numba**: on one thread (``numba.set_num_threads(1)``) and on all of them, with a
  temperature-independent coefficient (``h = 4 + 4 v``: the kernel and the time loop), with
  the default correlation (``flat_plate_mixed`` evaluated in numpy every step) and with the
  port background's convection (the log-law with stability factors,
  :func:`convection_aerodynamic`), whose whole span runs in one compiled call;
- **peer 1, the numpy reference** (:func:`_step_reference`, same blocks and arithmetic)
  on one day, scaled to four;
- **peer 2, scipy.linalg.solve_banded per column**: one LAPACK banded solve of each column's
  system per step (the linear solve alone, without the Newton iterations: a lower bound of the
  per-column route), timed on 200 columns × 48 steps and scaled.

Printed: wall and CPU seconds, column-steps per CPU second, and the ratios peer / ours (CPU
time for the one-thread runs: on a shared machine it is what the run takes on an idle core).
Run: ``python benchmarks/bench_surface_energy.py [--columns 10000] [--days 4]``. Other jobs
share the 2 cores of this machine: wall times vary by ±30 %, and far more for the threaded
run while the other core is busy (a parallel launch per step then waits for it).
"""

from __future__ import annotations

import argparse
import time

import numba
import numpy as np
from scipy.linalg import solve_banded

from imaging.background import surface_energy as se
from shipthermal.units import DAY

DT = 300.0


def problem(n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    names = rng.choice(["land", "building", "vegetation"], size=n, p=[0.5, 0.3, 0.2])
    cols = se.build_columns(list(names), rng.uniform(285.0, 295.0, n))
    n_t = int(DAY / DT)
    t = np.arange(n_t) * DT
    sun = np.clip(np.sin(2 * np.pi * (t / DAY - 0.25)), 0.0, None)
    absorbed = 850.0 * sun[:, None] * rng.uniform(0.65, 0.92, n)
    sky = (320.0 + 20.0 * sun)[:, None] * np.ones(n)
    temp_air = 293.0 + 6.0 * np.sin(2 * np.pi * (t / DAY - 0.375))
    forcing = se.SurfaceForcing(DT, absorbed, sky, temp_air, 60.0 - 20.0 * sun,
                                2.0 + 2.0 * sun)
    return cols, forcing


def run(cols, forcing, days, convection, backend="numba", cpu=False):
    """Wall time [s] (``cpu``: also the process's CPU time, which on one thread is the wall
    time the run would take on an idle core)."""
    t0 = time.perf_counter()
    c0 = time.process_time()
    se.solve_surface_energy(forcing, cols, convection=convection, mode="periodic",
                            tolerance=1e-12, max_days=days, min_days=max(days, 2),
                            backend=backend)
    wall = time.perf_counter() - t0
    return (wall, time.process_time() - c0) if cpu else wall


def banded_peer(cols, n_columns=200, n_steps=48):
    """Seconds per (column, step) of scipy.linalg.solve_banded on each column's system."""
    n_cells, capacity, cond = cols.padded()
    systems = []
    for j in range(n_columns):
        c = cols.class_index[j]
        m = n_cells[c]
        k = cond[c, :m + 1]
        ab = np.zeros((3, m + 1))                       # surface node + cells
        diag = np.concatenate([[k[0] + 20.0], capacity[c, :m] / DT + k[:m] + k[1:m + 1]])
        ab[1] = diag
        ab[0, 1:] = -k[:m]
        ab[2, :-1] = -k[:m]
        systems.append((ab, np.full(m + 1, 290.0)))
    t0 = time.perf_counter()
    for _ in range(n_steps):
        for ab, rhs in systems:
            solve_banded((1, 1), ab, rhs, check_finite=False)
    return (time.perf_counter() - t0) / (n_columns * n_steps)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--columns", type=int, default=10000)
    ap.add_argument("--days", type=int, default=4)
    args = ap.parse_args()
    n, days = args.columns, args.days
    cols, forcing = problem(n)
    steps = days * int(DAY / DT)
    cells = np.mean([cols.meshes[c].n_cells for c in cols.class_index])
    print(f"{n} columns ({cells:.1f} cells on average), {days} days of {DT:g} s steps "
          f"= {steps} steps; numba threads available: {numba.get_num_threads()}")
    linear = se.convection_linear(4.0, 4.0)
    correlation = se.convection_correlation()
    aerodynamic = se.convection_aerodynamic(0.05, stability=True, height_wind=10.0,
                                            height_temp=2.0)
    for size in (64, 64 * 40):                 # compile / load the serial and parallel kernels
        warm_cols, warm_forcing = problem(size)
        run(warm_cols, warm_forcing, 2, linear)
        run(warm_cols, warm_forcing, 2, aerodynamic)
    threads = numba.get_num_threads()
    rows = []
    for label, conv in (("h = 4 + 4v", linear), ("flat_plate_mixed", correlation),
                        ("log law (compiled)", aerodynamic)):
        numba.set_num_threads(1)
        t1, c1 = run(cols, forcing, days, conv, cpu=True)
        numba.set_num_threads(threads)
        tn = run(cols, forcing, days, conv)
        rows.append((label, t1, c1, tn))
    numba.set_num_threads(1)
    t_ref = run(cols, forcing, 2, linear, backend="reference", cpu=True)[1] / 2 * days
    numba.set_num_threads(threads)
    c0 = time.process_time()
    t_band = banded_peer(cols) * n * steps
    print(f"{'convection':18s} {'1 thread wall [s]':>18s} {'CPU [s]':>8s} "
          f"{f'{threads} threads wall [s]':>20s} {'col-steps/CPU s':>16s}")
    for label, t1, c1, tn in rows:
        print(f"{label:18s} {t1:18.2f} {c1:8.2f} {tn:20.2f} {n * steps / c1:16.3g}")
    base = rows[0][2]
    print(f"peer 1, numpy reference (CPU, 2 days scaled): {t_ref:8.2f} s   reference / ours "
          f"(CPU, h = 4 + 4v): {t_ref / base:6.1f}")
    print(f"peer 2, solve_banded per column (wall, scaled): {t_band:7.2f} s   solve_banded / "
          f"ours: {t_band / base:6.1f}")
    print(f"the default correlation (numpy, every step) adds {rows[1][2] - rows[0][2]:.2f} s "
          f"CPU to the 1-thread run")
    del c0


if __name__ == "__main__":
    main()
