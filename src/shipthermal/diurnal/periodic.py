"""The periodic run: spin-up over the repeated design day, then the recorded day.

The run starts ``lead_in`` before the first midnight (the end of the design day, from the
initial temperature, in steps of up to ``SPINUP_LEAD_IN_STEP``), then the design day
repeats, in one simulation, until the day's periodicity defect is below
``spinup_tolerance`` or ``spinup_max_days`` have been simulated; the last day is the
recorded one. The steps: :func:`build_mesh`, :func:`run_forcing`,
:func:`initial_temperature`, the simulation, :func:`run_lead_in` (or :func:`resume_spin_up`
from a checkpoint), :func:`step_plans`, :func:`run_days`, :func:`recorded_day`.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .. import geometry
from ..errors import require
from ..forcing.build import ForcingSettings, build_ship_forcing
from ..parameters import NIGHT_SETTLE
from ..results import EnergyLog, Results
from ..units import DAY, HOUR
from .result import DiurnalResult, concat_energy, part_groups, part_mean_table
from .settings import DiurnalSettings
from .stepping import dark_intervals, lead_in_seconds, lead_in_step, night_steps, run_intervals


def run_periodic(ship, environment, settings: DiurnalSettings, *, absorptivity=None,
                 emissivity=None, graph=None, traced=None, progress: bool = True,
                 checkpoint=None, checkpoint_interval: float = HOUR, resume: bool = False,
                 log=None, initial_state=None) -> DiurnalResult:
    """Spin a ship up under a periodic design day and record the converged day.

    The periodic case of :func:`~shipthermal.diurnal.run.run_diurnal` (its parameters; the
    weather of ``environment`` must be periodic).
    """
    say = log or (lambda msg: None)
    t_total = _time.perf_counter()
    timings = {}
    graph = build_mesh(ship, graph, timings, say)

    t0 = _time.perf_counter()
    table_times = np.arange(0.0, DAY, min(600.0, settings.output_interval))
    forcing = run_forcing(ship, environment, graph, settings, absorptivity, emissivity,
                          times=table_times, traced=traced, progress=progress)
    timings["forcing"] = _time.perf_counter() - t0
    say(f"forcing: ray tracing and tables ({timings['forcing']:.1f} s)")

    temp0 = initial_temperature(graph, environment, settings, initial_state)
    lead = lead_in_seconds(settings) if initial_state is None else 0.0
    run = SpinUp(sim=_simulation(graph, forcing, temp0, settings, lead))
    resuming = resume and checkpoint is not None and Path(checkpoint).exists()
    t0 = _time.perf_counter()
    if lead > 0.0 and not resuming:
        run_lead_in(run, settings, lead, progress, say)
    if resuming:
        resume_spin_up(run, checkpoint, say)
    plans = step_plans(settings, forcing, lead, say)
    converged, res = run_days(run, plans, settings, checkpoint, checkpoint_interval, progress,
                              say)
    timings["solve"] = _time.perf_counter() - t0
    # the solver's own timers and counters, lead-in included
    timings["solver_detail"] = {k: float(v) for k, v in res.timing.items()}

    rec, pm = recorded_day(res, run.day, environment, graph)
    timings["total"] = _time.perf_counter() - t_total
    energy = concat_energy(run.energy_parts)
    return DiurnalResult(ship=ship, graph=graph, forcing=forcing, results=rec, part_means=pm,
                         days=run.day, day_changes=run.day_changes, converged=converged,
                         energy=energy, timings=timings, settings=settings,
                         environment=environment)


def build_mesh(ship, graph, timings: dict, say):
    """``graph``, or the shell graph of ``ship`` built from its layups (its time in
    ``timings['mesh']``)."""
    t0 = _time.perf_counter()
    if graph is None:
        graph, _ = geometry.build_ship_mesh(ship)   # through the module: tests replace it
    timings["mesh"] = _time.perf_counter() - t0
    say(f"mesh: {ship.n_faces} surface faces, {graph.n_cells} cells ({timings['mesh']:.1f} s)")
    return graph


def run_forcing(ship, environment, graph, settings: DiurnalSettings, absorptivity, emissivity,
                *, times, traced, progress, window=None):
    """The forcing tables of a run at ``times`` (:func:`~shipthermal.forcing.build.
    build_ship_forcing` with the run's ray tracing and convection settings)."""
    options = ForcingSettings(samples_per_face=settings.samples_per_face,
                              rays_per_face=settings.rays_per_face, seed=settings.seed,
                              absorptivity=absorptivity, emissivity=emissivity,
                              backend=settings.backend, convection=settings.convection,
                              roughness=settings.convection_roughness)
    return build_ship_forcing(ship, environment, graph, options, times=times, window=window,
                              progress=progress, traced=traced)


def initial_temperature(graph, environment, settings: DiurnalSettings,
                        initial_state=None) -> np.ndarray:
    """Start temperature of every cell [K]: ``initial_state`` if given, else
    ``settings.initial_temperature`` (default the day's mean air temperature) with the
    wetted plates at the day's mean sea temperature."""
    env_day = environment.at(np.arange(0.0, DAY + 1.0, settings.output_interval))
    t_init = settings.initial_temperature or float(np.mean(env_day.temp_air))
    # Wetted plates start at the sea temperature (they follow it closely).
    temp0 = np.full(graph.n_cells, t_init)
    wetted = [k for k, n in enumerate(graph.part_names) if n.startswith("hull_wetted")]
    if wetted:
        temp0[np.isin(graph.cell_part, wetted)] = float(np.mean(env_day.temp_sea))
    if initial_state is not None:
        temp0 = np.asarray(initial_state, dtype=float)
        require(temp0.shape == (graph.n_cells,), "initial_state", temp0.shape,
                f"must hold one temperature per cell ({graph.n_cells})")
    return temp0


def _simulation(graph, forcing, temp0, settings: DiurnalSettings, lead: float):
    """One simulation from the start of the lead-in: the steps change length (lead-in,
    night) without restarting the scheme."""
    # deferred: the solver (model, simulation, linear: 35 ms, measured) stays out of every
    # command's start-up, which loads diurnal through app.thermal
    from ..model import RadiativeExchange, ThermalModel
    from ..simulation import Simulation

    conditions = forcing.conditions(with_exchange=True)
    exchange = RadiativeExchange(*forcing.radiative_exchange())
    model = ThermalModel(graph, conditions, initial_temperature=temp0, exchange=exchange)
    return Simulation(model, settings.time_step, int(settings.spinup_max_days) * DAY,
                      start_time=-lead, scheme=settings.scheme,
                      output_interval=settings.output_interval,
                      tolerance=settings.newton_tolerance,
                      energy_tolerance=settings.energy_tolerance,
                      surface_tolerance=settings.surface_tolerance)


@dataclass(eq=False)
class SpinUp:
    """A spin-up between its steps: the simulation, the days simulated, their periodicity
    defects [K], the cell temperatures at the start of the current day and the energy
    logs of the stretches done."""

    sim: object
    day: int = 0
    day_changes: list = field(default_factory=list)
    day_start: np.ndarray | None = None
    energy_parts: list = field(default_factory=list)

    def save(self, checkpoint, day_idx: int) -> None:
        """Checkpoint the simulation with the spin-up's bookkeeping (nothing without a
        ``checkpoint`` path)."""
        if checkpoint is None:
            return
        done = concat_energy(self.energy_parts)
        extra = {"day": day_idx, "day_changes": np.array(self.day_changes, float),
                 "day_start": self.day_start if self.day_start is not None else np.zeros(0)}
        extra.update({f"energy_{k}": getattr(done, k) for k in EnergyLog.FIELDS})
        self.sim.save_checkpoint(checkpoint, extra=extra)


def run_lead_in(run: SpinUp, settings: DiurnalSettings, lead: float, progress: bool,
                say) -> None:
    """The lead-in: the end of the design day before the first recorded one, from the
    initial temperature, in steps of up to ``SPINUP_LEAD_IN_STEP`` (not recorded; its
    energy is logged)."""
    sim = run.sim
    step = lead_in_step(settings)
    sim.set_time_step(step)
    sim.run_until(0.0, progress=progress, desc="lead-in")
    run.energy_parts.append(sim.results().energy)
    sim.clear_records()
    say(f"lead-in: {lead / HOUR:g} h before the first day in {step:g} s steps")


def resume_spin_up(run: SpinUp, checkpoint, say) -> None:
    """The simulation and the spin-up's bookkeeping from ``checkpoint``."""
    extra = run.sim.load_checkpoint(checkpoint)
    run.day = int(extra["day"])
    run.day_changes = [float(x) for x in extra["day_changes"]]
    run.day_start = extra["day_start"] if extra["day_start"].size else None
    run.energy_parts = [EnergyLog(*[np.asarray(extra[f"energy_{k}"], float)
                                    for k in EnergyLog.FIELDS])] if "energy_time" in extra else []
    say(f"resumed from {checkpoint} at t = {run.sim.time / HOUR:.2f} h (day {run.day + 1})")


def step_plans(settings: DiurnalSettings, forcing, lead: float, say) -> list:
    """The time step of every recording interval of the first day (after the lead-in's
    steps) and of the days after it (after the last day's): the design day repeats."""
    iv = settings.output_interval
    dark = dark_intervals(settings, forcing)
    plans = [night_steps(settings, dark,
                         lead_in_step(settings) if lead > 0.0 else settings.time_step)]
    plans.append(night_steps(settings, dark, plans[0][-1]))
    if np.any(plans[0] != settings.time_step):
        say(f"steps: {int(round(np.sum(iv / plans[0])))} a day ({settings.time_step:g} s; "
            f"{np.max(plans[0]):g} s from {NIGHT_SETTLE / HOUR:g} h after the last "
            "short-wave)")
    return plans


def run_days(run: SpinUp, plans: list, settings: DiurnalSettings, checkpoint,
             checkpoint_interval: float, progress: bool, say):
    """Simulate design days until one is periodic to ``settings.spinup_tolerance`` or
    ``settings.spinup_max_days`` are done; whether it converged and the last day's
    :class:`~shipthermal.results.Results`."""
    sim = run.sim
    days_max = int(settings.spinup_max_days)
    iv = settings.output_interval
    converged = False
    res = None
    while run.day < days_max:
        day = run.day
        day_end = (day + 1) * DAY
        if abs(sim.time - day * DAY) < 1e-6:
            sim.clear_records()
            sim.record_now()
            run.day_start = sim.temperature
        plan = plans[min(day, 1)]
        first = int(round((sim.time - day * DAY) / iv))
        last_save = sim.time

        def checkpoint_due(day=day, day_end=day_end):
            nonlocal last_save
            if (checkpoint is not None and sim.time < day_end - 1e-6
                    and sim.time - last_save >= checkpoint_interval - 1e-6):
                run.save(checkpoint, day)
                last_save = sim.time

        run_intervals(sim, plan[first:], sim.time, iv, f"day {day + 1}", progress,
                      checkpoint_due)
        res = sim.results()
        run.energy_parts.append(res.energy)
        # Periodicity defect of the day: the largest change of any cell temperature from
        # its start to its end. The difference between two solutions under the same
        # forcing does not grow (maximum principle of conduction with boundary flows that
        # decrease with the surface temperature), so the next day would differ from this
        # one by at most this much at every time: it bounds the day-to-day change.
        change = float(np.max(np.abs(sim.temperature - run.day_start)))
        run.day_changes.append(change)
        say(f"day {day + 1}: largest cell-temperature change over the day {change:.4f} K")
        run.day += 1
        if change <= settings.spinup_tolerance:
            converged = True
            break
        if run.day < days_max:
            run.save(checkpoint, run.day)
    return converged, res


def recorded_day(res: Results, days: int, environment, graph):
    """The last simulated day (of ``days``) on the local clock and its part-mean table
    (indexed by local hour)."""
    offset = (days - 1) * DAY
    rec = Results(graph=res.graph, times=res.times - offset, cell_temperature=res.cell_temperature,
                  face_temperature=res.face_temperature, face_flow=res.face_flow,
                  energy=res.energy, scheme=res.scheme, time_step=res.time_step,
                  timing=res.timing, backend=res.backend)
    pm = part_mean_table(rec, part_groups(graph.part_names), environment)
    pm.index = pd.Index(rec.times / HOUR, name="hour")
    return rec, pm
