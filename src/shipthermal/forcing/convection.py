"""Convection as the forcing applies it: the coefficient of every forced face at the table
times.

* air faces: each part's exterior model
  (:data:`~shipthermal.environment.convection.CONVECTION_MODELS`) in the apparent wind at
  face height over the part's flow length (:func:`air_faces`, :func:`air_convection`); the
  tables keep the forced part, the solver evaluates the law of the surface temperature
  (:func:`exterior_terms`);
* wetted faces: the hull in sea water at the SST (:func:`wetted_hull_convection`);
* inner faces: ISO 6946 to the compartment air, heat-flow direction from the outer
  estimate, or a constant coefficient (:func:`inner_convection`).

What the coefficients need of the surface temperature (film properties, the inner faces'
heat-flow direction) comes from a quasi-steady estimate
(:func:`quasi_steady_surface_temperature`): the root of the face's energy balance with
the heat capacity neglected and conduction through the part's layup to the compartment air
(:func:`back_side`), by 3 Newton steps (``_T_SURFACE_NEWTON_STEPS``) from the air
temperature.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.spatial import cKDTree

from ..conditions import LAW_PARAMETERS, ConvectionLaw
from ..environment import convection as conv
from ..parameters import CONVECTION_ROUGHNESS
from ..units import SIGMA
from .surface import SurfaceProperties, part_choices
from .tracing import TracedShip

INTERIOR_EMISSIVITY = 0.9
"""Hemispherical emissivity of the inner faces for the linearised interior radiation of the
inner film [-]: ISO 6946:2017 Annex C's value for ordinary building surfaces."""


_T_SURFACE_NEWTON_STEPS = 3
"""Newton steps of the quasi-steady surface temperature of the air faces (from the air
temperature). Measured on the frigate summer day at 2 m against 8 steps: the largest
relative change of any tabulated h is 2e-5 after 3 steps, 1e-6 after 4 and 0.7 after 2;
every step is a fifth of the tables' time."""
_WATER_FIXED_POINT_STEPS = 4    # wetted hull: film coefficient and surface temperature
_MIN_DELTA_T_WATER = 0.1  # [K] natural convection in water needs some ΔT; below this it is noise


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
    return cKDTree(traced.centroids).query(graph.bface_centroid[inner])[1]


@dataclass(frozen=True)
class AirFaces:
    """What the per-row convection and balance of the air faces need (stage 3b); built by
    :func:`air_faces`."""

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
        """``(model, columns of its faces among the air faces)`` for every model in use;
        the columns are ``slice(None)`` when one model has every air face (the usual case:
        the tables then take views of their time-by-face arrays, not copies, which were 8 %
        of the frigate's tables at 0.5 m)."""
        for k, model in enumerate(self.models):
            cols = np.flatnonzero(self.model_index == k)
            if len(cols) == len(self.model_index):
                yield model, slice(None)
            elif len(cols):
                yield model, cols


def air_convection_models(surface: SurfaceProperties, normals, lengths: FlowLengths,
                          convection, roughness=None) -> AirConvection:
    """Stage 3b's static half: model, roughness and facade P/A of each air face.

    ``convection``: a model (a name of
    :data:`~shipthermal.environment.convection.CONVECTION_MODELS` or a user's
    :class:`~shipthermal.environment.convection.ConvectionModel`) for every part, or
    ``{part: model}`` (parts, main parts or ``'hull'``; the rest
    :data:`~shipthermal.parameters.DEFAULT_CONVECTION_MODEL`);
    ``roughness``: a class name or ``{part: class}`` of
    :data:`~shipthermal.environment.convection.ROUGHNESS_MULTIPLIERS` (default
    :data:`~shipthermal.parameters.CONVECTION_ROUGHNESS`)."""
    names = surface.part_names
    by_part = part_choices(names, conv.DEFAULT_CONVECTION_MODEL, convection, "convection.model",
                           conv.convection_model)
    rough_part = part_choices(names, None, roughness, "convection.roughness",
                              lambda v, f: (conv.roughness_multiplier(v, f), v)[1],
                              defaults=CONVECTION_ROUGHNESS)
    model_by_part = {n: conv.convection_model(by_part[n]) for n in names}
    models = tuple(dict.fromkeys(model_by_part[n] for n in names))
    air_part = surface.outer_part[surface.outer_is_air]
    model_of_part = np.array([models.index(model_by_part[n]) for n in names])
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


def air_faces(surface: SurfaceProperties, traced: TracedShip, tri, convection,
              roughness=None) -> AirFaces:
    """The air faces of the outer surface: normals, height, environment view share, flow
    lengths (``tri``: the outer triangles) and convection models (``convection``,
    ``roughness`` as in :func:`air_convection_models`)."""
    a_ = np.flatnonzero(surface.outer_is_air)
    F_sky, F_sea = traced.view.F_sky, traced.view.F_sea
    share = (F_sky + F_sea)[a_]
    lengths = flow_lengths(surface, traced, tri)
    normals_air = traced.normals[a_]
    return AirFaces(cols=a_, normals=normals_air,
                    height=np.maximum(traced.centroids[a_, 2], 0.0), share=share,
                    inv_share=np.divide(1.0, share, out=np.zeros_like(share), where=share > 0),
                    lengths=lengths,
                    convection=air_convection_models(surface, normals_air, lengths, convection,
                                                     roughness))



def _exterior_flow(air: AirFaces, state, rows, environment) -> conv.ExteriorFlow:
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


def exterior_terms(air: AirFaces, flow: conv.ExteriorFlow, temp_film, law: bool = True):
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
        nat[..., cols, :, :] = np.broadcast_to(law.natural, shape[:-1] + (film.shape[-1], 2,
                                                                          len(LAW_PARAMETERS)))
        blend[..., cols] = law.blend
        mult[..., cols] = law.multiplier
    return hf, ConvectionLaw(nat, blend, mult, air.normals[:, 2])


def air_convection(air: AirFaces, state, rows, environment, absorbed, eps_env, u_back,
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


@dataclass(frozen=True)
class InnerFaces:
    """The inner faces: their outer twin, compartment air and upward normal component;
    built by :func:`inner_faces`."""

    twin: np.ndarray        # column of the outer face behind each inner face
    temp_room: np.ndarray   # compartment air [K]
    normal_z: np.ndarray    # upward component of the normal into the room [-]


def inner_faces(graph, surface: SurfaceProperties, traced, back: BackSide) -> InnerFaces:
    """The inner faces of ``graph`` with the outer face behind each and its compartment."""
    inner = surface.inner_bfaces
    part = surface.bpart[inner]
    temp_room = np.array([back.temp_part[n] for n in surface.part_names])[part] \
        if len(part) else np.zeros(0)
    return InnerFaces(twin=_inner_twins(graph, surface, traced), temp_room=temp_room,
                       normal_z=graph.bface_normal[inner, 2])


def inner_convection(temp_surface, inner: InnerFaces, back: BackSide, interior_h,
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
