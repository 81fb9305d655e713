"""The persistent thread pool of shipthermal._threads."""

import os
import threading

import pytest

from shipthermal._threads import SERIAL_BELOW_CELLS, kernel_threads, thread_map


def test_results_keep_the_order_of_the_items():
    assert thread_map(lambda x: x * x, range(10), 2) == [x * x for x in range(10)]
    assert thread_map(lambda x: x + 1, [], 2) == []


def test_one_thread_runs_in_the_caller():
    caller = threading.get_ident()
    assert thread_map(lambda _: threading.get_ident(), range(4), 1) == [caller] * 4


def test_the_pool_is_kept_and_bounded():
    seen = set()
    barrier = threading.Barrier(2, timeout=10)

    def work(_):
        barrier.wait()          # both workers are busy at once
        seen.add(threading.get_ident())

    thread_map(work, range(2), 2)
    started = threading.active_count()
    for _ in range(3):
        thread_map(work, range(4), 2)
    assert threading.active_count() == started
    assert len(seen) == 2


def test_a_nested_call_runs_in_the_worker():
    def inner(_):
        return threading.get_ident()

    def outer(_):
        return set(thread_map(inner, range(4), 2)) == {threading.get_ident()}

    assert all(thread_map(outer, range(4), 2))


def test_errors_reach_the_caller():
    def fail(x):
        if x == 3:
            raise ValueError("item 3")
        return x

    with pytest.raises(ValueError, match="item 3"):
        thread_map(fail, range(6), 2)


def test_idle_openmp_threads_sleep_unless_the_user_says_otherwise():
    # libgomp spinning beside a busy process made a 2-thread kernel 75x slower
    # (benchmarks/bench_threads.py); the package sets the wait policy before numba starts
    # its threads, and leaves a user's own choice alone
    import subprocess
    import sys

    code = ("import os, imaging.render, shipthermal.simulation; "
            "print(os.environ.get('OMP_WAIT_POLICY'))")
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True).stdout.split()
    assert out == ["PASSIVE"]
    out = subprocess.run([sys.executable, "-c", code], env={**env, "OMP_WAIT_POLICY": "ACTIVE"},
                         capture_output=True, text=True, check=True).stdout.split()
    assert out == ["ACTIVE"]


def test_small_models_step_on_one_thread_and_the_budget_comes_back():
    import numba

    budget = numba.get_num_threads()
    with kernel_threads(SERIAL_BELOW_CELLS - 1):
        assert numba.get_num_threads() == 1
    assert numba.get_num_threads() == budget
    with kernel_threads(SERIAL_BELOW_CELLS):
        assert numba.get_num_threads() == budget
    with pytest.raises(RuntimeError), kernel_threads(10):
        raise RuntimeError("a failed step")
    assert numba.get_num_threads() == budget

