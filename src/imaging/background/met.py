"""Hourly meteorological grids in NetCDF (CLDAS-like: time x lat x lon, temperature in K).

Expected layout (CF conventions; what :mod:`.synthetic` writes)::

    dimensions:  time (hourly, UTC), lat, lon
    temperature(time, lat, lon)  [K]   land-surface temperature; NaN/_FillValue where not land
    sst(time)                    [K]   optional: sea-surface temperature of the port waters
    tcwv(time)                   [g cm-2] optional: total column water vapour

CLDAS-V2.0 itself is a land-only product on a 0.0625 deg grid; SST and water vapour come from
other products (e.g. OISST, ERA5) and are carried here as extra variables for convenience.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import xarray as xr

from shipthermal.errors import InputError, require

__all__ = ["MetGrid", "read_met_grid"]

_TEMP_RANGE = (180.0, 350.0)


@dataclass(frozen=True)
class MetGrid:
    """One day of hourly gridded meteorology.

    Attributes
    ----------
    times_utc : ndarray of datetime64[s]
        Hourly time stamps (UTC), strictly consecutive.
    lat, lon : ndarray
        Grid coordinates [deg].
    temperature : ndarray (time, lat, lon)
        Temperature [K]; NaN where no data (e.g. sea cells of a land product).
    sst : ndarray (time,) or None
        Sea-surface temperature [K].
    tcwv : ndarray (time,) or None
        Total column water vapour [g cm-2].
    """

    times_utc: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    temperature: np.ndarray
    sst: np.ndarray | None
    tcwv: np.ndarray | None

    def interp_time(self, series: np.ndarray, when: np.datetime64) -> float:
        """Linear interpolation of an hourly series at ``when`` (UTC)."""
        t = (self.times_utc - self.times_utc[0]).astype("timedelta64[s]").astype(float)
        x = float((np.datetime64(when, "s") - self.times_utc[0]).astype("timedelta64[s]").astype(float))
        require(t[0] <= x <= t[-1], "met_grid.time", str(when),
                f"must lie within the met grid's span {self.times_utc[0]} .. {self.times_utc[-1]} UTC",
                "Provide met data covering the Landsat overpass")
        return float(np.interp(x, t, series))


def read_met_grid(path: str | os.PathLike, var: str = "temperature", n_hours: int = 24) -> MetGrid:
    """Read and validate an hourly met NetCDF.

    Parameters
    ----------
    path : path-like
        NetCDF file (netCDF4/HDF5 or classic).
    var : str
        Name of the temperature variable [K].
    n_hours : int
        Number of consecutive hourly steps required.

    Raises
    ------
    InputError
        Missing variables/dimensions, non-kelvin units, missing or duplicated hours (the
        missing time stamps are listed), an hour without any valid value, values outside
        180–350 K.
    """
    path = os.fspath(path)
    require(os.path.isfile(path), "met_path", path, "must be an existing NetCDF file")
    try:
        ds = xr.open_dataset(path)
    except Exception as exc:  # noqa: BLE001 - any backend error means "not a readable NetCDF"
        raise InputError("met_path", path, "must be a readable NetCDF file", str(exc)) from None
    with ds:
        require(var in ds.variables, f"met[{var}]", "missing", f"the file must hold the variable '{var}'",
                f"Variables present: {sorted(ds.data_vars)}")
        da = ds[var]
        require(set(da.dims) == {"time", "lat", "lon"}, f"met[{var}].dims", da.dims,
                "must be (time, lat, lon)")
        units = str(da.attrs.get("units", "K"))
        require(units in ("K", "kelvin", "Kelvin"), f"met[{var}].units", units, "must be K",
                "Convert to kelvin (CLDAS TAIR/LST are in K)")
        da = da.transpose("time", "lat", "lon")
        times = ds["time"].values.astype("datetime64[s]")
        temperature = da.values.astype(np.float64)
        lat = ds["lat"].values.astype(np.float64)
        lon = ds["lon"].values.astype(np.float64)
        sst = ds["sst"].values.astype(np.float64) if "sst" in ds.variables else None
        tcwv = ds["tcwv"].values.astype(np.float64) if "tcwv" in ds.variables else None
    step = np.timedelta64(3600, "s")
    if times.size == 0:
        raise InputError("met.time", "empty", f"must hold {n_hours} hourly steps")
    expected = times[0] + step * np.arange(n_hours)
    missing = np.setdiff1d(expected, times)
    if missing.size or times.size != n_hours or np.any(np.diff(times) != step):
        shown = ", ".join(str(t) for t in missing[:6]) + (" ..." if missing.size > 6 else "")
        raise InputError("met.time", f"{times.size} steps from {times[0]} to {times[-1]}",
                         f"must be {n_hours} consecutive hourly steps",
                         f"Missing hours: {shown}" if missing.size else "Remove duplicated or irregular steps")
    for k in range(n_hours):
        if not np.isfinite(temperature[k]).any():
            raise InputError(f"met[{var}][time={times[k]}]", "all NaN",
                             "every hour needs valid grid values", "Fill or replace the missing hour")
    finite = temperature[np.isfinite(temperature)]
    if finite.min() < _TEMP_RANGE[0] or finite.max() > _TEMP_RANGE[1]:
        bad = finite.min() if finite.min() < _TEMP_RANGE[0] else finite.max()
        raise InputError(f"met[{var}]", float(bad), f"must lie in {_TEMP_RANGE} K", "Check units (K) and fill values")
    for name, series in (("sst", sst), ("tcwv", tcwv)):
        if series is not None:
            require(series.shape == (n_hours,), f"met[{name}].shape", series.shape, f"must be ({n_hours},) (time)")
            if not np.all(np.isfinite(series)):
                k = int(np.flatnonzero(~np.isfinite(series))[0])
                raise InputError(f"met[{name}][time={times[k]}]", float(series[k]), "must be finite")
    return MetGrid(times, lat, lon, temperature, sst, tcwv)
