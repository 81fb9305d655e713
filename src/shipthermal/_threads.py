"""A persistent pool of worker threads for array work that releases the GIL.

Embree queries and large numpy expressions release the GIL, so a few Python threads run
them in parallel. A new executor for every call starts its threads again: 0.17–0.29 ms for
two threads against 0.05 ms for a call into a running pool (measured on a 2-core machine),
paid at every large call of the tracer, a few hundred in the forcing of a ship. The pool
here is made once per thread count and kept for the life of the process.

The thread count is the caller's (numba's budget, ``numba.get_num_threads()``, which a sweep
pins to one per case: then no thread is started at all). A task running on a worker of the
pool that asks for threads again runs its items itself, one after the other: the budget is
already in use, and a worker waiting on its own pool could wait forever. A process forked
from this one (multiprocessing, dask) starts with no pool and makes its own.
"""

from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor

import numba

__all__ = ["thread_map", "kernel_threads", "numba_threads", "SERIAL_BELOW_CELLS"]

#: Below this many cells a time loop's numba kernels run on one thread. A kernel of a few
#: 10⁴ cells takes tens of µs, about what waking a second thread and joining it costs;
#: measured on this 2-core machine, the built-in frigate's summer day (time loop): 16,284
#: cells (2 m) 2.89 s on one thread against 3.62 s on two, 55,320 cells (1 m) 9.56 s
#: against 8.15 s, 197,440 cells (0.5 m) 42.2 s against 30.7 s.
SERIAL_BELOW_CELLS = 30_000

_lock = threading.Lock()
_pools: dict[int, ThreadPoolExecutor] = {}
_worker = threading.local()


def _mark_worker():
    _worker.in_pool = True


def _forget_pools():
    """In a forked child: the parent's workers do not exist here."""
    global _lock
    _lock = threading.Lock()
    _pools.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pools)


def _pool(n_threads: int) -> ThreadPoolExecutor:
    """The pool of ``n_threads`` workers, made on first use (workers start on demand)."""
    with _lock:
        pool = _pools.get(n_threads)
        if pool is None:
            pool = _pools[n_threads] = ThreadPoolExecutor(
                n_threads, thread_name_prefix=f"shipthermal-{n_threads}",
                initializer=_mark_worker)
        return pool


@contextlib.contextmanager
def numba_threads(n: int):
    """numba's kernels on at most ``n`` threads while in the block; the caller's budget,
    ``numba.get_num_threads()``, after."""
    before = numba.get_num_threads()
    n = max(1, min(int(n), before))
    if n == before:
        yield
        return
    numba.set_num_threads(n)
    try:
        yield
    finally:
        numba.set_num_threads(before)


def kernel_threads(n_cells: int, serial_below: int | None = None):
    """numba's kernels on one thread while in the block when ``n_cells`` is below
    ``serial_below`` (default :data:`SERIAL_BELOW_CELLS`); otherwise (and after) the
    caller's budget (which a sweep pins to one per case)."""
    limit = SERIAL_BELOW_CELLS if serial_below is None else int(serial_below)
    return numba_threads(1 if int(n_cells) < limit else numba.get_num_threads())


def thread_map(fn: Callable, items: Iterable, n_threads: int) -> list:
    """``[fn(item) for item in items]`` on at most ``n_threads`` threads of the pool.

    Parameters
    ----------
    fn : callable
        Applied to each item; should spend its time in code that releases the GIL.
    items : iterable
    n_threads : int
        Threads to use. With one (or one item, or when called from a worker of the pool)
        the items run in the calling thread.

    Returns
    -------
    list
        The results in the order of ``items``; the first exception raised by ``fn`` is
        raised here.
    """
    items = list(items)
    n_threads = int(n_threads)
    if n_threads <= 1 or len(items) <= 1 or getattr(_worker, "in_pool", False):
        return [fn(item) for item in items]
    return list(_pool(n_threads).map(fn, items))
