"""Per-face boundary forcing of a ship for a periodic diurnal run.

This module wires the environment (:mod:`shipthermal.environment`), the ray tracer
(:mod:`shipthermal.raytrace`) and the ship (:mod:`shipthermal.geometry`) into boundary
conditions in the solver's format (:mod:`shipthermal.conditions`, ``docs/SOLVER-API.md``).
It adds no new physics kernel: it evaluates the published ones once, on a table of times
of one design day, and serves them to the solver by interpolation.

Data flow::

    ship surface (outer boundary faces of the cell graph)
        ├─ Embree: lit fraction per face and sun direction (cached per direction)
        ├─ Embree: view factors F_sky, F_sea, F_ij (reciprocity imposed)
    environment.at(table times)  ──►  tables (n_times, n_faces) of absorbed short-wave,
                                      convection coefficients; scalar series of T_air,
                                      L_down, sea long-wave, SST
    ShipForcing.conditions()      ──►  {patch: SurfaceBalance / Convection} with f(t)

:func:`build_ship_forcing` is a chain of small stages: :func:`surface_properties` (forced
patches, part, medium, optics) → :func:`flow_lengths` (convection lengths per part) →
convection (:func:`wetted_hull_convection`, :func:`air_convection` with a model of
:data:`~shipthermal.environment.convection.CONVECTION_MODELS` chosen by ``convection=``,
the inner films) → the tables.
    ShipForcing.radiative_exchange() ──► (bfaces, A_i ε_i ε_j F_ij) for RadiativeExchange

Physics per outer face i (normal n_i, area A_i, solar absorptivity α_i, long-wave
emissivity ε_i), at time t with sun direction s in the ship frame:

* **absorbed short-wave** [W m-2]
  ``q_i = α_i (E0_i + E1_i)`` with the incident irradiance
  ``E0_i = DNI·max(n_i·s, 0)·lit_i + DHI·F_sky,i + SW_sea↑·F_sea,i``
  (direct beam with traced self-shadowing; isotropic diffuse sky — the "isotropic sky"
  model, Liu & Jordan 1963 — seen through the traced sky view factor; sea-reflected
  short-wave as a Lambertian sea of radiosity SW_sea↑, reciprocity A_sea F_sea→i =
  A_i F_i→sea) and the first diffuse bounce off other ship faces
  ``E1_i = Σ_j F_ij (1 − α_j) E0_j`` (``ship_reflection=True``). The ship's shadow on the
  sea is not subtracted from SW_sea↑.
* **incident long-wave** from the environment ``L_env,i = F_sky,i L↓ + F_sea,i L_sea↑``.
  ``L↓`` is the hemispherical downwelling flux on a horizontal surface; using it with the
  sky view factor treats the sky radiance as isotropic. For vertical faces this is the
  isotropic approximation: the real clear sky is brighter near the horizon, so vertical
  faces receive somewhat more than ``F_sky L↓`` (a few to ~10 % of the sky part).
* **long-wave exchange between ship faces** (grey, diffuse, one absorption): the pair
  :meth:`ShipForcing.radiative_exchange` gives ``R_ij = A_i ε_i ε_j F_ij``. With it, the
  surface balance must only carry the environment share of the face's emission, so
  :meth:`ShipForcing.conditions` (``with_exchange=True``) sets the balance's emissivity to
  ``ε_i (F_sky,i + F_sea,i)`` and its ``longwave_in`` to ``L_env,i / (F_sky,i + F_sea,i)``:
  then ``ε_eff (L_in − σT⁴) + σ Σ_j R_ij (T_j⁴ − T_i⁴) / A_i`` is the face's net
  long-wave, conserving energy between faces exactly (the part (1 − ε_j) of i's emission
  reflected by j is taken to return to i). Without the exchange (``with_exchange=False``) the
  other ship faces a face sees are replaced by black bodies at the air temperature.
* **convection, air faces**: a model of
  :data:`~shipthermal.environment.convection.CONVECTION_MODELS` per part (default
  :data:`~shipthermal.parameters.DEFAULT_CONVECTION_MODEL`, the flat plate turbulent from
  its leading edge, forced + natural convection combined by Churchill 1977, n = 3;
  docs/CONVECTION.md).
  Forced: flat plate at the apparent wind at the face's height (true wind brought from
  10 m to the centroid height by the neutral log profile, then the ship's velocity
  subtracted); flow length = extent of the part's horizontal bounding box along the
  apparent wind. Natural: per face tilt (``n_z``), plate height = the part's height,
  ``A/P`` of the part's horizontal bounding box.
* **convection, wetted faces**: :func:`~shipthermal.environment.convection.h_hull_water`
  to sea water at the SST (ship speed + ``current_speed``, waterline length, draught);
  no sun, no long-wave.
* **inner faces**: convection to the compartment air ``ship.compartment_temperature``
  per part, ISO 6946:2017 Annex C coefficients *including* the linearised interior
  radiation ``ε 4σT_m³`` (interior radiation is not modelled otherwise), or a constant
  ``interior_h``.

Convection coefficients depend on the surface temperature (natural convection, film
properties, the heat-flow direction of ISO 6946). The air faces' coefficient is a forced
part, tabulated, and a law of the surface temperature
(:class:`~shipthermal.conditions.ConvectionLaw`, :meth:`ShipForcing.convection_law`) that
the solver evaluates at the surface temperature it solves for. What the tables still need
of the surface temperature, the air properties of the film (flat-plate models) and the
inner faces' heat-flow direction, comes from a quasi-steady estimate: the root of the face's
energy balance with the heat capacity neglected and conduction through the part's layup to
the compartment air (Newton, 3 steps). A thin plate follows that estimate within a few
kelvin; the film's properties change by ~0.3 % per kelvin.

Tables. Everything that varies per face and time is tabulated at the given ``times``
(seconds after local midnight, one periodic design day) as ``(n_times, n_faces)`` arrays
(float32 by default: 7 significant digits, far below the model's accuracy) and linearly
interpolated between table times, with ``t`` folded modulo 86 400 s, so day k of a
spin-up sees exactly day 0's forcing. Values are exact at the table times.
"""

from __future__ import annotations

import dataclasses
import functools
import time as _time
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np
import pandas as pd
import scipy.sparse as sp

from ._threads import thread_map
from .conditions import LAW_PARAMETERS, Convection, ConvectionLaw, SurfaceBalance, law_h
from .environment import Environment, to_ship_frame
from .environment import convection as conv
from .errors import check_range, require
from .geometry.parts import MAIN_PARTS, part_key, part_value
from .parameters import CONVECTION_ROUGHNESS, LONGWAVE_EMISSIVITY, SOLAR_ABSORPTIVITY
from .raytrace import make_tracer, sun_lit_fraction, symmetrize, view_factors
from .raytrace.viewfactors import ViewFactors
from .units import DAY, SIGMA

__all__ = ["MAX_TABLE_GAP", "INTERIOR_EMISSIVITY", "TracedShip", "ShipForcing", "trace_ship",
           "build_ship_forcing", "part_values", "quasi_steady_surface_temperature",
           "PeriodicTable", "RecordTable", "SurfaceProperties", "surface_properties",
           "FlowLengths", "flow_lengths", "BackSide", "back_side", "wetted_hull_convection",
           "air_convection", "AirConvection", "air_convection_models", "exterior_terms",
           "part_choices"]

INTERIOR_EMISSIVITY = 0.9
"""Hemispherical emissivity of the inner faces for the linearised interior radiation of the
inner film [-]: ISO 6946:2017 Annex C's value for ordinary building surfaces."""

MAX_TABLE_GAP = 3600.0
"""Largest allowed step between table times (with the wrap from the last to the first
time of the next day) [s]: the sun moves 15° per hour, so linear interpolation of lit
fractions across longer gaps would smear the shadows."""

_T_SURFACE_NEWTON_STEPS = 3
"""Newton steps of the quasi-steady surface temperature of the air faces (from the air
temperature). Measured on the frigate summer day at 2 m against 8 steps: the largest
relative change of any tabulated h is 2e-5 after 3 steps, 1e-6 after 4 and 0.7 after 2;
every step is a fifth of the tables' time."""
_WATER_FIXED_POINT_STEPS = 4    # wetted hull: film coefficient and surface temperature
_MIN_DELTA_T_WATER = 0.1  # [K] natural convection in water needs some ΔT; below this it is noise
# Elements per vectorised block of (times × faces). Each block's ~30 elementwise passes
# (convection correlations, quasi-steady estimate) then work on 2 MB arrays instead of
# 16 MB, and the frigate's 144 table rows make 36 blocks for the threads instead of 5.
# Frigate at 0.5 m, 2 threads, the same tables bit for bit: 2.8–3.5 s → 2.2–2.4 s
# (4 rows a block; 1, 2 and 8 rows were slower).
_ROW_CHUNK_ELEMENTS = 1 << 18


# ---------------------------------------------------------------------------------------
# Inputs
# ---------------------------------------------------------------------------------------
def part_values(part_names, defaults: Mapping[str, float], overrides, field_name: str,
                low: float, high: float, low_open: bool = False) -> dict[str, float]:
    """A value per part from per-main-part defaults and user overrides.

    Parameters
    ----------
    part_names : sequence of str
        Parts of the ship (``'superstructure_funnel'`` …).
    defaults : mapping
        Value per main part (``'hull'`` for both hull parts, as in
        :mod:`shipthermal.parameters`).
    overrides : float or mapping or None
        One number for every part, or ``{part: value}`` where a key may be a part, a main
        part (applies to its sub-parts unless they are given too) or ``'hull'`` (both hull
        parts).
    field_name : str
        Name used in error messages (``'absorptivity'``).
    low, high : float
        Allowed range [-].
    low_open : bool
        Exclude ``low``.

    Returns
    -------
    dict
        Part name → value.
    """
    if overrides is None:
        overrides = {}
    if not isinstance(overrides, Mapping):
        check_range(field_name, overrides, low, high, low_open=low_open)
        return {n: float(overrides) for n in part_names}
    allowed = set(part_names) | set(MAIN_PARTS) | {"hull"}
    for key, value in overrides.items():
        require(key in allowed, f"{field_name}[{key!r}]", key,
                f"unknown part; parts are {', '.join(part_names)} (or a main part / 'hull')")
        check_range(f"{field_name}[{key!r}]", value, low, high, low_open=low_open)
    out = {}
    for name in part_names:
        key = part_key(overrides, name)
        out[name] = float(overrides[key] if key is not None
                          else part_value(defaults, name, field_name))
    return out


def _check_times(times) -> np.ndarray:
    """Table times folded into [0, DAY), strictly increasing, covering the day."""
    t = np.atleast_1d(np.asarray(times, dtype=float))
    require(t.ndim == 1 and len(t) >= 2, "times", t,
            "must be a 1-D array of at least two times [s after local midnight]")
    check_range("times", t, 0.0, DAY, "s")
    require(bool(np.all(np.diff(t) > 0)), "times", t, "must be strictly increasing")
    if t[-1] == DAY:
        # 86 400 s is midnight of the next day: the same instant as 0 after folding
        t = t[:-1] if t[0] == 0.0 else np.concatenate([[0.0], t[:-1]])
    gaps = np.diff(np.concatenate([t, [t[0] + DAY]]))
    worst = int(np.argmax(gaps))
    require(len(t) >= 2 and gaps[worst] <= MAX_TABLE_GAP, "times",
            f"{len(t)} times, largest gap {gaps[worst]:.0f} s after t = {t[worst]:.0f} s",
            f"must cover the whole day [0, 86400) s with gaps (also from the last time to "
            f"the first time + 86400 s) of at most {MAX_TABLE_GAP:.0f} s",
            "Pass e.g. times=numpy.arange(0, 86400, 600.0)")
    return t


# ---------------------------------------------------------------------------------------
# Interpolation
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PeriodicTable:
    """Linear interpolation in a periodic table of times.

    Attributes
    ----------
    times : (n,) float
        Strictly increasing times in [0, period) [s].
    period : float
        [s].
    """

    times: np.ndarray
    period: float = DAY

    def weights(self, t: float) -> tuple[int, int, float]:
        """Rows ``i``, ``j`` and weight ``w`` with value(t) = (1 − w) row_i + w row_j.

        ``t`` is folded modulo the period (``np.mod`` of floats is exact, so t and
        t + k·period give the same rows and weight).
        """
        tf = float(np.mod(float(t), self.period))
        tt = self.times
        n = len(tt)
        i = int(np.searchsorted(tt, tf, side="right")) - 1
        if i < 0:  # before the first time: interval from the previous day's last time
            i = n - 1
            tf += self.period
        j = i + 1
        if j < n:
            t_j = tt[j]
        else:
            j = 0
            t_j = tt[0] + self.period
        w = (tf - tt[i]) / (t_j - tt[i])
        return i, j, w

    def __call__(self, table: np.ndarray, t: float):
        """Interpolate ``table`` (n, ...) at ``t`` (float64 result)."""
        i, j, w = _weights_at(self, t)
        if w == 0.0:
            return np.asarray(table[i], dtype=np.float64).copy() if np.ndim(table) > 1 \
                else float(table[i])
        a = np.asarray(table[i], dtype=np.float64)
        b = np.asarray(table[j], dtype=np.float64)
        out = a * (1.0 - w) + b * w
        return out if out.ndim else float(out)


def _weights_at(table, t):
    """``table.weights(t)``, remembered for the last ``t``: the solver asks every table of a
    ship (40 per step) at one time in turn, and a search costs 50 µs (10 % of a weather
    record's steps at 2 m)."""
    last = table.__dict__.get("_last")
    if last is not None and last[0] == t:
        return last[1]
    out = table.weights(t)
    object.__setattr__(table, "_last", (t, out))
    return out


@dataclass(frozen=True)
class RecordTable:
    """Linear interpolation in a table of times over a weather record (not periodic).

    Same interface as :class:`PeriodicTable`; times outside ``[times[0], times[-1]]`` take
    the end rows (the solver never asks for them: the record covers the run).

    Attributes
    ----------
    times : (n,) float
        Strictly increasing times [s after the environment start].
    """

    times: np.ndarray

    @property
    def period(self) -> float:
        """Span of the table [s] (the averaging time of the summaries)."""
        return float(self.times[-1] - self.times[0])

    def weights(self, t: float) -> tuple[int, int, float]:
        tt = self.times
        tf = min(max(float(t), float(tt[0])), float(tt[-1]))
        i = int(np.clip(np.searchsorted(tt, tf, side="right") - 1, 0, len(tt) - 2))
        return i, i + 1, (tf - tt[i]) / (tt[i + 1] - tt[i])

    __call__ = PeriodicTable.__call__


def _check_record_times(times, span: float, window=None) -> np.ndarray:
    """Table times over a weather record: increasing, from 0 to ``span`` (or over the
    ``window`` ``(start, end)`` [s] of it), small gaps."""
    t = np.atleast_1d(np.asarray(times, dtype=float))
    require(t.ndim == 1 and len(t) >= 2 and bool(np.all(np.diff(t) > 0)), "times", t,
            "must be a strictly increasing 1-D array of at least two times [s]")
    if window is None:
        require(t[0] <= 0.0 and t[-1] >= span - 1e-6, "times", f"{t[0]:g} … {t[-1]:g} s",
                f"must cover the weather record, 0 … {span:g} s")
    else:
        lo, hi = (float(x) for x in window)
        require(0.0 <= lo < hi <= span + 1e-6, "window", window,
                f"must be (start, end) within the weather record, 0 … {span:g} s")
        require(t[0] <= lo and t[-1] >= hi - 1e-6, "times", f"{t[0]:g} … {t[-1]:g} s",
                f"must cover the window {lo:g} … {hi:g} s of the weather record")
    require(float(np.max(np.diff(t))) <= MAX_TABLE_GAP, "times", float(np.max(np.diff(t))),
            f"gaps must be at most {MAX_TABLE_GAP:.0f} s")
    return t


# ---------------------------------------------------------------------------------------
# Ray tracing (cached per sun direction)
# ---------------------------------------------------------------------------------------
@dataclass(eq=False)
class TracedShip:
    """The outer surface of a ship with its tracer, view factors and a lit-fraction cache.

    Build it with :func:`trace_ship`. Reusable across environments (sensitivity runs): the
    view factors do not depend on the environment and lit fractions are cached per sun
    direction (same date and place ⇒ same directions, nothing is traced again).

    Attributes
    ----------
    vertices : (N, 3) float [m]
    faces : (K, 3) int
        Outer triangles (right-hand normal points out of the ship).
    receivers : (k,) int
        Faces that receive sun (air faces); lit fractions are stored for these.
    normals, areas, centroids : arrays
        Per face [-], [m²], [m].
    tracer : EmbreeTracer or NumbaTracer
    view : ViewFactors
        Over all K faces (reciprocity imposed); F_faces columns index ``faces``.
    shooters : (m,) int
        Faces that shot view-factor rays (all but those entirely under the sea, which see
        only the sea); ray sample k of ``faces[shooters][i]`` is that of face i of
        :func:`~shipthermal.raytrace.view_factors` called on ``faces[shooters]``.
    samples_per_face : int
    seed : int
    n_rays : dict
        Rays traced so far: ``{'sun': …, 'view': …}`` (view: rays shot; the few that start
        under the sea, from faces touching the waterline, count as sea without tracing).
    seconds : dict
        Wall time spent [s]: ``{'build': …, 'sun': …, 'view': …}``.
    """

    vertices: np.ndarray
    faces: np.ndarray
    receivers: np.ndarray
    normals: np.ndarray
    areas: np.ndarray
    centroids: np.ndarray
    tracer: object
    view: ViewFactors
    samples_per_face: int
    seed: int
    shooters: np.ndarray
    n_rays: dict = field(default_factory=dict)
    seconds: dict = field(default_factory=dict)
    _lit: dict = field(default_factory=dict, repr=False)

    @staticmethod
    def _key(direction) -> tuple:
        # 1e-12 of a unit vector: directions equal to round-off are one cache entry
        return tuple(np.round(np.asarray(direction, dtype=float), 12) + 0.0)

    def lit_fractions(self, sun_dirs, progress=None) -> np.ndarray:
        """Lit fraction of each receiver for each sun direction, traced once per direction.

        Parameters
        ----------
        sun_dirs : (n, 3) array_like
            Unit vectors towards the sun in the ship frame [-]; directions below the horizon
            give 0.
        progress : bool, optional
            tqdm bar for the rays traced.

        Returns
        -------
        (n, k) float32
            Lit fraction [-].
        """
        sun = np.atleast_2d(np.asarray(sun_dirs, dtype=float))
        keys = [self._key(s) for s in sun]
        missing = {}
        for k, s in zip(keys, sun):
            if k not in self._lit and k not in missing and s[2] > 0.0:
                missing[k] = s
        if missing:
            t0 = _time.perf_counter()
            res = sun_lit_fraction(self.tracer, self.vertices, self.faces[self.receivers],
                                   np.array(list(missing.values())),
                                   samples_per_face=self.samples_per_face, seed=self.seed,
                                   sea_level_z=0.0, progress=progress)
            for col, k in enumerate(missing):
                self._lit[k] = res.face[:, col].astype(np.float32)
            self.n_rays["sun"] = self.n_rays.get("sun", 0) + res.n_rays
            self.seconds["sun"] = self.seconds.get("sun", 0.0) + _time.perf_counter() - t0
        out = np.zeros((len(sun), len(self.receivers)), np.float32)
        for row, k in enumerate(keys):
            if k in self._lit:
                out[row] = self._lit[k]
        return out

    def clear_lit_cache(self) -> None:
        """Forget the cached lit fractions (a weather record's window of tables keeps its
        own copy; over a year the cache would hold every sun direction of the record:
        26 000 directions × the receivers in float32, 6 GB for the frigate at 0.5 m).
        A direction asked for again is traced again, to the same values (the sample points
        do not depend on the directions traced with them)."""
        self._lit.clear()


def _merge_triangles(tri: np.ndarray):
    """(K, 3, 3) corner coordinates → shared vertices and faces (exact duplicates merged)."""
    flat = tri.reshape(-1, 3)
    verts, inv = np.unique(flat, axis=0, return_inverse=True)
    return verts, inv.reshape(-1, 3).astype(np.int64)


def trace_ship(vertices, faces, receivers=None, *, samples_per_face: int = 16,
               rays_per_face: int = 256, seed: int = 0, backend: str = "auto",
               progress=None) -> TracedShip:
    """Build the tracer over a ship's outer surface and trace its view factors.

    Parameters
    ----------
    vertices : (N, 3) array_like
        Vertex coordinates in the ship frame (x bow, y port, z up, z = 0 the sea) [m].
    faces : (K, 3) array_like of int
        Outer triangles, normals out of the ship by the right-hand rule.
    receivers : (k,) array_like of int, optional
        Faces that receive sun (default: every face with its centroid above the sea).
    samples_per_face : int
        Sun-ray sample points per face.
    rays_per_face : int
        View-factor rays per face (binomial SE of a fraction F: sqrt(F(1−F)/rays)).
    seed : int
        Seed of every sample; results are a deterministic function of it.
    backend : {'auto', 'embree', 'numba'}
        Tracer (:func:`~shipthermal.raytrace.make_tracer`).
    progress : bool, optional
        tqdm bars.

    Returns
    -------
    TracedShip
    """
    require(int(samples_per_face) >= 1, "samples_per_face", samples_per_face, "must be >= 1")
    require(int(rays_per_face) >= 1, "rays_per_face", rays_per_face, "must be >= 1")
    t0 = _time.perf_counter()
    tracer = make_tracer(vertices, faces, backend=backend)
    v, f = tracer.vertices, tracer.faces
    tri = v[f]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    twice = np.linalg.norm(cross, axis=1)
    normals = cross / np.where(twice > 0, twice, 1.0)[:, None]
    centroids = tri.mean(axis=1)
    if receivers is None:
        receivers = np.flatnonzero(centroids[:, 2] > 0.0)
    receivers = np.asarray(receivers, dtype=np.int64)
    t1 = _time.perf_counter()
    # Faces entirely under the sea see only the sea (F_sea = 1): they shoot no rays; the
    # others shoot against the whole mesh, and their rows are embedded in the square
    # matrix reciprocity needs.
    shooters = np.flatnonzero(tri[:, :, 2].max(axis=1) > 0.0)
    sub = view_factors(tracer, v, f[shooters], rays_per_face=int(rays_per_face),
                       seed=int(seed), sea_level_z=0.0, reciprocity=False, progress=progress)
    n_faces = len(f)
    embed = sp.csr_matrix((np.ones(len(shooters)), (shooters, np.arange(len(shooters)))),
                          shape=(n_faces, len(shooters)))

    def full(values, fill):
        out = np.full(n_faces, fill, dtype=float)
        out[shooters] = values
        return out

    view = symmetrize(ViewFactors(
        F_sky=full(sub.F_sky, 0.0), F_sea=full(sub.F_sea, 1.0),
        F_faces=(embed @ sub.F_faces).tocsr(), se_sky=full(sub.se_sky, 0.0),
        se_sea=full(sub.se_sea, 0.0), rays_per_face=sub.rays_per_face, areas=0.5 * twice))
    t2 = _time.perf_counter()
    n_view = len(shooters) * int(rays_per_face)
    return TracedShip(vertices=v, faces=f, receivers=receivers, normals=normals,
                      areas=0.5 * twice, centroids=centroids, tracer=tracer, view=view,
                      samples_per_face=int(samples_per_face), seed=int(seed),
                      shooters=shooters, n_rays={"sun": 0, "view": n_view},
                      seconds={"build": t1 - t0, "view": t2 - t1, "sun": 0.0})


# ---------------------------------------------------------------------------------------
# Quasi-steady surface temperature (for temperature-dependent coefficients)
# ---------------------------------------------------------------------------------------
def quasi_steady_surface_temperature(absorbed, emissivity, longwave_in, temp_air,
                                     h_of_temperature: Callable, u_back, temp_back,
                                     steps: int = _T_SURFACE_NEWTON_STEPS):
    """Surface temperature balancing the face's fluxes with its heat capacity neglected.

    Solves ``q + ε (L_in − σT⁴) + h(T) (T_air − T) + U (T_back − T) = 0`` by Newton steps
    from ``T = T_air`` with ``h`` frozen in each derivative.

    Parameters
    ----------
    absorbed : array_like
        Absorbed short-wave [W m-2].
    emissivity : array_like
        Effective long-wave emissivity [-].
    longwave_in : array_like
        Incident long-wave irradiance [W m-2].
    temp_air : array_like
        Air (fluid) temperature [K].
    h_of_temperature : callable
        ``h(T_surface)`` [W m-2 K-1], elementwise; first called with ``temp_air`` itself,
        which may have fewer elements than the faces (it broadcasts against them).
    u_back : array_like
        Conductance from the surface to ``temp_back`` (layup + inner film) [W m-2 K-1].
    temp_back : array_like
        Compartment air temperature [K].
    steps : int
        Newton steps.

    Returns
    -------
    numpy.ndarray
        Surface temperature [K].
    """
    q = np.asarray(absorbed, dtype=float)
    eps = np.asarray(emissivity, dtype=float)
    lw = np.asarray(longwave_in, dtype=float)
    ta = np.asarray(temp_air, dtype=float)
    u = np.asarray(u_back, dtype=float)
    tb = np.asarray(temp_back, dtype=float)
    if steps < 1:
        return np.broadcast_to(ta, np.broadcast_shapes(q.shape, ta.shape)).astype(float)
    # f(T) = gain − (ε σ T³ + U) T + h (T_air − T) with the T-independent part
    # gain = q + ε L_in + U T_back; f'(T) = −(4 ε σ T³ + h + U) with h frozen
    gain = q + eps * lw + u * tb
    # the first step starts from T_air in its own shape (one value per table time in the
    # forcing): the same numbers as the broadcast array, at a fraction of the work
    temp = ta
    eps_sigma = eps * SIGMA
    for _ in range(steps):
        h = h_of_temperature(temp)
        emit = eps_sigma * (temp * temp * temp)  # ε σ T³ [W m-2 K-1]
        f = gain - (emit + u) * temp + h * (ta - temp)
        temp = temp + f / (4.0 * emit + h + u)
    return temp


def _threaded(fn, items) -> None:
    """``fn(item)`` for every item, on up to ``numba.get_num_threads()`` threads of the
    process's persistent pool."""
    import numba

    thread_map(fn, items, numba.get_num_threads())


def _row_chunks(n_rows, n_cols):
    step = max(1, _ROW_CHUNK_ELEMENTS // max(n_cols, 1))
    for start in range(0, n_rows, step):
        yield slice(start, min(n_rows, start + step))


# ---------------------------------------------------------------------------------------
# The forcing
# ---------------------------------------------------------------------------------------
@dataclass(eq=False)
class _Patch:
    name: str
    part: str
    kind: str            # 'air' | 'sea' | 'inner'
    bfaces: np.ndarray   # boundary-face indices, graph.patch_faces order
    cols: np.ndarray     # columns into the outer-face arrays (air/sea) or inner arrays


@dataclass(eq=False)
class ShipForcing:
    """Precomputed per-face forcing of a ship for one periodic design day.

    Build with :func:`build_ship_forcing`. All tables are indexed by table time (rows) and
    by face in ``graph.patch_faces(patch)`` order (columns).

    Attributes
    ----------
    times : (n,) float
        Table times, seconds after local midnight in [0, 86400) [s].
    table : PeriodicTable or RecordTable
        The interpolator (t folded modulo 86 400 s for a design day; over the whole
        record, not folded, for non-periodic weather).
    outer_bfaces : (K,) int
        Boundary faces of the outer patches (increasing); ``traced.faces[c]`` is the
        triangle of ``outer_bfaces[c]``.
    traced : TracedShip
        Geometry, tracer, view factors, lit-fraction cache.
    absorptivity, emissivity : dict
        Per part [-].
    alpha, epsilon : (K,) float
        Per outer face [-].
    temp_air, longwave_down, sea_longwave_up, temp_sea, h_water : (n,) float
        Scalar series at the table times [K], [W m-2], [W m-2], [K], [W m-2 K-1].
    convection_model : str or dict
        The exterior convection model of the air faces as chosen (a name, or names per
        part); ``convection_models`` gives the model of every part.
    convection_models : dict
        Part → model name (air parts).
    seconds : dict
        Wall time of each stage [s].
    """

    times: np.ndarray
    table: PeriodicTable | RecordTable
    outer_bfaces: np.ndarray
    outer_part: np.ndarray
    outer_is_air: np.ndarray
    traced: TracedShip
    part_names: tuple
    absorptivity: dict
    emissivity: dict
    alpha: np.ndarray
    epsilon: np.ndarray
    temp_air: np.ndarray
    longwave_down: np.ndarray
    sea_longwave_up: np.ndarray
    temp_sea: np.ndarray
    h_water: np.ndarray
    compartment_temperature: dict
    patches: dict
    _sw: dict          # patch -> (n, m) absorbed short-wave (air patches)
    _h: dict           # patch -> (n, m) convection coefficient: forced part (air patches,
                       # with the law of :meth:`convection_law`), the whole (inner patches)
    _lit: np.ndarray   # (n, k) lit fraction of the receivers
    inner_bfaces: np.ndarray
    unforced_patches: tuple
    sun_ship: np.ndarray
    convection_model: str | dict = conv.DEFAULT_CONVECTION_MODEL
    seconds: dict = field(default_factory=dict)
    _est: dict = field(default_factory=dict)   # patch -> (n, m) quasi-steady T_s (air)
    air_faces: _AirFaces | None = None
    convection_models: dict = field(default_factory=dict)
    convection_roughness: str | dict | None = None

    # ---- geometry and view factors per outer face -----------------------------------
    @property
    def F_sky(self) -> np.ndarray:
        """Sky view factor per outer face [-]."""
        return self.traced.view.F_sky

    @property
    def F_sea(self) -> np.ndarray:
        """Sea view factor per outer face [-]."""
        return self.traced.view.F_sea

    @property
    def F_ship(self) -> np.ndarray:
        """View factor to other ship faces per outer face [-]."""
        return np.asarray(self.traced.view.F_faces.sum(axis=1)).ravel()

    @property
    def n_rays(self) -> dict:
        """Rays traced: sun and view factors."""
        return dict(self.traced.n_rays)

    # ---- time series -----------------------------------------------------------------
    def _column_values(self, tables: dict, t: float, kind: str) -> np.ndarray:
        out = np.zeros(len(self.outer_bfaces))
        for name, p in self.patches.items():
            if p.kind == kind and name in tables:
                out[p.cols] = self.table(tables[name], t)
        return out

    def absorbed_shortwave(self, t: float) -> np.ndarray:
        """Absorbed short-wave of every outer face at ``t`` [W m-2] (0 on wetted faces),
        in ``outer_bfaces`` order."""
        return self._column_values(self._sw, t, "air")

    @functools.cached_property
    def _lit_rows(self) -> np.ndarray:
        """(n,) bool: some face absorbs short-wave at the table time."""
        lit = np.zeros(len(self.times), bool)
        for tab in self._sw.values():
            lit |= np.any(tab > 0.0, axis=1)
        return lit

    def dark(self, start: float, end: float) -> bool:
        """True when no face absorbs short-wave anywhere in ``[start, end]`` [s].

        A table row with short-wave reaches, through the linear interpolation, the open
        interval from the row before it to the row after it (on a periodic table folded
        over the period; the end rows of a record reach beyond it): the interval is dark
        when it meets none of those.
        """
        lit = self._lit_rows
        if not lit.any():
            return True
        tt = self.times
        if isinstance(self.table, PeriodicTable):
            period = self.table.period
            before = np.r_[tt[-1] - period, tt[:-1]][lit]
            after = np.r_[tt[1:], tt[0] + period][lit]
            # the first shift k·period with after + kP > start; it reaches the interval
            # when also before + kP < end
            k = np.floor((start - after) / period) + 1.0
            return not bool(np.any(before + k * period < end))
        before = np.r_[-np.inf, tt[:-1]][lit]
        after = np.r_[tt[1:], np.inf][lit]
        return not bool(np.any((before < end) & (after > start)))

    def lit_fraction(self, t: float) -> np.ndarray:
        """Lit fraction of the sun-receiving faces (``traced.receivers``) at ``t`` [-],
        linear in time between table times."""
        return self.table(self._lit, t)

    # ---- solver conditions -------------------------------------------------------------
    def conditions(self, with_exchange: bool = True) -> dict:
        """Boundary conditions ``{patch: SurfaceBalance | Convection}`` for the solver.

        Parameters
        ----------
        with_exchange : bool
            True when the model also gets :meth:`radiative_exchange` (the surface balance
            then carries only the environment share of each face's emission, see the
            module notes); False to replace the ship faces a face sees by black bodies at
            the air temperature.

        Returns
        -------
        dict
            Values are numbers, per-face arrays or ``f(t)`` returning per-face arrays in
            ``graph.patch_faces(patch)`` order (t in seconds after local midnight of day 0;
            folded modulo 86 400 s).
        """
        out = {}
        tab = self.table
        t_air = self.temp_air
        lw_down = self.longwave_down
        lw_sea = self.sea_longwave_up
        f_ship_all = self.F_ship
        for name, p in self.patches.items():
            if p.kind == "air":
                c = p.cols
                f_sky = self.F_sky[c].copy()
                f_sea = self.F_sea[c].copy()
                eps = self.epsilon[c].copy()
                if with_exchange:
                    env = f_sky + f_sea
                    inv = np.divide(1.0, env, out=np.zeros_like(env), where=env > 0)
                    w_sky, w_sea, w_ship = f_sky * inv, f_sea * inv, None
                    eps_eff = eps * env
                else:
                    w_sky, w_sea, w_ship = f_sky, f_sea, f_ship_all[c].copy()
                    eps_eff = eps

                def longwave_in(t, w_sky=w_sky, w_sea=w_sea, w_ship=w_ship):
                    lw = w_sky * tab(lw_down, t) + w_sea * tab(lw_sea, t)
                    if w_ship is not None:
                        lw = lw + w_ship * (SIGMA * tab(t_air, t) ** 4)
                    return lw

                sw = self._sw[name]
                hh = self._h[name]
                out[name] = SurfaceBalance(
                    absorbed_shortwave=lambda t, sw=sw: tab(sw, t),
                    emissivity=eps_eff,
                    longwave_in=longwave_in,
                    h=lambda t, hh=hh: tab(hh, t),
                    temp_air=lambda t: tab(t_air, t),
                    law=self.convection_law(name))
            elif p.kind == "sea":
                out[name] = Convection(h=lambda t: tab(self.h_water, t),
                                       temp_fluid=lambda t: tab(self.temp_sea, t))
            else:
                hh = self._h[name]
                out[name] = Convection(h=lambda t, hh=hh: tab(hh, t),
                                       temp_fluid=float(self.compartment_temperature[p.part]))
        return out

    def _air_positions(self, patch: str) -> np.ndarray:
        """Positions among the air faces of an air patch's faces."""
        air = self.air_faces
        pos = np.full(len(self.outer_bfaces), -1)
        pos[air.cols] = np.arange(len(air.cols))
        return pos[self.patches[patch].cols]

    def convection_law(self, patch: str) -> ConvectionLaw:
        """The law of the surface temperature of an air patch's coefficient
        (:class:`~shipthermal.conditions.ConvectionLaw`, with the forced part tabulated):
        natural convection of the part's model, its blending and roughness multiplier.
        Flat-plate models take the air properties at the film temperature of the
        quasi-steady estimate at the table times, their law's coefficients interpolated
        between them like every table; the others have none."""
        air = self.air_faces
        pos = self._air_positions(patch)
        model = air.convection.models[air.convection.model_index[pos[0]]]
        nz = air.normals[pos, 2]
        flow = conv.ExteriorFlow(normal_z=nz, wind_speed=0.0,
                                 length_flow=1.0, length_vertical=air.lengths.vertical[pos],
                                 length_horizontal=air.lengths.horizontal[pos],
                                 perimeter_over_area=air.convection.perimeter_over_area[pos],
                                 roughness=air.convection.roughness[pos])
        tab, t_air = self.table, self.temp_air
        if model.film_dependent:
            est = self._est[patch]
            rows: dict = {}

            def at_row(i):
                # the law at a table time's estimate (its film temperature), kept for the
                # few rows the solver is between
                if i not in rows:
                    if len(rows) >= 4:
                        rows.pop(next(iter(rows)))
                    film = 0.5 * (est[i].astype(float) + float(t_air[i]))
                    rows[i] = model.terms(film, flow)[1].natural
                return rows[i]

            def natural(t):
                i, j, w = tab.weights(t)
                return at_row(i) if w == 0.0 else (1.0 - w) * at_row(i) + w * at_row(j)
        else:
            natural = np.ascontiguousarray(model.terms(np.full(len(pos), 300.0), flow)[1].natural)
        law = model.terms(np.full(len(pos), 300.0), flow)[1]
        return ConvectionLaw(natural=natural, blend=np.broadcast_to(law.blend, nz.shape).copy(),
                             multiplier=np.broadcast_to(law.multiplier, nz.shape).copy(),
                             normal_z=nz.copy())

    def convection_coefficient(self, patch: str, t: float, temp_surface=None) -> np.ndarray:
        """The coefficient of an air patch's faces at ``t`` [W m-2 K-1]: the law at
        ``temp_surface`` [K] (default the quasi-steady estimate)."""
        law = self.convection_law(patch)
        nat = law.natural(t) if callable(law.natural) else law.natural
        ts = self.table(self._est[patch], t) if temp_surface is None else temp_surface
        return law_h(self.table(self._h[patch], t),
                     ConvectionLaw(nat, law.blend, law.multiplier, law.normal_z),
                     np.asarray(ts, dtype=float) - self.table(self.temp_air, t))

    def radiative_exchange(self):
        """Face-to-face long-wave exchange for ``RadiativeExchange(bfaces, area_exchange)``.

        Returns
        -------
        bfaces : (k,) int
            Boundary-face indices of the outer faces that see at least one other face.
        area_exchange : scipy.sparse.csr_matrix (k, k)
            Symmetric, entries ``A_i ε_i ε_j F_ij`` [m²] (reciprocity imposed on the traced
            F by :func:`~shipthermal.raytrace.symmetrize`, then averaged with its
            transpose so it is symmetric to the last bit).
        """
        F = self.traced.view.F_faces.tocsr()
        A = self.traced.view.areas
        R = sp.diags(A * self.epsilon) @ F @ sp.diags(self.epsilon)
        R = (0.5 * (R + R.T)).tocsr()
        R.eliminate_zeros()
        deg = np.asarray((R != 0).sum(axis=1)).ravel()
        keep = np.flatnonzero(deg > 0)
        R = R[keep][:, keep].tocsr()
        R.sum_duplicates()
        return self.outer_bfaces[keep].copy(), R

    # ---- reporting ---------------------------------------------------------------------
    def summary(self) -> pd.DataFrame:
        """Forcing per part: area-weighted view factors, solar and convection figures.

        Columns: ``medium``, ``faces``, ``area`` [m²], ``alpha``, ``epsilon`` [-],
        ``F_sky``, ``F_sea``, ``F_ship`` (area means) [-], ``sw_peak_mean`` (largest
        area-mean absorbed short-wave over the day) [W m-2], ``sw_peak_face`` (largest on
        any face) [W m-2], ``sw_time_of_peak`` [h], ``sw_daily_mean`` [W m-2], ``h_mean``
        (time and area mean, outer) [W m-2 K-1], ``h_inner_mean`` [W m-2 K-1],
        ``temp_compartment`` [K]. ``DataFrame.attrs`` holds rays traced and timings.
        """
        A = self.traced.areas
        rows = []
        for part in self.part_names:
            outer = [p for p in self.patches.values()
                     if p.part == part and p.kind in ("air", "sea")]
            inner = [p for p in self.patches.values() if p.part == part and p.kind == "inner"]
            if not outer and not inner:
                continue
            row = dict(part=part, faces=0, area=0.0)
            if outer:
                cols = np.concatenate([p.cols for p in outer])
                a = A[cols]
                area = a.sum()
                row.update(medium=outer[0].kind, faces=len(cols), area=float(area),
                           alpha=self.absorptivity[part], epsilon=self.emissivity[part],
                           F_sky=float(a @ self.F_sky[cols] / area),
                           F_sea=float(a @ self.F_sea[cols] / area),
                           F_ship=float(a @ self.F_ship[cols] / area))
                air = [p for p in outer if p.kind == "air"]
                if air:
                    sw = np.concatenate([self._sw[p.name] for p in air], axis=1).astype(float)
                    hh = np.concatenate([np.stack([self.convection_coefficient(p.name, t)
                                                   for t in self.times]) for p in air], axis=1)
                    ca = np.concatenate([p.cols for p in air])
                    aa = A[ca]
                    mean_t = sw @ aa / aa.sum()
                    k = int(np.argmax(mean_t))
                    row.update(sw_peak_mean=float(mean_t[k]), sw_peak_face=float(sw.max()),
                               sw_time_of_peak=float(self.times[k] / 3600.0),
                               sw_daily_mean=float(self._daily_mean(mean_t)),
                               h_mean=float(self._daily_mean(hh @ aa / aa.sum())))
                else:
                    row.update(sw_peak_mean=0.0, sw_peak_face=0.0, sw_time_of_peak=np.nan,
                               sw_daily_mean=0.0,
                               h_mean=float(self._daily_mean(self.h_water)))
            if inner:
                hh = np.concatenate([self._h[p.name] for p in inner], axis=1).astype(float)
                row["h_inner_mean"] = float(self._daily_mean(hh.mean(axis=1)))
                row["temp_compartment"] = float(self.compartment_temperature[part])
            rows.append(row)
        df = pd.DataFrame(rows).set_index("part")
        df.attrs["n_rays"] = self.n_rays
        df.attrs["seconds"] = dict(self.seconds)
        df.attrs["n_times"] = len(self.times)
        df.attrs["unforced_patches"] = self.unforced_patches
        return df

    def _daily_mean(self, series) -> float:
        """Time mean over the periodic day (or the whole record) of a series at the table
        times (trapezoid)."""
        if isinstance(self.table, RecordTable):
            y = np.asarray(series, dtype=float)
            return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(self.times))
                         / self.table.period)
        t = np.concatenate([self.times, [self.times[0] + DAY]])
        y = np.concatenate([series, series[:1]])
        return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)) / DAY)

    def report(self) -> str:
        """The summary as text (one line per part) with ray counts and timings."""
        df = self.summary()
        with pd.option_context("display.width", 200, "display.max_columns", 30,
                               "display.float_format", "{:.3f}".format):
            text = df.to_string()
        rays = ", ".join(f"{k} {v:,}" for k, v in self.n_rays.items())
        secs = ", ".join(f"{k} {v:.2f} s" for k, v in self.seconds.items())
        return f"{text}\nrays traced: {rays}\ntimings: {secs}"


# ---------------------------------------------------------------------------------------
# The chain: surface properties → flow lengths → convection → tables
# ---------------------------------------------------------------------------------------
@dataclass(eq=False)
class SurfaceProperties:
    """Stage 1: which boundary faces are forced, their part, medium and optics.

    Attributes
    ----------
    part_names : tuple of str
    patch_part : dict
        Patch → (part, ``'outer'`` | ``'inner'``).
    unforced : tuple of str
        Patches that are neither (left to the caller).
    outer_bfaces, inner_bfaces : (K,), (M,) int
        Boundary faces of the outer / inner patches (increasing).
    bpart : (n_bfaces,) int
        Part index of every boundary face (-1: unforced).
    outer_part : (K,) int
    outer_is_air : (K,) bool
    absorptivity, emissivity : dict
        Per part [-].
    alpha, epsilon : (K,) float
        Per outer face [-].
    """

    part_names: tuple
    patch_part: dict
    unforced: tuple
    outer_bfaces: np.ndarray
    inner_bfaces: np.ndarray
    bpart: np.ndarray
    outer_part: np.ndarray
    outer_is_air: np.ndarray
    absorptivity: dict
    emissivity: dict
    alpha: np.ndarray
    epsilon: np.ndarray


def surface_properties(ship, graph, absorptivity=None, emissivity=None) -> SurfaceProperties:
    """Stage 1: forced patches of ``graph`` and the optics of their faces.

    ``absorptivity`` and ``emissivity`` as in :func:`build_ship_forcing` (defaults
    :data:`~shipthermal.parameters.SOLAR_ABSORPTIVITY` and
    :data:`~shipthermal.parameters.LONGWAVE_EMISSIVITY`).
    """
    names = tuple(ship.part_names)
    alpha_part = part_values(names, SOLAR_ABSORPTIVITY, absorptivity, "absorptivity", 0.0, 1.0)
    eps_part = part_values(names, LONGWAVE_EMISSIVITY, emissivity, "emissivity", 0.0, 1.0,
                           low_open=True)
    is_outer = np.zeros(graph.n_bfaces, bool)
    is_inner = np.zeros(graph.n_bfaces, bool)
    patch_part = {}
    unforced = []
    for name in graph.patch_names:
        part, _, side = name.rpartition(":")
        if side not in ("outer", "inner") or not part:
            unforced.append(name)
            continue
        require(part in names, f"graph patch {name!r}", part,
                f"must name a part of the ship ({', '.join(names)})",
                "Build the graph from this ship (geometry.build_ship_mesh(ship))")
        patch_part[name] = (part, side)
        (is_outer if side == "outer" else is_inner)[graph.patch_faces(name)] = True
    outer_bfaces = np.flatnonzero(is_outer)
    require(len(outer_bfaces) > 0, "graph.patch_names", graph.patch_names,
            "must contain '{part}:outer' patches")
    part_index = {n: i for i, n in enumerate(names)}
    bpart = np.full(graph.n_bfaces, -1)
    for name, (part, _) in patch_part.items():
        bpart[graph.patch_faces(name)] = part_index[part]
    outer_part = bpart[outer_bfaces]
    medium = np.array([ship.outer_medium[n] for n in names])
    return SurfaceProperties(
        part_names=names, patch_part=patch_part, unforced=tuple(unforced),
        outer_bfaces=outer_bfaces, inner_bfaces=np.flatnonzero(is_inner), bpart=bpart,
        outer_part=outer_part, outer_is_air=medium[outer_part] == "air",
        absorptivity=alpha_part, emissivity=eps_part,
        alpha=np.array([alpha_part[n] for n in names])[outer_part],
        epsilon=np.array([eps_part[n] for n in names])[outer_part])


def _outer_triangles(graph, outer_bfaces) -> np.ndarray:
    """(K, 3, 3) corners of the outer faces, wound along the graph's outward normals."""
    tri = graph.points[graph.bface_vertices[outer_bfaces]]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", cross, graph.bface_normal[outer_bfaces]) < 0
    tri[flip] = tri[flip][:, ::-1]
    return tri


def _part_boxes(centroids, vertices_of_face, part_of_face, names):
    """Per part: x, y extents of the horizontal bounding box and the height above the
    sea of its faces [m]."""
    out = {}
    for k, name in enumerate(names):
        sel = part_of_face == k
        if not sel.any():
            continue
        pts = vertices_of_face[sel].reshape(-1, 3)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        lo_z = max(lo[2], 0.0) if hi[2] > 0 else lo[2]
        out[name] = (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo_z)
    return out


@dataclass(frozen=True)
class FlowLengths:
    """Stage 2: convection lengths of the air faces [m], one entry per air face.

    Attributes
    ----------
    along_x, along_y : (k,) float
        Extent of the part's horizontal bounding box along the ship's x and y; the forced
        flow length at apparent-wind angle θ off the bow is
        ``along_x |cos θ| + along_y |sin θ|`` (:meth:`along_wind`).
    vertical : (k,) float
        Height of the part above the sea (natural convection, vertical plates).
    horizontal : (k,) float
        ``A/P`` of the part's horizontal bounding box (natural convection, horizontal
        plates).
    """

    along_x: np.ndarray
    along_y: np.ndarray
    vertical: np.ndarray
    horizontal: np.ndarray

    def along_wind(self, off_bow_deg):
        """Forced-flow length [m] at the apparent wind ``off_bow_deg`` [deg] off the bow."""
        ang = np.radians(off_bow_deg)
        return self.along_x * np.abs(np.cos(ang)) + self.along_y * np.abs(np.sin(ang))


def flow_lengths(surface: SurfaceProperties, traced: TracedShip, tri) -> FlowLengths:
    """Stage 2: the lengths of each air face's part; none below the mesh edge length."""
    names = surface.part_names
    air = np.flatnonzero(surface.outer_is_air)
    part_box = _part_boxes(traced.centroids, tri, surface.outer_part, names)
    edge = float(np.sqrt(np.median(traced.areas) * 2.0))  # ≈ the mesh edge length [m]
    lengths = {n: (max(bx, edge), max(by, edge), max(bz, edge),
                   max(bx * by / (2.0 * (bx + by)), edge))
               for n, (bx, by, bz) in part_box.items()}
    lx, ly, lv, lh = (np.array([lengths.get(n, (edge,) * 4)[k] for n in names])
                      [surface.outer_part][air] for k in range(4))
    return FlowLengths(along_x=lx, along_y=ly, vertical=lv, horizontal=lh)


@dataclass(frozen=True)
class BackSide:
    """The path from each outer face through its layup to the compartment air.

    Attributes
    ----------
    temp_compartment : dict and (K,) float
        ``temp_part`` per part, ``temp_face`` per outer face [K].
    h_inner : (K,) float
        Inner film coefficient of the estimate (ISO 6946 horizontal heat flow plus the
        linearised interior radiation, or ``interior_h``) [W m-2 K-1].
    u_back : (K,) float
        Conductance layup + inner film [W m-2 K-1].
    """

    temp_part: dict
    temp_face: np.ndarray
    h_inner: np.ndarray
    u_back: np.ndarray


def back_side(ship, surface: SurfaceProperties, interior_h=None,
              interior_emissivity: float = INTERIOR_EMISSIVITY) -> BackSide:
    """The back-side conductance of every outer face for the quasi-steady estimate."""
    names = surface.part_names
    temp_part = {n: float(ship.compartment_temperature[n]) for n in names}
    temp_face = np.array([temp_part[n] for n in names])[surface.outer_part]
    h_in0 = interior_h if interior_h is not None else \
        conv.ISO6946_INTERIOR_CONVECTION["horizontal"] \
        + interior_emissivity * 4.0 * SIGMA * temp_face ** 3
    r_layup = np.array([ship.layups[n].thermal_resistance for n in names])[surface.outer_part]
    u_back = 1.0 / (r_layup + 1.0 / h_in0)
    return BackSide(temp_part=temp_part, temp_face=temp_face, u_back=u_back,
                    h_inner=np.broadcast_to(np.asarray(h_in0, dtype=float), u_back.shape))


def wetted_hull_convection(ship, environment, state, traced, surface, back: BackSide,
                           current_speed: float):
    """Stage 3a: one coefficient per table time for every wetted face [W m-2 K-1] (same
    length, draught and speed everywhere) and the wetted-surface estimate [K]."""
    sea = np.flatnonzero(~surface.outer_is_air)
    n_t = len(state.temp_sea)
    h_water = np.zeros(n_t)
    temp_wet = np.asarray(state.temp_sea, float).copy()
    if len(sea):
        tsea = np.asarray(state.temp_sea, float)
        tc = np.average(back.temp_face[sea], weights=traced.areas[sea])
        ub = np.average(back.u_back[sea], weights=traced.areas[sea])
        temp_wet = tsea + 1.0
        for _ in range(_WATER_FIXED_POINT_STEPS):
            dt = np.maximum(np.abs(temp_wet - tsea), _MIN_DELTA_T_WATER)
            h_water = conv.h_hull_water(tsea + dt, tsea, environment.ship_speed, ship.length,
                                        ship.draught, current_speed)
            temp_wet = (h_water * tsea + ub * tc) / (h_water + ub)
    return h_water, temp_wet


def _inner_twins(graph, surface: SurfaceProperties, traced) -> np.ndarray:
    """Column of the outer face behind every inner face (its estimate sets ISO 6946's
    heat-flow direction)."""
    inner, outer = surface.inner_bfaces, surface.outer_bfaces
    if not len(inner):
        return np.zeros(0, np.int64)
    n_surface = graph.metadata.get("n_surface_faces") if graph.metadata else None
    if graph.kind == "shell" and n_surface is not None and np.all(inner >= n_surface):
        is_outer = np.zeros(graph.n_bfaces, bool)
        is_outer[outer] = True
        if np.all(is_outer[inner - n_surface]):
            # shell graphs: inner face M + i belongs to surface triangle i = outer face i
            return np.searchsorted(outer, inner - n_surface)
    from scipy.spatial import cKDTree

    return cKDTree(traced.centroids).query(graph.bface_centroid[inner])[1]


@dataclass(frozen=True)
class _AirFaces:
    """What the per-row convection and balance of the air faces need (stage 3b)."""

    cols: np.ndarray          # columns of the air faces among the outer faces
    normals: np.ndarray       # (k, 3) outward normals [-]
    height: np.ndarray        # centroid height above the sea, >= 0 [m]
    share: np.ndarray         # F_sky + F_sea [-]
    inv_share: np.ndarray     # 1 / share (0 where share = 0)
    lengths: FlowLengths
    convection: "AirConvection"


@dataclass(frozen=True)
class AirConvection:
    """Stage 3b's static half: the exterior convection model of every air face.

    Attributes
    ----------
    models : tuple of ConvectionModel
        The models in use.
    model_index : (k,) int
        Model of each air face (index into ``models``).
    roughness : (k,) float
        Roughness multiplier R_f of each face's part [-].
    perimeter_over_area : (k,) float
        P/A of the face's facade or deck [m-1] (TARP): the part's horizontal bounding box for
        a horizontal face (``|n_z| ≥ 0.98``), else the rectangle of the box's extent across
        the face's horizontal normal by the part's height.
    """

    models: tuple
    model_index: np.ndarray
    roughness: np.ndarray
    perimeter_over_area: np.ndarray

    def groups(self):
        """``(model, columns of its faces among the air faces)`` for every model in use."""
        for k, model in enumerate(self.models):
            cols = np.flatnonzero(self.model_index == k)
            if len(cols):
                yield model, cols


def air_convection_models(surface: SurfaceProperties, normals, lengths: FlowLengths,
                          convection, roughness=None) -> AirConvection:
    """Stage 3b's static half: model, roughness and facade P/A of each air face.

    ``convection``: a model name (every part) or ``{part: name}`` (parts, main parts or
    ``'hull'``; the rest :data:`~shipthermal.parameters.DEFAULT_CONVECTION_MODEL`);
    ``roughness``: a class name or ``{part: class}`` of
    :data:`~shipthermal.environment.convection.ROUGHNESS_MULTIPLIERS` (default
    :data:`~shipthermal.parameters.CONVECTION_ROUGHNESS`)."""
    names = surface.part_names
    by_part = part_choices(names, conv.DEFAULT_CONVECTION_MODEL, convection, "convection.model",
                           lambda v, f: conv.convection_model(v, f).name)
    rough_part = part_choices(names, None, roughness, "convection.roughness",
                              lambda v, f: (conv.roughness_multiplier(v, f), v)[1],
                              defaults=CONVECTION_ROUGHNESS)
    used = tuple(dict.fromkeys(by_part[n] for n in names))
    models = tuple(conv.convection_model(m) for m in used)
    air_part = surface.outer_part[surface.outer_is_air]
    model_of_part = np.array([used.index(by_part[n]) for n in names])
    rf_of_part = np.array([conv.ROUGHNESS_MULTIPLIERS[rough_part[n]] for n in names])
    nz = normals[:, 2]
    horizontal = np.abs(nz) >= conv.WINDWARD_HORIZONTAL_COS
    hor = np.hypot(normals[:, 0], normals[:, 1])
    nx = np.divide(np.abs(normals[:, 0]), hor, out=np.zeros_like(hor), where=hor > 0)
    ny = np.divide(np.abs(normals[:, 1]), hor, out=np.ones_like(hor), where=hor > 0)
    width = lengths.along_x * ny + lengths.along_y * nx
    facade = 2.0 * (width + lengths.vertical) / (width * lengths.vertical)
    p_over_a = np.where(horizontal, 1.0 / lengths.horizontal, facade)
    return AirConvection(models=models, model_index=model_of_part[air_part],
                         roughness=rf_of_part[air_part], perimeter_over_area=p_over_a)


def part_choices(part_names, default, overrides, field_name: str, check,
                 defaults: Mapping | None = None) -> dict:
    """A name per part from a default (or per-main-part ``defaults``) and user overrides
    (one name, or ``{part: name}`` with parts, main parts or ``'hull'``); every name passes
    ``check(name, field) -> name``."""
    if overrides is None:
        overrides = {}
    if not isinstance(overrides, Mapping):
        one = check(overrides, field_name)
        return {n: one for n in part_names}
    allowed = set(part_names) | set(MAIN_PARTS) | {"hull"}
    for key, value in overrides.items():
        require(key in allowed, f"{field_name}[{key!r}]", key,
                f"unknown part; parts are {', '.join(part_names)} (or a main part / 'hull')")
        check(value, f"{field_name}[{key!r}]")
    out = {}
    for name in part_names:
        key = part_key(overrides, name)
        if key is not None:
            out[name] = overrides[key]
        else:
            out[name] = default if defaults is None else part_value(defaults, name, field_name)
    return out


def _exterior_flow(air: _AirFaces, state, rows, environment) -> conv.ExteriorFlow:
    """The wind of the air faces at the table rows: the apparent wind at face height, its
    flow length over the part and which faces face it."""
    speed_true = conv.wind_speed_at_height(state.wind_speed[rows, None], air.height[None, :])
    speed_rel, _, off_bow = conv.relative_wind(speed_true, state.wind_direction[rows, None],
                                               environment.ship_speed,
                                               environment.ship_heading)
    ang = np.radians(off_bow)
    # where the apparent wind comes from, in the ship frame (x bow, y port; off the bow
    # clockwise = towards starboard)
    wind_from = np.stack([np.cos(ang), -np.sin(ang)], axis=-1)
    windward = conv.is_windward(air.normals[None, :, :], wind_from)
    c = air.convection
    return conv.ExteriorFlow(normal_z=air.normals[:, 2], wind_speed=speed_rel,
                             length_flow=air.lengths.along_wind(off_bow),
                             length_vertical=air.lengths.vertical,
                             length_horizontal=air.lengths.horizontal, windward=windward,
                             perimeter_over_area=c.perimeter_over_area,
                             roughness=c.roughness)


def _flow_columns(flow: conv.ExteriorFlow, cols) -> conv.ExteriorFlow:
    """The flow of some air faces (columns)."""
    def sub(v):
        v = np.asarray(v)
        return v[..., cols] if v.ndim else v
    return conv.ExteriorFlow(**{f.name: sub(getattr(flow, f.name))
                                for f in dataclasses.fields(flow)})


def exterior_terms(air: _AirFaces, flow: conv.ExteriorFlow, temp_film, law: bool = True):
    """Forced part [W m-2 K-1] and :class:`~shipthermal.conditions.ConvectionLaw` arrays of
    every air face (each face by its part's model) at the film temperature ``temp_film``
    [K] (shape of ``flow``'s time rows × faces); ``law=False``: the forced part only."""
    temp_film = np.asarray(temp_film, dtype=float)
    shape = np.broadcast_shapes(temp_film.shape, np.shape(flow.wind_speed))
    hf = np.empty(shape)
    if not law:
        for model, cols in air.convection.groups():
            film = np.broadcast_to(temp_film, shape)[..., cols]
            hf[..., cols] = model.terms(film, _flow_columns(flow, cols), law=False)[0]
        return hf, None
    nat = np.empty(shape + (2, len(LAW_PARAMETERS)))
    blend = np.empty(shape)
    mult = np.empty(shape)
    for model, cols in air.convection.groups():
        sub = _flow_columns(flow, cols)
        film = np.broadcast_to(temp_film, shape)[..., cols]
        h_g, law = model.terms(film, sub)
        hf[..., cols] = h_g
        nat[..., cols, :, :] = np.broadcast_to(law.natural, shape[:-1] + (len(cols), 2,
                                                                          len(LAW_PARAMETERS)))
        blend[..., cols] = law.blend
        mult[..., cols] = law.multiplier
    return hf, ConvectionLaw(nat, blend, mult, air.normals[:, 2])


def air_convection(air: _AirFaces, state, rows, environment, absorbed, eps_env, u_back,
                   temp_back, F_sky, F_sea):
    """Stage 3b: convection of the air faces at the table rows ``rows``.

    The apparent wind at face height (true wind brought from 10 m by the neutral log
    profile, then the ship's velocity subtracted) over the flow length of the part along
    it; each face's model (:class:`AirConvection`) evaluated at the quasi-steady surface
    estimate (:func:`quasi_steady_surface_temperature`).

    Returns
    -------
    h_forced : (n_rows, k) float
        The forced part at the estimate's film temperature [W m-2 K-1]: what the solver
        takes with each model's law of the surface temperature.
    temp_surface : (n_rows, k) float
        The estimate [K].
    """
    ta = state.temp_air[rows, None]
    flow = _exterior_flow(air, state, rows, environment)
    lw_env = (F_sky[air.cols] * state.longwave_down[rows, None]
              + F_sea[air.cols] * state.sea_longwave_up[rows, None])

    def h_of(temp_s):
        shape = np.broadcast_shapes(np.shape(temp_s), np.shape(flow.wind_speed))
        out = np.empty(shape)
        temp_s = np.broadcast_to(temp_s, shape)
        for model, cols in air.convection.groups():
            out[..., cols] = model.h_direct(temp_s[..., cols], ta, _flow_columns(flow, cols))
        return out

    ts = quasi_steady_surface_temperature(absorbed, eps_env, lw_env * air.inv_share, ta, h_of,
                                          u_back, temp_back)
    hf, _ = exterior_terms(air, flow, 0.5 * (ts + ta), law=False)
    return hf, ts


def _absorbed_shortwave(state, rows, sun, lit, air: _AirFaces, traced, alpha, n_out,
                        ship_reflection):
    """Absorbed short-wave of every outer face at the table rows [W m-2]: direct (traced
    shadows), diffuse sky, sea-reflected, and the first diffuse bounce off the ship."""
    a_ = air.cols
    F_sky, F_sea = traced.view.F_sky, traced.view.F_sea
    incident = np.zeros((rows.stop - rows.start, n_out))
    cos_inc = np.clip(sun[rows] @ air.normals.T, 0.0, None)
    incident[:, a_] = (state.dni[rows, None] * cos_inc * lit[rows]
                       + state.dhi[rows, None] * F_sky[a_]
                       + state.sea_shortwave_up[rows, None] * F_sea[a_])
    if ship_reflection:
        # first diffuse bounce off the ship: E1 = F (1 − α) E0
        bounce = (traced.view.F_faces @ ((1.0 - alpha)[:, None] * incident.T)).T
        incident[:, a_] += bounce[:, a_]
    return alpha * incident


@dataclass(frozen=True)
class _InnerFaces:
    """The inner faces: their outer twin, compartment air and upward normal component."""

    twin: np.ndarray        # column of the outer face behind each inner face
    temp_room: np.ndarray   # compartment air [K]
    normal_z: np.ndarray    # upward component of the normal into the room [-]


def _inner_faces(graph, surface: SurfaceProperties, traced, back: BackSide) -> _InnerFaces:
    inner = surface.inner_bfaces
    part = surface.bpart[inner]
    temp_room = np.array([back.temp_part[n] for n in surface.part_names])[part] \
        if len(part) else np.zeros(0)
    return _InnerFaces(twin=_inner_twins(graph, surface, traced), temp_room=temp_room,
                       normal_z=graph.bface_normal[inner, 2])


def _tables(patches: dict, n_times: int, dtype):
    """Empty tables: absorbed short-wave and the surface estimate of the air patches,
    coefficients of the air (forced part) and inner patches, ``(n_times, faces of the
    patch)``."""
    sw = {n: np.empty((n_times, len(p.cols)), dtype) for n, p in patches.items()
          if p.kind == "air"}
    est = {n: np.empty((n_times, len(p.cols)), dtype) for n, p in patches.items()
           if p.kind == "air"}
    h = {n: np.empty((n_times, len(p.cols)), dtype) for n, p in patches.items()
         if p.kind in ("air", "inner")}
    return sw, h, est


def _store_rows(rows, patches, sw_tab, h_tab, est_tab, absorbed, h_air, ts_air, h_inner,
                air: _AirFaces):
    """Copy one block of rows into the per-patch tables (columns in patch-face order)."""
    air_pos = np.full(absorbed.shape[1], -1)
    air_pos[air.cols] = np.arange(len(air.cols))
    for name, p in patches.items():
        if p.kind == "air":
            sw_tab[name][rows] = absorbed[:, p.cols]
            h_tab[name][rows] = h_air[:, air_pos[p.cols]]
            est_tab[name][rows] = ts_air[:, air_pos[p.cols]]
        elif p.kind == "inner":
            h_tab[name][rows] = h_inner[:, p.cols]


def _patches(graph, surface: SurfaceProperties, ship) -> dict:
    out = {}
    for name, (part, side) in surface.patch_part.items():
        bf = graph.patch_faces(name)
        if side == "outer":
            cols = np.searchsorted(surface.outer_bfaces, bf)
            kind = "air" if ship.outer_medium[part] == "air" else "sea"
        else:
            cols = np.searchsorted(surface.inner_bfaces, bf)
            kind = "inner"
        out[name] = _Patch(name=name, part=part, kind=kind, bfaces=bf, cols=cols)
    return out


def _table_times(environment, times, window=None):
    w = environment.weather
    if w.periodic:
        require(window is None, "window", window, "is for weather records only (a periodic "
                "day's table covers its day)")
        require(abs(w.period - DAY) < 1e-6, "environment.weather.period", w.period,
                "must be 86400 s (one day)")
        times = _check_times(np.arange(0.0, DAY, 600.0) if times is None else times)
        return times, PeriodicTable(times)
    # a weather record: one table over the whole record or over a window of it (t = seconds
    # after its start)
    span = (w.time[-1] - environment.start).total_seconds()
    times = _check_record_times(np.arange(0.0, span + 1.0, 600.0) if times is None
                                else times, span, window)
    return times, RecordTable(times)


def build_ship_forcing(ship, environment: Environment, graph, *, times=None,
                       samples_per_face: int = 16, rays_per_face: int = 256, seed: int = 0,
                       absorptivity=None, emissivity=None, backend: str = "auto",
                       progress=None, ship_reflection: bool = True,
                       interior_h: float | None = None,
                       interior_emissivity: float = INTERIOR_EMISSIVITY,
                       current_speed: float = 0.0, traced: TracedShip | None = None,
                       dtype=np.float32,
                       convection: str | conv.ConvectionModel | Mapping =
                       conv.DEFAULT_CONVECTION_MODEL,
                       roughness: str | Mapping | None = None, window=None) -> ShipForcing:
    """Precompute the boundary forcing of every outer and inner face for a design day.

    Parameters
    ----------
    ship : shipthermal.geometry.ShipGeometry
        Parts, compartment temperatures, layups, length and draught (the graph's surface
        is what is traced; the ship supplies the per-part data).
    environment : shipthermal.environment.Environment
        With periodic (design-day, 24 h) weather, or a weather record (the tables then
        span the record, t in seconds after its start); its heading sets the ship frame.
    graph : shipthermal.mesh.CellGraph
        The solver's graph (shell, tet or mixed) with patches ``'{part}:outer'`` and
        ``'{part}:inner'``; other patches are left unforced (listed in
        ``ShipForcing.unforced_patches``).
    times : array_like, optional
        Table times in [0, 86400] [s after local midnight], strictly increasing, gaps ≤
        :data:`MAX_TABLE_GAP` (wrap included). Default every 600 s. The solver may ask for
        any t in between (linear interpolation) or on later days (folded).
    samples_per_face : int
        Sun-ray sample points per face (lit fraction resolution 1/samples_per_face).
    rays_per_face : int
        View-factor rays per face.
    seed : int
        Seed of all ray samples.
    absorptivity : float or mapping, optional
        Solar absorptivity per part [-] in [0, 1]; defaults
        :data:`shipthermal.parameters.SOLAR_ABSORPTIVITY`.
    emissivity : float or mapping, optional
        Long-wave emissivity per part [-] in (0, 1]; defaults
        :data:`shipthermal.parameters.LONGWAVE_EMISSIVITY`.
    backend : {'auto', 'embree', 'numba'}
        Ray tracer.
    progress : bool, optional
        tqdm bars for the ray tracing (None: only on a terminal).
    ship_reflection : bool
        Add the first diffuse bounce of short-wave off other ship faces.
    interior_h : float, optional
        Constant inner-face coefficient [W m-2 K-1]; default ISO 6946 Annex C with the
        linearised interior radiation.
    interior_emissivity : float
        Emissivity of inner faces for that radiative part [-].
    current_speed : float
        Water speed past the hull besides the ship's own (tidal current) [m s-1].
    traced : TracedShip, optional
        Reuse the tracer, view factors and lit-fraction cache of an earlier build of the
        same graph (sensitivity runs); ``samples_per_face``, ``rays_per_face``, ``seed``
        and ``backend`` are then those of ``traced``.
    dtype : numpy dtype
        Storage of the per-face tables (float32 halves the memory; float64 for tests).
    convection : str or ConvectionModel or mapping
        Exterior convection model of the air faces, a name of
        :data:`~shipthermal.environment.convection.CONVECTION_MODELS` (default
        :data:`~shipthermal.parameters.DEFAULT_CONVECTION_MODEL`), or ``{part: name}``
        (parts, main parts or ``'hull'``; others take the default). Each model's
        temperature dependence is evaluated by the solver at the solved surface
        temperature (:meth:`ShipForcing.conditions`).
    roughness : str or mapping, optional
        Roughness class per part of the DOE-2 / TARP roughness multiplier
        (:data:`~shipthermal.environment.convection.ROUGHNESS_MULTIPLIERS`; default
        :data:`~shipthermal.parameters.CONVECTION_ROUGHNESS`).
    window : (float, float), optional
        Weather records only: ``(start, end)`` [s after the record's start], the part of
        the record ``times`` must cover (default: the whole record). A long record is run
        window by window (:func:`shipthermal.diurnal.run_record`); each row of a window's
        tables equals the whole record's row at the same time.

    Returns
    -------
    ShipForcing
    """
    t_start = _time.perf_counter()
    require(isinstance(environment, Environment), "environment", type(environment).__name__,
            "must be a shipthermal.environment.Environment")
    if isinstance(convection, conv.ConvectionModel):
        convection = convection.name
    times, table = _table_times(environment, times, window)
    check_range("current_speed", current_speed, 0.0, 10.0, "m/s")
    check_range("interior_emissivity", interior_emissivity, 0.0, 1.0)
    if interior_h is not None:
        check_range("interior_h", interior_h, 0.0, 1000.0, "W m-2 K-1", low_open=True)

    surface = surface_properties(ship, graph, absorptivity, emissivity)
    outer_bfaces, inner_bfaces = surface.outer_bfaces, surface.inner_bfaces
    tri = _outer_triangles(graph, outer_bfaces)
    traced = _trace(traced, tri, surface, samples_per_face, rays_per_face, seed, backend,
                    progress)
    t_traced = _time.perf_counter()

    # environment at the table times, sun in the ship frame
    state = environment.at(times)
    sun = to_ship_frame(state.sun_vector, environment.ship_heading)
    n_t, n_out = len(times), len(outer_bfaces)
    a_ = np.flatnonzero(surface.outer_is_air)
    s_ = np.flatnonzero(~surface.outer_is_air)
    require(np.array_equal(traced.receivers, a_), "traced.receivers", None,
            "must be the air faces of this ship")
    lit = traced.lit_fractions(np.where((state.zenith < 90.0)[:, None], sun, [0.0, 0.0, -1.0]),
                               progress=progress)
    t_sun = _time.perf_counter()

    F_sky, F_sea = traced.view.F_sky, traced.view.F_sea
    share = (F_sky + F_sea)[a_]
    lengths = flow_lengths(surface, traced, tri)
    normals_air = traced.normals[a_]
    air = _AirFaces(cols=a_, normals=normals_air,
                    height=np.maximum(traced.centroids[a_, 2], 0.0), share=share,
                    inv_share=np.divide(1.0, share, out=np.zeros_like(share), where=share > 0),
                    lengths=lengths,
                    convection=air_convection_models(surface, normals_air, lengths, convection,
                                                     roughness))
    back = back_side(ship, surface, interior_h, interior_emissivity)
    h_water, temp_wet = wetted_hull_convection(ship, environment, state, traced, surface,
                                               back, current_speed)
    inner = _inner_faces(graph, surface, traced, back)
    patches = _patches(graph, surface, ship)
    sw_tab, h_tab, est_tab = _tables(patches, n_t, dtype)

    def block(rows):
        absorbed = _absorbed_shortwave(state, rows, sun, lit, air, traced, surface.alpha,
                                       n_out, ship_reflection)
        h_air, ts_air = air_convection(air, state, rows, environment, absorbed[:, a_],
                                       surface.epsilon[a_] * share, back.u_back[a_],
                                       back.temp_face[a_], F_sky, F_sea)
        h_inner = None
        if len(inner_bfaces):
            temp_surface = np.empty((rows.stop - rows.start, n_out))
            temp_surface[:, a_] = ts_air
            temp_surface[:, s_] = temp_wet[rows, None]
            h_inner = _inner_convection(temp_surface, inner, back, interior_h,
                                        interior_emissivity)
        _store_rows(rows, patches, sw_tab, h_tab, est_tab, absorbed, h_air, ts_air, h_inner,
                    air)

    # Blocks of rows are independent and write disjoint rows; their array arithmetic
    # releases the GIL, so they run on the process's thread budget (numba's, which a sweep
    # pins to one per case).
    _threaded(block, list(_row_chunks(n_t, n_out)))
    t_end = _time.perf_counter()

    seconds = {"trace_setup_and_view_factors": t_traced - t_start,
               "sun_rays": t_sun - t_traced, "tables": t_end - t_sun,
               "total": t_end - t_start}
    return ShipForcing(
        times=times, table=table, outer_bfaces=outer_bfaces,
        outer_part=surface.outer_part, outer_is_air=surface.outer_is_air, traced=traced,
        part_names=surface.part_names, absorptivity=surface.absorptivity,
        emissivity=surface.emissivity, alpha=surface.alpha, epsilon=surface.epsilon,
        temp_air=np.asarray(state.temp_air, float),
        longwave_down=np.asarray(state.longwave_down, float),
        sea_longwave_up=np.asarray(state.sea_longwave_up, float),
        temp_sea=np.asarray(state.temp_sea, float), h_water=np.asarray(h_water, float),
        compartment_temperature=back.temp_part, patches=patches, _sw=sw_tab, _h=h_tab,
        _lit=lit.astype(dtype), inner_bfaces=inner_bfaces,
        unforced_patches=surface.unforced, sun_ship=sun, convection_model=convection,
        seconds=seconds, _est=est_tab, air_faces=air,
        convection_models={surface.part_names[p]: air.convection.models[m].name for p, m in
                           zip(surface.outer_part[a_], air.convection.model_index)},
        convection_roughness=roughness)


def _trace(traced, tri, surface, samples_per_face, rays_per_face, seed, backend, progress):
    """The tracer of the outer surface: a new one, or ``traced`` checked against it."""
    if traced is None:
        verts, faces = _merge_triangles(tri)
        return trace_ship(verts, faces, np.flatnonzero(surface.outer_is_air),
                          samples_per_face=samples_per_face, rays_per_face=rays_per_face,
                          seed=seed, backend=backend, progress=progress)
    n = len(surface.outer_bfaces)
    require(isinstance(traced, TracedShip) and len(traced.faces) == n,
            "traced", type(traced).__name__,
            f"must be the TracedShip of this graph's {n} outer faces")
    require(np.allclose(traced.centroids, tri.mean(axis=1)), "traced", "centroids",
            "must come from the same graph (outer face centroids differ)")
    return traced


def _inner_convection(temp_surface, inner: _InnerFaces, back: BackSide, interior_h,
                      interior_emissivity):
    """Stage 3c: inner-face coefficients at the table rows of ``temp_surface`` (the outer
    estimate per outer face) [W m-2 K-1]."""
    twin, temp_room = inner.twin, inner.temp_room
    if interior_h is not None:
        return np.full((len(temp_surface), len(twin)), float(interior_h))
    # inner-face temperature of the same quasi-steady estimate: the drop from the outer
    # surface to the room splits between the layup and the inner film, T_in − T_room =
    # (T_out − T_room) U / h_in0. ISO 6946 uses its sign (heat-flow direction) and T_m for
    # the small radiative part.
    temp_inner = temp_room + (temp_surface[:, twin] - temp_room) * \
        (back.u_back[twin] / back.h_inner[twin])
    return conv.h_interior_iso6946(temp_inner, temp_room[None, :], inner.normal_z[None, :],
                                   include_radiation=True, emissivity=interior_emissivity)
