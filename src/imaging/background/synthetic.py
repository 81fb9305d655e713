"""The built-in synthetic port, written in the real input formats.

A fictitious port on the coast of northern China (default centre 38.93 N, 121.65 E, a
Dalian-like setting; UTM zone 51N), ``size_px`` x ``size_px`` pixels of 30 m (default 334 ->
10.0 km): sea in the south-east, a harbour basin with three piers, a breakwater with an
entrance, port warehouses and a town (buildings), vegetated hills in the north-west.
Everything is deterministic from ``seed``.

Files written (the loaders of this package read them back, so they are exercised):

* Landsat-8 Collection-2 L1 bands 2–7 and 10 (uint16 DN GeoTIFF, EPSG:326xx, fill 0) with
  the MTL in text and JSON form (real C2 rescaling constants of Landsat-8 band 10:
  ``RADIANCE_MULT 3.3420E-04``, ``RADIANCE_ADD 0.1``, ``K1 774.8853``, ``K2 1321.0789``;
  reflectance ``MULT 2.0E-05``, ``ADD -0.1``);
* a DEM GeoTIFF in EPSG:4326 at 1 arc-second, float32 (like Copernicus GLO-30), so the
  reader's reprojection onto the scene grid is exercised;
* an hourly CLDAS-like NetCDF: ``temperature(time, lat, lon)`` [K] on a 0.0625 deg grid,
  NaN over sea (a land product), plus ``sst(time)`` [K] and ``tcwv(time)`` [g cm-2];
* an ROI label GeoTIFF (training regions drawn inside each class).

**Truth model — read before trusting the LST test.** Band-10 DN are produced from the true
LST, the true emissivity and the atmosphere of the day's water vapour with *the same*
radiative transfer equation and atmospheric functions the retrieval inverts
(:func:`.lst.at_sensor_radiance`, Jiménez-Muñoz et al. 2014). The true emissivity is the NDVI
thresholds emissivity (default TIRS band-10 set) of the true reflectances. A recovery test
therefore checks the inversion chain (formats, rescaling, K1/K2, NDVI, emissivity, RTE
inversion, quantisation), not the accuracy of the atmospheric model against a real
atmosphere (that is measured against LOWTRAN 7 in ``test_bg_lst.py``: 2-3 K cold bias).

The land truth LST follows eq. 15 exactly: ``LST = T_met(x, y, t_ov) + b0[class] + b1 Dem +
b2 Slope + b3 Southness + texture``, with the known betas in :data:`SEASONS`; water is the
SST of the overpass time plus a little texture.

Climatological numbers (illustrative of the Bohai/Yellow Sea coast, rounded): July mean air
temperature near Dalian about 24 C, January about -4 C (China Meteorological Administration
1991–2020 normals); the sea is the built-in design day's own
(:func:`shipthermal.environment.climate_day`); column water vapour of the
mid-latitude summer / winter standard atmospheres 2.9 / 0.85 g cm-2 (AFGL, Anderson et al.
1986). Land-surface diurnal amplitudes and class offsets are plausible values, not data.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from datetime import datetime, timedelta, timezone

import numpy as np
import pandas as pd
import pvlib
import rasterio
import xarray as xr
from rasterio.crs import CRS
from rasterio.warp import transform as warp_transform
from scipy.ndimage import binary_erosion, gaussian_filter

from shipthermal.atomic import atomic_path
from shipthermal.environment.climatology import climate_day
from shipthermal.errors import InputError
from shipthermal.parameters import DESIGN_DAY_DATES

from ..parameters import SYNTHETIC_PIXEL_M
from .landsat.grid import REFLECTIVE_BANDS, THERMAL_BAND, SceneGrid, north_up_transform
from .lst import at_sensor_radiance, atmospheric_functions, emissivity_ndvi_threshold, ndvi
from .terrain import slope_aspect, southness

__all__ = ["SEASONS", "SeasonSpec", "SyntheticPort", "write_synthetic_port", "LANDSAT8_B10",
           "synthetic_surface", "synthetic_grid"]

LANDSAT8_B10 = {"mult": 3.3420e-4, "add": 0.1, "k1": 774.8853, "k2": 1321.0789}
"""Landsat-8 TIRS band-10 rescaling and thermal constants (Collection-2 MTL)."""
REFL_MULT, REFL_ADD = 2.0e-5, -0.1

# Endmember reflectances (B2..B7), typical spectral-library values, rounded. Class spectra
# are per-pixel mixtures of endmembers, so classes overlap a little as in real scenes.
_ENDMEMBERS = {
    "summer": {"water": (0.070, 0.060, 0.035, 0.020, 0.010, 0.006),
               "vegetation": (0.030, 0.060, 0.040, 0.350, 0.180, 0.090),
               "soil": (0.100, 0.130, 0.170, 0.230, 0.300, 0.250),
               "concrete": (0.180, 0.190, 0.200, 0.220, 0.240, 0.220),
               "roof": (0.080, 0.080, 0.080, 0.090, 0.100, 0.090)},
    "winter": {"water": (0.065, 0.055, 0.032, 0.018, 0.009, 0.005),
               "vegetation": (0.040, 0.060, 0.050, 0.280, 0.200, 0.110),
               "soil": (0.110, 0.140, 0.180, 0.240, 0.310, 0.260),
               "concrete": (0.190, 0.200, 0.210, 0.230, 0.250, 0.230),
               "roof": (0.085, 0.085, 0.085, 0.095, 0.105, 0.095)},
}
# class -> (endmember a, endmember b, fraction of a: low, high)
_MIXTURES = {1: ("water", "water", 1.0, 1.0), 2: ("vegetation", "soil", 0.6, 1.0),
             3: ("soil", "concrete", 0.4, 1.0), 4: ("roof", "concrete", 0.35, 0.9)}


@dataclass(frozen=True)
class SeasonSpec:
    """One season's synthetic day.

    Attributes
    ----------
    date_local : str
        Local date of the day (YYYY-MM-DD): the built-in design day's
        (:data:`shipthermal.parameters.DESIGN_DAY_DATES`).
    overpass_utc : str
        Landsat scene centre time (HH:MM:SS, UTC).
    temp_land_mean, temp_land_amplitude : float
        Met land-surface temperature daily mean and half-range [K]; peak at 13:00 local.
    water_vapour : float
        Total column water vapour [g cm-2].
    class_offsets : dict[int, float]
        Land-class LST offset over the met temperature at the overpass [K].
    beta : tuple[float, float, float]
        True eq. 15 coefficients: [K m-1], [K deg-1], [K per unit southness].
    basin_offset : float
        Harbour basin water offset over the open sea [K].
    """

    date_local: str
    overpass_utc: str
    temp_land_mean: float
    temp_land_amplitude: float
    water_vapour: float
    class_offsets: dict
    beta: tuple
    basin_offset: float


SEASONS = {
    "summer": SeasonSpec(DESIGN_DAY_DATES["summer"], "02:36:12.5000000", 300.0, 7.0, 2.9,
                         {2: -2.0, 3: 3.0, 4: 5.0}, (-0.0060, -0.050, 1.0), 0.3),
    "winter": SeasonSpec(DESIGN_DAY_DATES["winter"], "02:36:15.2500000", 271.0, 5.0, 0.85,
                         {2: -0.5, 3: 1.5, 4: 2.5}, (-0.0050, -0.040, 2.0), -0.1),
}
"""The synthetic scene of each built-in design day: its date is the design day's, its sea
the design day's sea (:func:`_temp_sst`), so the paper's chain on the synthetic port and
the ship see one sea."""

UTC_OFFSET_HOURS = 8.0
"""China Standard Time (UTC+8)."""


@dataclass
class SyntheticPort:
    """Paths of the written files and the truth arrays.

    Attributes
    ----------
    directory : str
    season : str
    mtl_txt, mtl_json, dem, met, roi : str
        File paths.
    grid : SceneGrid
    truth : dict[str, ndarray | float]
        ``class_map``, ``lst`` [K], ``emissivity`` [-], ``elevation`` [m], ``slope_deg``,
        ``southness``, ``temp_met_overpass`` [K], ``beta``, ``water_vapour`` [g cm-2].
    """

    directory: str
    season: str
    mtl_txt: str
    mtl_json: str
    dem: str
    met: str
    roi: str
    grid: SceneGrid
    truth: dict = field(repr=False)


def _unit_noise(rng, shape, sigma_px):
    f = gaussian_filter(rng.standard_normal(shape), sigma_px, mode="wrap")
    return f / f.std()


class _Layout:
    """Continuous geometry of the port in scene-normalised coordinates (u east, v south)."""

    def coast(self, u):
        # v of the coastline: land for v below it (north); the coast runs SW-NE.
        return 0.66 - 0.28 * (u - 0.3) + 0.03 * np.sin(9.0 * u)

    def land(self, u, v):
        land = v < self.coast(u)
        basin = (u > 0.42) & (u < 0.74) & (v > 0.40)
        land &= ~basin
        piers = (((u > 0.48) & (u < 0.50)) | ((u > 0.56) & (u < 0.58)) | ((u > 0.64) & (u < 0.66))) \
            & (v > 0.40) & (v < 0.58)
        breakwater = (v > 0.655) & (v < 0.665) & (u > 0.36) & (u < 0.70)
        sheltered = basin & (v < 0.655) & ~piers          # basin water inside the breakwater
        return land | piers | breakwater, sheltered, piers | breakwater

    def elevation(self, u, v):
        land, _, structures = self.land(u, v)
        hills = (260 * np.exp(-((u - 0.14) ** 2 + (v - 0.12) ** 2) / (2 * 0.07 ** 2))
                 + 180 * np.exp(-((u - 0.33) ** 2 + (v - 0.06) ** 2) / (2 * 0.06 ** 2))
                 + 140 * np.exp(-((u - 0.07) ** 2 + (v - 0.34) ** 2) / (2 * 0.05 ** 2)))
        plain = 4.0 + 60.0 * np.clip(self.coast(u) - v, 0, None)
        z = np.where(land, plain + hills, 0.0)
        return np.where(structures, 4.0, z)


def _temp_met(season: SeasonSpec, x_km, y_km, hour_local):
    """Met land temperature field [K] at scene-relative position (x east, y north, km)."""
    day = np.cos(2 * np.pi * (hour_local - 13.0) / 24.0)
    spatial = (0.06 * y_km - 0.04 * x_km) * (1.0 + 0.8 * day) + 0.5 * np.sin(x_km / 9.0) * np.cos(y_km / 7.0)
    return season.temp_land_mean + season.temp_land_amplitude * day + spatial


def _temp_sst(season: SeasonSpec, hour_local):
    """The design day's sea temperature [K] at local hours (the ship's bulk sea of the same
    day, :func:`shipthermal.environment.climate_day`)."""
    name = next(k for k, v in SEASONS.items() if v is season)
    return climate_day(name).temp_sea(np.asarray(hour_local, dtype=float))


def _atomic_geotiff(path, array, **profile):
    with atomic_path(path) as tmp, rasterio.open(
            tmp, "w", driver="GTiff", height=array.shape[-2], width=array.shape[-1],
            count=1 if array.ndim == 2 else array.shape[0], dtype=array.dtype, **profile) as dst:
        dst.write(array, 1) if array.ndim == 2 else dst.write(array)


def _atomic_text(path, text):
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)


def _mtl_groups(season: SeasonSpec, sun_elevation, sun_azimuth, names, shape, grid: SceneGrid):
    b10 = LANDSAT8_B10
    return {
        "PRODUCT_CONTENTS": {
            "ORIGIN": "Synthetic port (shipthermal), Collection-2 Level-1 layout",
            "LANDSAT_PRODUCT_ID": names["product"],
            "PROCESSING_LEVEL": "L1TP",
            **{f"FILE_NAME_BAND_{b}": names[b] for b in (*REFLECTIVE_BANDS, THERMAL_BAND)},
        },
        "IMAGE_ATTRIBUTES": {
            "SPACECRAFT_ID": "LANDSAT_8",
            "SENSOR_ID": "OLI_TIRS",
            "DATE_ACQUIRED": season.date_local,
            "SCENE_CENTER_TIME": season.overpass_utc + "Z",
            "CLOUD_COVER": "0.00",
            "SUN_AZIMUTH": f"{sun_azimuth:.8f}",
            "SUN_ELEVATION": f"{sun_elevation:.8f}",
        },
        "PROJECTION_ATTRIBUTES": {
            "MAP_PROJECTION": "UTM",
            "DATUM": "WGS84",
            "UTM_ZONE": str(grid.crs.to_epsg() - 32600),
            "GRID_CELL_SIZE_THERMAL": f"{SYNTHETIC_PIXEL_M:.2f}",
            "GRID_CELL_SIZE_REFLECTIVE": f"{SYNTHETIC_PIXEL_M:.2f}",
            "REFLECTIVE_LINES": str(shape[0]),
            "REFLECTIVE_SAMPLES": str(shape[1]),
        },
        "LEVEL1_RADIOMETRIC_RESCALING": {
            f"RADIANCE_MULT_BAND_{THERMAL_BAND}": f"{b10['mult']:.4E}",
            f"RADIANCE_ADD_BAND_{THERMAL_BAND}": f"{b10['add']:.5f}",
            **{f"REFLECTANCE_MULT_BAND_{b}": f"{REFL_MULT:.4E}" for b in REFLECTIVE_BANDS},
            **{f"REFLECTANCE_ADD_BAND_{b}": f"{REFL_ADD:.6f}" for b in REFLECTIVE_BANDS},
        },
        "LEVEL1_THERMAL_CONSTANTS": {
            f"K1_CONSTANT_BAND_{THERMAL_BAND}": f"{b10['k1']:.4f}",
            f"K2_CONSTANT_BAND_{THERMAL_BAND}": f"{b10['k2']:.4f}",
        },
    }


def _mtl_text(groups) -> str:
    numeric = ("RADIANCE_", "REFLECTANCE_", "K1_", "K2_", "SUN_", "CLOUD_", "UTM_", "GRID_", "REFLECTIVE_")
    lines = ["GROUP = LANDSAT_METADATA_FILE"]
    for gname, items in groups.items():
        lines.append(f"  GROUP = {gname}")
        for k, v in items.items():
            text = v if (k.startswith(numeric) or k == "DATE_ACQUIRED") else f'"{v}"'
            lines.append(f"    {k} = {text}")
        lines.append(f"  END_GROUP = {gname}")
    lines += ["END_GROUP = LANDSAT_METADATA_FILE", "END", ""]
    return "\n".join(lines)


def synthetic_grid(size_px: int, lat: float, lon: float) -> SceneGrid:
    """The synthetic port's grid: ``size_px`` square pixels of 30 m centred on (lat, lon) in
    the WGS 84 UTM zone of ``lon`` (north or south by ``lat``)."""
    n = int(size_px)
    res = SYNTHETIC_PIXEL_M
    epsg = (32600 if lat >= 0 else 32700) + int((lon + 180) // 6) % 60 + 1
    crs = CRS.from_epsg(epsg)
    (xc,), (yc,) = warp_transform("EPSG:4326", crs, [lon], [lat])
    x0 = np.round((xc - n * res / 2) / res) * res
    y0 = np.round((yc + n * res / 2) / res) * res
    return SceneGrid(north_up_transform(x0, y0, res, res), crs, (n, n))


def _surface(rng, n: int, season: str):
    """Class map, elevation [m], reflectances of bands 2-7 [-] (6, n, n) and the sheltered
    basin mask of the layout, drawn from ``rng`` in a fixed order (the same port for the
    same seed)."""
    layout = _Layout()
    rows, cols = np.mgrid[0:n, 0:n]
    u, v = (cols + 0.5) / n, (rows + 0.5) / n
    land, basin, structures = layout.land(u, v)
    elevation = layout.elevation(u, v)
    classes = np.where(land, 3, 1).astype(np.uint8)
    veg_noise = _unit_noise(rng, (n, n), 6)
    hills = elevation > 35
    classes[land & hills & (veg_noise > -0.6)] = 2
    classes[land & ~hills & (veg_noise > 1.4) & (v < 0.5)] = 2          # parks
    blocks = ((rows % 9) < 6) & ((cols % 11) < 8)                         # 180 m x 240 m blocks, roads between
    port_zone = (u > 0.40) & (u < 0.80) & (v > 0.24) & (v < 0.39)
    town = (u > 0.05) & (u < 0.36) & (v > 0.40) & (v < 0.60)
    classes[land & ~structures & blocks & (port_zone | town) & (elevation < 60)] = 4
    classes[structures] = 3

    refl = np.empty((len(REFLECTIVE_BANDS), n, n))
    brightness = 1.0 + 0.08 * _unit_noise(rng, (n, n), 3)   # common to all bands: NDVI barely moves
    em = {k: np.asarray(val)[:, None] for k, val in _ENDMEMBERS[season].items()}
    for c, (ea, eb, lo, hi) in _MIXTURES.items():
        m = classes == c
        frac = lo + (hi - lo) * (0.5 + 0.5 * np.tanh(_unit_noise(rng, (n, n), 2)[m]))
        refl[:, m] = frac * em[ea] + (1.0 - frac) * em[eb]
    refl *= brightness
    refl *= 1.0 + 0.03 * rng.standard_normal(refl.shape)
    # Sensor point-spread (about half a pixel, Landsat OLI) mixes classes at their borders,
    # which is where a real classifier errs.
    refl = gaussian_filter(refl, sigma=(0, 0.6, 0.6), mode="nearest")
    return classes, elevation, refl, basin


def synthetic_surface(seed: int = 2026, size_px: int = 334, lat: float = 38.93,
                      lon: float = 121.65) -> dict:
    """The synthetic port's surface without any temperature: what the physical background
    (:mod:`.physical`) needs of it.

    The same port as :func:`write_synthetic_port` of the summer scene with the same seed
    (classes, hills, reflectances of leaf-on vegetation), at any site: its grid is centred
    on (lat, lon) in the local UTM zone. Nothing in it depends on a climate.

    Returns
    -------
    dict
        ``grid`` (SceneGrid), ``class_map`` (uint8), ``elevation`` [m], ``reflectance``
        (6, rows, cols) of OLI bands 2-7 [-].
    """
    if not (isinstance(size_px, (int, np.integer)) and size_px >= 60):
        raise InputError("background.size_px", size_px, "must be an integer >= 60 (pixels of 30 m)")
    rng = np.random.default_rng([seed, 0])
    classes, elevation, refl, _ = _surface(rng, int(size_px), "summer")
    return {"grid": synthetic_grid(size_px, lat, lon), "class_map": classes,
            "elevation": elevation.astype(np.float32), "reflectance": refl.astype(np.float32)}


def write_synthetic_port(directory: str | os.PathLike, season: str = "summer", seed: int = 2026,
                         size_px: int = 334, lat: float = 38.93, lon: float = 121.65) -> SyntheticPort:
    """Generate the synthetic port of one season and write it in the real formats.

    Parameters
    ----------
    directory : path-like
        Existing or new directory for the files.
    season : {"summer", "winter"}
    seed : int
        Seed of all textures and ROI placement.
    size_px : int
        Scene side in 30 m pixels (>= 60).
    lat, lon : float
        Scene centre [deg]; the UTM zone follows from ``lon``.

    Returns
    -------
    SyntheticPort
    """
    if season not in SEASONS:
        raise InputError("season", season, f"must be one of {sorted(SEASONS)}")
    if not (isinstance(size_px, (int, np.integer)) and size_px >= 60):
        raise InputError("size_px", size_px, "must be an integer >= 60 (pixels of 30 m)")
    spec = SEASONS[season]
    directory = os.fspath(directory)
    os.makedirs(directory, exist_ok=True)
    rng = np.random.default_rng([seed, 0 if season == "summer" else 1])
    n = int(size_px)
    grid = synthetic_grid(n, lat, lon)
    layout = _Layout()
    classes, elevation, refl, basin = _surface(rng, n, season)
    red, nir = refl[REFLECTIVE_BANDS.index(4)], refl[REFLECTIVE_BANDS.index(5)]
    ndvi_true = ndvi(red, nir)
    emissivity = emissivity_ndvi_threshold(ndvi_true, red)
    ov = _overpass_lst(rng, spec, classes, elevation, basin)
    mtl_txt, mtl_json = _write_landsat(directory, spec, grid, refl, ov["lst"], emissivity,
                                       ov["overpass"], lat, lon)
    dem_path = _write_dem(directory, grid, layout)
    met_path, hours = _write_met(directory, spec, grid, layout, rng, lat, lon, season, seed)
    roi_path = _write_rois(directory, grid, classes, rng)
    truth = {"class_map": classes, "lst": ov["lst"], "emissivity": emissivity, "elevation": elevation,
             "slope_deg": ov["slope"], "southness": ov["south"], "temp_met_overpass": ov["t_met_ov"],
             "beta": np.array(spec.beta), "water_vapour": spec.water_vapour, "basin": basin,
             "reflectance": refl, "sst": _temp_sst(spec, hours)}
    return SyntheticPort(directory, season, mtl_txt, mtl_json, dem_path, met_path, roi_path, grid, truth)


def _product_stamp(spec: SeasonSpec) -> tuple[str, str]:
    """The scene's date stamp and Landsat product id."""
    stamp = spec.date_local.replace("-", "")
    return stamp, f"LC08_L1TP_119033_{stamp}_{stamp}_02_T1"


def _overpass_lst(rng, spec: SeasonSpec, classes, elevation, basin) -> dict:
    """The true LST at the overpass (met field + eq. 15 terrain + class offsets + noise on
    land, the SST with the basin's pattern on water), with the overpass instant, slope and
    southness."""
    n = classes.shape[0]
    res = SYNTHETIC_PIXEL_M
    rows, cols = np.mgrid[0:n, 0:n]
    slope, aspect = slope_aspect(elevation, res)
    south = southness(aspect)
    x_km = (cols + 0.5 - n / 2) * res / 1000.0
    y_km = -(rows + 0.5 - n / 2) * res / 1000.0
    overpass = datetime.strptime(f"{spec.date_local} {spec.overpass_utc[:8]}", "%Y-%m-%d %H:%M:%S")
    overpass = overpass.replace(tzinfo=timezone.utc)
    hour_ov_local = (overpass.hour + overpass.minute / 60 + overpass.second / 3600 + UTC_OFFSET_HOURS) % 24
    t_met_ov = _temp_met(spec, x_km, y_km, hour_ov_local)
    b1, b2, b3 = spec.beta
    lst = t_met_ov + b1 * elevation + b2 * slope + b3 * south + 0.4 * _unit_noise(rng, (n, n), 1)
    for c, off in spec.class_offsets.items():
        lst[classes == c] += off
    water = classes == 1
    lst[water] = (_temp_sst(spec, hour_ov_local) + spec.basin_offset * basin
                  + 0.12 * _unit_noise(rng, (n, n), 4))[water]
    return {"lst": lst, "overpass": overpass, "slope": slope, "south": south, "t_met_ov": t_met_ov}


def _write_landsat(directory: str, spec: SeasonSpec, grid: SceneGrid, refl, lst, emissivity,
                   overpass: datetime, lat: float, lon: float) -> tuple[str, str]:
    """Landsat-8 Level-1 files: bands 2-7 and 10 (DN from the reflectances and the LST
    through the band-10 atmosphere) and the MTL as text and JSON."""
    n = lst.shape[0]
    sun = pvlib.solarposition.get_solarposition(pd.DatetimeIndex([overpass]), lat, lon)
    sun_el, sun_az = float(sun["elevation"].iloc[0]), float(sun["azimuth"].iloc[0])
    _, product = _product_stamp(spec)
    names = {"product": product, **{b: f"{product}_B{b}.TIF" for b in (*REFLECTIVE_BANDS, THERMAL_BAND)}}
    profile = dict(crs=grid.crs, transform=grid.transform, nodata=0, compress="deflate")
    for k, b in enumerate(REFLECTIVE_BANDS):
        dn = np.round((refl[k] * np.sin(np.radians(sun_el)) - REFL_ADD) / REFL_MULT)
        _atomic_geotiff(os.path.join(directory, names[b]), np.clip(dn, 1, 65535).astype(np.uint16), **profile)
    atmosphere = atmospheric_functions(spec.water_vapour)
    b10 = LANDSAT8_B10
    radiance = at_sensor_radiance(lst, emissivity, atmosphere, b10["k1"], b10["k2"])
    dn10 = np.round((radiance - b10["add"]) / b10["mult"])
    _atomic_geotiff(os.path.join(directory, names[THERMAL_BAND]), np.clip(dn10, 1, 65535).astype(np.uint16), **profile)
    groups = _mtl_groups(spec, sun_el, sun_az, names, (n, n), grid)
    mtl_txt = os.path.join(directory, f"{product}_MTL.txt")
    mtl_json = os.path.join(directory, f"{product}_MTL.json")
    _atomic_text(mtl_txt, _mtl_text(groups))
    _atomic_text(mtl_json, json.dumps({"LANDSAT_METADATA_FILE": groups}, indent=2))
    return mtl_txt, mtl_json


def _write_dem(directory: str, grid: SceneGrid, layout: _Layout) -> str:
    """The DEM: EPSG:4326, 1 arc-second, float32, 600 m beyond the scene on every side."""
    n = grid.shape[0]
    res = SYNTHETIC_PIXEL_M
    crs, x0, y0 = grid.crs, grid.transform.c, grid.transform.f
    xs = [x0 - 600, x0 + n * res + 600, x0 - 600, x0 + n * res + 600]
    ys = [y0 + 600, y0 + 600, y0 - n * res - 600, y0 - n * res - 600]
    lons, lats = warp_transform(crs, "EPSG:4326", xs, ys)
    arcsec = 1.0 / 3600.0
    lon_min, lon_max = np.floor(min(lons) / arcsec) * arcsec, np.ceil(max(lons) / arcsec) * arcsec
    lat_min, lat_max = np.floor(min(lats) / arcsec) * arcsec, np.ceil(max(lats) / arcsec) * arcsec
    dem_w = int(round((lon_max - lon_min) / arcsec))
    dem_h = int(round((lat_max - lat_min) / arcsec))
    dem_t = north_up_transform(lon_min, lat_max, arcsec, arcsec)
    dlon = lon_min + (np.arange(dem_w) + 0.5) * arcsec
    dlat = lat_max - (np.arange(dem_h) + 0.5) * arcsec
    glon, glat = np.meshgrid(dlon, dlat)
    gx, gy = warp_transform("EPSG:4326", crs, glon.ravel(), glat.ravel())
    du = (np.asarray(gx) - x0) / (n * res)
    dv = (y0 - np.asarray(gy)) / (n * res)
    dem = layout.elevation(du, dv).reshape(dem_h, dem_w).astype(np.float32)
    dem_path = os.path.join(directory, "dem_glo30_1arcsec.tif")
    _atomic_geotiff(dem_path, dem, crs=CRS.from_epsg(4326), transform=dem_t, nodata=-9999.0, compress="deflate")
    return dem_path


def _write_met(directory: str, spec: SeasonSpec, grid: SceneGrid, layout: _Layout, rng,
               lat: float, lon: float, season: str, seed: int) -> tuple[str, np.ndarray]:
    """The hourly CLDAS-like met NetCDF (land temperature on a 0.0625 deg grid, SST, water
    vapour) of the scene's local day; its path and the hours."""
    n = grid.shape[0]
    res = SYNTHETIC_PIXEL_M
    crs, x0, y0 = grid.crs, grid.transform.c, grid.transform.f
    step = 0.0625
    lat_c = np.arange(np.round(lat / step) - 5, np.round(lat / step) + 6) * step
    lon_c = np.arange(np.round(lon / step) - 5, np.round(lon / step) + 6) * step
    mlon, mlat = np.meshgrid(lon_c, lat_c)
    mx, my = warp_transform("EPSG:4326", crs, mlon.ravel(), mlat.ravel())
    mx, my = np.asarray(mx).reshape(mlon.shape), np.asarray(my).reshape(mlon.shape)
    mu, mv = (mx - x0) / (n * res), (y0 - my) / (n * res)
    met_land = mv < layout.coast(mu)
    mxk, myk = (mx - (x0 + n * res / 2)) / 1000, (my - (y0 - n * res / 2)) / 1000
    day0 = datetime.strptime(spec.date_local, "%Y-%m-%d")
    times = [day0 - timedelta(hours=UTC_OFFSET_HOURS) + timedelta(hours=h) for h in range(24)]
    temp = np.empty((24, *mlon.shape))
    for h in range(24):
        temp[h] = _temp_met(spec, mxk, myk, h) + 0.1 * rng.standard_normal(mlon.shape)
    temp[:, ~met_land] = np.nan
    hours = np.arange(24)
    ds = xr.Dataset(
        {"temperature": (("time", "lat", "lon"), temp.astype(np.float32),
                         {"units": "K", "long_name": "land surface temperature (CLDAS-like)"}),
         "sst": (("time",), _temp_sst(spec, hours).astype(np.float32), {"units": "K", "long_name": "sea surface temperature"}),
         "tcwv": (("time",), np.full(24, spec.water_vapour, np.float32),
                  {"units": "g cm-2", "long_name": "total column water vapour"})},
        coords={"time": pd.DatetimeIndex(times), "lat": ("lat", lat_c, {"units": "degrees_north"}),
                "lon": ("lon", lon_c, {"units": "degrees_east"})},
        attrs={"title": f"Synthetic CLDAS-like hourly grid, {season}", "Conventions": "CF-1.8",
               "source": "shipthermal synthetic port", "seed": int(seed)})
    stamp, _ = _product_stamp(spec)
    met_path = os.path.join(directory, f"cldas_like_{stamp}.nc")
    with atomic_path(met_path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", format="NETCDF4")
    return met_path, hours


def _write_rois(directory: str, grid: SceneGrid, classes, rng) -> str:
    """Training ROIs: 13 x 13 boxes inside each class's interior (4 water, 6 vegetation,
    6 land, 24 building), as a label GeoTIFF on the scene grid."""
    n = classes.shape[0]
    roi = np.zeros((n, n), dtype=np.uint8)
    for c, boxes in ((1, 4), (2, 6), (3, 6), (4, 24)):
        inner = binary_erosion(classes == c, iterations=1)
        cand = np.flatnonzero(inner)
        if cand.size == 0:
            continue
        for centre in rng.choice(cand, size=min(boxes, cand.size), replace=False):
            r, q = divmod(int(centre), n)
            sl = (slice(max(r - 6, 0), r + 7), slice(max(q - 6, 0), q + 7))
            roi[sl][(classes[sl] == c) & inner[sl]] = c
    roi_path = os.path.join(directory, "roi_labels.tif")
    _atomic_geotiff(roi_path, roi, crs=grid.crs, transform=grid.transform, nodata=None, compress="deflate")
    return roi_path
