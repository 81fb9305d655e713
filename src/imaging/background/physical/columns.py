"""The columns of a scene: land pixels grouped by class and orientation, each group solved on
its class's (albedo × conductance) grid under its own sun and sky, and the bilinear corners
that place a pixel among its group's columns."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from shipthermal.errors import InputError

from ..classify import CLASS_NAMES
from ..surface_energy import (SurfaceForcing, build_columns, convection_aerodynamic,
                              longwave_incoming, shortwave_on_tilted, sky_view_factor,
                              solve_surface_energy)
from .ground import GroundCover


SLOPE_EDGES_DEG = (0.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 90.0)
ASPECT_SECTORS = 24
"""Orientation groups: below 2 deg of slope a pixel is solved as level ground; above, the
slope bins [deg] times 24 aspect sectors of 15 deg. Solving a pixel at its group's mean
orientation instead of its own (measured in the tests, slopes 0-40 deg at 50.9 N in July):
0.11 K mean, 1.3 K at worst (steep slopes at peak sun); with 8 sectors and 6 slope bins
it was 0.33 K and 3.1 K."""

ALBEDO_SAMPLES = 5
"""Albedos a class fitted on its albedo is solved at, evenly spanning its range."""

ALBEDO_SAMPLES_WET = 3
CONDUCTANCE_SAMPLES = 5
"""A class fitted on its wetness: 3 albedos spanning its range (the pixel's own albedo is
interpolated between them) x 5 surface conductances ``1/r_s`` evenly from its driest to its
wettest."""

DRY_RESISTANCE = 1.0e9
"""Surface resistance of a dry surface in a class that may be wet [s m-1] (no evaporation)."""

# ---------------------------------------------------------------------------------------
# Orientation groups
# ---------------------------------------------------------------------------------------
def orientation_bins(slope_deg, aspect_deg):
    """Group pixels by orientation.

    Returns
    -------
    index : ndarray int (rows, cols)
        Bin of each pixel (0: level ground, slope below ``SLOPE_EDGES_DEG[1]``).
    slope, aspect : ndarray (n_bins,)
        Mean slope [deg] and circular-mean aspect [deg] of the pixels of each bin (level
        ground: 0, 180).
    """
    s = np.nan_to_num(np.asarray(slope_deg, dtype=float))
    a = np.mod(np.nan_to_num(np.asarray(aspect_deg, dtype=float)), 360.0)   # level: no aspect
    sb = np.clip(np.searchsorted(SLOPE_EDGES_DEG, s, side="right") - 1, 0,
                 len(SLOPE_EDGES_DEG) - 2)
    width = 360.0 / ASPECT_SECTORS
    sector = np.floor(np.mod(a + 0.5 * width, 360.0) / width).astype(int) % ASPECT_SECTORS
    raw = np.where(sb == 0, 0, 1 + (sb - 1) * ASPECT_SECTORS + sector)
    used, index = np.unique(raw, return_inverse=True)
    index = index.reshape(s.shape)
    n = used.size
    counts = np.bincount(index.ravel(), minlength=n)
    slope = np.bincount(index.ravel(), s.ravel(), minlength=n) / counts
    sx = np.bincount(index.ravel(), np.sin(np.radians(a)).ravel(), minlength=n)
    cx = np.bincount(index.ravel(), np.cos(np.radians(a)).ravel(), minlength=n)
    aspect = np.mod(np.degrees(np.arctan2(sx, cx)), 360.0)
    level = used == 0
    slope[level] = 0.0
    aspect[level] = 180.0
    return index, slope, aspect


def _class_grid(cls):
    """The anchoring design of a class: ``(fit, albedos, conductances, default conductance)``.

    A class with a ``surface_resistance_range`` is fitted on its surface conductance
    ``g = 1/r_s`` [m s-1] (its wetness; the albedo is the pixel's own); a class without is
    fitted on its albedo within ``albedo_range``. A class without latent heat by default but
    with a range (paving that can be wet) starts dry (g = 0)."""
    if cls.surface_resistance_range is not None:
        r_lo, r_hi = cls.surface_resistance_range
        wet = 1.0 / r_lo
        dry = 1.0 / r_hi if cls.latent == "penman_monteith" and np.isfinite(r_hi) else 0.0
        default = 1.0 / cls.surface_resistance if cls.latent == "penman_monteith" else 0.0
        return ("surface_resistance", np.linspace(*cls.albedo_range, ALBEDO_SAMPLES_WET),
                np.linspace(dry, wet, CONDUCTANCE_SAMPLES), default)
    return ("albedo", np.linspace(*cls.albedo_range, ALBEDO_SAMPLES), np.array([-1.0]), -1.0)


def _positions(samples, values):
    """Fractional index of ``values`` in increasing ``samples`` (clipped to the ends)."""
    if samples.size == 1:
        return np.zeros(np.shape(values))
    return np.interp(values, samples, np.arange(samples.size, dtype=float))


def _corners(pos_a, pos_g, n_a, n_g, base):
    """The 4 columns and bilinear weights of pixels at fractional positions."""
    i0 = np.clip(np.floor(pos_a).astype(np.int64), 0, max(n_a - 2, 0))
    wa = np.clip(pos_a - i0, 0.0, 1.0) if n_a > 1 else np.zeros_like(pos_a)
    i1 = np.minimum(i0 + 1, n_a - 1)
    j0 = np.clip(np.floor(pos_g).astype(np.int64), 0, max(n_g - 2, 0))
    wg = np.clip(pos_g - j0, 0.0, 1.0) if n_g > 1 else np.zeros_like(pos_g)
    j1 = np.minimum(j0 + 1, n_g - 1)
    idx = np.stack([base + i0 * n_g + j0, base + i0 * n_g + j1, base + i1 * n_g + j0,
                    base + i1 * n_g + j1], axis=1)
    w = np.stack([(1 - wa) * (1 - wg), (1 - wa) * wg, wa * (1 - wg), wa * wg], axis=1)
    return idx, w


@dataclass(frozen=True, eq=False)
class _ColumnSet:
    """The columns of a scene: groups of (class, orientation) over its land pixels, each
    solved on its class's (albedo × conductance) grid (:func:`_class_grid`)."""

    names: dict              # class code -> name
    design: dict             # class code -> (fit, albedos, conductances, default conductance)
    g_of_pixel: np.ndarray   # group of every land pixel
    base: np.ndarray         # first column of every group
    slope: np.ndarray        # orientation bins' slope and aspect [deg]
    aspect: np.ndarray
    col_class: list          # SurfaceClass of every column
    col_albedo: np.ndarray   # [-]
    col_bin: np.ndarray      # orientation bin of every column
    resistance: np.ndarray   # surface resistance [s m-1] (-1: no latent heat)


def _column_set(ground: GroundCover, land, table) -> _ColumnSet:
    """Group the land pixels by class and orientation and lay out their columns."""
    flat = ground.class_map.ravel()
    names = {int(c): CLASS_NAMES[int(c)] for c in np.unique(flat[land])}
    for code, name in names.items():
        if name not in table:
            raise InputError(f"background.classes.{name}", None, "needs its surface properties "
                             f"(class {code} is in the scene)", f"Add [background.classes.{name}]"
                             f" (built-in classes: {', '.join(sorted(table))})")
    design = {c: _class_grid(table[n]) for c, n in names.items()}
    obin, slope, aspect = orientation_bins(ground.slope_deg, ground.aspect_deg)
    key = flat[land].astype(np.int64) * 1000 + obin.ravel()[land]
    groups, g_of_pixel = np.unique(key, return_inverse=True)
    g_class = (groups // 1000).astype(int)
    g_bin = (groups % 1000).astype(int)
    sizes = np.array([design[c][1].size * design[c][2].size for c in g_class])
    base = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    col_class, col_albedo, col_g, col_bin = [], [], [], []
    for g, c in enumerate(g_class):
        _, alb, cond, _ = design[c]
        aa, gg = np.meshgrid(alb, cond, indexing="ij")
        col_albedo.append(aa.ravel())
        col_g.append(gg.ravel())
        col_bin.append(np.full(aa.size, g_bin[g]))
        col_class += [table[names[c]]] * aa.size
    col_albedo, col_g, col_bin = (np.concatenate(x) for x in (col_albedo, col_g, col_bin))
    resistance = np.where(col_g > 0.0, 1.0 / np.where(col_g > 0.0, col_g, 1.0),
                          np.where(col_g == 0.0, DRY_RESISTANCE, -1.0))
    return _ColumnSet(names, design, g_of_pixel, base, slope, aspect, col_class, col_albedo,
                      col_bin, resistance)


def _column_forcing(cs: _ColumnSet, state, dtype=np.float64):
    """Absorbed short-wave and incoming long-wave of every column [W m-2], (n_t, n_columns)
    in ``dtype``: each orientation's plane-of-array sun, its sky view and the terrain at the
    air (float64 temporaries by blocks of rows, so a long record's float32 tables are never
    held twice)."""
    poa = _plane_of_array(state, cs.slope, cs.aspect, np.unique(cs.col_bin))
    svf = sky_view_factor(cs.slope)[cs.col_bin]
    n_t, n_c = poa.shape[0], cs.col_bin.size
    sw = np.empty((n_t, n_c), dtype)
    lw = np.empty((n_t, n_c), dtype)
    down, air = np.asarray(state.longwave_down), np.asarray(state.temp_air)
    for rows in _row_blocks(n_t, n_c):
        sw[rows] = (1.0 - cs.col_albedo)[None, :] * poa[rows][:, cs.col_bin]
        lw[rows] = longwave_incoming(down[rows, None], svf, air[rows, None])
    return sw, lw


def _plane_of_array(state, slope, aspect, used_bins):
    """Global irradiance on each orientation bin's plane [W m-2], (n_t, n_bins): pvlib's
    plane-of-array irradiance (:func:`.surface_energy.shortwave_on_tilted`, isotropic sky
    diffuse, ground-reflected with :data:`GROUND_ALBEDO`); level ground takes the GHI."""
    out = np.zeros((state.ghi.size, slope.size))
    tilted = np.array([b for b in used_bins if slope[b] > 0.0], dtype=int)
    out[:, [b for b in used_bins if slope[b] == 0.0]] = np.asarray(state.ghi)[:, None]
    if tilted.size:
        poa = shortwave_on_tilted(slope[tilted], aspect[tilted], state.zenith, state.azimuth,
                                  state.dni, state.ghi, state.dhi, albedo_ground=GROUND_ALBEDO)
        out[:, tilted] = poa["poa_global"]
    return np.maximum(out, 0.0)


WIND_HEIGHT_M = 10.0
"""Height of the environment's wind [m] (weather files are reduced to 10 m on reading)."""

AIR_HEIGHT_M = 2.0
"""Height of the weather's air temperature and humidity [m]: screen height (WMO standard
1.25-2 m; EPW/TMY and buoy air temperatures are screen-level)."""

GROUND_ALBEDO = 0.2
"""Albedo of the terrain a tilted pixel sees (pvlib's default, a generic ground). ASSUMPTION."""


def land_convection(col_class, pressure=101325.0):
    """The land columns' convection, ``h(T_s, T_air, wind)`` [W m-2 K-1] for columns of the
    classes ``col_class``: the surface layer's log-law aerodynamic resistance between the
    10 m wind (:data:`WIND_HEIGHT_M`), the screen-level air (:data:`AIR_HEIGHT_M`) and each
    class's roughness lengths, with the bulk-Richardson stability factors
    (:func:`.surface_energy.convection_aerodynamic`)."""
    return convection_aerodynamic(np.array([c.roughness_length for c in col_class]),
                                  np.array([c.roughness_length_heat for c in col_class]),
                                  np.array([c.displacement_height for c in col_class]),
                                  height_wind=WIND_HEIGHT_M, height_temp=AIR_HEIGHT_M,
                                  stability=True, pressure=pressure)


def _column_temperatures(col_class, resistance, sw, lw, state, environment, times, periodic,
                         classes, substeps=1):
    """Surface temperature of every column [K], (n_t, n_columns), and the solve's report
    (:func:`.surface_energy.solve_surface_energy`).

    The deep ground below the diurnal wave and the rooms under the roofs are at the mean air
    temperature of the simulated span (ASSUMPTION: an unconditioned port warehouse; the deep
    ground of a periodic day in equilibrium with its air).

    Convection is the surface layer's: the log-law aerodynamic resistance between the 10 m
    wind and each class's roughness lengths, with the bulk-Richardson stability factors
    (:func:`.surface_energy.convection_aerodynamic`, FAO-56 eq. 4; Dyer 1974, Webb 1970). A
    30 m pixel in a port is part of a rough surface many pixels wide, not the leading edge of
    a flat plate: the ship's flat-plate correlation gives h ≈ 9 W m-2 K-1 at a July noon
    where EnergyPlus's DOE-2 gives ≈ 15 (tests/background, the EnergyPlus peer), and a
    sunlit surface 4-5 K hotter."""
    bottom = float(np.mean(state.temp_air))
    cols = dataclasses.replace(build_columns(col_class, bottom, classes=classes),
                               surface_resistance=np.asarray(resistance, dtype=float))
    pressure = 101325.0 * (1.0 - 2.25577e-5 * environment.altitude) ** 5.25588
    forcing = SurfaceForcing(time_step=float(times[1] - times[0]), shortwave_absorbed=sw,
                             longwave_down=lw, temp_air=np.asarray(state.temp_air, float),
                             relative_humidity=np.clip(state.relative_humidity, 0.0, 100.0),
                             wind_speed=np.asarray(state.wind_speed, float), pressure=pressure)
    res = solve_surface_energy(forcing, cols, convection=land_convection(col_class, pressure),
                               mode="periodic" if periodic else "record", substeps=substeps,
                               outputs=("temp_surface",), output_dtype=sw.dtype)
    return res.temp_surface, res


def _row_blocks(n_rows: int, n_cols: int, elements: int = 1 << 22):
    """Slices of rows of about ``elements`` values each."""
    step = max(1, elements // max(n_cols, 1))
    for start in range(0, n_rows, step):
        yield slice(start, min(n_rows, start + step))
