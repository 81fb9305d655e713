"""Time tables of the forcing: the table times of a periodic design day or of a weather
record, and the linear interpolation between them.

A design day's table is periodic (:class:`PeriodicTable`: ``t`` folded modulo 86 400 s, so
day k of a spin-up sees exactly day 0's forcing); a weather record's is not
(:class:`RecordTable`: seconds after the record's start, over the whole record or a window
of it). Values are exact at the table times.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import check_range, require
from ..units import DAY, fold_time

MAX_TABLE_GAP = 3600.0
"""Largest allowed step between table times (with the wrap from the last to the first
time of the next day) [s]: the sun moves 15° per hour, so linear interpolation of lit
fractions across longer gaps would smear the shadows."""


def _check_times(times) -> np.ndarray:
    """Table times folded into [0, DAY), strictly increasing, covering the day."""
    t = np.atleast_1d(np.asarray(times, dtype=float))
    require(t.ndim == 1 and len(t) >= 2, "times", t,
            "must be a 1-D array of at least two times [s after local midnight]")
    check_range("times", t, 0.0, DAY, "s")
    require(bool(np.all(np.diff(t) > 0)), "times", t, "must be strictly increasing")
    if t[-1] == DAY:
        # 86 400 s is midnight of the next day: the same instant as 0 after folding
        t = t[:-1] if t[0] == 0.0 else np.concatenate([[0.0], t[:-1]])
    gaps = np.diff(np.concatenate([t, [t[0] + DAY]]))
    worst = int(np.argmax(gaps))
    require(len(t) >= 2 and gaps[worst] <= MAX_TABLE_GAP, "times",
            f"{len(t)} times, largest gap {gaps[worst]:.0f} s after t = {t[worst]:.0f} s",
            f"must cover the whole day [0, 86400) s with gaps (also from the last time to "
            f"the first time + 86400 s) of at most {MAX_TABLE_GAP:.0f} s",
            "Pass e.g. times=numpy.arange(0, 86400, 600.0)")
    return t


@dataclass(frozen=True)
class PeriodicTable:
    """Linear interpolation in a periodic table of times.

    Attributes
    ----------
    times : (n,) float
        Strictly increasing times in [0, period) [s].
    period : float
        [s].
    """

    times: np.ndarray
    period: float = DAY

    def weights(self, t: float) -> tuple[int, int, float]:
        """Rows ``i``, ``j`` and weight ``w`` with value(t) = (1 − w) row_i + w row_j.

        ``t`` is folded modulo the period (``np.mod`` of floats is exact, so t and
        t + k·period give the same rows and weight).
        """
        tf = float(fold_time(float(t), self.period))
        tt = self.times
        n = len(tt)
        i = int(np.searchsorted(tt, tf, side="right")) - 1
        if i < 0:  # before the first time: interval from the previous day's last time
            i = n - 1
            tf += self.period
        j = i + 1
        if j < n:
            t_j = tt[j]
        else:
            j = 0
            t_j = tt[0] + self.period
        w = (tf - tt[i]) / (t_j - tt[i])
        return i, j, w

    def __call__(self, table: np.ndarray, t: float):
        """Interpolate ``table`` (n, ...) at ``t`` (float64 result)."""
        i, j, w = _weights_at(self, t)
        if w == 0.0:
            return np.asarray(table[i], dtype=np.float64).copy() if np.ndim(table) > 1 \
                else float(table[i])
        a = np.asarray(table[i], dtype=np.float64)
        b = np.asarray(table[j], dtype=np.float64)
        out = a * (1.0 - w) + b * w
        return out if out.ndim else float(out)


def _weights_at(table, t):
    """``table.weights(t)``, remembered for the last ``t``: the solver asks every table of a
    ship (40 per step) at one time in turn, and a search costs 50 µs (10 % of a weather
    record's steps at 2 m)."""
    last = table.__dict__.get("_last")
    if last is not None and last[0] == t:
        return last[1]
    out = table.weights(t)
    object.__setattr__(table, "_last", (t, out))
    return out


@dataclass(frozen=True)
class RecordTable:
    """Linear interpolation in a table of times over a weather record (not periodic).

    Same interface as :class:`PeriodicTable`; times outside ``[times[0], times[-1]]`` take
    the end rows (the solver never asks for them: the record covers the run).

    Attributes
    ----------
    times : (n,) float
        Strictly increasing times [s after the environment start].
    """

    times: np.ndarray

    @property
    def period(self) -> float:
        """Span of the table [s] (the averaging time of the summaries)."""
        return float(self.times[-1] - self.times[0])

    def weights(self, t: float) -> tuple[int, int, float]:
        tt = self.times
        tf = min(max(float(t), float(tt[0])), float(tt[-1]))
        i = int(np.clip(np.searchsorted(tt, tf, side="right") - 1, 0, len(tt) - 2))
        return i, i + 1, (tf - tt[i]) / (tt[i + 1] - tt[i])

    __call__ = PeriodicTable.__call__


def _check_record_times(times, span: float, window=None) -> np.ndarray:
    """Table times over a weather record: increasing, from 0 to ``span`` (or over the
    ``window`` ``(start, end)`` [s] of it), small gaps."""
    t = np.atleast_1d(np.asarray(times, dtype=float))
    require(t.ndim == 1 and len(t) >= 2 and bool(np.all(np.diff(t) > 0)), "times", t,
            "must be a strictly increasing 1-D array of at least two times [s]")
    if window is None:
        require(t[0] <= 0.0 and t[-1] >= span - 1e-6, "times", f"{t[0]:g} … {t[-1]:g} s",
                f"must cover the weather record, 0 … {span:g} s")
    else:
        lo, hi = (float(x) for x in window)
        require(0.0 <= lo < hi <= span + 1e-6, "window", window,
                f"must be (start, end) within the weather record, 0 … {span:g} s")
        require(t[0] <= lo and t[-1] >= hi - 1e-6, "times", f"{t[0]:g} … {t[-1]:g} s",
                f"must cover the window {lo:g} … {hi:g} s of the weather record")
    require(float(np.max(np.diff(t))) <= MAX_TABLE_GAP, "times", float(np.max(np.diff(t))),
            f"gaps must be at most {MAX_TABLE_GAP:.0f} s")
    return t


def table_times(environment, times, window=None):
    """The checked table times of ``environment``'s weather and their interpolator: a
    design day's (default every 600 s) or a weather record's, whole or over ``window``
    (see :func:`~shipthermal.forcing.build.build_ship_forcing`)."""
    w = environment.weather
    if w.periodic:
        require(window is None, "window", window, "is for weather records only (a periodic "
                "day's table covers its day)")
        require(abs(w.period - DAY) < 1e-6, "environment.weather.period", w.period,
                "must be 86400 s (one day)")
        times = _check_times(np.arange(0.0, DAY, 600.0) if times is None else times)
        return times, PeriodicTable(times)
    # a weather record: one table over the whole record or over a window of it (t = seconds
    # after its start)
    span = (w.time[-1] - environment.start).total_seconds()
    times = _check_record_times(np.arange(0.0, span + 1.0, 600.0) if times is None
                                else times, span, window)
    return times, RecordTable(times)
