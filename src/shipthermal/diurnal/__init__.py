"""Diurnal ship thermal runs: spin-up over repeated design days, then one recorded day
(or, for a weather record, spin-up on its first day and then the record as it is).

Data flow (all the physics lives in the modules wired here)::

    ShipGeometry ──► shell cell graph (plate layups)                 geometry / mesh
    Environment  ──► per-face forcing tables + face-to-face exchange  forcing (Embree)
    graph + forcing ──► ThermalModel ──► Simulation (implicit, day after day)
    day k vs day k−1 part means  ──► converged?  ──► DiurnalResult (last day)

Spin-up: the run starts ``lead_in`` before the first midnight (the end of the design day,
from the initial temperature, in steps of up to ``SPINUP_LEAD_IN_STEP``), then the design
day repeats, in one simulation: BDF2 changes its step without restarting. By day the step
is ``time_step``; at night, once no face has absorbed short-wave for ``NIGHT_SETTLE``, it
grows to ``night_step`` (:func:`night_steps`). After each simulated day the
temperature of every cell at its end is compared with its start (the periodicity defect of
the day); the run stops when the largest change is below ``spinup_tolerance`` [K] (reported
with the number of days) or after ``spinup_max_days`` (reported as not converged). The
recorded day is the last one. The defect bounds the change to the next day at every time:
the difference of two solutions under the same forcing does not grow (conduction and
boundary flows that decrease with the surface temperature obey a maximum principle), so a
day that ends where it started is the periodic one to within that defect.

Weather records (non-periodic weather, :func:`run_record`): the record's first 24 h are
repeated as above until periodic; from that state the solver runs through the whole
record once, as recorded, window by window (forcing tables of the window, the solver's
state carried over; a checkpoint and a part of the outputs at each window's end). Every
output time of every recorded day is streamed to disk (:mod:`shipthermal.record_stream`), so a year
needs the memory of a window.

The package, one job per module: :mod:`.settings` (:class:`DiurnalSettings`),
:mod:`.stepping` (lead-in, night steps, stepping through recording intervals),
:mod:`.periodic` (the spin-up and recorded day), :mod:`.record` (weather records),
:mod:`.run` (:func:`run_diurnal`, the entry), :mod:`.result` (:class:`DiurnalResult` and its
products).
"""

from ..parameters import NIGHT_SETTLE, NIGHT_STEP
from .record import RECORD_WINDOW_DAYS, run_record
from .result import MAIN_SERIES, DiurnalResult, part_groups, plot_part_means
from .run import run_diurnal
from .settings import SPINUP_LEAD_IN, DiurnalSettings
from .stepping import (SPINUP_LEAD_IN_STEP, dark_intervals, lead_in_seconds, lead_in_step,
                       night_steps)

__all__ = ["DiurnalSettings", "DiurnalResult", "run_diurnal", "SPINUP_LEAD_IN",
           "SPINUP_LEAD_IN_STEP", "NIGHT_STEP", "NIGHT_SETTLE", "lead_in_seconds",
           "lead_in_step", "night_steps", "dark_intervals",
           "part_groups", "MAIN_SERIES", "run_record", "RECORD_WINDOW_DAYS",
           "plot_part_means"]
