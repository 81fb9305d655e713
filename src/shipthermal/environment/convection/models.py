"""The exterior convection models by name (:data:`CONVECTION_MODELS`): for each, a forced
part and a law of the surface temperature (:class:`shipthermal.conditions.ConvectionLaw`)
that the solver evaluates, and the same coefficient straight from the correlation
functions.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from shipthermal.conditions import LAW_PARAMETERS, ConvectionLaw, law_h
from shipthermal.errors import InputError
from shipthermal.parameters import CONVECTION_MODEL_SOURCES

from .envelope import (_mowitt_forced, _sparrow_forced, ASHRAE_VERTICAL, MCADAMS,
                       MOWITT_NATURAL, WALTON_STABLE, WALTON_UNSTABLE, h_exterior_doe2,
                       h_exterior_mowitt, h_exterior_tarp)
from .fluids import G, air_properties
from .plates import h_exterior_air, h_forced


@dataclass(frozen=True)
class ExteriorFlow:
    """What an exterior convection model needs to know of each face and its wind.

    Arrays broadcast against each other (rows: times, columns: faces).

    Attributes
    ----------
    normal_z : array_like
        Upward component of the outward unit normal [-].
    wind_speed : array_like
        Wind speed at the face (apparent wind at its height) [m s-1].
    length_flow : array_like
        Length of the part along the wind [m] (flat-plate models).
    length_vertical, length_horizontal : array_like
        Natural-convection lengths: height; area / perimeter [m] (flat-plate models).
    windward : array_like of bool
        The face faces the wind (:func:`is_windward`) (DOE-2, TARP, MoWiTT).
    perimeter_over_area : array_like
        Of the facade or deck the face belongs to [m-1] (TARP).
    roughness : array_like
        Roughness multiplier R_f [-] (:data:`ROUGHNESS_MULTIPLIERS`; DOE-2, TARP).
    """

    normal_z: object
    wind_speed: object
    length_flow: object = 1.0
    length_vertical: object = 1.0
    length_horizontal: object = 1.0
    windward: object = True
    perimeter_over_area: object = 1.0
    roughness: object = 1.0


def _natural(shape) -> np.ndarray:
    return np.zeros(tuple(shape) + (2, len(LAW_PARAMETERS)))


def _walton_law(normal_z, shape) -> np.ndarray:
    """Walton's natural convection as a law (both sides ``c |ΔT|^1/3``)."""
    c = np.broadcast_to(np.abs(np.asarray(normal_z, dtype=float)), shape)
    nat = _natural(shape)
    nat[..., 0, 0] = np.where(c == 0.0, ASHRAE_VERTICAL,
                              WALTON_UNSTABLE[0] / (WALTON_UNSTABLE[1] - c))
    nat[..., 1, 0] = np.where(c == 0.0, ASHRAE_VERTICAL, WALTON_STABLE[0] / (WALTON_STABLE[1] + c))
    nat[..., :, 1] = 1.0 / 3.0
    return nat


def _flat_plate_law(temp_film, normal_z, length_vertical, length_horizontal, shape,
                    pressure=101325.0) -> np.ndarray:
    """:func:`h_natural` as a law at the film temperature's properties: the Churchill–Chu
    vertical term (g cos θ over the height), Lloyd & Moran's two unstable branches and the
    stable 0.52 Ra^1/5 (g sin θ over A/P), and Walton's stable floor."""
    props = air_properties(np.broadcast_to(np.asarray(temp_film, dtype=float), shape), pressure)
    nz = np.broadcast_to(np.clip(np.asarray(normal_z, dtype=float), -1.0, 1.0), shape)
    sin_t = np.abs(nz)
    cos_t = np.sqrt(np.clip(1.0 - nz ** 2, 0.0, 1.0))
    lv = np.broadcast_to(np.asarray(length_vertical, dtype=float), shape)
    lh = np.broadcast_to(np.asarray(length_horizontal, dtype=float), shape)
    k = props.conductivity
    # g β / (ν α): Ra per (K m³)
    ra_unit = G * props.expansion * props.density ** 2 * props.heat_capacity / (
        props.viscosity * props.conductivity)
    ra_h = ra_unit * sin_t * lh ** 3            # Ra_h / |ΔT|
    ra_v = ra_unit * cos_t * lv ** 3            # Ra_v / |ΔT|
    nat = _natural(shape)
    kh = k / lh
    nat[..., 0, 0] = 0.54 * kh * ra_h ** 0.25
    nat[..., 0, 1] = 0.25
    nat[..., 0, 2] = 0.15 * kh * np.cbrt(ra_h)
    nat[..., 0, 3] = 1.0 / 3.0
    nat[..., 1, 0] = 0.52 * kh * ra_h ** 0.2
    nat[..., 1, 1] = 0.2
    nat[..., 1, 2] = np.where(sin_t > 0.0, WALTON_STABLE[0] / (WALTON_STABLE[1] + sin_t), 0.0)
    nat[..., 1, 3] = 1.0 / 3.0
    # Churchill & Chu: h = (k/L)(0.825 + 0.387 Ra^(1/6)/ψ)² = (a + b |ΔT|^(1/6))²
    vertical = cos_t > 1e-12
    x = 0.492 / props.prandtl
    psi = (1.0 + x ** (9.0 / 16.0)) ** (8.0 / 27.0)
    root = np.sqrt(k / lv)
    a = np.where(vertical, 0.825 * root, 0.0)
    b = np.where(vertical, root * 0.387 / psi * ra_v ** (1.0 / 6.0), 0.0)
    nat[..., :, 4] = a[..., None]
    nat[..., :, 5] = b[..., None]
    return nat


def _natural_flat_plate(temp_film, flow: ExteriorFlow) -> np.ndarray:
    """The natural part of the flat-plate models' law (:func:`_flat_plate_law` for a flow)."""
    return _flat_plate_law(temp_film, flow.normal_z, flow.length_vertical,
                           flow.length_horizontal, _flow_shape(temp_film, flow))


def _terms_flat_plate(boundary_layer):
    def terms(temp_film, flow: ExteriorFlow, law: bool = True):
        shape = _flow_shape(temp_film, flow)
        props = air_properties(np.broadcast_to(np.asarray(temp_film, dtype=float), shape))
        hf = h_forced(flow.wind_speed, flow.length_flow, props, boundary_layer)
        if not law:
            return np.broadcast_to(hf, shape), None
        nat = _natural_flat_plate(temp_film, flow)
        return np.broadcast_to(hf, shape), ConvectionLaw(nat, 3.0, 1.0, _bz(flow.normal_z, shape))
    return terms


def _flow_shape(temp_film, flow: ExteriorFlow) -> tuple:
    return np.broadcast_shapes(np.shape(temp_film), *(np.shape(getattr(flow, f.name))
                                                      for f in dataclasses.fields(flow)))


def _bz(value, shape) -> np.ndarray:
    return np.broadcast_to(np.asarray(value, dtype=float), shape)


def _terms_doe2(temp_film, flow: ExteriorFlow, law: bool = True):
    shape = _flow_shape(temp_film, flow)
    hf = _mowitt_forced(flow.wind_speed, flow.windward)
    if not law:
        return _bz(hf, shape), None
    return (_bz(hf, shape), ConvectionLaw(_walton_law(flow.normal_z, shape), 2.0,
                                          _bz(flow.roughness, shape), _bz(flow.normal_z, shape)))


def _terms_mowitt(temp_film, flow: ExteriorFlow, law: bool = True):
    shape = _flow_shape(temp_film, flow)
    if not law:
        return _bz(_mowitt_forced(flow.wind_speed, flow.windward), shape), None
    nat = _natural(shape)
    nat[..., :, 0] = MOWITT_NATURAL
    nat[..., :, 1] = 1.0 / 3.0
    hf = _mowitt_forced(flow.wind_speed, flow.windward)
    return _bz(hf, shape), ConvectionLaw(nat, 2.0, 1.0, _bz(flow.normal_z, shape))


def _terms_tarp(temp_film, flow: ExteriorFlow, law: bool = True):
    shape = _flow_shape(temp_film, flow)
    hf = _sparrow_forced(flow.wind_speed, flow.perimeter_over_area, flow.windward,
                         flow.roughness)
    if not law:
        return _bz(hf, shape), None
    return (_bz(hf, shape), ConvectionLaw(_walton_law(flow.normal_z, shape), 1.0, 1.0,
                                          _bz(flow.normal_z, shape)))


def _terms_linear(a, b):
    def terms(temp_film, flow: ExteriorFlow, law: bool = True):
        shape = _flow_shape(temp_film, flow)
        v = np.abs(np.asarray(flow.wind_speed, dtype=float))
        return _bz(a + b * v, shape), (ConvectionLaw(_natural(shape), 1.0, 1.0, 0.0) if law
                                       else None)
    return terms


@dataclass(frozen=True)
class ConvectionModel:
    """An exterior (air-side) convection correlation.

    Attributes
    ----------
    name : str
        Key in :data:`CONVECTION_MODELS`.
    terms : callable
        ``terms(temp_film [K], flow: ExteriorFlow, law=True) -> (h_forced [W m-2 K-1],
        ConvectionLaw or None)``: the forced part and the law of the surface temperature
        (:class:`shipthermal.conditions.ConvectionLaw`) that the solver evaluates at the
        solved surface temperature; air properties (flat-plate models) at ``temp_film``.
    source : str
        Where the correlation comes from.
    validity : str
        Range in which its source supports it.
    film_dependent : bool
        Its terms depend on ``temp_film`` (air properties).
    direct : callable, optional
        ``direct(temp_surface, temp_air, flow) -> h``: the same coefficient from closed-form
        correlation functions (a faster path for the forcing's quasi-steady estimate); without
        it :meth:`h_direct` is :meth:`h`, the law the solver evaluates.
    natural : callable, optional
        ``natural(temp_film, flow) -> (..., 2, 6)``: the law's natural part alone (see
        :meth:`natural_law`); without it that part comes from ``terms``.

    Notes
    -----
    A new correlation is its name, source and validity in
    :data:`shipthermal.parameters.CONVECTION_MODEL_SOURCES` (what a scenario may choose,
    readable without loading the physics) and its ``terms`` in this module's
    ``_MODEL_TERMS``; nothing else changes.
    """

    name: str
    terms: Callable
    source: str
    validity: str
    film_dependent: bool = False
    direct: Callable | None = None
    natural: Callable | None = None

    def natural_law(self, temp_film, flow: ExteriorFlow) -> np.ndarray:
        """The natural part of the law alone, ``terms(temp_film, flow)[1].natural`` without
        the forced part (what the solver's steps ask of a film-dependent model at every
        table time; half the cost)."""
        if self.natural is None:
            return self.terms(temp_film, flow)[1].natural
        return self.natural(temp_film, flow)

    def h_direct(self, temp_surface, temp_air, flow: ExteriorFlow):
        """The same coefficient from the correlation functions of this package (numpy, no
        law arrays: the fast path of the forcing's quasi-steady estimate) [W m-2 K-1]."""
        if self.direct is None:
            return self.h(temp_surface, temp_air, flow)
        return self.direct(np.asarray(temp_surface, dtype=float),
                           np.asarray(temp_air, dtype=float), flow)

    def h(self, temp_surface, temp_air, flow: ExteriorFlow):
        """The coefficient at a surface temperature [W m-2 K-1] (film temperature
        ``(T_s + T_air)/2``), through :func:`shipthermal.conditions.law_h`: the function the
        solver evaluates."""
        ts = np.asarray(temp_surface, dtype=float)
        ta = np.asarray(temp_air, dtype=float)
        hf, law = self.terms(0.5 * (ts + ta), flow)
        return law_h(hf, law, ts - ta)


def _direct_flat_plate(boundary_layer):
    def h(ts, ta, f: ExteriorFlow):
        return h_exterior_air(ts, ta, f.normal_z, f.wind_speed, f.length_flow,
                              f.length_vertical, f.length_horizontal,
                              boundary_layer=boundary_layer)
    return h


def _direct_linear(a, b):
    def h(ts, ta, f: ExteriorFlow):
        shape = np.broadcast_shapes(ts.shape, ta.shape, np.shape(f.wind_speed))
        return np.broadcast_to(a + b * np.abs(np.asarray(f.wind_speed, dtype=float)),
                               shape).astype(float)
    return h


_MODEL_TERMS = {
    "flat_plate_mixed": (_terms_flat_plate("mixed"), True, _direct_flat_plate("mixed"),
                         _natural_flat_plate),
    "flat_plate_turbulent": (_terms_flat_plate("turbulent"), True,
                             _direct_flat_plate("turbulent"), _natural_flat_plate),
    "doe2": (_terms_doe2, False, lambda ts, ta, f: h_exterior_doe2(
        ts, ta, f.normal_z, f.wind_speed, f.windward, f.roughness), None),
    "tarp": (_terms_tarp, False, lambda ts, ta, f: h_exterior_tarp(
        ts, ta, f.normal_z, f.wind_speed, f.perimeter_over_area, f.windward, f.roughness),
             None),
    "mowitt": (_terms_mowitt, False, lambda ts, ta, f: h_exterior_mowitt(
        ts, ta, f.wind_speed, f.windward), None),
    "mcadams": (_terms_linear(*MCADAMS), False, _direct_linear(*MCADAMS), None),
    "iso6946": (_terms_linear(4.0, 4.0), False, _direct_linear(4.0, 4.0), None)}
"""Per model: (terms, film_dependent, direct, natural) of :class:`ConvectionModel`."""

CONVECTION_MODELS: dict[str, ConvectionModel] = {
    name: ConvectionModel(name, _MODEL_TERMS[name][0], **info,
                          film_dependent=_MODEL_TERMS[name][1], direct=_MODEL_TERMS[name][2],
                          natural=_MODEL_TERMS[name][3])
    for name, info in CONVECTION_MODEL_SOURCES.items()}
"""Exterior convection models by name (pvlib-style named set); names, sources and validity
from :data:`shipthermal.parameters.CONVECTION_MODEL_SOURCES`."""


def convection_model(name: str | ConvectionModel, field: str = "convection.model"
                     ) -> ConvectionModel:
    """Look a model up in :data:`CONVECTION_MODELS` (a :class:`ConvectionModel` passes
    through); an unknown name raises :class:`InputError` listing the known ones."""
    if isinstance(name, ConvectionModel):
        return name
    if name not in CONVECTION_MODELS:
        raise InputError(field, name, f"must be one of {', '.join(CONVECTION_MODELS)}",
                         "See shipthermal.environment.convection.CONVECTION_MODELS for the "
                         "sources and validity of each")
    return CONVECTION_MODELS[name]
