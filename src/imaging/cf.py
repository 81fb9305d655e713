"""The CF conventions of the NetCDF products: the grid mapping of a map grid and the
attributes of its time and map axes.

A CF grid mapping variable names the projection with its parameters (CF §5.6, Appendix F)
and carries the CRS as WKT twice: ``crs_wkt`` (CF 1.7) and ``spatial_ref`` with a
``GeoTransform`` (what GDAL, QGIS and rioxarray read), so that every reader finds the
georeferencing without a global attribute.
"""

from __future__ import annotations

import numpy as np

from shipthermal.units import cf_time_units, zone_text

__all__ = ["GRID_MAPPING", "CONVENTIONS", "grid_mapping_attrs", "geotransform", "time_attrs",
           "map_axis_attrs"]

#: Name of the grid mapping variable (the name rioxarray and GDAL look for first)
GRID_MAPPING = "spatial_ref"

#: The ``Conventions`` attribute: the newest CF version the reference checker, cfchecker
#: 4.1 (CF-1.0 to CF-1.8), verifies; nothing in the files needs CF-1.9 or later.
CONVENTIONS = "CF-1.8"

#: Ellipsoids by PROJ name: semi-major axis [m], inverse flattening [-] (SOURCED: PROJ's
#: ellipsoid list, ``proj -le``)
_ELLIPSOIDS = {"WGS84": (6378137.0, 298.257223563), "GRS80": (6378137.0, 298.257222101),
               "intl": (6378388.0, 297.0)}


def _ellipsoid(p: dict) -> dict:
    name = p.get("ellps") or {"WGS84": "WGS84", "NAD83": "GRS80"}.get(p.get("datum", ""))
    if "a" in p and "rf" in p:
        a, rf = float(p["a"]), float(p["rf"])
    elif name in _ELLIPSOIDS:
        a, rf = _ELLIPSOIDS[name]
    else:
        return {}
    return {"semi_major_axis": a, "inverse_flattening": rf, "longitude_of_prime_meridian": 0.0}


def grid_mapping_attrs(crs) -> dict:
    """The CF grid mapping attributes of a rasterio CRS (``{}`` without a CRS).

    Transverse Mercator (UTM zones included), polar stereographic and latitude-longitude get
    their CF names and parameters (what Landsat scenes and the synthetic port use); any other
    projection is carried by ``crs_wkt`` and ``spatial_ref`` alone (GDAL, QGIS and rioxarray
    read it; a CF checker then reports the missing ``grid_mapping_name``).
    """
    if crs is None:
        return {}
    wkt = crs.to_wkt()
    p = crs.to_dict()
    proj = p.get("proj")
    attrs: dict = {}
    if proj == "utm":
        zone = int(p["zone"])
        attrs = {"grid_mapping_name": "transverse_mercator",
                 "longitude_of_central_meridian": -183.0 + 6.0 * zone,
                 "latitude_of_projection_origin": 0.0,
                 "scale_factor_at_central_meridian": 0.9996, "false_easting": 500000.0,
                 "false_northing": 10000000.0 if p.get("south") else 0.0}
    elif proj == "tmerc":
        attrs = {"grid_mapping_name": "transverse_mercator",
                 "longitude_of_central_meridian": float(p.get("lon_0", 0.0)),
                 "latitude_of_projection_origin": float(p.get("lat_0", 0.0)),
                 "scale_factor_at_central_meridian": float(p.get("k_0", p.get("k", 1.0))),
                 "false_easting": float(p.get("x_0", 0.0)),
                 "false_northing": float(p.get("y_0", 0.0))}
    elif proj == "stere" and abs(float(p.get("lat_0", 0.0))) == 90.0:
        attrs = {"grid_mapping_name": "polar_stereographic",
                 "straight_vertical_longitude_from_pole": float(p.get("lon_0", 0.0)),
                 "latitude_of_projection_origin": float(p["lat_0"]),
                 "false_easting": float(p.get("x_0", 0.0)),
                 "false_northing": float(p.get("y_0", 0.0))}
        if "lat_ts" in p:
            attrs["standard_parallel"] = float(p["lat_ts"])
        else:
            attrs["scale_factor_at_projection_origin"] = float(p.get("k_0", p.get("k", 1.0)))
    elif proj in ("longlat", "latlong"):
        attrs = {"grid_mapping_name": "latitude_longitude"}
    attrs.update(_ellipsoid(p) if attrs else {})
    if crs.to_epsg():
        attrs["epsg_code"] = f"EPSG:{crs.to_epsg()}"
    attrs.update({"crs_wkt": wkt, "spatial_ref": wkt})
    return attrs


def geotransform(transform, crop=None) -> str:
    """GDAL's ``GeoTransform`` (``"x0 dx 0 y0 0 dy"``, upper-left corner) of the rows
    ``crop[0]:`` and columns ``crop[2]:`` of a grid with the affine ``transform``."""
    r0, c0 = (crop[0], crop[2]) if crop is not None else (0, 0)
    x0 = transform.c + c0 * transform.a + r0 * transform.b
    y0 = transform.f + c0 * transform.d + r0 * transform.e
    return " ".join(repr(float(v)) for v in (x0, transform.a, transform.b, y0, transform.d,
                                            transform.e))


def time_attrs(date: str, time_zone: str) -> tuple[dict, dict]:
    """``(attributes, encoding)`` of a ``time`` coordinate counted in seconds from local
    midnight of ``date`` in the IANA ``time_zone``: CF units with the zone's UTC offset
    (xarray decodes them to UTC datetimes), the zone named in the long name. Seconds, not
    hours: frame times are whole seconds, so they decode exactly (10 min is not a finite
    binary fraction of an hour)."""
    units = cf_time_units(date, time_zone, "seconds")
    attrs = {"standard_name": "time", "axis": "T",
             "long_name": f"time (counted from local midnight of {date}, "
                          f"{zone_text(date, time_zone)})"}
    return attrs, {"units": units, "calendar": "standard", "dtype": "float64"}


def map_axis_attrs(axis: str, crs) -> dict:
    """Attributes of the ``x`` or ``y`` coordinate of pixel centres [m]."""
    name = {"x": "easting", "y": "northing"}[axis]
    geographic = crs is not None and crs.is_geographic
    if geographic:
        std = {"x": "longitude", "y": "latitude"}[axis]
        return {"standard_name": std, "units": {"x": "degree_east", "y": "degree_north"}[axis],
                "axis": axis.upper(), "long_name": f"{std} of pixel centre"}
    return {"standard_name": f"projection_{axis}_coordinate", "units": "m",
            "axis": axis.upper(), "long_name": f"{name} of pixel centre"}


def pixel_centres(transform, crop) -> tuple[np.ndarray, np.ndarray]:
    """Map x of columns and y of rows of the pixel centres of ``crop``
    (``(row0, row1, col0, col1)``) [m]."""
    r0, r1, c0, c1 = crop
    x = transform.c + (np.arange(c0, c1) + 0.5) * transform.a
    y = transform.f + (np.arange(r0, r1) + 0.5) * transform.e
    return x, y
