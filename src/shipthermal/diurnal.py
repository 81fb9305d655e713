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
output time of every recorded day is streamed to disk (:mod:`.record_stream`), so a year
needs the memory of a window.
"""

from __future__ import annotations

import json
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np
import pandas as pd

from . import geometry
from .errors import check_positive, require
from .figures import LINE_STYLES, PART_LINE_STYLES, save_figure
from .geometry import main_part
from .geometry.surface_maps import render_surface_map
from .parameters import DEFAULT_CONVECTION_MODEL, NIGHT_SETTLE, NIGHT_STEP
from .record_stream import RecordFile, RecordParts, assemble, in_sample, sample_days
from .results import EnergyLog, Results, atomic_path, graph_vtkhdf, write_surface_vtkhdf
from .units import DAY, HOUR, with_units

__all__ = ["DiurnalSettings", "DiurnalResult", "run_diurnal", "SPINUP_LEAD_IN",
           "SPINUP_LEAD_IN_STEP", "NIGHT_STEP", "NIGHT_SETTLE", "lead_in_seconds",
           "lead_in_step", "night_steps", "dark_intervals",
           "part_groups", "MAIN_SERIES"]

#: Default lead-in before the first simulated midnight [s]. The start-up error of the
#: plates decays within hours (the built-in frigate's day 3 repeated day 2 to 1e-13 K after
#: a day-2-vs-day-1 change of 2.7 K): 6 h from the day's mean air temperature leave a
#: defect below the default ``spinup_tolerance`` so that one recorded day suffices.
SPINUP_LEAD_IN = 6.0 * 3600.0

#: Longest time step of the lead-in [s] (the run's own ``time_step`` when that is longer).
#: The lead-in is not recorded: it only has to bring the start-up error down, which decays
#: whatever the step. Measured on the built-in frigate at 0.5 m (summer, 300 s day steps):
#: 6 h of lead-in in 24 steps of 900 s instead of 72 of 300 s took 7.2 s instead of
#: 17.2 s; the defect of the recorded day rose from 0.0029 K to 0.0040 K and its face
#: temperatures moved by at most 1.1e-3 K (1800 s steps: 0.0084 K and 5.5e-3 K, too close
#: to the default 0.01 K spin-up tolerance).
SPINUP_LEAD_IN_STEP = 900.0

#: Columns of the part-mean table, in plotting order
MAIN_SERIES = ("hull", "deck", "superstructure", "hull_wetted")


def part_groups(part_names) -> dict:
    """Pool sub-parts for reporting: ``hull_dry`` → ``hull`` (the visible hull),
    ``hull_wetted`` stays, ``superstructure_mast`` → ``superstructure``."""
    out = {}
    for name in part_names:
        main = main_part(name)
        out[name] = "hull" if main in ("hull_dry", "hull") else main
    return out


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
    """

    time_step: float = 300.0
    scheme: str = "bdf2"
    output_interval: float = 1800.0
    spinup_tolerance: float = 0.01
    spinup_max_days: int = 10
    samples_per_face: int = 16
    rays_per_face: int = 256
    seed: int = 0
    backend: str = "auto"
    convection: str | Mapping = DEFAULT_CONVECTION_MODEL
    convection_roughness: str | Mapping | None = None
    initial_temperature: float | None = None
    lead_in: float = SPINUP_LEAD_IN
    night_step: float = NIGHT_STEP

    def __post_init__(self):
        check_positive("time_step", self.time_step, "s")
        k = DAY / self.time_step
        require(abs(k - round(k)) < 1e-9, "time_step", self.time_step,
                "must divide 24 h (86400 s) into whole steps", "e.g. 60, 120, 300, 600, 900")
        check_positive("spinup_tolerance", self.spinup_tolerance, "K")
        require(int(self.spinup_max_days) >= 1, "spinup_max_days", self.spinup_max_days, "must be ≥ 1")
        require(0.0 <= self.lead_in < DAY, "lead_in", self.lead_in, "must lie in [0, 86400) s")
        check_positive("night_step", self.night_step, "s")


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


def _settle_intervals(settings: DiurnalSettings) -> int:
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
    settle = _settle_intervals(settings)
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
    starts = iv * np.arange(first - _settle_intervals(settings), first + int(round(span / iv)))
    return np.array([forcing.dark(t, t + iv) for t in starts], bool)


def _run_intervals(sim, steps, start: float, interval: float, desc: str, progress: bool,
                   after=None) -> None:
    """Step ``sim`` through consecutive recording intervals from ``start`` [s], interval k
    in steps of ``steps[k]``, with one progress bar; ``after()`` once after each interval."""
    from tqdm.auto import tqdm

    with tqdm(total=int(round(np.sum(interval / steps))), unit="step", desc=desc,
              disable=not progress, leave=False) as bar:
        for k, dt in enumerate(steps):
            sim.set_time_step(dt)
            sim.run_until(start + (k + 1) * interval, progress=False)
            bar.update(int(round(interval / dt)))
            if after is not None:
                after()


@dataclass(eq=False)
class DiurnalResult:
    """A converged (or capped) diurnal run: the last simulated day.

    Attributes
    ----------
    ship : ShipGeometry
    graph : CellGraph
    forcing : ShipForcing
    results : Results
        The recorded day with ``times`` in seconds after local midnight [s].
    part_means : pandas.DataFrame
        Area-mean outer-surface temperature per reporting part, plus ``temp_air``,
        ``temp_sea`` (bulk) and ``temp_sea_skin``, indexed by local hour [K].
    days : int
        Days simulated (spin-up included).
    day_changes : list of float
        Largest cell-temperature change over each day, end vs start [K] (the periodicity
        defect; it bounds the change to the following day).
    converged : bool
    energy : EnergyLog
        Every step of the whole run.
    timings : dict
        Wall times [s]: mesh, forcing (ray tracing + tables), solve, total.
    record : RecordFile, optional
        A weather record's outputs on disk (:func:`run_record`), read lazily; ``results``
        then holds the final state only and ``forcing`` the last window's tables.
    """

    ship: object
    graph: object
    forcing: object
    results: Results
    part_means: pd.DataFrame
    days: int
    day_changes: list
    converged: bool
    energy: EnergyLog
    timings: dict
    settings: DiurnalSettings
    environment: object = None
    meta: dict = field(default_factory=dict)
    record: object = None

    @property
    def n_surface_faces(self) -> int:
        return int(self.ship.n_faces)

    def __repr__(self) -> str:
        # the dataclass's own repr prints every array: a few lines instead
        kind = (f"{self.meta['record_days']} recorded days" if self.is_record
                else "one periodic day")
        return (f"DiurnalResult({self.ship.name}: {self.ship.n_faces} faces, "
                f"{self.graph.n_cells} cells; {kind} after {self.days} days, "
                f"{'converged' if self.converged else 'not converged'}; "
                f"{len(self.results.times)} outputs; parts {', '.join(self.part_means.columns)})")

    def part_mean_at(self, part: str, hour: float) -> float:
        """Area-mean outer temperature of a reporting part at a local hour [K] (linear)."""
        s = self.part_means[part]
        return float(np.interp(hour, s.index.to_numpy(), s.to_numpy()))

    def outer_face_temperature(self) -> np.ndarray:
        """(nt, M) outer-surface temperature of each ship triangle [K] (a weather record's:
        the streamed file's dataset, read as indexed)."""
        if self.record is not None:
            return self.record.face_temperature
        m = self.ship.n_faces
        return self.results.face_temperature[:, :m]

    @property
    def is_record(self) -> bool:
        """Whether this is a weather-record run (:func:`run_record`) over several days."""
        return "record_days" in self.meta

    def summary(self) -> dict:
        """JSON-ready summary (spin-up, energy, timings, part extremes)."""
        pm = self.part_means
        parts = {c: {"min_K": float(pm[c].min()), "max_K": float(pm[c].max()),
                     "hour_of_max": float(pm[c].idxmax())} for c in pm.columns}
        return {"ship": self.ship.name, "surface_faces": self.n_surface_faces,
                "edge_length_m": (float(self.ship.edge_length)
                                  if np.isfinite(self.ship.edge_length) else None),
                "cells": int(self.graph.n_cells), "days": self.days,
                "converged": self.converged,
                "day_changes_K": [None if not np.isfinite(x) else float(x) for x in self.day_changes],
                "spinup_tolerance_K": self.settings.spinup_tolerance,
                "energy": self.energy.summary(), "timings_s": self.timings, "parts": parts,
                "settings": {k: getattr(self.settings, k) for k in self.settings.__dataclass_fields__},
                **self.meta}

    # ------------------------------------------------------------------ outputs -----------
    def write(self, out_dir, map_hours=(7.0, 12.0), formats=("csv", "png", "vtkhdf", "json"),
              progress: bool = False, figures=None) -> dict:
        """Write the run's products into ``out_dir`` (each file atomically).

        * ``part_means.csv`` — hourly table of part means, air and sea [K] (headers
          ``name [unit]``, as every CSV product: docs/DATA.md);
        * ``part_means.png`` — 24 h curves of hull, deck, superstructure with air and sea;
        * ``surface_HHMM.png`` — the ship coloured by outer-surface temperature;
        * ``thermal.vtkhdf`` — the recorded day, cells (ParaView ≥ 5.12; the surface as a
          VTU series: ``results.to_vtu``);
        * ``surface.vtkhdf`` — the ship's outer surface over the recorded day: the
          temperature of every triangle the images are rendered from, with its part;
        * ``thermal_summary.json`` — spin-up, energy balance, timings.

        ``figures`` (:class:`shipthermal.figures.FigureOptions`): resolution and vector copies
        of the pictures. Returns a mapping product → path.
        """
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        written = {}
        if "csv" in formats:
            with atomic_path(out / "part_means.csv") as tmp:
                with_units(self.part_means, {c: "K" for c in self.part_means.columns}).to_csv(
                    tmp, float_format="%.4f")
            written["part_means_csv"] = out / "part_means.csv"
            fs = pd.DataFrame(self.forcing.summary()) if self.forcing is not None else None
            if fs is not None:
                with atomic_path(out / "forcing_summary.csv") as tmp:
                    with_units(fs).to_csv(tmp, float_format="%.5g")
                written["forcing_csv"] = out / "forcing_summary.csv"
        if "png" in formats:
            where = self.where()
            written["part_means_png"] = plot_part_means(self.part_means, out / "part_means.png",
                                                        title=f"{self.ship.name}: area-mean "
                                                        f"outer-surface temperature{where}",
                                                        figures=figures)
            env = self.environment
            heading = float(getattr(env, "ship_heading", 0.0))
            view = self.meta.get("sensor_view_deg") or (0.0, 0.0)
            clim = None
            if map_hours:
                allt = np.concatenate([self.face_temperature_at(h) for h in map_hours])
                clim = (float(np.percentile(allt, 1)), float(np.percentile(allt, 99)))
            for hour in map_hours:
                name = out / f"surface_{int(hour):02d}{int(round(60 * (hour % 1))):02d}.png"
                sun_az, sun_el = 180.0, -90.0
                if env is not None:
                    st = env.at([hour * HOUR])
                    sun_az, sun_el = float(st.azimuth[0]), 90.0 - float(st.zenith[0])
                render_surface_map(self.ship.vertices, self.ship.faces,
                                   self.face_temperature_at(hour), name, heading_deg=heading,
                                   sun_azimuth_deg=sun_az, sun_elevation_deg=sun_el,
                                   view_zenith_deg=view[0], view_azimuth_deg=view[1],
                                   clim=clim, title=f"{self.ship.name}, outer surface at "
                                   f"{_clock(hour)} local{where}", figures=figures)
                written[f"surface_{hour:g}h"] = name
        if "vtkhdf" in formats:
            start = getattr(self.environment, "start", None)
            units = f"s since {start.isoformat(sep=' ')}" if start is not None else None
            ship = self.ship
            m = ship.n_faces
            if self.record is not None:
                # the sampled days of a record (record_stream.SAMPLE_DAYS_MAX)
                rec = self.record
                times = rec.sample_times
                written["vtkhdf"] = graph_vtkhdf(out / "thermal.vtkhdf", self.graph, times,
                                                 lambda k: rec.sample_row(k)[0], time_units=units)
                outer = (lambda k: rec.sample_row(k)[1][:m])
            else:
                times = self.results.times
                written["vtkhdf"] = self.results.to_vtkhdf(out / "thermal.vtkhdf",
                                                           time_units=units)
                outer = self.outer_face_temperature()
            written["vtkhdf_surface"] = write_surface_vtkhdf(
                out / "surface.vtkhdf", ship.vertices, ship.faces, ship.face_part, ship.part_names,
                times, outer, time_units=units)
        if "json" in formats:
            with atomic_path(out / "thermal_summary.json") as tmp:
                tmp.write_text(json.dumps(self.summary(), indent=2, default=_json_default))
            written["summary_json"] = out / "thermal_summary.json"
        return written

    def where(self) -> str:
        """``" — season, date, lat N lon E"`` for picture titles (what is known)."""
        bits = [str(self.meta[k]) for k in ("season", "date") if self.meta.get(k)]
        env = self.environment
        if env is not None and hasattr(env, "latitude"):
            bits.append(f"{env.latitude:.2f} N {env.longitude:.2f} E")
        return (" — " + ", ".join(bits)) if bits else ""

    def face_temperature_at(self, hour: float) -> np.ndarray:
        """Outer-surface temperature per triangle at a local hour (linear in time) [K]."""
        if self.record is not None:
            return self.record.face_temperature_at(hour * HOUR)
        t = self.results.times / HOUR
        tf = self.outer_face_temperature()
        k = int(np.clip(np.searchsorted(t, hour) - 1, 0, len(t) - 2))
        w = float(np.clip((hour - t[k]) / (t[k + 1] - t[k]), 0.0, 1.0))
        return (1 - w) * tf[k] + w * tf[k + 1]


def _clock(hour: float) -> str:
    return f"{int(hour):02d}:{int(round(60 * (hour % 1))):02d}"


def _json_default(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def plot_part_means(part_means: pd.DataFrame, path, title: str = "", figures=None) -> Path:
    """PNG of the 24 h part-mean curves with air and sea temperature: every curve its own
    colour-blind-safe colour and dash pattern (:data:`shipthermal.figures.PART_LINE_STYLES`;
    other parts take the remaining :data:`~shipthermal.figures.LINE_STYLES`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5), dpi=110)
    labels = {"temp_air": "air", "temp_sea": "sea (bulk)", "temp_sea_skin": "sea skin",
              "hull": "hull (dry)",
              "hull_wetted": "hull (wetted)"}
    spare = iter(LINE_STYLES[1:] * 3)
    for col in part_means.columns:
        colour, ls, lw = PART_LINE_STYLES.get(col) or (*next(spare), 1.6)
        ax.plot(part_means.index, part_means[col], color=colour, ls=ls, lw=lw,
                label=labels.get(col, col))
    end = max(24, int(np.ceil(float(part_means.index.max()) / 24.0)) * 24)
    ax.set_xlabel("local time [h]" if end == 24 else "hours since local midnight of the "
                  "first recorded day [h]")
    ax.set_ylabel("temperature [K]")
    ax.set_xlim(0, end)
    ax.set_xticks(range(0, end + 1, 3 if end == 24 else (6 if end <= 96 else 24)))
    ax.grid(alpha=0.3)
    ax.legend(ncol=3, fontsize=8)
    ax.set_title(title, fontsize=10)
    path = Path(path)
    save_figure(fig, path, figures, bbox_inches="tight")
    plt.close(fig)
    return path


def run_diurnal(ship, environment, settings: DiurnalSettings | None = None, *,
                absorptivity=None, emissivity=None, graph=None, traced=None,
                progress: bool = True, checkpoint=None, checkpoint_interval: float = HOUR,
                resume: bool = False, log=None, initial_state=None) -> DiurnalResult:
    """Spin a ship up under a periodic design day and record the converged day.

    Parameters
    ----------
    ship : ShipGeometry
    environment : shipthermal.environment.Environment
        Periodic (design-day) weather; heading and speed of the ship.
    settings : DiurnalSettings
    absorptivity, emissivity : float or mapping part → value, optional
        Solar absorptivity and broadband long-wave emissivity per part [-].
    graph : CellGraph, optional
        A prebuilt shell graph of ``ship`` (default: built here from the ship's layups).
    traced : TracedShip, optional
        Reuse the ray tracing of an earlier run of the same ship (sensitivity studies).
    progress : bool
        Progress bars.
    checkpoint : path, optional
        Checkpoint file (.npz) written every ``checkpoint_interval`` of simulated time (on
        recording times: at most one per ``settings.output_interval``).
    resume : bool
        Continue from ``checkpoint`` if it exists (same result as an uninterrupted run).
    log : callable, optional
        ``log(str)`` for progress messages (default: silent).
    initial_state : (n_cells,) array, optional
        Start from these cell temperatures [K] (e.g. a converged run of the same mesh:
        sensitivity runs then need fewer spin-up days).

    Returns
    -------
    DiurnalResult
    """
    # lazy: the solver stack (numba kernels, pvlib, the ray tracer) takes seconds to import
    from .forcing import build_ship_forcing
    from .model import RadiativeExchange, ThermalModel
    from .simulation import Simulation

    settings = settings or DiurnalSettings()
    if not environment.weather.periodic:
        return run_record(ship, environment, settings, absorptivity=absorptivity,
                          emissivity=emissivity, graph=graph, traced=traced,
                          progress=progress, log=log, checkpoint=checkpoint, resume=resume)
    say = log or (lambda msg: None)
    t_total = _time.perf_counter()
    timings = {}
    t0 = _time.perf_counter()
    if graph is None:
        graph, _ = geometry.build_ship_mesh(ship)   # through the module: tests replace it
    timings["mesh"] = _time.perf_counter() - t0
    say(f"mesh: {ship.n_faces} surface faces, {graph.n_cells} cells ({timings['mesh']:.1f} s)")

    t0 = _time.perf_counter()
    table_times = np.arange(0.0, DAY, min(600.0, settings.output_interval))
    forcing = build_ship_forcing(ship, environment, graph, times=table_times,
                                 samples_per_face=settings.samples_per_face,
                                 rays_per_face=settings.rays_per_face, seed=settings.seed,
                                 absorptivity=absorptivity, emissivity=emissivity,
                                 backend=settings.backend, progress=progress, traced=traced,
                                 convection=settings.convection,
                                 roughness=settings.convection_roughness)
    timings["forcing"] = _time.perf_counter() - t0
    say(f"forcing: ray tracing and tables ({timings['forcing']:.1f} s)")

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
    conditions = forcing.conditions(with_exchange=True)
    exchange = RadiativeExchange(*forcing.radiative_exchange())
    model = ThermalModel(graph, conditions, initial_temperature=temp0, exchange=exchange)
    days_max = int(settings.spinup_max_days)
    lead = lead_in_seconds(settings) if initial_state is None else 0.0
    groups = part_groups(graph.part_names)

    def means(res: Results) -> pd.DataFrame:
        pm = res.part_mean("outer", groups=groups)
        return pm[[c for c in MAIN_SERIES if c in pm.columns]
                  + [c for c in pm.columns if c not in MAIN_SERIES]]

    day_changes: list = []
    energy_parts: list = []
    day_start = None
    day = 0
    resuming = resume and checkpoint is not None and Path(checkpoint).exists()
    iv = settings.output_interval
    # One simulation from the start of the lead-in: the steps change length (lead-in,
    # night) without restarting the scheme.
    sim = Simulation(model, settings.time_step, days_max * DAY, start_time=-lead,
                     scheme=settings.scheme, output_interval=iv)
    t0 = _time.perf_counter()
    if lead > 0.0 and not resuming:
        # Lead-in: the end of the design day before the first recorded one, from the
        # initial temperature, in steps of up to SPINUP_LEAD_IN_STEP (not recorded; its
        # energy is logged).
        step = lead_in_step(settings)
        sim.set_time_step(step)
        sim.run_until(0.0, progress=progress, desc="lead-in")
        energy_parts.append(sim.results().energy)
        sim.clear_records()
        say(f"lead-in: {lead / HOUR:g} h before the first day in {step:g} s steps")
    if resuming:
        extra = sim.load_checkpoint(checkpoint)
        day = int(extra["day"])
        day_changes = [float(x) for x in extra["day_changes"]]
        day_start = extra["day_start"] if extra["day_start"].size else None
        energy_parts = [EnergyLog(*[np.asarray(extra[f"energy_{k}"], float)
                                    for k in EnergyLog.FIELDS])] if "energy_time" in extra else []
        say(f"resumed from {checkpoint} at t = {sim.time / HOUR:.2f} h (day {day + 1})")
    # The design day repeats: the steps of the first day (after the lead-in's) and of the
    # days after it (after the last day's).
    dark = dark_intervals(settings, forcing)
    plans = [night_steps(settings, dark,
                         lead_in_step(settings) if lead > 0.0 else settings.time_step)]
    plans.append(night_steps(settings, dark, plans[0][-1]))
    if np.any(plans[0] != settings.time_step):
        say(f"steps: {int(round(np.sum(iv / plans[0])))} a day ({settings.time_step:g} s; "
            f"{np.max(plans[0]):g} s from {NIGHT_SETTLE / HOUR:g} h after the last "
            "short-wave)")

    def save(day_idx):
        if checkpoint is None:
            return
        done = _concat_energy(energy_parts)
        extra = {"day": day_idx, "day_changes": np.array(day_changes, float),
                 "day_start": day_start if day_start is not None else np.zeros(0)}
        extra.update({f"energy_{k}": getattr(done, k) for k in EnergyLog.FIELDS})
        sim.save_checkpoint(checkpoint, extra=extra)

    converged = False
    res = None
    while day < days_max:
        day_end = (day + 1) * DAY
        if abs(sim.time - day * DAY) < 1e-6:
            sim.clear_records()
            sim.record_now()
            day_start = sim.temperature
        plan = plans[min(day, 1)]
        first = int(round((sim.time - day * DAY) / iv))
        last_save = sim.time

        def checkpoint_due(day=day, day_end=day_end):
            nonlocal last_save
            if (checkpoint is not None and sim.time < day_end - 1e-6
                    and sim.time - last_save >= checkpoint_interval - 1e-6):
                save(day)
                last_save = sim.time

        _run_intervals(sim, plan[first:], sim.time, iv, f"day {day + 1}", progress,
                       checkpoint_due)
        res = sim.results()
        energy_parts.append(res.energy)
        # Periodicity defect of the day: the largest change of any cell temperature from
        # its start to its end. The difference between two solutions under the same
        # forcing does not grow (maximum principle of conduction with boundary flows that
        # decrease with the surface temperature), so the next day would differ from this
        # one by at most this much at every time: it bounds the day-to-day change.
        change = float(np.max(np.abs(sim.temperature - day_start)))
        day_changes.append(change)
        say(f"day {day + 1}: largest cell-temperature change over the day {change:.4f} K")
        day += 1
        if change <= settings.spinup_tolerance:
            converged = True
            break
        if day < days_max:
            save(day)
    timings["solve"] = _time.perf_counter() - t0
    # the solver's own timers and counters, lead-in included
    timings["solver_detail"] = {k: float(v) for k, v in res.timing.items()}

    # The recorded day, on the local clock.
    offset = (day - 1) * DAY
    rec = Results(graph=res.graph, times=res.times - offset, cell_temperature=res.cell_temperature,
                  face_temperature=res.face_temperature, face_flow=res.face_flow,
                  energy=res.energy, scheme=res.scheme, time_step=res.time_step,
                  timing=res.timing, backend=res.backend)
    env = environment.at(rec.times)
    pm = means(rec)
    pm["temp_air"] = env.temp_air
    pm["temp_sea"] = env.temp_sea
    pm["temp_sea_skin"] = env.temp_sea_skin
    pm.index = pd.Index(rec.times / HOUR, name="hour")
    timings["total"] = _time.perf_counter() - t_total
    energy = _concat_energy(energy_parts)
    return DiurnalResult(ship=ship, graph=graph, forcing=forcing, results=rec, part_means=pm,
                         days=day, day_changes=day_changes, converged=converged, energy=energy,
                         timings=timings, settings=settings, environment=environment)


#: Days of a weather record per window (forcing tables, checkpoint, part of the outputs).
RECORD_WINDOW_DAYS = 1


def run_record(ship, environment, settings: DiurnalSettings | None = None, *,
               absorptivity=None, emissivity=None, graph=None, traced=None,
               progress: bool = True, log=None, checkpoint=None, resume: bool = False,
               work_dir=None, window_days: int = RECORD_WINDOW_DAYS,
               end_day: int | None = None, face_dtype=np.float32) -> DiurnalResult:
    """Spin a ship up on the first day of a weather record, then run the record, window by
    window, its outputs streamed to disk.

    Parameters
    ----------
    ship, settings, absorptivity, emissivity, graph, traced, progress, log
        As :func:`run_diurnal`.
    environment : shipthermal.environment.Environment
        With a non-periodic weather record starting at local midnight and covering whole
        days (:meth:`Scenario.weather_record` with ``weather.day = 'record'``).
    checkpoint : path, optional
        Checkpoint file (.npz), written at the end of every window (the spin-up's own
        next to it, ``<stem>.spinup.npz``); the outputs' parts go to the folder
        ``<stem>.record`` beside it.
    resume : bool
        Continue from ``checkpoint`` if it exists (the same result as an uninterrupted
        run, bit for bit: the whole solver state is in it).
    work_dir : path, optional
        Folder of the outputs' parts and of the assembled ``record.h5`` (default: beside
        the checkpoint; without one, a temporary folder removed with the result).
    window_days : int
        Days per window (:data:`RECORD_WINDOW_DAYS`): forcing tables, checkpoint, part.
    end_day : int, optional
        Stop after this many recorded days (default: the whole record); a later call with
        ``resume`` goes on from there.
    face_dtype : numpy dtype
        Storage of the streamed face temperatures (float32: 3e-5 K at 300 K).

    Returns
    -------
    DiurnalResult
        ``part_means`` spans the recorded days (indexed by hours since local midnight of
        the first, 0 … 24·N) and ``record`` holds every output (:class:`~shipthermal.
        record_stream.RecordFile`, read lazily); ``results`` holds the final state only;
        ``days`` counts spin-up and recorded days; ``meta['record_days']`` the recorded
        days; the energy log covers spin-up and record.

    Notes
    -----
    Each window gets its own forcing tables (:func:`~shipthermal.forcing.build_ship_forcing`
    with ``window``: the rows of the whole record's tables at the same times, the ray
    tracing and view factors done once) and the simulation goes on under them with its
    whole state (:meth:`Simulation.continue_with
    <shipthermal.simulation.Simulation.continue_with>`): the result does not depend on
    the window length, nor on interruptions.
    """
    # lazy: the solver stack (numba kernels, pvlib, the ray tracer) takes seconds to import
    from .forcing import build_ship_forcing
    from .model import RadiativeExchange, ThermalModel
    from .simulation import Simulation

    settings = settings or DiurnalSettings()
    say = log or (lambda msg: None)
    w = environment.weather
    span = (w.time[-1] - environment.start).total_seconds()
    n_days = span / DAY
    require(n_days >= 1.0 - 1e-9 and abs(n_days - round(n_days)) < 1e-9,
            "environment.weather", f"{w.time[0]} … {w.time[-1]}",
            "a record run needs whole days from local midnight to local midnight")
    n_days = int(round(n_days))
    require(int(window_days) >= 1, "window_days", window_days, "must be ≥ 1")
    stop = n_days if end_day is None else int(end_day)
    require(1 <= stop <= n_days, "end_day", end_day, f"must lie in 1 … {n_days}")
    iv = settings.output_interval
    per_day = int(round(DAY / iv))
    t_total = _time.perf_counter()
    timings = {"record_forcing": 0.0, "record_solve": 0.0, "record_outputs": 0.0}

    ckpt = None if checkpoint is None else Path(checkpoint)
    temporary = work_dir is None and ckpt is None
    if work_dir is None and ckpt is not None:
        work_dir = ckpt.with_suffix(".record")
    elif temporary:
        import tempfile

        work_dir = tempfile.mkdtemp(prefix="shipthermal-record-")
    parts = RecordParts(Path(work_dir) / "parts")
    spin_ckpt = None if ckpt is None else ckpt.with_name(f"{ckpt.stem}.spinup.npz")
    resuming = resume and ckpt is not None and ckpt.exists()
    if resuming:
        with np.load(ckpt) as d:
            done = int(d["extra_record_day"])
            spin_info = {k[len("extra_spin_"):]: d[k].copy() for k in d.files
                         if k.startswith("extra_spin_")}
        require(done <= stop, "end_day", end_day,
                f"must be ≥ the {done} days the checkpoint has done already")
        spin_energy = EnergyLog(*[spin_info.pop(f"energy_{k}") for k in EnergyLog.FIELDS])
        spin_days = int(spin_info["days"])
        spin_converged = bool(spin_info["converged"])
        day_changes = [float(x) for x in spin_info["day_changes"]]
        timings.update(json.loads(str(spin_info["timings"])))
        if graph is None:
            graph, _ = geometry.build_ship_mesh(ship)
        temp0 = None
        say(f"record: resumed from {ckpt} after {done} of {n_days} recorded day(s)")
    else:
        done = 0
        say(f"record: spin-up on the first day ({w.time[0]:%Y-%m-%d}), then {n_days} day(s)")
        spin = run_diurnal(ship, environment.first_day(), settings, absorptivity=absorptivity,
                           emissivity=emissivity, graph=graph, traced=traced,
                           progress=progress, log=log, checkpoint=spin_ckpt, resume=resume)
        graph, traced = spin.graph, spin.forcing.traced
        absorptivity, emissivity = spin.forcing.absorptivity, spin.forcing.emissivity
        spin_energy, spin_days = spin.energy, spin.days
        spin_converged, day_changes = spin.converged, list(spin.day_changes)
        timings.update(spin.timings)
        timings["spinup_total"] = timings.pop("total")
        temp0 = spin.results.final_temperature
        parts.drop_from(0)
    groups = part_groups(graph.part_names)
    sampled = sample_days(n_days)
    table_step = min(600.0, iv)
    grid = np.arange(0.0, span + 1.0, table_step)
    margin = _settle_intervals(settings) * iv

    def window_forcing(d0, d1):
        # the window's rows of the record's table grid, from the settle intervals before
        # its start (the night steps look back that far) to its end
        i0 = max(int(np.searchsorted(grid, d0 * DAY - margin, side="right")) - 1, 0)
        i1 = int(np.searchsorted(grid, d1 * DAY - 1e-6))
        f = build_ship_forcing(ship, environment, graph, times=grid[i0:i1 + 1],
                               window=(float(grid[i0]), d1 * DAY),
                               samples_per_face=settings.samples_per_face,
                               rays_per_face=settings.rays_per_face, seed=settings.seed,
                               absorptivity=absorptivity, emissivity=emissivity,
                               backend=settings.backend, progress=progress and traced is None,
                               traced=traced, convection=settings.convection,
                               roughness=settings.convection_roughness)
        f.traced.clear_lit_cache()
        return f

    sim = exchange = forcing = None
    n_parts = done_parts = 0
    if resuming:
        with np.load(ckpt) as d:
            done_parts = int(d["extra_record_parts"])
        parts.drop_from(done_parts)
    n_parts = done_parts
    day = done
    from tqdm.auto import tqdm

    bar = tqdm(total=stop, initial=done, unit="day", desc="record", disable=not progress,
               leave=False)
    t_loop = _time.perf_counter()
    try:
        while day < stop:
            d1 = min(day + int(window_days), stop)
            t0 = _time.perf_counter()
            forcing = window_forcing(day, d1)
            traced = forcing.traced
            if exchange is None:
                exchange = RadiativeExchange(*forcing.radiative_exchange())
            conditions = forcing.conditions(with_exchange=True)
            timings["record_forcing"] += _time.perf_counter() - t0
            if sim is None:
                # (resuming: the checkpoint replaces the initial state)
                model = ThermalModel(graph, conditions, exchange=exchange,
                                     initial_temperature=300.0 if temp0 is None else temp0)
                sim = Simulation(model, settings.time_step, span, scheme=settings.scheme,
                                 output_interval=iv)
                if resuming:
                    sim.load_checkpoint(ckpt)
            else:
                sim.continue_with(ThermalModel(graph, conditions, exchange=exchange,
                                               initial_temperature=sim.temperature))
            plan = night_steps(settings, dark_intervals(settings, forcing, (d1 - day) * DAY,
                                                        start=day * DAY), sim.time_step)
            for d in range(day, d1):
                t0 = _time.perf_counter()
                k = (d - day) * per_day
                _run_intervals(sim, plan[k:k + per_day], d * DAY, iv,
                               f"record day {d + 1}", False)
                timings["record_solve"] += _time.perf_counter() - t0
                if d + 1 == d1:
                    t0 = _time.perf_counter()
                    _write_part(parts, n_parts, sim, environment, groups, graph,
                                ship.n_faces, sampled, face_dtype)
                    n_parts += 1
                    sim.clear_records()
                    if ckpt is not None:
                        extra = {"record_day": d1, "record_parts": n_parts,
                                 "spin_days": spin_days, "spin_converged": spin_converged,
                                 "spin_day_changes": np.array(day_changes, float),
                                 "spin_timings": json.dumps(
                                     {k: v for k, v in timings.items()
                                      if not k.startswith("record_")}, default=float)}
                        extra.update({f"spin_energy_{k}": getattr(spin_energy, k)
                                      for k in EnergyLog.FIELDS})
                        sim.save_checkpoint(ckpt, extra=extra)
                        if spin_ckpt is not None and spin_ckpt.exists():
                            spin_ckpt.unlink()
                    timings["record_outputs"] += _time.perf_counter() - t0
                bar.update(1)
                elapsed = _time.perf_counter() - t_loop
                date = (environment.start + pd.Timedelta(days=d)).strftime("%Y-%m-%d")
                left = elapsed / (d + 1 - done) * (stop - d - 1)
                say(f"record day {d + 1} of {n_days} ({date}) simulated: "
                    f"{elapsed:.0f} s for {d + 1 - done} day(s), about {left:.0f} s left")
            day = d1
    except BaseException:
        if temporary:
            import shutil

            shutil.rmtree(work_dir, ignore_errors=True)
        raise
    finally:
        bar.close()

    t0 = _time.perf_counter()
    part_columns = list(parts.read(0)["part_columns"])
    path = assemble(parts, n_parts, Path(work_dir) / "record.h5", ship=ship,
                    part_columns=part_columns, start=str(environment.start),
                    record_days=n_days, days_done=stop, output_interval=iv,
                    label=f"weather-record thermal run ({ship.name})", face_dtype=face_dtype)
    record = RecordFile(path)
    if temporary:
        record.remove_when_unused(work_dir)
    timings["record_outputs"] += _time.perf_counter() - t0
    pm = record.part_means()
    energy = record.energy()
    final = _final_results(sim, ckpt, graph, energy, settings)
    timings["total"] = _time.perf_counter() - t_total
    meta = {"record_days": n_days, "spinup_days": spin_days,
            "record_start": str(w.time[0]), "record_end": str(w.time[-1]),
            "weather_source": w.source, "record_window_days": int(window_days)}
    if stop < n_days:
        meta["record_days_done"] = stop
    result = DiurnalResult(ship=ship, graph=graph, forcing=forcing, results=final,
                           part_means=pm, days=spin_days + stop, day_changes=day_changes,
                           converged=spin_converged,
                           energy=_concat_energy([spin_energy, energy]), timings=timings,
                           settings=settings, environment=environment, meta=meta,
                           record=record)
    return result


def _write_part(parts, index, sim, environment, groups, graph, n_faces, sampled, face_dtype):
    """The window's recorded outputs (and energy log) as part ``index`` of the record."""
    res = sim.results()
    pm = res.part_mean("outer", groups=groups)
    pm = pm[[c for c in MAIN_SERIES if c in pm.columns]
            + [c for c in pm.columns if c not in MAIN_SERIES]]
    env = environment.at(res.times)
    pm["temp_air"] = env.temp_air
    pm["temp_sea"] = env.temp_sea
    pm["temp_sea_skin"] = env.temp_sea_skin
    keep = in_sample(res.times, sampled, DAY)
    arrays = {"times": res.times,
              "face_temperature": res.face_temperature[:, :n_faces].astype(face_dtype),
              "part_means": pm.to_numpy(), "part_columns": np.array(pm.columns, dtype=str),
              "sample_times": res.times[keep],
              "sample_cell_temperature": res.cell_temperature[keep].astype(np.float32),
              "sample_face_temperature": res.face_temperature[keep].astype(np.float32),
              "sample_face_flow": res.face_flow[keep].astype(np.float32)}
    arrays.update({f"energy_{k}": getattr(res.energy, k) for k in EnergyLog.FIELDS})
    parts.write(index, **arrays)


def _final_results(sim, ckpt, graph, energy, settings) -> Results:
    """The record's final state as :class:`Results` (one time), from the simulation or, when
    a resumed run had nothing left to do, from its checkpoint."""
    if sim is not None:
        time_, temp, face, flow = sim.time, sim.temperature, sim.face_temperature, sim.face_flow
    else:
        with np.load(ckpt) as d:
            time_, temp, face, flow = (float(d["time"]), d["temp"].copy(),
                                       d["temp_face"].copy(), d["flow_face"].copy())
    return Results(graph=graph, times=np.array([time_]), cell_temperature=temp[None, :],
                   face_temperature=face[None, :], face_flow=flow[None, :], energy=energy,
                   scheme=settings.scheme, time_step=settings.time_step)


def _concat_energy(parts) -> EnergyLog:
    if not parts:
        return EnergyLog.from_lists({k: [] for k in EnergyLog.FIELDS})
    return EnergyLog(*[np.concatenate([getattr(p, k) for p in parts]) for k in EnergyLog.FIELDS])
