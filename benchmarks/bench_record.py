"""A weather record of weeks to a year through the thermal stage: wall time, peak memory and
where the time goes, against the same record run in one window (the peer, in the same run).

Run: ``python benchmarks/bench_record.py [--days 365] [--edge 2.0] [--peer-days 7]
[--weather FILE.epw] [--temp-sea 287] [--window 1] [--threads 1] [--jobs 1]``

Reports, for the built-in frigate under a typical year (by default EnergyPlus's San
Francisco International TMY3 file shipped with ``pyenergyplus``, a bay shore; ``temp_sea``
the bay's mean, 287 K), scenario defaults otherwise (300 s day steps, 900 s night steps,
30-min outputs, BDF2):

* the record run (:func:`shipthermal.diurnal.run_record`: spin-up on the first day, then
  the record in windows of ``--window`` days, outputs streamed to disk): wall and CPU
  time, peak resident memory of its process, the split spin-up / forcing tables / steps /
  outputs, steps and Newton passes per recorded day, the outputs file's size;
* the peer: the same scenario over ``--peer-days`` days run twice, in daily windows and in
  one window over the whole span (the tables of every day at once, every output kept in
  memory until the end: what a record run did before it ran in windows), each in its own
  process: wall-time and peak-memory ratios, and the largest difference of any face
  temperature between the two (0: the windows change nothing);
* with ``--jobs N`` (N > 1) the record split over N processes (``solver.jobs``) against the
  same record in one piece, both in this run: wall-time ratio, peak memory (of the largest
  process) and the largest difference of any face temperature at any output time.

Each run is a child process (its own peak memory). ``--threads`` sets numba's threads (1 by
default: the 2 CPUs here are shared with other jobs, and two-thread kernels then wait on
each other, up to 14× slower per step than one thread, measured under a load of 10).

Not a test. Timings move by ±30 % with the machine's load (printed).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SRC = HERE.parent / "src"


def _default_weather() -> str:
    import pyenergyplus

    return str(Path(pyenergyplus.__file__).parent / "data" / "weather"
               / "USA_CA_San.Francisco.Intl.AP.724940_TMY3.epw")


def _scenario(args, days: int):
    from shipthermal.app.scenario import load_scenario

    return load_scenario({
        "name": "bench-record",
        "location": {"latitude": 37.62, "longitude": -122.40, "time_zone": "Etc/GMT+8"},
        "time": {"season": "winter", "date": args.date},
        "weather": {"source": args.weather, "format": "epw", "temp_sea": args.temp_sea,
                    "day": "record", "days": days},
        "ship": {"edge_length": args.edge}})


def child(args) -> dict:
    """One record run in this process; its figures as a dict."""
    import resource

    import numpy as np

    from shipthermal.app.thermal import thermal_inputs
    from shipthermal.diurnal import run_record

    import dataclasses

    sc = _scenario(args, args.days)
    inputs = thermal_inputs(sc)
    inputs.pop("checkpoint_interval")
    inputs["settings"] = dataclasses.replace(inputs["settings"], jobs=args.jobs)
    work = Path(tempfile.mkdtemp(prefix="bench-record-"))
    t0, c0 = time.perf_counter(), time.process_time()
    res = run_record(**inputs, progress=False, checkpoint=work / "c.npz",
                     window_days=args.window, face_dtype=np.float64 if args.float64
                     else np.float32)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    tm = res.timings
    out = {"days": args.days, "window": args.window, "faces": int(res.ship.n_faces),
           "cells": int(res.graph.n_cells), "wall_s": wall, "cpu_s": cpu,
           "peak_rss_MB": max(resource.getrusage(who).ru_maxrss for who in
                              (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)) / 1024,
           "spinup_s": tm.get("spinup_total", 0.0), "forcing_s": tm["record_forcing"],
           "steps_s": tm["record_solve"], "outputs_s": tm["record_outputs"],
           "steps": int(len(res.energy.time)), "spinup_days": res.meta["spinup_days"],
           "outputs_file_MB": res.record.path.stat().st_size / 1e6}
    if args.dump:
        np.save(args.dump, res.record.face_temperature[:])
    return out


def _spawn(args, days: int, window: int, dump: str | None = None, jobs: int = 1) -> dict:
    cmd = [sys.executable, __file__, "--child", "--days", str(days), "--window", str(window),
           "--edge", str(args.edge), "--weather", args.weather, "--temp-sea",
           str(args.temp_sea), "--date", args.date, "--jobs", str(jobs)]
    if dump:
        cmd += ["--dump", dump, "--float64"]
    env = dict(os.environ, NUMBA_NUM_THREADS=str(args.threads),
               PYTHONPATH=os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]))
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if done.returncode:
        raise RuntimeError(done.stderr[-3000:])
    return json.loads(done.stdout.strip().splitlines()[-1])


def _line(name: str, r: dict) -> str:
    per_day = r["steps_s"] / r["days"]
    return (f"{name:<34} {r['wall_s']:8.1f} s wall {r['cpu_s']:8.1f} s CPU "
            f"{r['peak_rss_MB']:7.0f} MB peak | spin-up {r['spinup_s']:6.1f} s, tables "
            f"{r['forcing_s']:6.1f} s, steps {r['steps_s']:7.1f} s ({per_day:.2f} s/day), "
            f"outputs {r['outputs_s']:5.1f} s")


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--days", type=int, default=365)
    p.add_argument("--edge", type=float, default=2.0)
    p.add_argument("--window", type=int, default=1)
    p.add_argument("--peer-days", type=int, default=7)
    p.add_argument("--weather", default=None)
    p.add_argument("--temp-sea", type=float, default=287.0)
    p.add_argument("--date", default="2023-01-01")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--jobs", type=int, default=1,
                   help="also run the record split over this many processes (> 1)")
    p.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--dump", default=None, help=argparse.SUPPRESS)
    p.add_argument("--float64", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    args.weather = args.weather or _default_weather()
    if args.child:
        print(json.dumps(child(args)))
        return
    import numpy as np

    print(f"frigate at {args.edge:g} m, {Path(args.weather).name} from {args.date}, "
          f"numba threads {args.threads}, load {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        a, b = str(Path(tmp) / "daily.npy"), str(Path(tmp) / "one.npy")
        daily = _spawn(args, args.peer_days, 1, a)
        one = _spawn(args, args.peer_days, args.peer_days, b)
        diff = float(np.max(np.abs(np.load(a) - np.load(b))))
    print(f"peer: {args.peer_days} days in daily windows against one window "
          f"({daily['faces']} faces, {daily['cells']} cells)")
    print(_line(f"  daily windows ({args.peer_days} d)", daily))
    print(_line(f"  one window ({args.peer_days} d)", one))
    print(f"  ratio daily / one window: wall {daily['wall_s'] / one['wall_s']:.2f}, peak memory "
          f"{daily['peak_rss_MB'] / one['peak_rss_MB']:.2f}; largest |dT| of any face at any "
          f"output time {diff:.3g} K")
    if args.jobs > 1:
        with tempfile.TemporaryDirectory() as tmp:
            a, b = str(Path(tmp) / "split.npy"), str(Path(tmp) / "piece.npy")
            split = _spawn(args, args.days, 1, a, jobs=args.jobs)
            rec = _spawn(args, args.days, 1, b)
            diff = float(np.max(np.abs(np.load(a) - np.load(b))))
        print(f"record: {args.days} days split over {args.jobs} processes against one "
              f"piece, load {os.getloadavg()[0]:.1f}")
        print(_line(f"  split over {args.jobs} ({args.days} d)", split))
        print(f"  ratio split / one piece: wall {split['wall_s'] / rec['wall_s']:.2f}, peak "
              f"memory of the largest process {split['peak_rss_MB'] / rec['peak_rss_MB']:.2f};"
              f" largest |dT| of any face at any output time {diff:.3g} K")
    else:
        rec = _spawn(args, args.days, args.window)
    print(f"record: {args.days} days in windows of {args.window} day(s), load "
          f"{os.getloadavg()[0]:.1f}")
    print(_line(f"  record ({args.days} d)", rec))
    print(f"  {rec['steps'] / (args.days + rec['spinup_days'] + 0.25):.0f} steps a simulated "
          f"day; outputs file {rec['outputs_file_MB']:.0f} MB; thermal stage per recorded "
          f"day {rec['wall_s'] / args.days:.2f} s (daily-window peer of {args.peer_days} "
          f"days: {daily['wall_s'] / args.peer_days:.2f} s); peak memory against the "
          f"{args.peer_days}-day peer in one window {rec['peak_rss_MB'] / one['peak_rss_MB']:.2f}x")


if __name__ == "__main__":
    main()
