"""From a scenario to the answer in one object: :class:`Simulation` → :class:`SimulationResult`.

In the spirit of pvlib's ``ModelChain`` and Oceananigans' ``Simulation``: the class adds no
physics, it wires the stages the command line runs, in the same order and with the same
functions, so a notebook and ``shipthermal run --image`` give the same numbers::

    import shipthermal as st
    sim = st.Simulation("my_port.toml")          # or st.Simulation.default("summer")
    res = sim.run()                              # thermal + background + imaging
    res.image("2023-07-15 13:00", "8-14")        # xarray.DataArray, x / y [m], CRS, units
    res.crossovers                               # tz-aware timestamps, band, direction
    res.report("out/report.html")

The stages (each computed once, on first use, and kept):

1. inputs — :func:`~shipthermal.app.pipeline.prepare`: the ship, the weather record and
   the port background are read before anything long starts;
2. thermal — :func:`~shipthermal.app.thermal.run_scenario_thermal` (spin-up and the
   recorded day or weather record), handed on as
   :func:`~shipthermal.app.thermal.ship_thermal_history`;
3. imaging — :func:`~shipthermal.app.pipeline.imaging_scenario` (the same scene as the
   command line: mooring, heading, view, sensor, per-face emissivities, weather) and
   :func:`imaging.experiment.render_series` over
   :func:`~shipthermal.app.pipeline.frame_times` with the image panels' moments added
   (:func:`imaging.experiment.series_times`): SCR, contrast and crossovers;
4. products — :meth:`SimulationResult.save` writes a run folder of the kind
   ``shipthermal run --image`` writes (:func:`~shipthermal.app.pipeline.store_thermal`,
   :func:`imaging.experiment.experiment_products`); :meth:`SimulationResult.report` its
   self-contained HTML report.

Times are accepted as tz-aware timestamps, as strings or naive timestamps in the
scenario's time zone (``"2023-07-15 13:00"``, or ``"13:00"`` on ``time.date``), as
:class:`pandas.Timedelta` after local midnight of ``time.date``, or as numbers of hours
after it. Results carry tz-aware times and their units (``attrs``).

This :class:`Simulation` is the whole chain of a scenario; the thermal solver's own
time stepper is :class:`shipthermal.simulation.Simulation`.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import html
import re
import tempfile
import warnings
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import pandas as pd

from ..errors import InputError
from ..figures import FigureOptions
from ..parameters import parse_band
from ..units import DAY, HOUR
from . import pipeline
from .mooring import check_mooring_on
from .report import is_report_file, write_report
from .rundir.folder import RunDir
from .rundir.inputs import scenario_inputs
from .scenario import Scenario, default_scenario, load_scenario, loads_scenario
from .scenario.values import SEASONS
from .thermal import run_scenario_thermal, ship_thermal_history

# xarray, pyvista and the imaging package are imported where they are used: the
# thermal-only users of the chain (validation, calibration) do not load them

__all__ = ["Simulation", "SimulationResult"]

#: ``HH:MM`` or ``HH:MM:SS``: a clock time on the scenario's date
_CLOCK = re.compile(r"^\s*(\d{1,2}):(\d{2})(?::(\d{2}))?\s*$")

#: What :meth:`SimulationResult.image` can return: name → (Frame attribute, units, long name)
IMAGE_QUANTITIES = {
    "radiance": ("radiance", "W m-2 sr-1", "at-aperture band radiance"),
    "leaving_radiance": ("leaving", "W m-2 sr-1", "surface-leaving band radiance, area-mixed"),
    "brightness_temperature": ("radiance", "K", "apparent (at-aperture) brightness "
                               "temperature"),
    "irradiance": ("irradiance", "W m-2", "focal-plane irradiance"),
}


def _as_scenario(scenario):
    """A :class:`~shipthermal.app.scenario.Scenario` from a Scenario, a season name, a
    TOML file, TOML text or a mapping of the file's shape."""
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, Mapping):
        return load_scenario(scenario)
    if isinstance(scenario, str) and scenario in SEASONS:
        return default_scenario(scenario)
    if isinstance(scenario, str) and "\n" in scenario:
        return loads_scenario(scenario)
    if isinstance(scenario, (str, Path)):
        if not Path(scenario).is_file():
            raise InputError("scenario", str(scenario), "must be a scenario file (TOML), "
                             f"a Scenario, TOML text or a season ({', '.join(SEASONS)})",
                             "Check the path; `shipthermal schema` lists the keys")
        return load_scenario(scenario)
    raise InputError("scenario", type(scenario).__name__, "must be a Scenario, a path to a "
                     f"TOML file, TOML text, a mapping or a season ({', '.join(SEASONS)})")


def _site(loc) -> str:
    """``38.91° N, 121.63° E (Etc/GMT-8)``."""
    lat, lon = loc.latitude, loc.longitude
    return (f"{abs(lat):.2f}° {'N' if lat >= 0 else 'S'}, {abs(lon):.2f}° "
            f"{'E' if lon >= 0 else 'W'} ({loc.time_zone})")


def _clock_text(seconds: float) -> str:
    m = int(round(seconds / 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}"


class Simulation:
    """One scenario from its inputs to images, SCR and crossovers.

    Parameters
    ----------
    scenario : Scenario, path-like, str or mapping
        A :class:`~shipthermal.app.scenario.Scenario`, a scenario file (TOML), TOML text,
        a mapping of the file's shape, or ``"summer"`` / ``"winter"`` (the built-in
        defaults, :func:`~shipthermal.app.scenario.default_scenario`).
    changes : mapping, optional
        Dotted scenario keys to change, e.g. ``{"ship.edge_length": 4.0}``; the scenario
        is validated again with them (:meth:`Scenario.updated
        <shipthermal.app.scenario.Scenario.updated>`).
    progress : bool
        Progress bars of the thermal run and the imaging series.
    **more_changes
        Further changes as keywords, e.g. ``**{"imaging.bands": ["8-14"]}``.

    Attributes
    ----------
    scenario : Scenario
        The validated scenario (changes applied); it drives every stage.
    notes : list of str
        What the inputs said on the way (mesh repairs, weather gaps filled, a berth that
        touches a pier).

    Examples
    --------
    >>> import shipthermal as st
    >>> sim = st.Simulation("summer", {"ship.edge_length": 4.0})   # doctest: +SKIP
    >>> res = sim.run()                                            # doctest: +SKIP
    >>> res.image("13:00", "8-14")                                 # doctest: +SKIP
    """

    def __init__(self, scenario: Any = "summer", changes: Mapping | None = None, *,
                 progress: bool = True, **more_changes):
        sc = _as_scenario(scenario)
        all_changes = {**dict(changes or {}), **more_changes}
        if all_changes:
            sc = sc.updated(all_changes)
        self.scenario = sc
        self.progress = bool(progress)
        self.notes: list[str] = []
        self._ship = None
        self._background = None
        self._result = None
        self._weather_checked = False

    @classmethod
    def default(cls, season: str = "summer", changes: Mapping | None = None,
                **kwargs) -> "Simulation":
        """The built-in default scenario of a season (Dalian design day, frigate, synthetic
        port), with ``changes``."""
        return cls(default_scenario(season), changes, **kwargs)

    def with_changes(self, changes: Mapping | None = None, **more_changes) -> "Simulation":
        """A new simulation of this scenario with dotted keys changed (nothing is shared:
        it runs afresh)."""
        return type(self)(self.scenario, {**dict(changes or {}), **more_changes},
                          progress=self.progress)

    # ---- inputs -------------------------------------------------------------------------
    @property
    def ship(self):
        """The ship (:class:`~shipthermal.geometry.ShipGeometry`), built or read once."""
        if self._ship is None:
            ship, report = self.scenario.ship(return_report=True)
            self.notes.extend(f"ship: {line}" for line in report.get("repairs", []))
            self._ship = ship
        return self._ship

    @property
    def background(self):
        """The port background of ``[background]``, built once
        (:func:`~shipthermal.app.pipeline.build_background`)."""
        if self._background is None:
            pipeline.check_imaging_bands(self.scenario)
            self._background = pipeline.build_background(self.scenario,
                                                         progress=self.progress)
        return self._background

    def prepare(self, imaging: bool = True) -> "Simulation":
        """Read every input before anything long runs: the ship, the weather record and,
        with ``imaging``, the port background; a bad file raises
        :class:`~shipthermal.errors.InputError` here. The ship's berth is checked against
        the background (:func:`~shipthermal.app.mooring.check_mooring_on`): a footprint on
        land is refused, a small overlap is a warning (and a note)."""
        if imaging:
            pipeline.check_imaging_bands(self.scenario)
        ship = self.ship
        if not self._weather_checked:
            self.notes.extend(self.scenario.check_weather())
            self._weather_checked = True
        if imaging:
            for line in check_mooring_on(self.scenario, ship, self.background):
                if f"mooring: {line}" not in self.notes:
                    self.notes.append(f"mooring: {line}")
                    warnings.warn(line, UserWarning, stacklevel=2)
        return self

    # ---- running ------------------------------------------------------------------------
    def run(self, imaging: bool = True, progress: bool | None = None) -> "SimulationResult":
        """Run the chain: inputs, thermal run and (with ``imaging``) the image series.

        The thermal run is done once per simulation: a second call returns the same
        result (with its imaging rendered when asked for now).

        Parameters
        ----------
        imaging : bool
            Also build the background and render the SCR / crossover series now (otherwise
            on first use of :attr:`SimulationResult.scr` and friends).
        progress : bool, optional
            Progress bars (default: the simulation's ``progress``).

        Returns
        -------
        SimulationResult
        """
        show = self.progress if progress is None else bool(progress)
        if self._result is None:
            self.prepare(imaging=imaging)
            thermal = run_scenario_thermal(self.scenario, ship=self.ship, progress=show)
            self._result = SimulationResult(self, thermal)
        if imaging:
            self._result._render_series(show)
        return self._result

    def result_from(self, thermal) -> "SimulationResult":
        """The result of a thermal run of this scenario made elsewhere (a
        :class:`~shipthermal.diurnal.DiurnalResult`, e.g. a calibration's run), imaged by
        this simulation's chain."""
        return SimulationResult(self, thermal)

    @property
    def status(self) -> str:
        """``"not run"``, ``"thermal done"`` or ``"thermal and imaging done"``."""
        if self._result is None:
            return "not run"
        return "thermal and imaging done" if self._result._series is not None \
            else "thermal done"

    # ---- display ------------------------------------------------------------------------
    def _lines(self) -> list[tuple[str, str]]:
        sc = self.scenario
        loc, w, sh = sc.location, sc.weather, sc.ship
        weather = "built-in design day" if w.source == "builtin" else \
            f"{Path(w.source).name} ({w.day})"
        ship = sh.builtin or "user ship"
        edge = f", edge {sh.edge_length:g} m" if sh.edge_length else ""
        return [("site", _site(loc)),
                ("day", f"{sc.time.date} ({sc.time.season}); weather: {weather}"),
                ("ship", f"{ship}{edge}, heading {sh.heading:g}°"),
                ("bands", ", ".join(sc.bands) + " µm"),
                ("status", self.status)]

    def __repr__(self) -> str:
        head = f"Simulation({self.scenario.name!r})"
        return "\n".join([head] + [f"  {k:<7}{v}" for k, v in self._lines()])

    def _repr_html_(self) -> str:
        return _html_table(f"Simulation {self.scenario.name}", self._lines())


def _html_table(title: str, rows) -> str:
    body = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
                   f"<td style='text-align:left'>{html.escape(v)}</td></tr>" for k, v in rows)
    return f"<div><strong>{html.escape(title)}</strong><table>{body}</table></div>"


class SimulationResult:
    """What a :class:`Simulation` computed: the thermal run, and the imaging on demand.

    Attributes
    ----------
    simulation : Simulation
        The chain that made it (its scenario, ship and background).
    thermal : shipthermal.diurnal.DiurnalResult
        The thermal run: the recorded day (or weather record) of every face and cell.

    Everything else is computed on first use and kept: :attr:`history` (the imaging
    stage's input), :attr:`imaging_scenario` (the scene), :attr:`series` (SCR and
    contrast of every frame), and one renderer per view direction for :meth:`image`.
    """

    def __init__(self, simulation: Simulation, thermal):
        self.simulation = simulation
        self.thermal = thermal
        self._history = None
        self._imaging_scenario = None
        self._renderers: dict = {}
        self._series = None

    # ---- thermal ------------------------------------------------------------------------
    @property
    def scenario(self):
        """The scenario (:class:`~shipthermal.app.scenario.Scenario`)."""
        return self.simulation.scenario

    @property
    def start(self):
        """Local midnight of ``time.date`` (tz-aware): the time axis's zero."""
        return self.scenario.start

    @property
    def history(self):
        """The ship's outer-surface temperatures over time
        (:class:`imaging.thermal_history.ShipThermalHistory`), the imaging stage's input."""
        if self._history is None:
            self._history = ship_thermal_history(self.thermal)
        return self._history

    def _timestamps(self, seconds):
        return pd.DatetimeIndex(self.start + pd.to_timedelta(np.asarray(seconds, float),
                                                              unit="s"), name="time")

    @property
    def part_means(self):
        """Area-mean outer-surface temperature per part, with the air, the sea (bulk) and
        the sea skin [K]: a :class:`pandas.DataFrame` indexed by tz-aware time (units in
        ``attrs["units"]``)."""
        pm = self.thermal.part_means.copy()
        pm.index = self._timestamps(pm.index.to_numpy(dtype=float) * HOUR)
        pm.attrs["units"] = {c: "K" for c in pm.columns}
        pm.attrs["long_name"] = "area-mean outer-surface temperature per part; air; sea"
        return pm

    def seconds(self, when) -> float:
        """A time as seconds after local midnight of ``time.date`` [s] (the solver clock),
        checked against the simulated span.

        ``when``: a tz-aware timestamp (any zone), a string or naive timestamp in the
        scenario's zone (``"2023-07-15 13:00"``; ``"13:00"`` on ``time.date``), a
        :class:`pandas.Timedelta` after local midnight, or a number of hours after it.
        """
        sc = self.scenario
        tz = sc.location.time_zone
        if isinstance(when, bool):
            raise InputError("time", when, "must be a time, not a bool")
        if isinstance(when, (int, float, np.integer, np.floating)):
            s = float(when) * HOUR
        elif isinstance(when, (pd.Timedelta, _dt.timedelta, np.timedelta64)):
            s = pd.Timedelta(when).total_seconds()
        else:
            if isinstance(when, str) and _CLOCK.match(when):
                h, m, sec = _CLOCK.match(when).groups()
                when = f"{sc.time.date} {int(h):02d}:{m}:{sec or '00'}"
            try:
                ts = pd.Timestamp(when)
            except (ValueError, TypeError) as exc:
                raise InputError("time", when, f"must be a time ({exc})",
                                 f"e.g. '{sc.time.date} 13:00' (in {tz}), '13:00', a "
                                 "tz-aware timestamp or hours after local midnight") from None
            ts = ts.tz_localize(tz) if ts.tzinfo is None else ts.tz_convert(tz)
            s = (ts - self.start).total_seconds()
        lo, hi = self._span_s()
        if not (lo - 1e-6 <= s <= hi + 1e-6):
            first = self._timestamps([lo])[0]
            last = self._timestamps([hi])[0]
            raise InputError("time", str(when), f"must lie within the simulated span "
                             f"{first:%Y-%m-%d %H:%M} … {last:%Y-%m-%d %H:%M} ({tz})",
                             "Give a time of that span (strings are read in the scenario's "
                             "time zone; numbers are hours after local midnight)")
        return float(min(max(s, lo), hi))

    def _span_s(self) -> tuple[float, float]:
        t = self.history.times_s
        if self.history.period_s is None:
            return float(t[0]), float(t[-1])
        return 0.0, DAY

    def surface(self, when):
        """Outer-surface temperature of every ship triangle at a time [K].

        Returns
        -------
        xarray.DataArray
            Dimension ``face`` (the ship's triangles), with the coordinate ``part`` (part
            name of each face) and ``x``, ``y``, ``z`` (face centroids in the ship frame
            [m]: x forward, y to port, z up from the waterline); ``attrs``: ``units``,
            ``time`` (ISO, local).
        """
        # lazy: xarray takes most of a second to import (measured)
        import xarray as xr

        s = self.seconds(when)
        h = self.history
        centre = h.vertices[h.faces].mean(axis=1)
        names = np.asarray(h.part_names, dtype=object)[h.face_part]
        ts = self._timestamps([s])[0]
        return xr.DataArray(
            h.at(s), dims=("face",), name="surface_temperature",
            coords={"part": ("face", names.astype(str)),
                    "x": ("face", centre[:, 0], {"units": "m"}),
                    "y": ("face", centre[:, 1], {"units": "m"}),
                    "z": ("face", centre[:, 2], {"units": "m"})},
            attrs={"units": "K", "long_name": "outer-surface temperature",
                   "time": ts.isoformat(), "ship": self.thermal.ship.name})

    def surface_mesh(self, when):
        """The ship's outer surface at a time as a :class:`pyvista.PolyData` with the cell
        array ``temperature_K`` (for ParaView: ``.save("ship.vtp")``)."""
        # lazy: pyvista takes seconds to import (measured)
        import pyvista as pv

        h = self.history
        faces = np.hstack([np.full((h.n_faces, 1), 3), h.faces]).ravel()
        mesh = pv.PolyData(np.asarray(h.vertices, float), faces)
        mesh.cell_data["temperature_K"] = h.at(self.seconds(when))
        mesh.cell_data["part"] = np.asarray(h.face_part)
        return mesh

    # ---- imaging ------------------------------------------------------------------------
    @property
    def imaging_scenario(self):
        """The scene of the imaging stage (:class:`imaging.experiment.ImagingScenario`,
        :func:`~shipthermal.app.pipeline.imaging_scenario`): the same as ``shipthermal run
        --image`` renders."""
        if self._imaging_scenario is None:
            sim = self.simulation
            sim.prepare(imaging=True)
            self._imaging_scenario = pipeline.imaging_scenario(self.scenario, sim.background,
                                                               self.history)
        return self._imaging_scenario

    def _scene(self, view=None):
        """``(ImagingScenario, SceneRenderer)`` of a view (None: the scenario's); the
        renderer (its view rays) is built once per view."""
        isc = self.imaging_scenario
        key = None if view is None else (float(view[0]), float(view[1]))
        if key is not None and key == (isc.view_zenith_deg, isc.view_azimuth_deg):
            key = None
        if key is not None:
            isc = dataclasses.replace(isc, view_zenith_deg=key[0], view_azimuth_deg=key[1])
        if key not in self._renderers:
            self._renderers[key] = isc.renderer(self.history)
        return isc, self._renderers[key]

    def _render_series(self, progress: bool | None = None) -> dict:
        if self._series is None:
            # deferred: the renderer and the atmosphere add 70 ms to the chain's import
            # (measured); a thermal-only run needs neither
            from imaging.experiment import render_series, series_times

            sc = self.scenario
            given = pipeline.experiment_inputs(sc)
            typical = given["typical_hours"]
            isc, renderer = self._scene()
            record = pipeline.record_span_s(sc) is not None
            show = self.simulation.progress if progress is None else progress
            self._series = render_series(
                self.history, isc, given["bands"], series_times(given["times"], typical),
                keep_times_s=np.asarray(typical, float) * HOUR, progress=show,
                renderer=renderer, stack_step_s=HOUR if record else None)
        return self._series

    @property
    def series(self) -> dict:
        """``{band: SeriesResult}`` (:class:`imaging.experiment.SeriesResult`): every frame
        of the SCR / crossover series (``imaging.scr_interval``, and the moments of
        ``imaging.times``), rendered on first use."""
        return self._render_series()

    def metrics(self, band: str):
        """Per frame of a band: SCR, contrast, target and background statistics, sun
        zenith, mean temperatures, path radiance (:class:`pandas.DataFrame` indexed by
        tz-aware time; units in ``attrs["units"]``)."""
        sr = self.series[self._band(band)]
        m = sr.metrics.drop(columns=["time_s", "time_h"])
        m.index = self._timestamps(sr.metrics["time_s"].to_numpy())
        m.attrs["units"] = {
            "scr": "1", "contrast": "W m-2 sr-1", "mean_target": "W m-2 sr-1",
            "mean_background": "W m-2 sr-1", "std_background": "W m-2 sr-1",
            "n_target": "1", "n_background": "1", "sun_zenith_deg": "deg",
            "ship_mean_temp": "K", "water_mean_temp": "K", "path_radiance": "W m-2 sr-1",
            "tau_300k": "1"}
        m.attrs["band"] = sr.band
        return m

    @property
    def scr(self):
        """The local signal-to-clutter ratio (paper eq. 22) of every frame: a
        :class:`pandas.DataFrame` indexed by tz-aware time, one column per band [-]."""
        series = self.series
        df = pd.DataFrame({b: sr.metrics["scr"].to_numpy() for b, sr in series.items()},
                          index=self._timestamps(next(iter(series.values())).times_s))
        df.columns.name = "band"
        df.attrs["units"] = {b: "1" for b in series}
        df.attrs["long_name"] = "local signal-to-clutter ratio (eq. 22)"
        return df

    @property
    def crossovers(self):
        """The thermal-crossover moments: zero crossings of the ship-background contrast
        (:func:`imaging.metrics.crossover_times`). A :class:`pandas.DataFrame` with the
        columns ``time`` (tz-aware, to the second), ``band`` and ``direction``
        (``dark->bright``: the ship turns brighter than its surroundings), in time
        order."""
        rows = [{"time": c.time, "band": b, "direction": c.direction}
                for b, sr in self.series.items() for c in sr.crossovers]
        df = pd.DataFrame(rows, columns=["time", "band", "direction"])
        # to the second: the roots of the interpolated contrast are not finer than that
        df["time"] = self._timestamps(df["time"].to_numpy(dtype=float)).round("s")
        df = df.sort_values(["time", "band"], kind="stable").reset_index(drop=True)
        df.attrs["long_name"] = "thermal-crossover moments (contrast zero crossings)"
        return df

    def _band(self, band) -> str:
        """The scenario's name of a band (``"lwir"``, ``(8, 14)`` → ``"8-14"``)."""
        bands = self.scenario.bands
        if band not in bands:
            try:
                band = parse_band(band)[0]
            except InputError:
                pass                 # reported below with the scenario's bands
        if band not in bands:
            raise InputError("band", band, f"must be one of the scenario's imaging bands "
                             f"({', '.join(bands)})", "Add it with "
                             "Simulation(..., **{'imaging.bands': [...]})")
        return band

    def image(self, when, band: str, quantity: str = "radiance", view=None):
        """The sensor's image of the ship in its port at a time and band.

        Parameters
        ----------
        when : str, pandas.Timestamp, float or a sequence of them
            A moment as :meth:`seconds` reads it (``"2023-07-15 13:00"``, ``"13:00"``,
            ``13.0`` hours); a sequence gives a ``time`` dimension.
        band : str
            One of the scenario's ``imaging.bands`` (e.g. ``"8-14"``) [µm].
        quantity : {"radiance", "leaving_radiance", "brightness_temperature", "irradiance"}
            At-aperture band radiance [W m-2 sr-1] (paper eq. 1, after the sensor's PSF and
            noise when set), surface-leaving radiance [W m-2 sr-1] (eq. 2), the apparent
            brightness temperature of the at-aperture radiance [K] (no atmospheric
            correction), or the focal-plane irradiance [W m-2].
        view : (float, float), optional
            Sensor ``(zenith, compass azimuth)`` seen from the ship [deg] instead of the
            scenario's ``imaging.sensor`` direction (a renderer per view is kept).

        Returns
        -------
        xarray.DataArray
            Dimensions ``(y, x)`` (or ``(time, y, x)``): map coordinates of the pixel
            centres [m] (row 0 north), ``time`` (UTC, the local time in ``attrs``),
            ``ship_coverage`` (area fraction of each pixel the ship covers [-]) and
            ``spatial_ref`` (the CRS as WKT, CF ``grid_mapping``); ``attrs``: ``units``,
            ``band``, ``crs_wkt``, sun position, scenario.
        """
        # deferred: xarray and the renderer add 0.2 s to the chain's import (measured)
        import xarray as xr
        from imaging.experiment import render_series

        if quantity not in IMAGE_QUANTITIES:
            raise InputError("quantity", quantity, f"must be one of "
                             f"{', '.join(IMAGE_QUANTITIES)}")
        band = self._band(band)
        many = not isinstance(when, (str, bytes)) and np.ndim(when) == 1 \
            and not isinstance(when, pd.Timestamp)
        whens = list(when) if many else [when]
        secs = np.array([self.seconds(w) for w in whens])
        order = np.unique(secs)
        isc, renderer = self._scene(view)
        sr = render_series(self.history, isc, (band,), order, keep_times_s=order,
                           crop_px=None, progress=False, renderer=renderer)[band]
        attr, units, long_name = IMAGE_QUANTITIES[quantity]
        grid = renderer.background.grid
        t = grid.transform
        ny, nx = renderer.shape
        x = t.c + (np.arange(nx) + 0.5) * t.a
        y = t.f + (np.arange(ny) + 0.5) * t.e
        crs_wkt = grid.crs.to_wkt() if grid.crs is not None else ""
        arrays = []
        for s in secs:
            fr = sr.frames[float(s)]
            a = np.asarray(getattr(fr, attr), dtype=np.float32)
            if quantity == "brightness_temperature":
                # deferred: 7 ms of the chain's import (measured); the renderer above has
                # loaded them by now
                from shipthermal.optics.planck import brightness_temperature
                from shipthermal.optics.responses import user_bands

                with user_bands(isc.user_bands):            # a user sensor's band
                    a = brightness_temperature(np.maximum(a, 1e-12), band).astype(np.float32)
            arrays.append((a, fr))
        stamps = self._timestamps(secs)
        utc = stamps.tz_convert("UTC").tz_localize(None)
        coords = {"y": ("y", y, {"units": "m", "long_name": "northing of pixel centre"}),
                  "x": ("x", x, {"units": "m", "long_name": "easting of pixel centre"}),
                  "ship_coverage": (("y", "x"), renderer.coverage.astype(np.float32),
                                    {"units": "1", "long_name": "ship area fraction of the "
                                     "pixel"}),
                  "spatial_ref": ((), 0, {"crs_wkt": crs_wkt, "spatial_ref": crs_wkt})}
        attrs = {"units": units, "long_name": f"{long_name} {band} µm", "quantity": quantity,
                 "band": band, "crs_wkt": crs_wkt, "grid_mapping": "spatial_ref",
                 "scenario": self.scenario.name, "time_zone": self.scenario.location.time_zone,
                 "view_zenith_deg": isc.view_zenith_deg,
                 "view_azimuth_deg": isc.view_azimuth_deg}
        if many:
            data = np.stack([a for a, _ in arrays])
            coords["time"] = ("time", utc.to_numpy())
            attrs["local_time"] = [s.isoformat() for s in stamps]
            attrs["sun_zenith_deg"] = [float(fr.sun_zenith_deg) for _, fr in arrays]
            attrs["sun_azimuth_deg"] = [float(fr.sun_azimuth_deg) for _, fr in arrays]
            dims = ("time", "y", "x")
        else:
            data, fr = arrays[0]
            coords["time"] = utc.to_numpy()[0]
            attrs["local_time"] = stamps[0].isoformat()
            attrs["sun_zenith_deg"] = float(fr.sun_zenith_deg)
            attrs["sun_azimuth_deg"] = float(fr.sun_azimuth_deg)
            dims = ("y", "x")
        return xr.DataArray(data, dims=dims, coords=coords, attrs=attrs, name=quantity)

    # ---- products -------------------------------------------------------------------------
    def save(self, run_dir=None, *, force: bool = False, imaging: bool = True,
             report: bool | None = None) -> Path:
        """Write a run folder with the files ``shipthermal run --image`` writes: the
        scenario copy, ``thermal/<name>/`` (part means, summary, energy, history; pictures
        and VTKHDF as ``outputs.formats`` asks), ``imaging/`` (background, NetCDF image
        stacks, GeoTIFFs, panels, SCR curves, metrics, ``crossovers.csv``) and, with
        ``html`` in ``outputs.formats``, ``report.html``.

        Parameters
        ----------
        run_dir : path-like, optional
            The folder (default ``outputs.directory``). A finished run there is replaced
            only with ``force``; folders that shipthermal did not write are refused.
        imaging : bool
            Include the imaging stage.
        report : bool, optional
            Write ``report.html`` (default: as ``outputs.formats`` says).

        Returns
        -------
        pathlib.Path
            The run folder.
        """
        sc = self.scenario
        out = Path(run_dir if run_dir is not None else
                   pipeline.output_inputs(sc)["directory"])
        case = sc.name
        series = self._render_series() if imaging else None
        with RunDir(out, force=force, command=["shipthermal.Simulation", case], kind="run",
                    scenario=sc, inputs=scenario_inputs(sc)) as run:
            run.add_scenario(sc)
            run.manifest["cases"][case]["scenario"] = "scenario.toml"
            run.record(f"thermal/{case} (solve)", float(self.thermal.timings.get("total", 0)))
            pipeline.store_thermal(run, case, self.thermal, sc)
            if imaging:
                self._write_imaging(run, case, series)
            if report if report is not None else "html" in sc.outputs.formats:
                run.claim("report.html")
                run.mark_finished()
                write_report(run.path, finishing=True)
        return out

    def _write_imaging(self, run, case: str, series: dict) -> None:
        # deferred: the background's writers (scikit-learn, pykrige) and the renderer add
        # 0.8 s to the chain's import (measured)
        from imaging.background.outputs import write_outputs
        from imaging.experiment import experiment_products


        sc = self.scenario
        isc = self.imaging_scenario
        given = pipeline.experiment_inputs(sc)
        season = isc.season
        with run.stage("imaging") as tmp:
            write_outputs(self.simulation.background, tmp / "background" / case)
            experiment_products(tmp, {(season, b): sr for b, sr in series.items()},
                                {season: isc}, {season: self.history},
                                {season: given["typical_hours"]},
                                given["shared_panel_scale"],
                                figures=FigureOptions.from_outputs(sc.outputs))

    def report(self, path, *, run_dir=None, force: bool = False) -> Path:
        """Write the self-contained HTML report (the one ``shipthermal run`` writes: the
        answer first, the day under a time slider, thermal, imaging) to ``path``.

        The report is made from a run folder: ``run_dir`` keeps it (:meth:`save`, with
        ``force``); otherwise a temporary one is written and removed. Returns ``path``.
        """
        target = Path(path)
        if target.is_dir() or target.suffix.lower() not in (".html", ".htm"):
            raise InputError("path", str(path), "must name an .html file",
                             "e.g. res.report('out/report.html')")
        if target.exists() and not is_report_file(target):
            raise InputError("path", str(path), "is a file that shipthermal did not write",
                             "Choose a new file name: a report replaces only a report")
        target.parent.mkdir(parents=True, exist_ok=True)
        if run_dir is not None:
            return write_report(self.save(run_dir, force=force, report=True), target)
        with tempfile.TemporaryDirectory(prefix="shipthermal-report-") as tmp:
            return write_report(self.save(Path(tmp) / self.scenario.name, report=False),
                                target)

    # ---- display ------------------------------------------------------------------------
    def _lines(self) -> list[tuple[str, str]]:
        sc = self.scenario
        th = self.thermal
        loc = sc.location
        pm = th.part_means
        deck = (f", deck {pm['deck'].min():.1f}–{pm['deck'].max():.1f} K"
                if "deck" in pm else "")
        days = (f"{th.meta.get('spinup_days', th.days)} spin-up + "
                f"{th.meta['record_days']} recorded days" if th.is_record
                else f"{th.days} day{'s' if th.days != 1 else ''}")
        rows = [("site", f"{_site(loc)}, {sc.time.date} ({sc.time.season})"),
                ("thermal", f"{th.ship.name}, {th.ship.n_faces} faces, {days} "
                            f"({'converged' if th.converged else 'not converged'}){deck}")]
        if self._series is None:
            rows.append(("imaging", "not rendered yet (on first use of .scr, .crossovers)"))
        else:
            sr = next(iter(self._series.values()))
            rows.append(("imaging", f"{', '.join(self._series)} µm, {sr.times_s.size} frames "
                                    f"every {sc.imaging.scr_interval / 60:g} min"))
            cross = [f"{b} {_clock_text(c.time)} {c.direction}"
                     for b, s in self._series.items() for c in s.crossovers]
            shown = "; ".join(cross[:6]) + (f"; … ({len(cross)} in all)" if len(cross) > 6
                                             else "")
            rows.append(("crossovers", shown or "none"))
        return rows

    def __repr__(self) -> str:
        head = f"SimulationResult({self.scenario.name!r})"
        return "\n".join([head] + [f"  {k:<11}{v}" for k, v in self._lines()])

    def _repr_html_(self) -> str:
        return _html_table(f"SimulationResult {self.scenario.name}", self._lines())
