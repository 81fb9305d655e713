"""Ship surface temperatures through time: the imaging stage's input from the thermal stage.

:class:`ShipThermalHistory` is the hand-over format: the outer surface triangles of the
ship (ship frame: x forward, y to port, z up, waterline z = 0), their parts, and a
temperature per triangle at a series of times [s after local midnight]. The diurnal
thermal run converts its results to it (outer faces ``b < M`` of the solver's
``Results.face_temperature``, see ``docs/SOLVER-API.md``)::

    hist = ShipThermalHistory(ship.vertices, ship.faces, ship.face_part, ship.part_names,
                              res.times, res.face_temperature[:, :ship.n_faces],
                              temp_air=..., temp_sea=...)

:func:`synthetic_history` is a **synthetic stand-in** for tests and demos until that run
exists: an illustrative waveform around the design day's air temperature, *not* a
heat-transfer result (see its docstring).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from shipthermal.errors import InputError, check_finite, check_range, require
from shipthermal.geometry.parts import part_key
from shipthermal.parameters import BAND_EMISSIVITY
from shipthermal.units import DAY, HOUR, fold_time

__all__ = ["ShipThermalHistory", "synthetic_history", "emissivity_key", "SYNTHETIC_PART_RESPONSE"]


def emissivity_key(part_name: str) -> str:
    """Emissivity table key (hull, deck, superstructure) of a ship part or sub-part name.

    ``hull_wetted``/``hull_dry``/``hull`` -> ``hull``; ``superstructure_mast`` ->
    ``superstructure``: the key of :data:`shipthermal.parameters.BAND_EMISSIVITY` that
    :func:`shipthermal.geometry.parts.part_key` finds.
    """
    return part_key(BAND_EMISSIVITY, part_name)


def _interp_periodic(times, values, t, period):
    """Linear interpolation of ``values`` (nt, ...) at scalar ``t``; times outside the samples
    wrap by ``period`` (None: clamp to the ends; callers check the range). ``values`` may be
    read lazily (e.g. an h5py dataset): only the two rows around ``t`` are read then."""
    if not isinstance(values, np.ndarray):
        return _interp_rows(times, values, t, period)
    if period is not None and not times[0] <= t <= times[-1]:
        t0 = times[0]
        t = fold_time(t, period, t0)
        if times[-1] < t0 + period:
            times = np.append(times, t0 + period)
            values = np.concatenate([values, values[:1]], axis=0)
    k = int(np.searchsorted(times, t, side="right") - 1)
    k = min(max(k, 0), len(times) - 2)
    w = (t - times[k]) / (times[k + 1] - times[k])
    return (1.0 - w) * values[k] + w * values[k + 1]


def _interp_rows(times, rows, t, period):
    """:func:`_interp_periodic` on rows read as indexed (float64), two of them."""
    n = len(times)
    if period is not None and not times[0] <= t <= times[-1]:
        t0 = times[0]
        t = fold_time(t, period, t0)
        if t > times[-1]:        # between the last row and the first of the next period
            w = (t - times[-1]) / (t0 + period - times[-1])
            return (1.0 - w) * np.asarray(rows[n - 1], float) + w * np.asarray(rows[0], float)
    k = int(np.searchsorted(times, t, side="right") - 1)
    k = min(max(k, 0), n - 2)
    w = (t - times[k]) / (times[k + 1] - times[k])
    pair = np.asarray(rows[k:k + 2], dtype=float)
    return (1.0 - w) * pair[0] + w * pair[1]


@dataclass(frozen=True, eq=False)
class ShipThermalHistory:
    """Outer-surface temperatures of a ship at a series of times.

    Attributes
    ----------
    vertices : (N, 3) float array
        Ship-frame vertex coordinates [m]: x forward (bow +x), y to port, z up, z = 0 at the
        waterline (the :mod:`shipthermal.geometry` convention).
    faces : (M, 3) int array
        Outer surface triangles, wound with outward normals.
    face_part : (M,) int array
        Index into ``part_names`` of each triangle.
    part_names : tuple of str
        Part names (main parts or ``<main>_<detail>`` sub-parts).
    times_s : (nt,) float array
        Strictly increasing times [s after local midnight of the day].
    face_temperature : (nt, M) float array, or an array read lazily
        Surface temperature of each triangle at each time [K]. A weather record's (a year:
        59 694 faces × 17 520 times) is an h5py dataset of the thermal stage's file: only
        the two rows around a time asked for are read (and checked).
    temp_air : (nt,) float array or None
        Air temperature at the same times [K] (kept for plots and checks).
    temp_sea : (nt,) float array or None
        Sea skin temperature [K] (the thermal run's ``temp_sea_skin``: bulk SST + warm layer
        − cool skin); the ship's hull sees the sea with it. None: the imaging stage uses the
        background water temperature.
    period_s : float or None
        Period [s] for times outside ``times_s`` (default one day: a spun-up diurnal run is
        periodic); None: times outside ``[times_s[0], times_s[-1]]`` are an error.
    label : str
        Where the temperatures come from (e.g. ``"diurnal run, summer"``).
    """

    vertices: np.ndarray
    faces: np.ndarray
    face_part: np.ndarray
    part_names: tuple
    times_s: np.ndarray
    face_temperature: np.ndarray
    temp_air: np.ndarray | None = None
    temp_sea: np.ndarray | None = None
    period_s: float | None = DAY
    label: str = ""
    _emissivity_keys: tuple = field(default=(), repr=False, init=False)

    def __post_init__(self):
        v = np.array(self.vertices, dtype=float)
        f = np.array(self.faces, dtype=np.int64)
        p = np.array(self.face_part, dtype=np.int64)
        t = np.array(self.times_s, dtype=float).reshape(-1)
        lazy = not isinstance(self.face_temperature, np.ndarray) and hasattr(
            self.face_temperature, "shape") and hasattr(self.face_temperature, "dtype")
        temp = self.face_temperature if lazy else np.array(self.face_temperature, dtype=float)
        names = tuple(str(n) for n in self.part_names)
        require(v.ndim == 2 and v.shape[1] == 3 and len(v) >= 3, "history.vertices", v.shape,
                "must be an (N, 3) array of at least 3 points [m]")
        require(f.ndim == 2 and f.shape[1] == 3 and len(f) >= 1, "history.faces", f.shape,
                "must be an (M, 3) integer array")
        require(int(f.min()) >= 0 and int(f.max()) < len(v), "history.faces",
                (int(f.min()), int(f.max())), f"indices must lie in [0, {len(v) - 1}]")
        check_finite("history.vertices", v)
        require(p.shape == (len(f),), "history.face_part", p.shape,
                f"must hold one part index per face ({len(f)})")
        require(int(p.min()) >= 0 and int(p.max()) < len(names), "history.face_part",
                (int(p.min()), int(p.max())), f"must index part_names (0..{len(names) - 1})")
        keys = tuple(emissivity_key(n) for n in names)
        require(t.size >= 2, "history.times_s", t, "needs at least 2 times")
        check_finite("history.times_s", t)
        require(bool(np.all(np.diff(t) > 0)), "history.times_s", t, "must be strictly increasing")
        require(temp.shape == (t.size, len(f)), "history.face_temperature", temp.shape,
                f"must be (n_times, n_faces) = ({t.size}, {len(f)})",
                "Pass only the outer surface faces (b < M of the solver's face_temperature)")
        if not lazy:        # (lazy rows are checked as they are read)
            check_range("history.face_temperature", temp, 100.0, 1000.0, "K")
        out = {}
        for name in ("temp_air", "temp_sea"):
            val = getattr(self, name)
            if val is not None:
                val = np.array(val, dtype=float).reshape(-1)
                require(val.shape == t.shape, f"history.{name}", val.shape,
                        f"must have one value per time ({t.size})")
                check_range(f"history.{name}", val, 100.0, 400.0, "K")
                val.setflags(write=False)
            out[name] = val
        if self.period_s is not None:
            require(float(self.period_s) >= t[-1] - t[0] and self.period_s > 0,
                    "history.period_s", self.period_s,
                    f"must be >= the span of times_s ({t[-1] - t[0]:g} s) or None")
        for arr in (v, f, p, t) + (() if lazy else (temp,)):
            arr.setflags(write=False)
        for name, val in (("vertices", v), ("faces", f), ("face_part", p), ("times_s", t),
                          ("face_temperature", temp), ("part_names", names),
                          ("_emissivity_keys", keys), *out.items()):
            object.__setattr__(self, name, val)

    @property
    def n_faces(self) -> int:
        return int(len(self.faces))

    @property
    def face_emissivity_key(self) -> np.ndarray:
        """Emissivity table key of each face: ``'hull'``, ``'deck'`` or ``'superstructure'``."""
        return np.array(self._emissivity_keys)[self.face_part]

    def _check_time(self, t):
        t = float(t)
        require(np.isfinite(t), "t", t, "must be a finite time [s after local midnight]")
        if self.period_s is None:
            check_range("t", t, float(self.times_s[0]), float(self.times_s[-1]), "s",)
        return t

    def at(self, t) -> np.ndarray:
        """Face temperatures at time ``t`` [s after local midnight], linear in time [K] (M,)."""
        t = self._check_time(t)
        out = _interp_periodic(self.times_s, self.face_temperature, t, self.period_s)
        if not isinstance(self.face_temperature, np.ndarray):
            check_range("history.face_temperature", out, 100.0, 1000.0, "K")
        return out

    def temp_air_at(self, t) -> float | None:
        """Air temperature at ``t`` [s] [K] (None when not given)."""
        if self.temp_air is None:
            return None
        return float(_interp_periodic(self.times_s, self.temp_air, self._check_time(t),
                                      self.period_s))

    def temp_sea_at(self, t) -> float | None:
        """Sea surface temperature at ``t`` [s] [K] (None when not given)."""
        if self.temp_sea is None:
            return None
        return float(_interp_periodic(self.times_s, self.temp_sea, self._check_time(t),
                                      self.period_s))

    def part_mean(self, t) -> dict:
        """Area-weighted mean temperature per emissivity key at ``t`` [s] [K]."""
        tri = self.vertices[self.faces]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        temp = self.at(t)
        keys = self.face_emissivity_key
        return {k: float(np.sum(area[keys == k] * temp[keys == k]) / np.sum(area[keys == k]))
                for k in sorted(set(keys))}


SYNTHETIC_PART_RESPONSE = {
    # emissivity key: (daytime excess per unit sin(sun elevation) [K], night deficit [K])
    "deck": (14.0, 2.5),
    "hull": (7.0, 1.0),
    "superstructure": (10.0, 1.5),
}
"""Amplitudes of the synthetic stand-in (:func:`synthetic_history`): ASSUMPTION, chosen to
look like a sunlit painted steel ship (decks warmest at noon, a few kelvin below the air at
night by sky cooling); not fitted to anything and not a heat-transfer result."""


def synthetic_history(ship, season: str = "summer", step_s: float = 1800.0,
                      lag_h: float = 1.0, response: dict | None = None) -> ShipThermalHistory:
    """SYNTHETIC STAND-IN for a diurnal thermal run (tests and demos only — not physics).

    Parameters
    ----------
    ship : shipthermal.geometry.ShipGeometry
        The ship (its outer surface, parts and ship-frame coordinates are used as they are).
    season : {"summer", "winter"}
        Built-in design day (:func:`shipthermal.environment.climate_day`) for the air
        temperature, SST and the sun.
    step_s : float
        Output interval [s]; must divide one day.
    lag_h : float
        Delay of the waveform behind the sun [h] (plate heat capacity, illustrative).
    response : dict or None
        ``{emissivity key: (day excess [K], night deficit [K])}``; default
        :data:`SYNTHETIC_PART_RESPONSE`.

    Returns
    -------
    ShipThermalHistory
        ``label`` starts with ``"SYNTHETIC"``.

    Notes
    -----
    ``T_face(t) = T_air(t) + w (A_part max(sin h(t - lag), 0) - C_part)`` with ``h`` the SPA
    sun elevation, ``w = (1 + n_z) / 2`` (up-facing faces respond fully, vertical faces by
    half, down-facing not at all) and ``(A, C)`` from ``response``. No energy balance, no
    shadows, no conduction: an illustrative waveform of the right size, for exercising the
    imaging chain until the real producer (the diurnal thermal run) is connected.
    """
    # deferred: shipthermal.environment loads pvlib and pandas (0.8 s over the renderer's
    # imports, measured); only the synthetic stand-in needs them
    import pandas as pd

    from shipthermal.environment import climate_day
    from shipthermal.environment.sun import solar_position

    require(float(step_s) > 0 and abs(DAY / step_s - round(DAY / step_s)) < 1e-9, "step_s",
            step_s, "must be > 0 and divide 86400 s")
    day = climate_day(season)
    resp = dict(SYNTHETIC_PART_RESPONSE if response is None else response)
    times = np.arange(0.0, DAY + 0.5 * step_s, float(step_s))
    hours = times / HOUR
    idx = pd.Timestamp(day.date).tz_localize(day.tz) + pd.to_timedelta(hours - lag_h, unit="h")
    sun = solar_position(pd.DatetimeIndex(idx), day.latitude, day.longitude)
    sin_el = np.clip(np.sin(np.radians(sun["elevation"].to_numpy())), 0.0, None)
    tri = np.asarray(ship.vertices)[np.asarray(ship.faces)]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nz = n[:, 2] / np.linalg.norm(n, axis=1)
    w = 0.5 * (1.0 + nz)
    keys = np.array([emissivity_key(p) for p in ship.part_names])[np.asarray(ship.face_part)]
    missing = sorted(set(keys) - set(resp))
    if missing:
        raise InputError("response", sorted(resp), f"needs entries for {missing}")
    amp = np.array([resp[k][0] for k in keys])
    deficit = np.array([resp[k][1] for k in keys])
    temp_air = np.asarray(day.temp_air(hours % 24.0), dtype=float)
    temp = temp_air[:, None] + w[None, :] * (amp[None, :] * sin_el[:, None] - deficit[None, :])
    return ShipThermalHistory(ship.vertices, ship.faces, ship.face_part, ship.part_names,
                              times, temp, temp_air=temp_air,
                              temp_sea=np.asarray(day.temp_sea(hours % 24.0), dtype=float),
                              label=f"SYNTHETIC stand-in ({day.name}; not a thermal solution)")
