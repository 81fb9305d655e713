"""The settings of a diurnal run: time stepping, spin-up, ray tracing and convection
choices (:class:`DiurnalSettings`) and the default lead-in before the first midnight.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from ..errors import check_positive, require
from ..forcing.build import ForcingSettings
from ..parameters import (DAY_STEP, NEWTON_ENERGY_TOLERANCE, NEWTON_SURFACE_TOLERANCE,
                          NEWTON_TOLERANCE, NIGHT_STEP, OUTPUT_INTERVAL, SPINUP_MAX_DAYS,
                          SPINUP_TOLERANCE)
from ..units import DAY


#: Default lead-in before the first simulated midnight [s]. The start-up error of the
#: plates decays within hours (the built-in frigate's day 3 repeated day 2 to 1e-13 K after
#: a day-2-vs-day-1 change of 2.7 K): 6 h from the day's mean air temperature leave a
#: defect below the default ``spinup_tolerance`` so that one recorded day suffices.
SPINUP_LEAD_IN = 6.0 * 3600.0


@dataclass(frozen=True)
class DiurnalSettings:
    """Time stepping and spin-up of a diurnal run.

    Attributes
    ----------
    time_step : float
        [s], divides 24 h.
    scheme : str
        ``backward_euler`` | ``crank_nicolson`` | ``bdf2``.
    output_interval : float
        Recording interval of the final day [s] (a multiple of ``time_step``).
    spinup_tolerance : float
        Largest change of any cell temperature over a day (end vs start) that counts as
        periodic [K].
    spinup_max_days : int
        Most days simulated (the lead-in not counted).
    lead_in : float
        Time simulated before the first midnight, from the initial temperature [s]
        (rounded up to whole output intervals); ``SPINUP_LEAD_IN`` by default.
    samples_per_face, rays_per_face, seed, backend
        Ray tracing (see :func:`shipthermal.forcing.build_ship_forcing`).
    convection : str or mapping
        Exterior convection model of the air faces, a name of
        :data:`shipthermal.environment.convection.CONVECTION_MODELS`, or ``{part: name}``.
    convection_roughness : str or mapping, optional
        Roughness class (per part) of the DOE-2 / TARP roughness multiplier (default
        :data:`shipthermal.parameters.CONVECTION_ROUGHNESS`).
    initial_temperature : float, optional
        Start temperature [K]; default the day's mean air temperature.
    night_step : float
        Longest time step of the night [s] (see ``NIGHT_STEP``): the night takes the longest
        multiple of ``time_step`` up to it that divides ``output_interval``. ``time_step``
        (or less) keeps the steps uniform.
    newton_tolerance, energy_tolerance, surface_tolerance : float
        Newton's stopping rule in every step: the estimated correction left [K], the
        step's energy residual relative to its gross boundary heat and the surface
        temperatures' last change relative to the largest (see
        :data:`~shipthermal.parameters.NEWTON_TOLERANCE`).
    jobs : int
        Processes a weather record is split over: contiguous segments of days, each spun
        up :data:`~shipthermal.parameters.RECORD_SEGMENT_WARM_DAYS` before its first day
        (:func:`~shipthermal.diurnal.record.run_record`); 1 runs the record in one piece.
        A periodic day ignores it.
    """

    time_step: float = DAY_STEP
    scheme: str = "bdf2"
    output_interval: float = OUTPUT_INTERVAL
    spinup_tolerance: float = SPINUP_TOLERANCE
    spinup_max_days: int = SPINUP_MAX_DAYS
    # (the ray tracing and convection defaults are the forcing build's own)
    samples_per_face: int = ForcingSettings.samples_per_face
    rays_per_face: int = ForcingSettings.rays_per_face
    seed: int = ForcingSettings.seed
    backend: str = ForcingSettings.backend
    convection: str | Mapping = ForcingSettings.convection
    convection_roughness: str | Mapping | None = None
    initial_temperature: float | None = None
    lead_in: float = SPINUP_LEAD_IN
    night_step: float = NIGHT_STEP
    newton_tolerance: float = NEWTON_TOLERANCE
    energy_tolerance: float = NEWTON_ENERGY_TOLERANCE
    surface_tolerance: float = NEWTON_SURFACE_TOLERANCE
    jobs: int = 1

    def __post_init__(self):
        check_positive("time_step", self.time_step, "s")
        k = DAY / self.time_step
        require(abs(k - round(k)) < 1e-9, "time_step", self.time_step,
                "must divide 24 h (86400 s) into whole steps", "e.g. 60, 120, 300, 600, 900")
        check_positive("spinup_tolerance", self.spinup_tolerance, "K")
        require(int(self.spinup_max_days) >= 1, "spinup_max_days", self.spinup_max_days, "must be ≥ 1")
        require(0.0 <= self.lead_in < DAY, "lead_in", self.lead_in, "must lie in [0, 86400) s")
        check_positive("night_step", self.night_step, "s")
        check_positive("newton_tolerance", self.newton_tolerance, "K")
        check_positive("energy_tolerance", self.energy_tolerance)
        check_positive("surface_tolerance", self.surface_tolerance)
        require(int(self.jobs) == self.jobs and int(self.jobs) >= 1, "jobs", self.jobs,
                "must be a whole number ≥ 1")
