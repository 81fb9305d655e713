"""The :class:`Scenario`: the validated sections and the builders that hand each stage its
inputs (weather record, environment, sensor, per-face properties), so both stages read
the same values.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import difflib
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ...atomic import atomic_write_text
from ...errors import InputError
from ...materials import MATERIALS
from .imaging_sections import BackgroundSettings, CalendarSettings, ImagingSettings
from .sections import MaterialSpec, ShipSettings
from .site_sections import _RECORD_HINT, Location, Time, WeatherSettings, _is_leap
from .spec import _BAD, ScenarioError, _Context, _opt, _section, _thaw, clock_seconds
from .thermal_sections import ConvectionSettings, OutputSettings, SolverSettings
from ...parameters import season_of_date
from .values import (CLIMATE_MONTHS, CLIMATE_RADIUS_DEG, DALIAN, DAY, MAX_RECORD_DAYS, SEASONS,
                     SENSOR_BANDS)
from .writing import _dump_toml


@dataclass(frozen=True)
class Scenario:
    """A validated scenario (build with :func:`load_scenario` / :func:`default_scenario`).

    Sections are attributes (``scenario.location.latitude``, ``scenario.ship.heading``);
    builders (:meth:`environment`, ``ship()``, :meth:`weather_record`, :meth:`sensor`) are
    lazy and import the heavy libraries only when called.
    """

    name: str = _opt(None, "name", "Scenario name (names the run directory)",
                     dynamic=lambda ctx: ctx.season, default_text="the season",
                     allowed_text="letters, digits, _ . - (1-64 characters)")
    description: str = _opt("", "str", "Free text")
    location: Location = _opt(None, "section", "Site", cls=Location)
    time: Time = _opt(None, "section", "Simulated day", cls=Time)
    weather: WeatherSettings = _opt(None, "section", "Weather", cls=WeatherSettings)
    ship: ShipSettings = _opt(None, "section", "Ship", cls=ShipSettings)
    solver: SolverSettings = _opt(None, "section", "Thermal solver", cls=SolverSettings)
    convection: ConvectionSettings = _opt(None, "section", "Convection of the air faces",
                                          cls=ConvectionSettings)
    materials: Mapping = _opt({}, "materials", "Materials of the user's, by name, for "
                              "ship.layups (every property with its source)", cls=MaterialSpec)
    background: BackgroundSettings = _opt(None, "section", "Port background",
                                          cls=BackgroundSettings)
    imaging: ImagingSettings = _opt(None, "section", "Imaging", cls=ImagingSettings)
    calendar: CalendarSettings = _opt(None, "section", "Detectability calendar",
                                      cls=CalendarSettings)
    outputs: OutputSettings = _opt(None, "section", "Outputs", cls=OutputSettings)
    source: str = field(default="", compare=False, repr=False, metadata={"internal": True})

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        """Checks across sections (run once every section is valid)."""
        dt = obj.solver.time_step
        if ctx.failed("solver.time_step"):
            pass
        elif not ctx.failed("time.output_interval") and not _multiple(obj.time.output_interval, dt):
            ctx.err("time.output_interval", obj.time.output_interval,
                    f"must be a multiple of solver.time_step ({dt:g} s)")
        fmt = obj.weather.file_format
        if fmt in ("epw", "tmy2", "tmy3") and not ctx.failed("weather", "time.date"):
            year = int(obj.time.date[:4])
            if obj.weather.year is not None and obj.weather.year != year:
                ctx.err("weather.year", obj.weather.year, f"must equal the year of time.date "
                        f"({year}): the typical year's rows are coerced to it",
                        "Leave weather.year out (it defaults to the date's year)")
            elif fmt in ("tmy2", "tmy3") and obj.weather.year is None and _is_leap(year):
                ctx.err("time.date", obj.time.date, "must not fall in a leap year with a TMY3 "
                        "file (typical years have no 29 February)", "e.g. use 2023")
        cp = obj.outputs.checkpoint_interval
        if cp > 0 and not ctx.failed("solver.time_step", "outputs.checkpoint_interval") \
                and not _multiple(cp, dt):
            ctx.err("outputs.checkpoint_interval", cp,
                    f"must be 0 or a multiple of solver.time_step ({dt:g} s)")
        if obj.weather.source == "builtin" and not ctx.failed("weather.source"):
            lat, lon = obj.location.latitude, obj.location.longitude
            if abs(lat - DALIAN["latitude"]) > CLIMATE_RADIUS_DEG and not ctx.failed(
                    "location.latitude"):
                ctx.err("location.latitude", lat, f"must lie within {CLIMATE_RADIUS_DEG:g} deg "
                        f"of Dalian ({DALIAN['latitude']} N) with weather.source = 'builtin' "
                        "(a Dalian climatology)", _RECORD_HINT)
            if abs(lon - DALIAN["longitude"]) > CLIMATE_RADIUS_DEG and not ctx.failed(
                    "location.longitude"):
                ctx.err("location.longitude", lon, f"must lie within {CLIMATE_RADIUS_DEG:g} "
                        f"deg of Dalian ({DALIAN['longitude']} E) with weather.source = "
                        "'builtin' (a Dalian climatology)", _RECORD_HINT)
            month = _dt.date.fromisoformat(obj.time.date).month
            months = CLIMATE_MONTHS[obj.time.season]
            if month not in months and not ctx.failed("time.date", "time.season"):
                ctx.err("time.date", obj.time.date, f"must fall in months {list(months)} for "
                        f"the built-in {obj.time.season} design day (mid-"
                        f"{'July' if obj.time.season == 'summer' else 'January'} climatology)",
                        "Change time.season, the date, or give a weather file")
        bg = obj.background
        if (bg.model == "paper" and bg.source == "builtin" and obj.weather.source != "builtin"
                and not ctx.failed("weather.source", "background")):
            ctx.err("background.model", "paper", "with background.source = 'builtin' needs "
                    "weather.source = 'builtin': the synthetic port's met grid is the built-in "
                    "Dalian design day, another climate than the weather file's",
                    "Use background.model = 'physical' (the port follows the weather file), or "
                    "real files with their own met grid (background.source = 'files')")
        half = obj.background.half_extent_m
        if half is not None and not ctx.failed("ship.mooring_position", "background"):
            x, y = obj.ship.mooring_position
            if max(abs(x), abs(y)) > half:
                ctx.err("ship.mooring_position", [x, y], f"must lie inside the port scene: "
                        f"|x|, |y| <= {half:g} m (background.size_px x 30 m / 2)")
        for band in () if ctx.failed("ship.band_emissivity", "imaging.sensor.preset",
                                     "imaging.sensor.response_file") else obj.imaging.bands:
            missing = []
            for part in ("hull", "deck", "superstructure"):
                try:
                    obj.emissivity(part, band)
                except InputError:
                    missing.append(part)
            if missing:
                ctx.err("ship.band_emissivity", band, f"needs a value for imaging band "
                        f"{band!r} for {', '.join(missing)} (no band listed there contains it)",
                        f'Add "{band}" = <emissivity> to [ship.band_emissivity.{missing[0]}]'
                        + (" and the other parts" if len(missing) > 1 else ""))
        obj = _check_layups(obj, raw, ctx)
        if obj.outputs.directory is None:
            obj = dataclasses.replace(obj, outputs=dataclasses.replace(
                obj.outputs, directory=f"runs/{obj.name}"))
        return obj

    # ---- derived values -------------------------------------------------------------------
    @property
    def start(self):
        """Local midnight of ``time.date`` (tz-aware pandas Timestamp): the solver clock's 0."""
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        import pandas as pd

        return pd.Timestamp(self.time.date).tz_localize(self.location.time_zone)

    @property
    def atmosphere_model(self) -> str:
        """The LOWTRAN model atmosphere of the images (a name of
        :data:`imaging.atmosphere.MODEL_NAMES`).

        ``[imaging.atmosphere] model`` names it, or ``'auto'`` picks it: with the built-in
        weather (the Dalian design days) mid-latitude summer / winter as ``time.season``
        (the paper's settings); with a weather file the model whose surface air temperature
        is closest to the day's mean air temperature
        (:func:`imaging.atmosphere.model_for_site`, at the site's latitude and the month of
        ``time.date``). The model is then scaled to each hour's weather. A weather record
        (``weather.day = 'record'``) with ``'auto'`` is placed day by day
        (:attr:`atmosphere_by_day`); this is then the whole record's model.
        """
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from imaging.atmosphere import model_for_site, model_name

        m = self.imaging.atmosphere.model
        if m != "auto":
            return model_name(m)
        if self.weather.source == "builtin":
            return model_name(self.time.season)
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from ..run_environment import day_weather

        temp = float(np.mean(day_weather(self.environment())["temp_air"]))
        month = _dt.date.fromisoformat(self.time.date).month
        return model_for_site(self.location.latitude, month, temp)

    @property
    def atmosphere_by_day(self) -> bool:
        """Whether each local day of the images gets its own model atmosphere: a weather
        record (``weather.day = 'record'``, from a file) with ``[imaging.atmosphere] model =
        'auto'``: a year's winter overpasses are seen through a winter atmosphere and its
        summer ones through a summer atmosphere
        (:meth:`imaging.experiment.ImagingScenario.atmosphere_model_at`)."""
        return (self.imaging.atmosphere.model == "auto" and self.weather.source != "builtin"
                and self.weather.day == "record")

    @property
    def atmosphere_season(self) -> str:
        """Label of the images' atmosphere: 'summer' / 'winter' for the paper's mid-latitude
        summer / winter, else the model's name (:attr:`atmosphere_model`)."""
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from imaging.atmosphere import model_label

        return model_label(self.atmosphere_model)

    def emissivity_band(self, band) -> str:
        """The band whose emissivities a sensor band takes: a named sensor band (or the
        user's) as its half-maximum range ``"lo-hi"`` [µm], others unchanged."""
        if not (isinstance(band, str) and (band == "user" or band in SENSOR_BANDS)) \
                or band in ("3-5", "8-14"):
            return band
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from shipthermal.optics.responses import named_band, nominal_range

        resp = self.instrument().bands[0].response if band == "user" else named_band(band)
        lo, hi = nominal_range(resp)
        return f"{lo:g}-{hi:g}"

    @property
    def bands(self) -> tuple:
        """Imaging band names (canonical)."""
        return self.imaging.bands

    def image_seconds(self) -> tuple:
        """Image times as seconds after local midnight of ``time.date`` [s]."""
        return tuple(clock_seconds(t) for t in self.imaging.times)

    def map_seconds(self) -> tuple:
        """Surface-map times as seconds after local midnight [s]."""
        return tuple(clock_seconds(t) for t in self.time.map_times)

    def emissivity(self, part: str, band) -> float:
        """Emissivity of a ship part in a band [-] (same values for both stages; a sensor's
        named band takes the value of its half-maximum range, :meth:`emissivity_band`)."""
        return self.ship.emissivity(part, self.emissivity_band(band))

    def solar_absorptivity(self, part: str) -> float:
        """Solar absorptivity of a ship part [-]."""
        return self.ship.solar_absorptivity_of(part)

    def longwave_emissivity(self, part: str) -> float:
        """Broadband long-wave emissivity of a ship part [-]."""
        return self.ship.longwave_emissivity_of(part)

    def face_property(self, ship, name: str, band=None):
        """One value per triangle of ``ship`` from the scenario's per-part tables.

        Parameters
        ----------
        ship : ShipGeometry
            Usually ``scenario.ship()``.
        name : {'solar_absorptivity', 'longwave_emissivity', 'emissivity',
                'compartment_temperature'}
            ``'emissivity'`` needs ``band``.
        band : str or (float, float), optional
            Sensor band for ``'emissivity'``.

        Returns
        -------
        numpy.ndarray
            (M,) float, [-] or [K] for the compartment temperature.
        """
        lookups = {"solar_absorptivity": self.ship.solar_absorptivity_of,
                   "longwave_emissivity": self.ship.longwave_emissivity_of,
                   "compartment_temperature": self.ship.compartment_temperature_of,
                   "emissivity": lambda part: self.emissivity(part, band)}
        if name not in lookups:
            raise InputError("name", name, f"must be one of {', '.join(lookups)}")
        if name == "emissivity" and band is None:
            raise InputError("band", None, "is required for 'emissivity' (e.g. '8-14')")
        per_part = np.array([lookups[name](p) for p in ship.part_names], dtype=float)
        return per_part[np.asarray(ship.face_part)]

    # ---- builders -----------------------------------------------------------------------
    def weather_record(self):
        """The :class:`~shipthermal.environment.Weather` the run uses, starting at
        :attr:`start` (periodic for the built-in day and for ``weather.day = 'periodic'``).

        Offsets (``*_offset``) are applied here, the same way to the built-in day and to a
        file: air temperature and wind speed shifted (wind clipped at 0), cloud cover
        shifted and clipped to [0, 1]; humidity, sea temperature and irradiance unchanged.
        Files are read here, not at load. The built-in day's SST is its daily mean when
        ``weather.sea_skin`` models the warm layer, else its prescribed cycle.
        """
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from shipthermal.environment import Weather, climate_day

        w, loc = self.weather, self.location
        if w.source == "builtin":
            day = dataclasses.replace(climate_day(self.time.season), date=self.time.date,
                                      latitude=loc.latitude, longitude=loc.longitude,
                                      altitude=loc.altitude, tz=loc.time_zone)
            # with a skin model the warm layer makes the SST's diurnal cycle
            weather = day.weather(60, sst_cycle=w.sea_skin == "none")
            periodic, source = True, None
        else:
            weather, _ = self._file_weather()
            periodic, source = w.day == "periodic", f"{weather.source} from {self.time.date}"
        return Weather(time=weather.time, temp_air=weather.temp_air + w.temp_air_offset,
                       relative_humidity=weather.relative_humidity,
                       wind_speed=np.maximum(weather.wind_speed + w.wind_speed_offset, 0.0),
                       wind_direction=weather.wind_direction,
                       cloud_cover=np.clip(weather.cloud_cover + w.cloud_cover_offset, 0.0, 1.0),
                       temp_sea=weather.temp_sea, ghi=weather.ghi,
                       longwave_down=weather.longwave_down, periodic=periodic,
                       source=source or weather.source, solar_interval=weather.solar_interval)

    def weather_span(self, record=None):
        """``(first, last)`` instants of weather the run needs (tz-aware, both included):
        the 24 h of ``time.date`` for a periodic day; for ``weather.day = 'record'``
        ``weather.days`` whole days from ``time.date`` (default: every whole day the
        record covers, read from ``record``, a
        :class:`~shipthermal.environment.station.StationRecord`)."""
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        import pandas as pd

        start = self.start
        if self.weather.day == "periodic":
            return start, start + pd.Timedelta(hours=23)
        days = self.weather.days
        if record is not None and len(record.frame):
            # lazy: loading a scenario imports no stage library (test_load_is_lazy)
            from shipthermal.environment.station import EDGE_HOLD_S

            first, last = record.frame.index[0], record.frame.index[-1]
            covered = int((last + pd.Timedelta(seconds=EDGE_HOLD_S) - start).total_seconds()
                          // DAY)
            starts_inside = first <= start + pd.Timedelta(seconds=EDGE_HOLD_S)
            if days is None and covered > MAX_RECORD_DAYS:
                raise InputError("weather.days", None, f"the record covers {covered} days "
                                 f"from time.date; a record run takes at most "
                                 f"{MAX_RECORD_DAYS}", "Set weather.days")
            if days is None:
                days = covered
            elif starts_inside and 1 <= covered < days:
                # the file starts in time but ends before the days asked for
                name = Path(self.weather.source).name
                raise InputError("weather.days", days, f"{name} covers {covered} whole "
                                 f"day(s) from time.date {self.time.date} (its last "
                                 f"observation {last:%Y-%m-%d %H:%M %Z})",
                                 f"Set weather.days = {covered} or less, an earlier "
                                 "time.date, or give a longer file")
        days = max(int(days or 1), 1)
        return start, start + pd.Timedelta(days=days)

    def _file_weather(self):
        """The weather file over :meth:`weather_span`: ``(Weather, WeatherReport)``; every
        problem of the file over the span raised together as one :class:`ScenarioError`."""
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from shipthermal.environment.station import check_weather

        w = self.weather
        if not os.path.isfile(w.source):
            raise InputError("weather.source", w.source, "must be an existing file",
                             "The file was moved or deleted after the scenario was loaded")
        rec = _read_station_cached(w.source, w.file_format, self.location.time_zone,
                                   w.temp_unit, w.cloud_unit, int(self.time.date[:4]),
                                   w.use_measured_irradiance, w.use_measured_longwave,
                                   os.path.getmtime(w.source))
        first, last = self.weather_span(rec)
        weather, report, problems = check_weather(
            rec, first, last, max_gap_hours=w.max_gap_hours, wind_height=w.wind_height,
            fallback={"temp_sea": w.temp_sea, "cloud_cover": w.cloud_cover,
                      "wind_direction": w.wind_direction},
            periodic=w.day == "periodic",
            site=(self.location.latitude, self.location.longitude),
            max_site_distance_km=w.max_site_distance)
        if problems:
            raise ScenarioError(problems, f"weather file {Path(w.source).name}")
        return weather, report

    def check_weather(self) -> list:
        """Open the weather file and check it over the simulated span (columns, units,
        coverage of the date, gaps): every problem raised at once as a
        :class:`ScenarioError`; otherwise the report's lines (gaps interpolated, constants
        used, wind height), an empty list for the built-in weather."""
        if self.weather.source == "builtin":
            return []
        weather, report = self._file_weather()
        span = f"{weather.time[0]:%Y-%m-%d %H:%M} … {weather.time[-1]:%Y-%m-%d %H:%M %Z}"
        return [f"weather {weather.source}: {len(weather.time)} hourly values, "
                f"{span}"] + report.lines()

    def environment(self):
        """The run's :class:`~shipthermal.environment.Environment`: built once per scenario
        object (the weather file read and the offsets applied once) and the same object for
        every stage that asks — the thermal stage's forcing, and the imaging stage's sea,
        aerosol and sky (:mod:`shipthermal.app.run_environment`).

        Location, date, time zone, weather, ship heading and speed and the sky models all
        come from the scenario; ``environment().start == scenario.start``.
        """
        env = self.__dict__.get("_environment")
        if env is not None:
            return env
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from shipthermal.environment import Environment

        w, loc = self.weather, self.location
        env = Environment(loc.latitude, loc.longitude, self.weather_record(),
                          ship_heading=self.ship.heading, ship_speed=self.ship.speed,
                          altitude=loc.altitude, clear_sky_model=w.clear_sky_model,
                          cloud_model=w.cloud_model, decomposition=w.decomposition,
                          linke_turbidity=w.linke_turbidity, sea_emissivity=w.sea_emissivity,
                          sea_skin=w.sea_skin)
        object.__setattr__(self, "_environment", env)      # frozen: a cache, not a field
        return env

    def sensor(self):
        """The :class:`imaging.sensor.SensorSpec` of ``[imaging.sensor]`` (the preset's
        optics where the keys are not given)."""
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from imaging.sensor import SensorSpec

        s = self.imaging.sensor
        return SensorSpec(altitude_m=s.altitude_m, focal_length_m=s.focal_length_m,
                          aperture_m=s.aperture_m, pixel_pitch_m=s.pixel_pitch_m,
                          optics_transmittance=s.optics_transmittance)

    def instrument(self):
        """The :class:`imaging.instruments.Instrument` of ``[imaging.sensor]``: the preset
        with this scenario's optics, or the user's (``response_file``, read once per
        scenario object; NETD ``netd_k``)."""
        # lazy: loading a scenario imports no stage library (test_load_is_lazy)
        from imaging.instruments import instrument, user_instrument

        inst = self.__dict__.get("_instrument")
        if inst is not None:
            return inst
        s = self.imaging.sensor
        if s.preset == "user":
            inst = user_instrument("user", {"user": s.response_file}, self.sensor(),
                                   netd_K=s.netd_k or None)
        else:
            inst = dataclasses.replace(instrument(s.preset), spec=self.sensor())
        object.__setattr__(self, "_instrument", inst)      # frozen: a cache, not a field
        return inst

    # ---- serialisation ----------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain nested dict (TOML shape, all values explicit; ``load_scenario`` accepts it)."""
        return _thaw(self)

    def to_toml(self) -> str:
        """The scenario as TOML; ``loads_scenario(sc.to_toml()) == sc``."""
        head = ["# Scenario written by shipthermal.app.scenario (all values explicit)"]
        if self.source:
            head.append(f"# loaded from {self.source}")
        return "\n".join(head) + "\n" + _dump_toml(self.to_dict())

    def write(self, path) -> Path:
        """Write :meth:`to_toml` to ``path`` atomically (temporary name, then rename)."""
        return atomic_write_text(path, self.to_toml())

    def updated(self, changes: Mapping[str, Any]) -> "Scenario":
        """A re-validated copy with dotted keys changed, e.g. ``{"ship.heading": 90}``
        (for sweeps)."""
        data = self.to_dict()
        for key, value in changes.items():
            node = data
            parts = key.split(".")
            for p in parts[:-1]:
                node = node.setdefault(p, {})
            node[parts[-1]] = value
        return _load(data, Path.cwd().resolve(), "scenario (dict)")


_STATION_CACHE: dict = {}


def _read_station_cached(path, fmt, tz, temp_unit, cloud_unit, year, irradiance, longwave,
                         mtime):
    """Read a weather file once per process (the run, the imaging stage and ``validate``
    ask for it several times); keyed by every option and the file's modification time."""
    # lazy: loading a scenario imports no stage library (test_load_is_lazy)
    from shipthermal.environment.station import read_station

    key = (path, fmt, tz, temp_unit, cloud_unit, year, irradiance, longwave, mtime)
    if key not in _STATION_CACHE:
        if len(_STATION_CACHE) > 8:
            _STATION_CACHE.clear()
        _STATION_CACHE[key] = read_station(path, fmt, tz=tz, temp_unit=temp_unit,
                                           cloud_unit=cloud_unit, year=year,
                                           use_measured_irradiance=irradiance,
                                           use_measured_longwave=longwave)
    return _STATION_CACHE[key]


def _multiple(x: float, step: float) -> bool:
    n = round(x / step)
    return n >= 1 and abs(n * step - x) <= 1e-9 * max(x, 1.0)


# ---------------------------------------------------------------------------------------
# Loading
# ---------------------------------------------------------------------------------------
def _peek_season(raw: Mapping) -> str:
    """The season of the defaults: ``time.season`` if given; with a weather file, the half of
    the year of ``time.date`` at the site (:func:`shipthermal.parameters.season_of_date`);
    else summer."""
    t = raw.get("time") if isinstance(raw, Mapping) else None
    s = t.get("season") if isinstance(t, Mapping) else None
    if s in SEASONS:
        return s
    w = raw.get("weather")
    source = w.get("source") if isinstance(w, Mapping) else None
    date = t.get("date") if isinstance(t, Mapping) else None
    if isinstance(source, str) and source != "builtin" and date is not None:
        try:
            month = (date if isinstance(date, _dt.date) else _dt.date.fromisoformat(str(date))).month
            loc = raw.get("location")
            lat = loc.get("latitude", DALIAN["latitude"]) if isinstance(loc, Mapping) else \
                DALIAN["latitude"]
            return season_of_date(month, float(lat))
        except (ValueError, TypeError):
            pass                 # the date or latitude is reported by their own checks
    return "summer"


def _load(raw: Any, base_dir: Path, source: str) -> Scenario:
    season = _peek_season(raw) if isinstance(raw, Mapping) else "summer"
    ctx = _Context(base_dir, season)
    raw = _plain(raw)
    obj = _section(Scenario, raw, "", ctx)
    if ctx.errors or obj is _BAD:
        if not ctx.errors:     # a section failed without saying why: never expected
            ctx.err("scenario", None, "could not be built")
        raise ScenarioError(ctx.errors, source)
    return dataclasses.replace(obj, source=source)


def _plain(value: Any) -> Any:
    """Mappings → dicts, tuples → lists (dict input may come from :meth:`to_dict` or code)."""
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    return value


def _check_layups(obj, raw, ctx):
    """Layers name a built-in or a [materials] material; a paint's optics sit on the outer
    layer only, and are not given twice for a part. The ship gets the user's materials."""
    if ctx.failed("ship.layups", "materials"):
        return obj
    user = dict(obj.materials)
    raw_ship = raw.get("ship", {}) if isinstance(raw.get("ship"), dict) else {}
    for part, layers in obj.ship.layups.items():
        for i, layer in enumerate(layers):
            where = f"ship.layups.{part}[{i}]"
            if layer.material not in MATERIALS and layer.material not in user:
                known = sorted(MATERIALS) + sorted(user)
                ctx.err(f"{where}.material", layer.material,
                        "must be a built-in material ("
                        + ", ".join(repr(m) for m in sorted(MATERIALS)) + ")"
                        + (" or one of [materials] (" + ", ".join(repr(m) for m in sorted(user))
                           + ")" if user else " or a name of [materials]"),
                        (_suggest_name(layer.material, known) + " " if
                         _suggest_name(layer.material, known) else "")
                        + f"Or add [materials.{layer.material}] with conductivity, density, "
                        "specific_heat and source")
            for key in ("solar_absorptivity", "longwave_emissivity"):
                if getattr(layer, key) is None:
                    continue
                if i > 0:
                    ctx.err(f"{where}.{key}", getattr(layer, key), "may be given on the "
                            "outer layer only (the surface: a paint's optics)",
                            f"Move it to ship.layups.{part}[0]")
                elif part in (raw_ship.get(key) or {}):
                    ctx.err(f"ship.{key}.{part}", raw_ship[key][part], f"is given twice: "
                            f"ship.layups.{part}[0].{key} = {getattr(layer, key)} sets it too",
                            "Keep one of them")
    return dataclasses.replace(obj, ship=dataclasses.replace(
        obj.ship, user_materials=obj.materials))


def _suggest_name(name, known) -> str:
    close = difflib.get_close_matches(str(name), known, n=1, cutoff=0.6)
    return f"Did you mean {close[0]!r}?" if close else ""
