"""The time steps of a diurnal run: the lead-in before the first midnight, the long steps
of the night once no face has had short-wave for ``NIGHT_SETTLE``, and the stepping of a
simulation through its recording intervals.
"""

from __future__ import annotations

import numpy as np
from tqdm.auto import tqdm

from ..errors import require
from ..parameters import NIGHT_SETTLE
from ..units import DAY
from .settings import DiurnalSettings


#: Longest time step of the lead-in [s] (the run's own ``time_step`` when that is longer).
#: The lead-in is not recorded: it only has to bring the start-up error down, which decays
#: whatever the step. Measured on the built-in frigate at 0.5 m (summer, 300 s day steps):
#: 6 h of lead-in in 24 steps of 900 s instead of 72 of 300 s took 7.2 s instead of
#: 17.2 s; the defect of the recorded day rose from 0.0029 K to 0.0040 K and its face
#: temperatures moved by at most 1.1e-3 K (1800 s steps: 0.0084 K and 5.5e-3 K, too close
#: to the default 0.01 K spin-up tolerance).
SPINUP_LEAD_IN_STEP = 900.0


def lead_in_seconds(settings: DiurnalSettings) -> float:
    """The lead-in of a run [s]: ``settings.lead_in`` rounded up to whole output intervals
    (so that the step grid and the recording grid stay aligned with midnight)."""
    k = np.ceil(settings.lead_in / settings.output_interval - 1e-9)
    return float(min(k * settings.output_interval, DAY - settings.output_interval))


def lead_in_step(settings: DiurnalSettings) -> float:
    """The time step of the lead-in [s]: the longest step up to ``SPINUP_LEAD_IN_STEP`` that
    divides the recording interval (hence the lead-in, whole intervals long), and never
    shorter than ``settings.time_step``."""
    h, iv = settings.time_step, settings.output_interval
    if lead_in_seconds(settings) == 0.0 or h >= SPINUP_LEAD_IN_STEP:
        return float(h)
    return max(h, iv / np.ceil(iv / SPINUP_LEAD_IN_STEP - 1e-9))


def settle_intervals(settings: DiurnalSettings) -> int:
    """``NIGHT_SETTLE`` in whole recording intervals (rounded up)."""
    return int(np.ceil(NIGHT_SETTLE / settings.output_interval - 1e-9))


def night_steps(settings: DiurnalSettings, dark, previous_step: float | None = None) -> np.ndarray:
    """Time step of each recording interval of a day [s].

    Parameters
    ----------
    settings : DiurnalSettings
    dark : (n,) bool
        Whether each recording interval (``output_interval`` long) is free of short-wave:
        the ``NIGHT_SETTLE`` before the day first (rounded up to whole intervals), then the
        day's.
    previous_step : float, optional
        The step taken just before the day [s] (default ``time_step``).

    An interval takes the night step (the longest multiple of ``time_step`` up to
    ``settings.night_step`` that divides the interval) when it and the ``NIGHT_SETTLE``
    before it are dark, ``time_step`` otherwise. A step at most doubles from the last (BDF2's
    zero-stability), so the first night interval takes the longest step up to twice the
    last that divides the recording interval.
    """
    iv, h = settings.output_interval, settings.time_step
    settle = settle_intervals(settings)
    dark = np.asarray(dark, bool)
    n_day = len(dark) - settle
    require(n_day >= 1, "dark", len(dark),
            f"must cover the day and the {settle} interval(s) before it")
    steps = np.full(n_day, h)
    candidates = h * np.arange(1, int(settings.night_step / h * (1 + 1e-12)) + 1)
    candidates = candidates[np.abs(iv / candidates - np.round(iv / candidates)) < 1e-9]
    if len(candidates) <= 1:
        return steps
    prev = h if previous_step is None else float(previous_step)
    for b in range(n_day):
        if dark[b: b + settle + 1].all():
            steps[b] = candidates[candidates <= 2.0 * prev * (1 + 1e-12)].max()
        prev = steps[b]
    return steps


def dark_intervals(settings: DiurnalSettings, forcing, span: float = DAY,
                   start: float = 0.0) -> np.ndarray:
    """The ``dark`` argument of :func:`night_steps` for the ``span`` [s] (a day, or a window
    of a weather record) from ``start`` [s, on the recording grid] under ``forcing``:
    :meth:`ShipForcing.dark <shipthermal.forcing.ShipForcing.dark>` of each recording
    interval, the settle intervals before ``start`` first."""
    iv = settings.output_interval
    first = int(round(start / iv))
    starts = iv * np.arange(first - settle_intervals(settings), first + int(round(span / iv)))
    return np.array([forcing.dark(t, t + iv) for t in starts], bool)


def run_intervals(sim, steps, start: float, interval: float, desc: str, progress: bool,
                   after=None) -> None:
    """Step ``sim`` through consecutive recording intervals from ``start`` [s], interval k
    in steps of ``steps[k]``, with one progress bar; ``after()`` once after each interval."""
    with tqdm(total=int(round(np.sum(interval / steps))), unit="step", desc=desc,
              disable=not progress, leave=False) as bar:
        for k, dt in enumerate(steps):
            sim.set_time_step(dt)
            sim.run_until(start + (k + 1) * interval, progress=False)
            bar.update(int(round(interval / dt)))
            if after is not None:
                after()
