"""Hourly meteorological grids: CF NetCDF or GRIB, any common layout, temperature in any unit.

What is read
------------
* **Files**: NetCDF (netCDF4/HDF5 or classic, through xarray) and GRIB 1/2 (through cfgrib and
  the ecCodes wheels; detected from the file's first bytes, not its name).
* **Dimensions**: a time axis named ``time``, ``valid_time``, ``Time``, ``t`` or ``datetime``
  (GRIB forecasts with ``time`` x ``step`` are flattened to their valid times); horizontal
  axes either geographic (``lat``/``lon``, ``latitude``/``longitude``, 1-D or 2-D, longitudes
  in -180..180 or 0..360) or projected (``x``/``y`` with a CF ``grid_mapping`` variable
  naming the CRS). Singleton axes (``height``, ``number``, ``surface``) are dropped.
* **Temperature variable**: ``var`` if given, else the first of :data:`TEMPERATURE_NAMES`,
  else the variable whose ``standard_name`` is ``air_temperature`` or ``surface_temperature``.
* **Units** from the ``units`` attribute (K, degC, degF in their usual spellings, GDAL's
  ``[C]``); ``units=`` overrides the label. The **kelvin-labelled-°C trap** (values near 280
  labelled °C, e.g. ERA5 GRIB converted with GDAL) and its mirror (values near 10 labelled K)
  are caught: the values are checked against the unit they claim.
* **SST and water vapour** from the file when present (:data:`SST_NAMES`, :data:`TCWV_NAMES`),
  as a time series or as gridded fields (averaged over the valid cells of the clipped box;
  ERA5 ``sst`` is NaN over land). Fallbacks when absent: see :func:`met_for_scene`.

CLDAS-V2.0 (the paper's product) is land-only on a 0.0625 deg grid; ERA5 is global at 0.25 deg.
Both are much larger than a port scene: :func:`met_for_scene` clips the grid to the scene plus
a margin of cells before kriging, and picks the 24 hours around the Landsat overpass.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr

from shipthermal.errors import InputError, require

from ..parameters import MET_UNITS

__all__ = ["MetGrid", "read_met_grid", "met_for_scene", "STANDARD_WATER_VAPOUR", "MET_UNITS"]

_TEMP_RANGE = (180.0, 350.0)
"""Plausible near-surface temperatures [K] (world records -89 / +57 degC, with margin)."""

TEMPERATURE_NAMES = ("temperature", "t2m", "2t", "tas", "air_temperature", "TAIR", "T2", "TMP_2maboveground",
                     "skt", "lst", "LST")
SST_NAMES = ("sst", "SST", "tos", "analysed_sst", "sea_surface_temperature")
TCWV_NAMES = ("tcwv", "TCWV", "prw", "pwat", "PWAT", "total_column_water_vapour")
TIME_NAMES = ("time", "valid_time", "Time", "t", "datetime")
LAT_NAMES = ("lat", "latitude", "nav_lat", "XLAT", "y_lat")
LON_NAMES = ("lon", "longitude", "nav_lon", "XLONG", "x_lon")

_KELVIN = ("K", "k", "kelvin", "Kelvin", "degK", "degrees_K", "[K]")
_CELSIUS = ("degC", "C", "°C", "deg C", "degree_Celsius", "degrees_Celsius", "celsius", "Celsius", "[C]",
            "degrees C", "deg_C", "Cel")
_FAHRENHEIT = ("degF", "F", "°F", "deg F", "degree_Fahrenheit", "degrees_Fahrenheit", "fahrenheit",
               "Fahrenheit", "[F]")

STANDARD_WATER_VAPOUR = {"summer": 2.92, "winter": 0.85, None: 1.42}
"""Fallback total column water vapour [g cm-2] when the met file carries none: the AFGL model
atmospheres (Anderson et al. 1986, AFGL-TR-86-0110): mid-latitude summer 2.92, mid-latitude
winter 0.85, US Standard 1976 1.42 (season unknown)."""

_TCWV_TO_G_CM2 = {"g cm-2": 1.0, "g cm**-2": 1.0, "g/cm2": 1.0, "g/cm^2": 1.0, "cm": 1.0,
                  "kg m-2": 0.1, "kg m**-2": 0.1, "kg/m2": 0.1, "kg/m^2": 0.1, "mm": 0.1}
"""Column water vapour unit -> g cm-2 (1 kg m-2 = 1 mm of liquid water = 0.1 g cm-2)."""


@dataclass(frozen=True)
class MetGrid:
    """Hourly gridded meteorology.

    Attributes
    ----------
    times_utc : ndarray of datetime64[s]
        Hourly time stamps (UTC), strictly consecutive.
    x, y : ndarray (ny, nx)
        Cell centres in ``crs``: longitude / latitude [deg] for a geographic grid, else [m].
    crs : str
        CRS of ``x``, ``y`` (``"EPSG:4326"`` for geographic grids; WKT otherwise).
    temperature : ndarray (time, ny, nx)
        Temperature [K]; NaN where no data (e.g. sea cells of a land product).
    sst : ndarray (time,) or None
        Sea-surface temperature [K].
    tcwv : ndarray (time,) or None
        Total column water vapour [g cm-2].
    variable : str
        Name of the temperature variable read.
    units_read : str
        Unit the temperature was converted from (``K``, ``degC``, ``degF``).
    notes : tuple[str, ...]
        What was inferred, clipped or filled on the way (reported in the background summary).
    sst_field, tcwv_field : ndarray (time, ny, nx) or None
        Gridded SST [K] / water vapour [g cm-2] before averaging (kept for clipping).
    """

    times_utc: np.ndarray
    x: np.ndarray
    y: np.ndarray
    crs: str
    temperature: np.ndarray
    sst: np.ndarray | None
    tcwv: np.ndarray | None
    variable: str = "temperature"
    units_read: str = "K"
    notes: tuple = ()
    sst_field: np.ndarray | None = None
    tcwv_field: np.ndarray | None = None

    @property
    def geographic(self) -> bool:
        return self.crs == "EPSG:4326"

    @property
    def lat(self) -> np.ndarray:
        """Latitudes of the cells [deg] (2-D; geographic grids only)."""
        require(self.geographic, "met.crs", self.crs, "lat/lon only exist for geographic grids")
        return self.y

    @property
    def lon(self) -> np.ndarray:
        """Longitudes of the cells [deg] (2-D; geographic grids only)."""
        require(self.geographic, "met.crs", self.crs, "lat/lon only exist for geographic grids")
        return self.x

    @property
    def n_cells(self) -> int:
        return int(self.x.size)

    def points_in(self, crs):
        """Cell centres transformed to ``crs`` (PROJ through rasterio), flattened (x, y) [m]."""
        from rasterio.warp import transform as warp_transform

        xs, ys = warp_transform(self.crs, crs, self.x.ravel().tolist(), self.y.ravel().tolist())
        return np.asarray(xs), np.asarray(ys)

    def interp_time(self, series: np.ndarray, when: np.datetime64) -> float:
        """Linear interpolation of an hourly series at ``when`` (UTC)."""
        t = (self.times_utc - self.times_utc[0]).astype("timedelta64[s]").astype(float)
        x = float((np.datetime64(when, "s") - self.times_utc[0]).astype("timedelta64[s]").astype(float))
        require(t[0] <= x <= t[-1], "met_grid.time", str(when),
                f"must lie within the met grid's span {self.times_utc[0]} .. {self.times_utc[-1]} UTC",
                "Provide met data covering the Landsat overpass")
        return float(np.interp(x, t, series))


# ---------------------------------------------------------------------------------------------
# opening
# ---------------------------------------------------------------------------------------------
def _is_grib(path: str) -> bool:
    with open(path, "rb") as f:
        head = f.read(4)
    return head == b"GRIB"


def _open(path: str, field: str) -> xr.Dataset:
    if _is_grib(path):
        try:
            import cfgrib  # noqa: F401
        except ImportError:  # pragma: no cover - cfgrib is a dependency; kept for slim installs
            raise InputError(field, path, "is a GRIB file, which needs cfgrib and the ecCodes wheels",
                             "pip install cfgrib eccodes (or convert it to NetCDF)") from None
        _check_grib_complete(path, field)
        try:
            # indexpath='': no .idx file written next to the user's data
            return xr.open_dataset(path, engine="cfgrib", backend_kwargs={"indexpath": ""},
                                   decode_timedelta=True)
        except Exception as exc:  # noqa: BLE001 - cfgrib raises many types for unreadable files
            raise InputError(field, path, "must be a readable GRIB file",
                             f"cfgrib: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") from None
    try:
        return xr.open_dataset(path)
    except Exception as exc:  # noqa: BLE001 - any backend error means "not a readable NetCDF"
        raise InputError(field, path, "must be a readable NetCDF file (or GRIB)",
                         str(exc).splitlines()[0] if str(exc) else type(exc).__name__) from None


def _check_grib_complete(path: str, field: str) -> None:
    """Walk the GRIB messages: a truncated download ends inside a message, which ecCodes would
    otherwise skip silently (the last hours would just be missing)."""
    import eccodes

    size = os.path.getsize(path)
    pos = n = 0
    with open(path, "rb") as f:
        while True:
            try:
                h = eccodes.codes_grib_new_from_file(f)
            except Exception as exc:  # noqa: BLE001 - ecCodes raises its own hierarchy
                raise InputError(field, path, f"is a truncated or damaged GRIB file (message {n + 1} unreadable)",
                                 f"Download it again (ecCodes: {exc})") from None
            if h is None:
                break
            try:
                pos = f.tell()
                n += 1
            finally:
                eccodes.codes_release(h)
    if n == 0 or size - pos > 64:
        raise InputError(field, path, f"is a truncated GRIB file ({n} complete messages, "
                         f"{size - pos} bytes left over of {size})", "Download it again")


def _pick_variable(ds: xr.Dataset, var: str | None, field: str) -> str:
    names = sorted(str(v) for v in ds.data_vars)
    # a GDAL-converted GRIB holds one variable per band (Band1 .. Band744): keep the line short
    present = names if len(names) <= 8 else names[:8] + [f"... {len(names) - 8} more"]
    if var is not None:
        require(var in ds.data_vars, f"met[{var}]", "missing", f"the file must hold the variable '{var}'",
                f"Variables present: {present}")
        return var
    for name in TEMPERATURE_NAMES:
        if name in ds.data_vars:
            return name
    for name in ds.data_vars:
        if ds[name].attrs.get("standard_name") in ("air_temperature", "surface_temperature"):
            return str(name)
    gdal = sum(n.startswith("Band") for n in names) > len(names) // 2
    raise InputError("met[temperature]", "missing",
                     f"the file must hold a temperature variable (one of {list(TEMPERATURE_NAMES[:5])}, "
                     "or standard_name air_temperature)",
                     f"Variables present: {present}; "
                     + ("this looks like a GDAL conversion (one variable per band, no time axis): give "
                        "the original GRIB file instead" if gdal else "name one with background.met_variable"))


def _find(ds, names, standard=None):
    for n in names:
        if n in ds.variables or n in ds.coords:
            return n
    if standard:
        for n in ds.variables:
            if ds[n].attrs.get("standard_name") == standard:
                return str(n)
    return None


def _time_values(da: xr.DataArray, field: str):
    """Bring ``da`` to (time, ...) and return it with its valid times (datetime64[s])."""
    tdims = [d for d in da.dims if d in TIME_NAMES
             or (d in da.coords and np.issubdtype(da[d].dtype, np.datetime64))]
    if "step" in da.dims and da.sizes["step"] > 1 and "valid_time" in da.coords:
        # GRIB forecasts: time x step -> one axis of valid times
        tname = next(d for d in da.dims if d in ("time", "valid_time"))
        da = da.stack(_vt=(tname, "step"))
        vt = da["valid_time"].values.ravel()
        da = da.assign_coords(_vt=vt).rename(_vt="time_valid")
        keep = ~np.isnat(vt)
        da = da.isel(time_valid=np.flatnonzero(keep))
        return da.transpose("time_valid", ...), da["time_valid"].values.astype("datetime64[s]"), "time_valid"
    if not tdims:
        has_scalar_time = any(n in da.coords for n in TIME_NAMES)
        raise InputError(f"{field}.time", "no time axis" + (" (one time step)" if has_scalar_time else ""),
                         "the met grid must hold hourly steps along a time axis "
                         f"(named one of {list(TIME_NAMES)})",
                         "Download the hours of the whole day (24 hourly fields) into one file")
    tname = tdims[0]
    da = da.transpose(tname, ...)
    if "valid_time" in da.coords and da["valid_time"].dims == (tname,):
        t = da["valid_time"].values
    else:
        t = da[tname].values
    require(np.issubdtype(np.asarray(t).dtype, np.datetime64), f"{field}.{tname}", str(np.asarray(t)[:3]),
            "must be decodable dates (CF 'units: hours since ...')")
    return da, np.asarray(t).astype("datetime64[s]"), tname


def _horizontal(ds: xr.Dataset, da: xr.DataArray, tname: str, field: str):
    """(x, y, crs, data (time, ny, nx)) of a variable's horizontal grid."""
    extra = [d for d in da.dims if d != tname]
    squeeze = [d for d in extra if da.sizes[d] == 1]
    if squeeze:
        da = da.isel({d: 0 for d in squeeze})
        extra = [d for d in extra if d not in squeeze]
    require(len(extra) == 2, f"{field}.dims", tuple(da.dims),
            "must be (time, y, x): one time axis and two horizontal axes (other axes of length 1)",
            "Select one level / ensemble member before reading")
    lat_n = _find(ds, LAT_NAMES, "latitude")
    lon_n = _find(ds, LON_NAMES, "longitude")
    if lat_n and lon_n:
        lat, lon = ds[lat_n], ds[lon_n]
        if lat.ndim == 1 and lon.ndim == 1:
            require({lat.dims[0], lon.dims[0]} == set(extra), f"{field}.dims", tuple(da.dims),
                    f"the horizontal axes must be the coordinates {lat_n}, {lon_n}")
            da = da.transpose(tname, lat.dims[0], lon.dims[0])
            lon2, lat2 = np.meshgrid(lon.values.astype(float), lat.values.astype(float))
        else:
            require(tuple(lat.dims) == tuple(lon.dims) and set(lat.dims) == set(extra), f"{field}.dims",
                    tuple(da.dims), f"2-D {lat_n}/{lon_n} must span the variable's horizontal axes")
            da = da.transpose(tname, *lat.dims)
            lat2, lon2 = lat.values.astype(float), lon.values.astype(float)
        lon2 = (lon2 + 180.0) % 360.0 - 180.0          # 0..360 grids (ERA5 NetCDF) -> -180..180
        return lon2, lat2, "EPSG:4326", da.values
    # projected x/y with a CF grid mapping
    xn = next((d for d in extra if d in ("x", "X", "easting", "projection_x_coordinate")
               or ds[d].attrs.get("standard_name") == "projection_x_coordinate"), None) if all(
        d in ds.coords for d in extra) else None
    yn = next((d for d in extra if d in ("y", "Y", "northing", "projection_y_coordinate")
               or ds[d].attrs.get("standard_name") == "projection_y_coordinate"), None) if xn else None
    require(xn is not None and yn is not None, f"{field}.dims", tuple(da.dims),
            "needs lat/lon coordinates (lat, latitude, ...) or projected x/y coordinates",
            "Name the horizontal coordinates per CF (standard_name latitude/longitude or "
            "projection_x/y_coordinate)")
    gm = da.attrs.get("grid_mapping") or ("spatial_ref" if "spatial_ref" in ds.variables else
                                           "crs" if "crs" in ds.variables else None)
    require(gm is not None and gm in ds.variables, f"{field}.grid_mapping", gm,
            "a projected x/y grid must name its CRS in a CF grid_mapping variable",
            "Add grid_mapping (with crs_wkt or the CF projection parameters), or use lat/lon")
    from rasterio.crs import CRS

    attrs = dict(ds[gm].attrs)
    try:
        if "crs_wkt" in attrs or "spatial_ref" in attrs:
            crs = CRS.from_wkt(attrs.get("crs_wkt") or attrs["spatial_ref"])
        else:
            # the CF projection parameters alone (no WKT): pyproj reads them
            from pyproj import CRS as ProjCRS

            crs = CRS.from_wkt(ProjCRS.from_cf(attrs).to_wkt())
    except ImportError:
        raise InputError(f"{field}.grid_mapping", gm, "without crs_wkt, reading the CF projection "
                         "parameters needs pyproj", "pip install pyproj, or add a crs_wkt attribute") from None
    except Exception as exc:  # noqa: BLE001 - CRSError, KeyError alike
        raise InputError(f"{field}.grid_mapping", gm, "must describe a CRS (crs_wkt or CF parameters)",
                         str(exc)) from None
    scale = {"km": 1000.0, "kilometre": 1000.0, "kilometer": 1000.0}.get(str(ds[xn].attrs.get("units", "m")), 1.0)
    da = da.transpose(tname, yn, xn)
    x2, y2 = np.meshgrid(ds[xn].values.astype(float) * scale, ds[yn].values.astype(float) * scale)
    return x2, y2, crs.to_wkt(), da.values


def _unit_kind(label: str):
    label = label.strip()
    for kind, names in (("K", _KELVIN), ("degC", _CELSIUS), ("degF", _FAHRENHEIT)):
        if label in names:
            return kind
    return None


def _to_kelvin(values: np.ndarray, label: str | None, override: str, field: str):
    """Convert to K; returns (values_K, unit used, note or None)."""
    finite = values[np.isfinite(values)]
    med = float(np.median(finite)) if finite.size else float("nan")
    if override != "auto":
        kind, note = override, f"{field}: units set to {override} (file says {label!r})"
    elif label is None or label == "":
        if _TEMP_RANGE[0] <= med <= _TEMP_RANGE[1]:
            kind, note = "K", f"{field}: no units attribute; values (median {med:.1f}) taken as K"
        else:
            raise InputError(f"{field}.units", None, "the temperature needs a units attribute (K, degC or degF)",
                             "Set background.met_units")
    else:
        kind, note = _unit_kind(label), None
        if kind is None:
            raise InputError(f"{field}.units", label, "must be a temperature unit (K, degC or degF)",
                             "Set background.met_units to the true unit")
        if kind in ("degC", "degF") and med > 150.0:
            raise InputError(f"{field}.units", label,
                             f"the values (median {med:.1f}) are kelvin, not {kind}: the label is wrong "
                             "(GDAL tags ERA5 GRIB temperatures '[C]')",
                             "Set background.met_units = 'K' to read them as kelvin")
        if kind == "K" and med < 150.0:
            raise InputError(f"{field}.units", label,
                             f"the values (median {med:.1f}) cannot be kelvin: they look like degC/degF",
                             "Set background.met_units = 'degC' (or 'degF')")
    out = values.astype(np.float64)
    if kind == "degC":
        out = out + 273.15
    elif kind == "degF":
        out = (out - 32.0) * 5.0 / 9.0 + 273.15
    return out, kind, note


def read_met_grid(path: str | os.PathLike, var: str | None = None, n_hours: int | None = 24,
                  units: str = "auto", field: str = "met_path") -> MetGrid:
    """Read and validate an hourly met grid (NetCDF or GRIB; module docstring).

    Parameters
    ----------
    path : path-like
        NetCDF or GRIB file.
    var : str, optional
        Temperature variable; default: detected (:data:`TEMPERATURE_NAMES`).
    n_hours : int or None
        Number of consecutive hourly steps required; ``None`` keeps every step (select a day
        later with :func:`met_for_scene`).
    units : {"auto", "K", "degC", "degF"}
        Temperature unit; ``auto`` reads the ``units`` attribute and checks it.
    field : str
        Name of the input in error messages.

    Raises
    ------
    InputError
        Unreadable or truncated file, no time axis, unknown layout, missing variable, wrong or
        mislabelled units, irregular/missing hours (listed), an hour without any valid value,
        values outside 180–350 K.
    """
    path = os.fspath(path)
    require(units in MET_UNITS, "met_units", units, f"must be one of {MET_UNITS}")
    require(os.path.isfile(path), field, path, "must be an existing NetCDF or GRIB file")
    ds = _open(path, field)
    with ds:
        name = _pick_variable(ds, var, field)
        da, times, tname = _time_values(ds[name], f"met[{name}]")
        x, y, crs, raw = _horizontal(ds, da, tname, f"met[{name}]")
        label = da.attrs.get("units")
        temperature, kind, note = _to_kelvin(np.asarray(raw, dtype=np.float64), label, units, f"met[{name}]")
        notes = [note] if note else []
        extra = {}
        for key, names in (("sst", SST_NAMES), ("tcwv", TCWV_NAMES)):
            vn = _find(ds, names)
            if vn is None or vn == name:
                extra[key] = None
                continue
            v, vt, vtn = _time_values(ds[vn], f"met[{vn}]")
            if v.ndim == 1:
                arr = np.asarray(v.values, dtype=np.float64)
            else:
                *_, arr = _horizontal(ds, v, vtn, f"met[{vn}]")
                arr = np.asarray(arr, dtype=np.float64)
                require(arr.shape[1:] == temperature.shape[1:], f"met[{vn}].shape", arr.shape,
                        f"must be on the temperature grid {temperature.shape[1:]}")
            require(vt.shape == times.shape and np.all(vt == times), f"met[{vn}].time", vt.size,
                    f"must share the time axis of {name}")
            ulabel = str(v.attrs.get("units", "K" if key == "sst" else "g cm-2"))
            if key == "sst":
                arr, _, n2 = _to_kelvin(arr, ulabel, "auto", f"met[{vn}]")
                if n2:
                    notes.append(n2)
            else:
                factor = _TCWV_TO_G_CM2.get(ulabel.strip())
                require(factor is not None, f"met[{vn}].units", ulabel,
                        f"must be one of {sorted(_TCWV_TO_G_CM2)}")
                arr = arr * factor
            extra[key] = arr
    order = np.argsort(times, kind="stable")
    if np.any(order != np.arange(times.size)):
        times, temperature = times[order], temperature[order]
        extra = {k: (None if v is None else v[order]) for k, v in extra.items()}
    grid = MetGrid(times, x, y, crs, temperature, None, None, name, kind, tuple(notes))
    for key in ("sst", "tcwv"):
        v = extra[key]
        if v is not None and v.ndim == 1:
            grid = replace(grid, **{key: v})
        elif v is not None:
            grid = replace(grid, **{f"{key}_field": v})
    if n_hours is not None:
        grid = _select_hours(grid, grid.times_utc[0] if times.size else None, n_hours)
    return grid


# ---------------------------------------------------------------------------------------------
# selecting the day and the scene
# ---------------------------------------------------------------------------------------------
def _select_hours(met: MetGrid, start, n_hours: int) -> MetGrid:
    times = met.times_utc
    step = np.timedelta64(3600, "s")
    if times.size == 0:
        raise InputError("met.time", "empty", f"must hold {n_hours} hourly steps")
    expected = np.datetime64(start, "s") + step * np.arange(n_hours)
    missing = np.setdiff1d(expected, times)
    sel = np.flatnonzero((times >= expected[0]) & (times <= expected[-1]))
    if missing.size or sel.size != n_hours or np.any(np.diff(times[sel]) != step):
        shown = ", ".join(str(t) for t in missing[:6]) + (" ..." if missing.size > 6 else "")
        raise InputError("met.time", f"{times.size} steps from {times[0]} to {times[-1]}",
                         f"must be {n_hours} consecutive hourly steps from {expected[0]} UTC",
                         f"Missing hours: {shown}" if missing.size else "Remove duplicated or irregular steps")

    def cut(a):
        return None if a is None else a[sel]

    met = replace(met, times_utc=times[sel], temperature=met.temperature[sel], sst=cut(met.sst),
                  tcwv=cut(met.tcwv), sst_field=cut(met.sst_field), tcwv_field=cut(met.tcwv_field))
    for k in range(n_hours):
        if not np.isfinite(met.temperature[k]).any():
            raise InputError(f"met[{met.variable}][time={met.times_utc[k]}]", "all NaN",
                             "every hour needs valid grid values", "Fill or replace the missing hour")
    finite = met.temperature[np.isfinite(met.temperature)]
    if finite.min() < _TEMP_RANGE[0] or finite.max() > _TEMP_RANGE[1]:
        bad = finite.min() if finite.min() < _TEMP_RANGE[0] else finite.max()
        raise InputError(f"met[{met.variable}]", float(bad), f"must lie in {_TEMP_RANGE} K",
                         "Check units (background.met_units) and fill values")
    for name, series in (("sst", met.sst), ("tcwv", met.tcwv)):
        if series is not None and not np.all(np.isfinite(series)):
            k = int(np.flatnonzero(~np.isfinite(series))[0])
            raise InputError(f"met[{name}][time={met.times_utc[k]}]", float(series[k]), "must be finite")
    return met


def day_start_for(overpass_utc, n_hours: int = 24, utc_offset_hours: float = 0.0) -> np.datetime64:
    """First hour (UTC) of the met window for an overpass: local midnight of the overpass's
    local day, shifted later when the overpass falls after the window's last hour."""
    off = np.timedelta64(int(round(utc_offset_hours * 3600)), "s")
    ov = np.datetime64(overpass_utc, "s")
    start = (ov + off).astype("datetime64[D]").astype("datetime64[s]") - off
    last = start + np.timedelta64(3600 * (n_hours - 1), "s")
    if ov > last:
        start = ov.astype("datetime64[h]").astype("datetime64[s]") - np.timedelta64(3600 * (n_hours - 2), "s")
    return start


def _window_present(times, start, n_hours) -> bool:
    expected = np.datetime64(start, "s") + np.timedelta64(3600, "s") * np.arange(n_hours)
    return bool(np.isin(expected, times).all())


def _scene_box(grid, crs: str):
    from rasterio.warp import transform_bounds

    t = grid.transform
    xs = (t.c, t.c + grid.shape[1] * t.a)
    ys = (t.f, t.f + grid.shape[0] * t.e)
    return transform_bounds(grid.crs, crs, min(xs), min(ys), max(xs), max(ys), densify_pts=21)


def _spacing(a: np.ndarray, axis: int) -> float:
    d = np.abs(np.diff(a, axis=axis))
    d = d[np.isfinite(d) & (d > 0)]
    return float(np.median(d)) if d.size else 0.0


def clip_to_scene(met: MetGrid, grid, margin_cells: int = 4) -> MetGrid:
    """Keep the met cells within the scene's bounding box plus ``margin_cells`` cells.

    Raises :class:`InputError` when the grid misses the scene or covers only part of it
    (kriging far outside the data only returns the mean).
    """
    require(int(margin_cells) >= 0, "met_margin_cells", margin_cells, "must be an integer >= 0")
    west, south, east, north = _scene_box(grid, met.crs)
    dx = max(_spacing(met.x, 1), _spacing(met.x, 0))
    dy = max(_spacing(met.y, 0), _spacing(met.y, 1))
    gx0, gx1 = np.nanmin(met.x) - dx / 2, np.nanmax(met.x) + dx / 2
    gy0, gy1 = np.nanmin(met.y) - dy / 2, np.nanmax(met.y) + dy / 2
    unit = "deg" if met.geographic else "m"
    have = f"x {gx0:.4f}..{gx1:.4f}, y {gy0:.4f}..{gy1:.4f} {unit}"
    need = f"x {west:.4f}..{east:.4f}, y {south:.4f}..{north:.4f} {unit}"
    if west > gx1 or east < gx0 or south > gy1 or north < gy0:
        raise InputError("met.extent", have, f"misses the scene entirely (scene: {need})",
                         "Use a met grid around the port (check the file and the scene location)")
    require(gx0 <= west and east <= gx1 and gy0 <= south and north <= gy1, "met.extent", have,
            f"must cover the whole scene ({need})", "Use a met grid that extends beyond the scene")
    m = int(margin_cells)
    keep = ((met.x >= west - (m + 0.5) * dx) & (met.x <= east + (m + 0.5) * dx)
            & (met.y >= south - (m + 0.5) * dy) & (met.y <= north + (m + 0.5) * dy))
    rows = np.flatnonzero(keep.any(axis=1))
    cols = np.flatnonzero(keep.any(axis=0))
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1

    def cut(a):
        return None if a is None else a[..., r0:r1, c0:c1]

    n0 = met.n_cells
    out = replace(met, x=met.x[r0:r1, c0:c1], y=met.y[r0:r1, c0:c1], temperature=cut(met.temperature),
                  sst_field=cut(met.sst_field), tcwv_field=cut(met.tcwv_field))
    note = f"met grid clipped to the scene + {m} cells: {out.n_cells} of {n0} cells"
    return replace(out, notes=met.notes + (note,))


def _field_series(field: np.ndarray, name: str):
    """Mean over the valid cells of each hour; None when no cell is valid at some hour."""
    valid = np.isfinite(field)
    if not valid.any(axis=(1, 2)).all():
        return None, 0
    with np.errstate(invalid="ignore"):
        return np.nanmean(field, axis=(1, 2)), int(valid.sum(axis=(1, 2)).min())


def met_for_scene(met: MetGrid, grid, overpass_utc, *, margin_cells: int = 4, n_hours: int = 24,
                  season: str | None = None, utc_offset_hours: float = 0.0) -> MetGrid:
    """The hours and cells of a met grid that a scene needs, with SST and water vapour series.

    Parameters
    ----------
    met : MetGrid
        From :func:`read_met_grid` (any number of hours).
    grid : SceneGrid
        The scene.
    overpass_utc : datetime-like
        Landsat overpass; the window is its local day (:func:`day_start_for`), or the file's
        own 24 hours when they hold the overpass but not that local day.
    margin_cells : int
        Cells kept beyond the scene on each side.
    season : {"summer", "winter"} or None
        Picks the water-vapour fallback.
    utc_offset_hours : float
        Local standard time minus UTC [h] (defines the local day).

    Returns
    -------
    MetGrid
        ``n_hours`` hours, clipped cells, ``sst`` and ``tcwv`` series always set; ``notes``
        states where each came from.

    Notes
    -----
    SST: the file's series, else the mean of its gridded SST over the valid (sea) cells of the
    clipped box, else (fallback) the daily mean of the clipped 2 m temperature held constant:
    the water pixels then keep their Landsat temperature all day (only SST(t) - SST(overpass)
    enters the background; the diurnal SST amplitude of open water is a few tenths of a kelvin).
    Water vapour: the file's series or clipped-field mean, else :data:`STANDARD_WATER_VAPOUR`
    for the season (used only by the single-channel LST retrieval).
    """
    start = day_start_for(overpass_utc, n_hours, utc_offset_hours)
    ov = np.datetime64(overpass_utc, "s")
    t = met.times_utc
    require(t.size > 0 and t[0] <= ov <= t[-1], "met.time", f"{t[0]} .. {t[-1]} UTC" if t.size else "empty",
            f"must contain the Landsat overpass {ov} UTC", "Use met data of the overpass day")
    if (not _window_present(t, start, n_hours) and t.size >= n_hours
            and t[0] <= ov <= t[n_hours - 1] and _window_present(t, t[0], n_hours)):
        start = t[0]
    met = _select_hours(met, start, n_hours)
    met = clip_to_scene(met, grid, margin_cells)
    notes = list(met.notes)
    sst, tcwv = met.sst, met.tcwv
    if sst is not None:
        notes.append(f"SST from the file's series '{'sst'}'")
    elif met.sst_field is not None and (fs := _field_series(met.sst_field, "sst"))[0] is not None:
        sst = fs[0]
        notes.append(f"SST from the gridded field: mean of >= {fs[1]} sea cells of the clipped box")
    else:
        with np.errstate(invalid="ignore"):
            level = float(np.nanmean(met.temperature))
        sst = np.full(met.times_utc.size, level)
        notes.append(f"no SST in the met file: constant {level:.2f} K (daily mean 2 m temperature); "
                     "water pixels keep their Landsat temperature all day")
    if tcwv is not None:
        notes.append("water vapour from the file's series")
    elif met.tcwv_field is not None and (fw := _field_series(met.tcwv_field, "tcwv"))[0] is not None:
        tcwv = fw[0]
        notes.append(f"water vapour from the gridded field: mean of >= {fw[1]} cells of the clipped box")
    else:
        wv = STANDARD_WATER_VAPOUR.get(season, STANDARD_WATER_VAPOUR[None])
        tcwv = np.full(met.times_utc.size, wv)
        notes.append(f"no water vapour in the met file: {wv} g cm-2 (AFGL "
                     f"{'mid-latitude ' + season if season in ('summer', 'winter') else 'US Standard'} atmosphere)")
    return replace(met, sst=np.asarray(sst, float), tcwv=np.asarray(tcwv, float), notes=tuple(notes))
