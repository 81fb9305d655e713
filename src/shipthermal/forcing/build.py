"""The build of a ship's forcing: :func:`build_ship_forcing` in named steps — input checks
and table times, surface properties, ray tracing, the environment and the sun at the table
times, the air, wetted and inner faces, then the tables, filled block of rows by block of
rows on the process's threads — with its choices in :class:`ForcingSettings`.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Mapping

import numba
import numpy as np

from .._threads import thread_map
from ..environment import Environment, to_ship_frame
from ..environment import convection as conv
from ..errors import check_range, require
from ..parameters import SUN_SAMPLES_PER_FACE, VIEW_RAYS_PER_FACE
from .convection import (INTERIOR_EMISSIVITY, AirFaces, BackSide, InnerFaces, air_convection,
                         air_faces, back_side, inner_convection, inner_faces,
                         wetted_hull_convection)
from .ship_forcing import ShipForcing
from .shortwave import absorbed_shortwave
from .surface import SurfaceProperties, forced_patches, surface_properties
from .tables import table_times
from .tracing import TracedShip, outer_surface_tracer, outer_triangles

# Elements per vectorised block of (times × faces). Each block's ~30 elementwise passes
# (convection correlations, quasi-steady estimate) then work on 2 MB arrays instead of
# 16 MB, and the frigate's 144 table rows make 36 blocks for the threads instead of 5.
# Frigate at 0.5 m, 2 threads, the same tables bit for bit: 2.8–3.5 s → 2.2–2.4 s
# (4 rows a block; 1, 2 and 8 rows were slower).
_ROW_CHUNK_ELEMENTS = 1 << 18


def _threaded(fn, items) -> None:
    """``fn(item)`` for every item, on up to ``numba.get_num_threads()`` threads of the
    process's persistent pool."""
    thread_map(fn, items, numba.get_num_threads())


def _row_chunks(n_rows, n_cols):
    """Slices of the table rows, about ``_ROW_CHUNK_ELEMENTS`` (rows × columns) each."""
    step = max(1, _ROW_CHUNK_ELEMENTS // max(n_cols, 1))
    for start in range(0, n_rows, step):
        yield slice(start, min(n_rows, start + step))


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
                air: AirFaces):
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


@dataclass(frozen=True)
class ForcingSettings:
    """What a forcing build is asked to do besides its ship, weather, graph and times.

    Attributes
    ----------
    samples_per_face : int
        Sun-ray sample points per face (lit fraction resolution 1/samples_per_face).
    rays_per_face : int
        View-factor rays per face.
    seed : int
        Seed of all ray samples.
    backend : {'auto', 'embree', 'numba'}
        Ray tracer.
    absorptivity : float or mapping, optional
        Solar absorptivity per part [-] in [0, 1]; defaults
        :data:`shipthermal.parameters.SOLAR_ABSORPTIVITY`.
    emissivity : float or mapping, optional
        Long-wave emissivity per part [-] in (0, 1]; defaults
        :data:`shipthermal.parameters.LONGWAVE_EMISSIVITY`.
    ship_reflection : bool
        Add the first diffuse bounce of short-wave off other ship faces.
    interior_h : float, optional
        Constant inner-face coefficient [W m-2 K-1]; default ISO 6946 Annex C with the
        linearised interior radiation.
    interior_emissivity : float
        Emissivity of inner faces for that radiative part [-].
    current_speed : float
        Water speed past the hull besides the ship's own (tidal current) [m s-1].
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

    The values are checked by :func:`build_ship_forcing`, each where the build first uses
    it.
    """

    samples_per_face: int = SUN_SAMPLES_PER_FACE
    rays_per_face: int = VIEW_RAYS_PER_FACE
    seed: int = 0
    backend: str = "auto"
    absorptivity: float | Mapping | None = None
    emissivity: float | Mapping | None = None
    ship_reflection: bool = True
    interior_h: float | None = None
    interior_emissivity: float = INTERIOR_EMISSIVITY
    current_speed: float = 0.0
    dtype: object = np.float32
    convection: str | conv.ConvectionModel | Mapping = conv.DEFAULT_CONVECTION_MODEL
    roughness: str | Mapping | None = None


def build_ship_forcing(ship, environment: Environment, graph,
                       settings: ForcingSettings | None = None, *, times=None,
                       traced: TracedShip | None = None, progress=None,
                       window=None) -> ShipForcing:
    """Precompute the boundary forcing of every outer and inner face for a design day (or
    a weather record).

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
    settings : ForcingSettings, optional
        Ray tracing, optics, convection and storage (default ``ForcingSettings()``).
    times : array_like, optional
        Table times in [0, 86400] [s after local midnight], strictly increasing, gaps ≤
        :data:`~shipthermal.forcing.tables.MAX_TABLE_GAP` (wrap included). Default every
        600 s. The solver may ask for any t in between (linear interpolation) or on later
        days (folded).
    traced : TracedShip, optional
        Reuse the tracer, view factors and lit-fraction cache of an earlier build of the
        same graph (sensitivity runs); ``samples_per_face``, ``rays_per_face``, ``seed``
        and ``backend`` of ``settings`` are then those of ``traced``.
    progress : bool, optional
        tqdm bars for the ray tracing (None: only on a terminal).
    window : (float, float), optional
        Weather records only: ``(start, end)`` [s after the record's start], the part of
        the record ``times`` must cover (default: the whole record). A long record is run
        window by window (:func:`shipthermal.diurnal.run_record`); each row of a window's
        tables equals the whole record's row at the same time.

    Returns
    -------
    ShipForcing
    """
    s = settings or ForcingSettings()
    t_start = _time.perf_counter()
    convection, times, table = _checked_inputs(environment, s, times, window)
    surface = surface_properties(ship, graph, s.absorptivity, s.emissivity)
    tri = outer_triangles(graph, surface.outer_bfaces)
    traced = outer_surface_tracer(traced, tri, surface, s.samples_per_face, s.rays_per_face,
                                  s.seed, s.backend, progress)
    t_traced = _time.perf_counter()

    state, sun, lit = _sun_at_table_times(environment, times, traced, surface, progress)
    t_sun = _time.perf_counter()

    air = air_faces(surface, traced, tri, convection, s.roughness)
    back = back_side(ship, surface, s.interior_h, s.interior_emissivity)
    h_water, temp_wet = wetted_hull_convection(ship, environment, state, traced, surface,
                                               back, s.current_speed)
    rows = _RowInputs(environment=environment, state=state, sun=sun, lit=lit, traced=traced,
                      surface=surface, air=air, back=back, temp_wet=temp_wet,
                      inner=inner_faces(graph, surface, traced, back))
    patches = forced_patches(graph, surface, ship)
    sw_tab, h_tab, est_tab = _fill_tables(rows, patches, len(times), s)
    t_end = _time.perf_counter()

    seconds = {"trace_setup_and_view_factors": t_traced - t_start,
               "sun_rays": t_sun - t_traced, "tables": t_end - t_sun,
               "total": t_end - t_start}
    a_ = air.cols
    return ShipForcing(
        times=times, table=table, outer_bfaces=surface.outer_bfaces,
        outer_part=surface.outer_part, outer_is_air=surface.outer_is_air, traced=traced,
        part_names=surface.part_names, absorptivity=surface.absorptivity,
        emissivity=surface.emissivity, alpha=surface.alpha, epsilon=surface.epsilon,
        temp_air=np.asarray(state.temp_air, float),
        longwave_down=np.asarray(state.longwave_down, float),
        sea_longwave_up=np.asarray(state.sea_longwave_up, float),
        temp_sea=np.asarray(state.temp_sea, float), h_water=np.asarray(h_water, float),
        compartment_temperature=back.temp_part, patches=patches, _sw=sw_tab, _h=h_tab,
        _lit=lit.astype(s.dtype), inner_bfaces=surface.inner_bfaces,
        unforced_patches=surface.unforced, sun_ship=sun, convection_model=convection,
        seconds=seconds, _est=est_tab, air_faces=air,
        convection_models={surface.part_names[p]: air.convection.models[m].name for p, m in
                           zip(surface.outer_part[a_], air.convection.model_index)},
        convection_roughness=s.roughness)


def _checked_inputs(environment, s: ForcingSettings, times, window):
    """The checks of the inputs that come before any work, in this order; the convection
    choice by name, the table times and their interpolator."""
    require(isinstance(environment, Environment), "environment", type(environment).__name__,
            "must be a shipthermal.environment.Environment")
    convection = s.convection
    if isinstance(convection, conv.ConvectionModel):
        convection = convection.name
    times, table = table_times(environment, times, window)
    check_range("current_speed", s.current_speed, 0.0, 10.0, "m/s")
    check_range("interior_emissivity", s.interior_emissivity, 0.0, 1.0)
    if s.interior_h is not None:
        check_range("interior_h", s.interior_h, 0.0, 1000.0, "W m-2 K-1", low_open=True)
    return convection, times, table


def _sun_at_table_times(environment, times, traced: TracedShip, surface: SurfaceProperties,
                        progress):
    """The environment at the table times, the sun in the ship frame and the lit fraction of
    the sun-receiving (air) faces (traced for the directions not in the cache)."""
    state = environment.at(times)
    sun = to_ship_frame(state.sun_vector, environment.ship_heading)
    require(np.array_equal(traced.receivers, np.flatnonzero(surface.outer_is_air)),
            "traced.receivers", None, "must be the air faces of this ship")
    lit = traced.lit_fractions(np.where((state.zenith < 90.0)[:, None], sun, [0.0, 0.0, -1.0]),
                               progress=progress)
    return state, sun, lit


@dataclass(frozen=True)
class _RowInputs:
    """What the tables' rows are computed from."""

    environment: Environment
    state: object              # the environment at the table times
    sun: np.ndarray            # (n, 3) unit vector to the sun, ship frame
    lit: np.ndarray            # (n, k) lit fraction of the receivers
    traced: TracedShip
    surface: SurfaceProperties
    air: AirFaces
    back: BackSide
    temp_wet: np.ndarray       # (n,) wetted-surface estimate [K]
    inner: InnerFaces


def _table_rows(r: _RowInputs, rows: slice, s: ForcingSettings):
    """Absorbed short-wave of the outer faces, forced part and surface estimate of the air
    faces and coefficients of the inner faces (None without inner faces) at ``rows``."""
    surface, back, air = r.surface, r.back, r.air
    a_ = air.cols
    s_ = np.flatnonzero(~surface.outer_is_air)
    n_out = len(surface.outer_bfaces)
    F_sky, F_sea = r.traced.view.F_sky, r.traced.view.F_sea
    absorbed = absorbed_shortwave(r.state, rows, r.sun, r.lit, air, r.traced, surface.alpha,
                                  n_out, s.ship_reflection)
    h_air, ts_air = air_convection(air, r.state, rows, r.environment, absorbed[:, a_],
                                   surface.epsilon[a_] * air.share, back.u_back[a_],
                                   back.temp_face[a_], F_sky, F_sea)
    h_inner = None
    if len(surface.inner_bfaces):
        temp_surface = np.empty((rows.stop - rows.start, n_out))
        temp_surface[:, a_] = ts_air
        temp_surface[:, s_] = r.temp_wet[rows, None]
        h_inner = inner_convection(temp_surface, r.inner, back, s.interior_h,
                                   s.interior_emissivity)
    return absorbed, h_air, ts_air, h_inner


def _fill_tables(r: _RowInputs, patches: dict, n_times: int, s: ForcingSettings):
    """The per-patch tables (absorbed short-wave, coefficients, surface estimates), filled
    block of rows by block of rows."""
    sw_tab, h_tab, est_tab = _tables(patches, n_times, s.dtype)

    def block(rows):
        _store_rows(rows, patches, sw_tab, h_tab, est_tab, *_table_rows(r, rows, s), r.air)

    # Blocks of rows are independent and write disjoint rows; their array arithmetic
    # releases the GIL, so they run on the process's thread budget (numba's, which a sweep
    # pins to one per case).
    _threaded(block, list(_row_chunks(n_times, len(r.surface.outer_bfaces))))
    return sw_tab, h_tab, est_tab
