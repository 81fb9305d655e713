"""Numba's parallel kernels beside a busy process: idle OpenMP threads asleep (the product's
setting, ``shipthermal.OMP_WAIT_POLICY``) against libgomp's default spinning (the peer), in
the same run.

Run: ``python benchmarks/bench_threads.py [--launches 5000] [--size 16000]``

Each measurement is a fresh process (libgomp reads its wait policy once): ``--launches``
calls of a two-thread element-wise kernel over ``--size`` float64 values (the size of a 2 m
frigate's cell arrays), timed quiet and again while a second process keeps one core busy
(what a sweep's other worker, a test run or any other job does on a 2-core machine).
Prints wall and CPU time per launch and the ratio spinning / passive.

Not a test. Timings move with the machine's load (printed).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import subprocess
import sys
import time

CHILD = r"""
import json, sys, time
import numpy as np
from numba import njit, prange, set_num_threads, threading_layer

@njit(parallel=True)
def kernel(a, b):
    for i in prange(a.size):
        b[i] = a[i] * 1.0001 + 0.5

n, size = int(sys.argv[1]), int(sys.argv[2])
set_num_threads(2)
a = np.ones(size)
b = np.empty_like(a)
kernel(a, b)
t, c = time.perf_counter(), time.process_time()
for _ in range(n):
    kernel(a, b)
print(json.dumps({"wall": time.perf_counter() - t, "cpu": time.process_time() - c,
                  "layer": threading_layer()}))
"""


def _busy(stop):
    x = 0
    while not stop.is_set():
        for _ in range(100_000):
            x += 1


def _measure(policy: str | None, launches: int, size: int) -> dict:
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    if policy is not None:
        env["OMP_WAIT_POLICY"] = policy
    out = subprocess.run([sys.executable, "-c", CHILD, str(launches), str(size)], env=env,
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--launches", type=int, default=5000)
    p.add_argument("--size", type=int, default=16000)
    args = p.parse_args(argv)
    print(f"{args.launches} launches of a 2-thread kernel over {args.size} values, "
          f"{os.cpu_count()} CPUs, load {os.getloadavg()[0]:.1f}")
    rows = {}
    for load in ("quiet", "one core busy"):
        stop = mp.Event()
        busy = mp.Process(target=_busy, args=(stop,)) if load != "quiet" else None
        if busy:
            busy.start()
            time.sleep(0.5)
        try:
            for name, policy in (("passive (shipthermal)", "PASSIVE"),
                                 ("spinning (libgomp default)", None)):
                r = rows[(load, name)] = _measure(policy, args.launches, args.size)
                print(f"  {load:14s} {name:27s} {r['layer']:4s} "
                      f"{1e6 * r['wall'] / args.launches:9.1f} us wall "
                      f"{1e6 * r['cpu'] / args.launches:9.1f} us CPU per launch")
        finally:
            if busy:
                stop.set()
                busy.join()
    for load in ("quiet", "one core busy"):
        ratio = (rows[(load, "spinning (libgomp default)")]["wall"]
                 / rows[(load, "passive (shipthermal)")]["wall"])
        print(f"ratio spinning / passive, {load}: {ratio:.2f}")


if __name__ == "__main__":
    main()
