"""Surface energy balance of land background pixels over layered columns.

Each land pixel is a one-dimensional column (layers of :mod:`.surface_classes`, surface
first) whose top face carries the surface energy balance

    S_abs + ε L↓ − ε σ T_s⁴ − h (T_s − T_air) − λE(T_s) − G = 0,

and whose bottom is a fixed deep-ground temperature (``'deep'``) or an indoor air space reached
through a film coefficient (``'room'``). Many columns are advanced together on a uniform time
grid.

Pieces, each a function:

* :func:`column_mesh` — finite volumes refined toward the surface (geometric growth), layer
  interfaces on cell faces, harmonic-mean (series) face conductances;
* :func:`shortwave_on_tilted`, :func:`sky_view_factor`, :func:`longwave_incoming` — the
  forcing of a tilted pixel (pvlib's transposition; isotropic sky view (1 + cos s) / 2);
* :func:`convection_correlation`, :func:`convection_aerodynamic`, :func:`convection_linear` —
  convective coefficients ``h(temp_surface, temp_air, wind_speed)``;
* :func:`saturation_vapour_pressure`, :func:`latent_heat_flux` — Penman–Monteith resistance
  form;
* :func:`solve_surface_energy` — the time loop (periodic design day or record with a periodic
  spin-up on its first day), with a numba kernel (:func:`_step_numba`: columns in parallel,
  Thomas algorithm per column) and a plain numpy reference (:func:`_step_reference`) doing the
  same arithmetic.

Time discretisation: θ-scheme, backward Euler by default (θ = 1). The surface node has no
heat capacity, so its balance is an algebraic constraint enforced at the new time level;
backward Euler is L-stable, so the stiff modes of the thin top cells (time constants of
seconds against 300 s steps) are damped instead of ringing as under Crank–Nicolson (θ = ½,
A- but not L-stable), which is offered for the second-order accuracy when the time step
resolves the top cells. Within a step the surface balance is solved by Newton on the Schur
complement of the column (T⁴ and the latent term at the new temperature, never lagged); the
convective coefficient is evaluated with the surface temperature at the start of the step.
"""

from __future__ import annotations

import types
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pvlib
from numba import njit, prange

from shipthermal.environment.convection import ExteriorFlow, convection_model
from shipthermal.errors import InputError, check_finite, check_range, require
from shipthermal.parameters import DEFAULT_CONVECTION_MODEL
from shipthermal.units import DAY, SIGMA, ZERO_CELSIUS

from .surface_classes import SURFACE_CLASSES, Layer, SurfaceClass, surface_class

__all__ = [
    "LATENT_HEAT_VAPORISATION",
    "SPECIFIC_HEAT_AIR",
    "GAS_CONSTANT_DRY_AIR",
    "VON_KARMAN",
    "GROUND_CONVECTION_LENGTHS",
    "SCHEMES",
    "ColumnMesh",
    "column_mesh",
    "Columns",
    "build_columns",
    "SurfaceForcing",
    "SurfaceEnergyResult",
    "saturation_vapour_pressure",
    "saturation_vapour_pressure_slope",
    "air_heat_capacity",
    "psychrometric_constant",
    "latent_heat_flux",
    "convection_correlation",
    "convection_aerodynamic",
    "convection_linear",
    "sky_view_factor",
    "shortwave_on_tilted",
    "longwave_incoming",
    "forcing_from_environment",
    "solve_surface_energy",
]

# ---------------------------------------------------------------------------------------------
# Constants (FAO-56 [2] of :mod:`.surface_classes`, so that its eq. 3 is reproduced exactly)
# ---------------------------------------------------------------------------------------------
LATENT_HEAT_VAPORISATION = 2.45e6
"""λ [J kg-1]: FAO-56 eq. 8 (value at about 20 °C; it falls by 2.4 % from 0 to 40 °C)."""
SPECIFIC_HEAT_AIR = 1013.0
"""c_p of moist air [J kg-1 K-1]: FAO-56 eq. 8."""
GAS_CONSTANT_DRY_AIR = 287.0
"""R [J kg-1 K-1]: FAO-56 eq. 3 notes (ρ_a = P / (1.01 T R), 1.01 T the virtual temperature)."""
RATIO_MOLECULAR_WEIGHT = 0.622
"""ε = M_w / M_d [-]: FAO-56 eq. 8."""
VON_KARMAN = 0.41
"""k [-]: FAO-56 eq. 4."""
_ES0, _ES_A, _ES_B = 610.8, 17.27, 237.3  # FAO-56 eq. 11 (Tetens): e° = 610.8 exp(a T/(T + b)) Pa

GROUND_CONVECTION_LENGTHS = {"length_flow": 30.0, "length_vertical": 30.0,
                             "length_horizontal": 7.5}
"""Characteristic lengths [m] of a ground pixel in the flat-plate correlations: the flow length
and the along-slope height are the 30 m of a Landsat pixel (ASSUMPTION: the scale the model
represents; with h ∝ L^-0.2 in turbulent forced flow, 10 m or 100 m change h by +25 % / −21 %),
the horizontal natural-convection length is area / perimeter of that square, 30/4 m (DERIVED);
above Ra ≈ 1e7 the horizontal coefficient does not depend on it (0.15 Ra^1/3)."""

SCHEMES = {"backward_euler": 1.0, "crank_nicolson": 0.5}
"""Time schemes by name → θ."""

_NEWTON_TOL = 1.0e-7
"""Newton stops after an update below this [K]: the error left is about |F''/(2F')| δ² with
|F''/(2F')| < 1e-3 K-1 here (F' is dominated by the top half cell's conductance, ~1e3
W m-2 K-1; F'' by 12 εσT² and the latent term's e°''), i.e. below 1e-17 K: round-off."""
_NEWTON_MAX = 60


# ---------------------------------------------------------------------------------------------
# Mesh
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ColumnMesh:
    """Finite-volume mesh of one column (cells from the surface down).

    Attributes
    ----------
    thickness : numpy.ndarray
        (m,) cell thickness [m].
    depth : numpy.ndarray
        (m,) depth of the cell centres [m].
    capacity : numpy.ndarray
        (m,) heat capacity per area ρ c Δz [J m-2 K-1].
    conductance : numpy.ndarray
        (m + 1,) face conductances [W m-2 K-1]: ``[0]`` surface face → first cell centre,
        ``[i]`` cell i−1 → cell i (series resistance Δz/2k of both half cells: the
        harmonic mean), ``[m]`` last cell → bottom (the half cell, plus the room film
        for ``'room'``).
    layer : numpy.ndarray
        (m,) index of each cell's layer.
    bottom : str
        ``'deep'`` or ``'room'``.
    """

    thickness: np.ndarray
    depth: np.ndarray
    capacity: np.ndarray
    conductance: np.ndarray
    layer: np.ndarray
    bottom: str

    @property
    def n_cells(self) -> int:
        return len(self.thickness)


def _layer_cells(thickness: float, first: float, growth: float, max_cell: float) -> list:
    """Cell sizes filling one layer: a geometric series from ``first`` (capped at
    ``max_cell``), scaled so it ends exactly on the layer's bottom face."""
    sizes = []
    s = first
    total = 0.0
    while total < thickness * (1.0 - 1e-12):
        sizes.append(s)
        total += s
        s = min(s * growth, max_cell)
    if len(sizes) > 1 and total - thickness > 0.5 * sizes[-1]:
        # the last cell overshoots by more than half of itself: drop it, stretch the rest
        total -= sizes.pop()
    return [x * thickness / total for x in sizes]


def column_mesh(layers: Sequence[Layer], bottom: str = "deep",
                room_film_coefficient: float | None = None, first_cell: float = 0.002,
                growth: float = 1.3, max_cell: float = 0.25) -> ColumnMesh:
    """Cells of a layered column, refined toward the surface.

    Parameters
    ----------
    layers : sequence of Layer
        From the surface down.
    bottom : {'deep', 'room'}
        Bottom boundary; ``'room'`` adds the film ``1 / room_film_coefficient`` to the last
        face's resistance.
    room_film_coefficient : float, optional
        [W m-2 K-1] (``bottom == 'room'``).
    first_cell : float
        Thickness of the top cell [m] (2 mm: a twentieth of the diurnal damping depth of
        asphalt, √(2α/ω) ≈ 0.1 m).
    growth : float
        Ratio of successive cell thicknesses [-] (≥ 1).
    max_cell : float
        Largest cell [m].

    Returns
    -------
    ColumnMesh

    Notes
    -----
    Cells grow geometrically through the layers; each layer's series is scaled so the
    interface is a cell face, and the next layer continues from the last size. A face
    between cells i and i+1 conducts ``1 / (Δz_i / 2k_i + Δz_{i+1} / 2k_{i+1})`` (the
    harmonic mean of k for equal cells): exact for the steady flux through the two half
    cells.
    """
    require(bottom in ("deep", "room"), "column.bottom", bottom, "must be 'deep' or 'room'")
    check_range("column.first_cell", first_cell, 1e-5, 1.0, "m")
    check_range("column.growth", growth, 1.0, 3.0)
    thick, k, rc, which = [], [], [], []
    s = first_cell
    for i, layer in enumerate(layers):
        cells = _layer_cells(layer.thickness, min(s, layer.thickness), growth, max_cell)
        thick += cells
        k += [layer.conductivity] * len(cells)
        rc += [layer.heat_capacity] * len(cells)
        which += [i] * len(cells)
        s = min(cells[-1] * growth, max_cell)
    dz = np.asarray(thick)
    k = np.asarray(k)
    half = 0.5 * dz / k
    cond = np.empty(len(dz) + 1)
    cond[0] = 1.0 / half[0]
    cond[1:-1] = 1.0 / (half[:-1] + half[1:])
    r_bottom = half[-1]
    if bottom == "room":
        require(room_film_coefficient is not None and room_film_coefficient > 0,
                "column.room_film_coefficient", room_film_coefficient,
                "must be > 0 W m-2 K-1 for bottom = 'room'")
        r_bottom += 1.0 / room_film_coefficient
    cond[-1] = 1.0 / r_bottom
    depth = np.cumsum(dz) - 0.5 * dz
    return ColumnMesh(dz, depth, np.asarray(rc) * dz, cond, np.asarray(which), bottom)


# ---------------------------------------------------------------------------------------------
# Columns and forcing
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Columns:
    """N columns, each of one surface class.

    Attributes
    ----------
    classes : tuple of SurfaceClass
        The distinct classes.
    meshes : tuple of ColumnMesh
        One per class.
    class_index : numpy.ndarray
        (N,) index into ``classes`` of each column.
    bottom_temperature : numpy.ndarray
        (N,) deep-ground temperature (``'deep'``) or room temperature (``'room'``) [K].
    emissivity : numpy.ndarray
        (N,) long-wave emissivity [-].
    surface_resistance : numpy.ndarray
        (N,) r_s [s m-1], −1 where the class has no latent heat.
    """

    classes: tuple
    meshes: tuple
    class_index: np.ndarray
    bottom_temperature: np.ndarray
    emissivity: np.ndarray
    surface_resistance: np.ndarray

    @property
    def n_columns(self) -> int:
        return len(self.class_index)

    @property
    def n_cells_max(self) -> int:
        return max(m.n_cells for m in self.meshes)

    def padded(self) -> tuple:
        """Per-class arrays padded to the largest column: ``(n_cells (C,), capacity (C, M),
        conductance (C, M + 1))``."""
        m_max = self.n_cells_max
        n = np.array([m.n_cells for m in self.meshes], dtype=np.int64)
        cap = np.zeros((len(self.meshes), m_max))
        cond = np.zeros((len(self.meshes), m_max + 1))
        for c, mesh in enumerate(self.meshes):
            cap[c, :mesh.n_cells] = mesh.capacity
            cond[c, :mesh.n_cells + 1] = mesh.conductance
        return n, cap, cond


def build_columns(class_of_column: Sequence, bottom_temperature,
                  classes=SURFACE_CLASSES, first_cell: float = 0.002, growth: float = 1.3,
                  max_cell: float = 0.25) -> Columns:
    """Columns for pixels of given classes.

    Parameters
    ----------
    class_of_column : sequence of str, int or SurfaceClass
        (N,) class of each column: a name or a code of ``classes``, or a class.
    bottom_temperature : float or array_like
        (N,) deep-ground temperature of ``'deep'`` classes, room temperature of ``'room'``
        classes [K].
    classes : mapping
        Name → :class:`SurfaceClass` (e.g. after
        :func:`~.surface_classes.apply_overrides`).
    first_cell, growth, max_cell
        Mesh of every class (:func:`column_mesh`).

    Returns
    -------
    Columns
    """
    by_code = {c.code: c for c in classes.values()}
    distinct: dict = {}
    index = np.empty(len(class_of_column), dtype=np.int64)
    for j, item in enumerate(class_of_column):
        if isinstance(item, SurfaceClass):
            cls = item
        elif isinstance(item, (int, np.integer)):
            if int(item) not in by_code:
                raise InputError(f"columns.class[{j}]", int(item),
                                 f"must be a land class code: {sorted(by_code)}")
            cls = by_code[int(item)]
        else:
            cls = surface_class(str(item), classes)
        index[j] = distinct.setdefault(cls.name, (len(distinct), cls))[0]
    cls_tuple = tuple(c for _, c in sorted(distinct.values(), key=lambda x: x[0]))
    meshes = tuple(column_mesh(c.layers, c.bottom, c.room_film_coefficient, first_cell, growth,
                               max_cell) for c in cls_tuple)
    n = len(index)
    tb = np.broadcast_to(np.asarray(bottom_temperature, dtype=float), (n,)).copy()
    check_range("columns.bottom_temperature", tb, 150.0, 400.0, "K")
    emis = np.array([cls_tuple[i].emissivity for i in index])
    rs = np.array([cls_tuple[i].surface_resistance if cls_tuple[i].latent == "penman_monteith"
                   else -1.0 for i in index])
    return Columns(cls_tuple, meshes, index, tb, emis, rs)


@dataclass(frozen=True)
class SurfaceForcing:
    """Forcing of N columns on a uniform time grid (n_t instants, ``time_step`` apart).

    Attributes
    ----------
    time_step : float
        Spacing of the grid [s]; a day must be a whole number of steps.
    shortwave_absorbed : numpy.ndarray
        (n_t, N) absorbed short-wave [W m-2] ((1 − albedo) × incident).
    longwave_down : numpy.ndarray
        (n_t, N) incoming long-wave [W m-2] (sky and surroundings weighted by the sky view:
        :func:`longwave_incoming`); the surface absorbs ε of it.
    temp_air : numpy.ndarray
        (n_t,) or (n_t, N) air temperature [K].
    relative_humidity : numpy.ndarray
        (n_t,) or (n_t, N) [%].
    wind_speed : numpy.ndarray
        (n_t,) or (n_t, N) wind speed at the height the convection model expects [m s-1].
    pressure : float or numpy.ndarray
        Air pressure [Pa], scalar, (n_t,) or (n_t, N).
    """

    time_step: float
    shortwave_absorbed: np.ndarray
    longwave_down: np.ndarray
    temp_air: np.ndarray
    relative_humidity: np.ndarray
    wind_speed: np.ndarray
    pressure: float | np.ndarray = 101325.0

    @property
    def n_times(self) -> int:
        return self.shortwave_absorbed.shape[0]

    @property
    def n_columns(self) -> int:
        return self.shortwave_absorbed.shape[1]

    def field(self, name: str) -> np.ndarray:
        """A field broadcast to (n_t, N) (a view, not a copy)."""
        return np.broadcast_to(_column_shape(getattr(self, name), self.n_times),
                               (self.n_times, self.n_columns))

    def validate(self) -> None:
        """Shapes and physical ranges, naming the field."""
        check_range("forcing.time_step", self.time_step, 1.0, DAY, "s")
        require(self.shortwave_absorbed.ndim == 2, "forcing.shortwave_absorbed",
                self.shortwave_absorbed.shape, "must be (n_t, N)")
        nt, n = self.shortwave_absorbed.shape
        for name, lo, hi, unit in (("shortwave_absorbed", 0.0, 1500.0, "W m-2"),
                                   ("longwave_down", 0.0, 700.0, "W m-2"),
                                   ("temp_air", 180.0, 340.0, "K"),
                                   ("relative_humidity", 0.0, 100.0, "%"),
                                   ("wind_speed", 0.0, 75.0, "m s-1"),
                                   ("pressure", 3.0e4, 1.2e5, "Pa")):
            value = _floats(getattr(self, name))
            try:
                np.broadcast_to(_column_shape(value, nt), (nt, n))
            except ValueError:
                raise InputError(f"forcing.{name}", value.shape,
                                 f"must broadcast to (n_t, N) = ({nt}, {n})") from None
            # extremes first (no float64 copy of a long record's float32 arrays); the full
            # check names the first bad entry
            low, high = (np.min(value), np.max(value)) if value.size else (lo, hi)
            if not (np.isfinite(low) and np.isfinite(high) and lo <= low and high <= hi):
                check_range(f"forcing.{name}", value, lo, hi, unit)


def _floats(value) -> np.ndarray:
    """``value`` as a float array: float32 kept as it is (a long record's forcing), anything
    else as float64."""
    a = np.asarray(value)
    return a if a.dtype == np.float32 else np.asarray(a, dtype=float)


def _column_shape(value, n_times: int) -> np.ndarray:
    """(n_t,) → (n_t, 1) so a per-time series broadcasts over columns."""
    a = _floats(value)
    return a[:, None] if a.ndim == 1 and a.shape[0] == n_times else a


@dataclass(frozen=True)
class SurfaceEnergyResult:
    """Surface temperature and energy-balance terms on the forcing grid.

    Fluxes are instantaneous at the grid times, signs as in micrometeorology: radiation
    positive toward the surface, ``sensible``, ``latent`` positive away from it (upward),
    ``ground`` positive into the column; ``shortwave_net + longwave_net − sensible − latent −
    ground = 0`` at every instant (to the Newton tolerance).

    Attributes
    ----------
    temp_surface : numpy.ndarray
        (n_t, N) [K].
    shortwave_net, longwave_net, sensible, latent, ground : numpy.ndarray
        (n_t, N) [W m-2].
    h_convection : numpy.ndarray
        (n_t, N) convective coefficient used in the step ending at each instant [W m-2 K-1].
    temp_cells : numpy.ndarray
        (N, M) cell temperatures at the end of the run (padded with NaN) [K].
    energy_residual : numpy.ndarray
        (N,) stored-energy change of the run minus the time integral of the boundary fluxes
        (surface terms and the bottom flux) [J m-2].
    energy_scale : numpy.ndarray
        (N,) time integral of the absolute boundary fluxes [J m-2] (to judge the residual).
    surface_imbalance : numpy.ndarray
        (N,) largest |S_abs + ε L↓ − εσT⁴ − H − λE − G| over the run [W m-2].
    spinup_days : int
        Days of the periodic spin-up (the whole run in periodic mode).
    spinup_change : numpy.ndarray
        (N,) largest change of the surface temperature between the last two spin-up days [K].
    scheme : str
    substeps : int
        Solver steps per forcing interval.
    """

    temp_surface: np.ndarray
    shortwave_net: np.ndarray
    longwave_net: np.ndarray
    sensible: np.ndarray
    latent: np.ndarray
    ground: np.ndarray
    h_convection: np.ndarray
    temp_cells: np.ndarray
    energy_residual: np.ndarray
    energy_scale: np.ndarray
    surface_imbalance: np.ndarray
    spinup_days: int
    spinup_change: np.ndarray
    scheme: str
    substeps: int


# ---------------------------------------------------------------------------------------------
# Moist air and latent heat
# ---------------------------------------------------------------------------------------------
def saturation_vapour_pressure(temp):
    """Saturation vapour pressure over water [Pa].

    Parameters
    ----------
    temp : array_like
        Temperature [K].

    Notes
    -----
    FAO-56 eq. 11 (Tetens 1930): e° = 610.8 exp(17.27 T_c / (T_c + 237.3)) Pa, T_c in °C.
    """
    tc = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    return _ES0 * np.exp(_ES_A * tc / (tc + _ES_B))


def saturation_vapour_pressure_slope(temp):
    """d e°/dT [Pa K-1] of :func:`saturation_vapour_pressure` (exact derivative; FAO-56
    eq. 13 rounds 17.27 × 237.3 = 4098.171 to 4098).

    Parameters
    ----------
    temp : array_like
        [K].
    """
    tc = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    return saturation_vapour_pressure(temp) * (_ES_A * _ES_B) / ((tc + _ES_B) * (tc + _ES_B))


def air_heat_capacity(temp_air, pressure=101325.0):
    """Volumetric heat capacity of air ρ_a c_p [J m-3 K-1].

    Parameters
    ----------
    temp_air : array_like
        [K].
    pressure : array_like
        [Pa].

    Notes
    -----
    FAO-56 eq. 3 notes: ρ_a = P / (1.01 T R), R = 287 J kg-1 K-1; c_p = 1013 J kg-1 K-1.
    """
    return SPECIFIC_HEAT_AIR * np.asarray(pressure, dtype=float) / (
        1.01 * GAS_CONSTANT_DRY_AIR * np.asarray(temp_air, dtype=float))


def psychrometric_constant(pressure=101325.0):
    """γ = c_p P / (ε λ) [Pa K-1] (FAO-56 eq. 8).

    Parameters
    ----------
    pressure : array_like
        [Pa].
    """
    return SPECIFIC_HEAT_AIR * np.asarray(pressure, dtype=float) / (
        RATIO_MOLECULAR_WEIGHT * LATENT_HEAT_VAPORISATION)


def latent_heat_flux(temp_surface, temp_air, relative_humidity, h_convection,
                     surface_resistance, pressure=101325.0):
    """Latent heat flux of a vegetated (or wet) surface, Penman–Monteith resistance form.

    Parameters
    ----------
    temp_surface : array_like
        [K].
    temp_air : array_like
        [K].
    relative_humidity : array_like
        [%].
    h_convection : array_like
        Convective (sensible) coefficient [W m-2 K-1]; the aerodynamic resistance is
        ``r_a = ρ_a c_p / h`` (the same for heat and vapour).
    surface_resistance : array_like
        Bulk surface resistance r_s [s m-1].
    pressure : array_like
        [Pa].

    Returns
    -------
    numpy.ndarray
        λE [W m-2], positive upward.

    Notes
    -----
    ``λE = (ρ_a c_p / γ) (e°(T_s) − e_a) / (r_a + r_s)``, e_a = RH/100 · e°(T_air): the form
    FAO-56 eq. 3 is derived from before e°(T_s) is linearised about T_air (FAO-56 ch. 2,
    after Monteith 1965). Written here as ``(ρ_a c_p/γ) h (e°(T_s) − e_a) / (ρ_a c_p + h r_s)``.
    """
    rho_cp = air_heat_capacity(temp_air, pressure)
    coef = rho_cp / psychrometric_constant(pressure) * h_convection / (
        rho_cp + np.asarray(h_convection) * surface_resistance)
    ea = np.asarray(relative_humidity) / 100.0 * saturation_vapour_pressure(temp_air)
    return coef * (saturation_vapour_pressure(temp_surface) - ea)


# ---------------------------------------------------------------------------------------------
# Convection
# ---------------------------------------------------------------------------------------------
def convection_correlation(model: str = DEFAULT_CONVECTION_MODEL, normal_z=1.0,
                           length_flow: float = GROUND_CONVECTION_LENGTHS["length_flow"],
                           length_vertical: float = GROUND_CONVECTION_LENGTHS["length_vertical"],
                           length_horizontal: float = GROUND_CONVECTION_LENGTHS[
                               "length_horizontal"]) -> Callable:
    """Convective coefficient from one of the project's exterior correlations.

    Parameters
    ----------
    model : str
        Key of :data:`shipthermal.environment.convection.CONVECTION_MODELS` (default the
        ship's default, :data:`shipthermal.parameters.DEFAULT_CONVECTION_MODEL`).
    normal_z : float or array_like
        (N,) upward component of the surface normal, cos(slope) [-].
    length_flow, length_vertical, length_horizontal : float
        Characteristic lengths [m] (:data:`GROUND_CONVECTION_LENGTHS`).

    Returns
    -------
    callable
        ``h(temp_surface [K], temp_air [K], wind_speed [m s-1]) -> [W m-2 K-1]``.
    """
    cm = convection_model(model, "background.convection.model")

    def h(temp_surface, temp_air, wind_speed):
        return cm.h(temp_surface, temp_air,
                    ExteriorFlow(normal_z=normal_z, wind_speed=wind_speed,
                                 length_flow=length_flow, length_vertical=length_vertical,
                                 length_horizontal=length_horizontal))

    h.__doc__ = f"{cm.name}: {cm.source}"
    return h


def convection_aerodynamic(roughness_length, roughness_length_heat=None,
                           displacement_height=0.0, height_wind: float = 10.0,
                           height_temp: float | None = None, stability: bool = False,
                           pressure=101325.0) -> Callable:
    """Convective coefficient ``ρ_a c_p / r_a`` from the neutral logarithmic wind profile.

    Parameters
    ----------
    roughness_length : float or array_like
        (N,) z_0m [m] (a class's ``roughness_length``).
    roughness_length_heat : float or array_like, optional
        (N,) z_0h [m]; default z_0m / 10.
    displacement_height : float or array_like
        (N,) d [m].
    height_wind : float
        Height of the wind measurement above the surface [m].
    height_temp : float, optional
        Height of the air temperature [m]; default ``height_wind``.
    stability : bool
        Multiply the neutral coefficient by a bulk-Richardson stability factor:
        ``(1 − 16 Ri)^0.75`` unstable, ``(1 − 5 Ri)²`` stable, Ri clipped at 0.19.
    pressure : float
        [Pa] for ρ_a c_p.

    Returns
    -------
    callable
        ``h(temp_surface [K], temp_air [K], wind_speed [m s-1]) -> [W m-2 K-1]``.

    Notes
    -----
    FAO-56 eq. 4: ``r_a = ln((z_m − d)/z_0m) ln((z_h − d)/z_0h) / (k² u_z)``, k = 0.41 (with
    z_m = z_h = 2 m and the grass of FAO-56 this is r_a = 208/u_2). Calm air would give h → 0:
    the wind is floored at 0.5 m s-1 (ASSUMPTION: free convection keeps a minimum exchange;
    the floor FAO-56 advises for very low measured winds). Stability (optional, ASSUMPTION:
    the usual bulk-Richardson shortcut, ζ ≈ Ri): unstable, Dyer's (1974) φ_m = (1 − 16ζ)^-1/4
    and φ_h = (1 − 16ζ)^-1/2 give the factor (1 − 16 Ri)^3/4; stable, Webb's (1970)
    φ = 1 + 5ζ with ζ = Ri/(1 − 5 Ri) gives (1 − 5 Ri)²; Ri = g z (T_air − T_s) /
    (T_air u²), evaluated with the surface temperature at the start of the step.
    """
    z0m = np.asarray(roughness_length, dtype=float)
    z0h = z0m / 10.0 if roughness_length_heat is None else np.asarray(roughness_length_heat,
                                                                         dtype=float)
    d = np.asarray(displacement_height, dtype=float)
    zt = height_wind if height_temp is None else height_temp
    check_range("convection.height_wind", height_wind, 0.1, 200.0, "m")
    if np.any(height_wind - d <= z0m) or np.any(zt - d <= z0h):
        raise InputError("convection.height_wind", height_wind,
                         "must exceed displacement height + roughness length")
    log_product = np.log((height_wind - d) / z0m) * np.log((zt - d) / z0h)

    def h(temp_surface, temp_air, wind_speed):
        u = np.maximum(np.asarray(wind_speed, dtype=float), 0.5)
        hn = air_heat_capacity(temp_air, pressure) * VON_KARMAN ** 2 * u / log_product
        if not stability:
            return hn
        ta = np.asarray(temp_air, dtype=float)
        ri = 9.80665 * zt * (ta - np.asarray(temp_surface)) / (ta * u * u)
        ri = np.minimum(ri, 0.19)
        factor = np.where(ri < 0.0, (1.0 - 16.0 * np.minimum(ri, 0.0)) ** 0.75,
                          (1.0 - 5.0 * np.maximum(ri, 0.0)) ** 2)
        return hn * factor

    return h


def convection_linear(a: float, b: float) -> Callable:
    """``h = a + b v`` [W m-2 K-1] (e.g. ISO 6946 a = b = 4, or a user curve of EnergyPlus).

    Parameters
    ----------
    a : float
        [W m-2 K-1].
    b : float
        [J m-3 K-1].
    """
    def h(temp_surface, temp_air, wind_speed):
        return a + b * np.asarray(wind_speed, dtype=float) + 0.0 * np.asarray(temp_surface)

    return h


# ---------------------------------------------------------------------------------------------
# Forcing of tilted pixels
# ---------------------------------------------------------------------------------------------
def sky_view_factor(surface_tilt):
    """Sky-view factor of an unobstructed tilted plane, isotropic sky: (1 + cos s)/2 [-].

    Parameters
    ----------
    surface_tilt : array_like
        Slope s [deg] (0 horizontal).
    """
    return 0.5 * (1.0 + np.cos(np.radians(np.asarray(surface_tilt, dtype=float))))


def shortwave_on_tilted(surface_tilt, surface_azimuth, solar_zenith, solar_azimuth, dni, ghi,
                        dhi, albedo_ground=0.2, model: str = "isotropic", dni_extra=None,
                        airmass=None) -> dict:
    """Short-wave incident on tilted pixels (pvlib transposition).

    Parameters
    ----------
    surface_tilt : array_like
        (N,) terrain slope [deg].
    surface_azimuth : array_like
        (N,) aspect: compass azimuth of the downslope direction, the direction the surface
        faces [deg clockwise from north].
    solar_zenith, solar_azimuth : array_like
        (n_t,) apparent sun position [deg] (azimuth clockwise from north).
    dni, ghi, dhi : array_like
        (n_t,) irradiance [W m-2].
    albedo_ground : float or array_like
        Albedo of the surroundings seen below the horizon [-].
    model : {'isotropic', 'haydavies', 'perez', ...}
        pvlib's sky-diffuse model (``haydavies`` and ``perez`` need ``dni_extra``;
        ``perez`` also ``airmass``).
    dni_extra, airmass : array_like, optional
        (n_t,) extraterrestrial DNI [W m-2] and relative air mass [-].

    Returns
    -------
    dict
        ``poa_global``, ``poa_direct``, ``poa_sky_diffuse``, ``poa_ground_diffuse``:
        (n_t, N) [W m-2].

    Notes
    -----
    :func:`pvlib.irradiance.get_total_irradiance` with pvlib's conventions (surface_azimuth
    is the azimuth the surface normal points to); direct = DNI · max(cos θ_i, 0).
    """
    col = lambda x: None if x is None else np.asarray(x, dtype=float)[:, None]  # noqa: E731
    row = lambda x: np.asarray(x, dtype=float).reshape(1, -1)  # noqa: E731
    tilt = row(surface_tilt)
    azim = row(surface_azimuth)
    out = pvlib.irradiance.get_total_irradiance(
        tilt, azim, col(solar_zenith), col(solar_azimuth), col(dni), col(ghi), col(dhi),
        dni_extra=col(dni_extra), airmass=col(airmass), albedo=albedo_ground, model=model)
    shape = np.broadcast_shapes(tilt.shape, np.shape(col(dni)))
    return {k: np.nan_to_num(np.broadcast_to(np.asarray(out[k], dtype=float), shape))
            for k in ("poa_global", "poa_direct", "poa_sky_diffuse", "poa_ground_diffuse")}


def longwave_incoming(longwave_sky, sky_view, temp_surroundings, emissivity_surroundings=0.95):
    """Long-wave reaching a pixel: sky through its sky view, surroundings through the rest.

    Parameters
    ----------
    longwave_sky : array_like
        (n_t, 1) or (n_t, N) long-wave down on a horizontal plane [W m-2].
    sky_view : array_like
        (N,) sky-view factor [-].
    temp_surroundings : array_like
        Temperature of the terrain and buildings seen instead of the sky [K].
    emissivity_surroundings : float
        Their emissivity [-] (their reflection of the sky is neglected).

    Returns
    -------
    numpy.ndarray
        ``V L_sky + (1 − V) ε σ T⁴`` [W m-2].
    """
    v = np.asarray(sky_view, dtype=float)
    ts = np.asarray(temp_surroundings, dtype=float)
    return v * np.asarray(longwave_sky) + (1.0 - v) * emissivity_surroundings * SIGMA * ts ** 4


def forcing_from_environment(state, time_step: float, albedo, surface_tilt=0.0,
                             surface_azimuth=180.0, sky_view=None, temp_surroundings=None,
                             albedo_ground: float = 0.2, diffuse_model: str = "isotropic",
                             pressure=101325.0) -> SurfaceForcing:
    """Forcing of N land pixels from the environment the ship sees.

    Parameters
    ----------
    state : shipthermal.environment.EnvironmentState
        The environment at the n_t instants of a uniform grid (``env.at(times)``).
    time_step : float
        Spacing of those instants [s].
    albedo : float or array_like
        (N,) short-wave albedo of each pixel [-] (the class's, or fitted per pixel).
    surface_tilt, surface_azimuth : float or array_like
        (N,) terrain slope and aspect (downslope compass azimuth) [deg].
    sky_view : array_like, optional
        (N,) sky-view factor [-]; default that of the tilted plane alone
        (:func:`sky_view_factor`); pass a smaller one where buildings hide the sky.
    temp_surroundings : float or array_like, optional
        Temperature of what fills the rest of the view [K]; default the air temperature.
    albedo_ground : float
        Albedo of the surroundings for the ground-reflected short-wave [-].
    diffuse_model : str
        pvlib sky-diffuse model (:func:`shortwave_on_tilted`); ``haydavies``/``perez`` get
        pvlib's extraterrestrial DNI and air mass at the state's times.
    pressure : float or array_like
        Air pressure [Pa].

    Returns
    -------
    SurfaceForcing
        Absorbed short-wave ``(1 − albedo) · poa_global``, incoming long-wave
        ``V L↓ + (1 − V) σ T_surr⁴`` (:func:`longwave_incoming`, surroundings black), air
        temperature, humidity and the 10 m wind of the state.
    """
    tilt = np.atleast_1d(np.asarray(surface_tilt, dtype=float))
    azim = np.atleast_1d(np.asarray(surface_azimuth, dtype=float))
    alb = np.atleast_1d(np.asarray(albedo, dtype=float))
    n = max(tilt.size, azim.size, alb.size, 1 if sky_view is None else np.size(sky_view))
    tilt, azim, alb = (np.broadcast_to(x, (n,)) for x in (tilt, azim, alb))
    check_range("forcing.albedo", alb, 0.0, 1.0)
    check_range("forcing.surface_tilt", tilt, 0.0, 90.0, "deg")
    extra = airmass = None
    if diffuse_model != "isotropic":
        extra = pvlib.irradiance.get_extra_radiation(state.times).to_numpy()
        airmass = pvlib.atmosphere.get_relative_airmass(np.asarray(state.zenith))
    sw = shortwave_on_tilted(tilt, azim, state.zenith, state.azimuth, state.dni, state.ghi,
                             state.dhi, albedo_ground, diffuse_model, extra, airmass)
    view = sky_view_factor(tilt) if sky_view is None else np.broadcast_to(
        np.asarray(sky_view, dtype=float), (n,))
    t_surr = (np.asarray(state.temp_air)[:, None] if temp_surroundings is None
              else np.asarray(temp_surroundings, dtype=float))
    lw = longwave_incoming(np.asarray(state.longwave_down)[:, None], view, t_surr, 1.0)
    return SurfaceForcing(float(time_step), (1.0 - alb) * sw["poa_global"],
                          np.ascontiguousarray(np.broadcast_to(lw, sw["poa_global"].shape)),
                          np.asarray(state.temp_air, dtype=float),
                          np.asarray(state.relative_humidity, dtype=float),
                          np.asarray(state.wind_speed, dtype=float), pressure)


# ---------------------------------------------------------------------------------------------
# Step kernels
# ---------------------------------------------------------------------------------------------
def _factorise(n_cells, capacity, conductance, dt, theta):
    """The time-independent part of the Thomas elimination from the bottom up, per class:
    ``C/Δt``, ``Q_i`` and ``1/den_i`` (elimination T_i = P_i + Q_i T_{i−1})."""
    n_cls, m_max = capacity.shape
    cap_dt = capacity / dt
    q = np.zeros((n_cls, m_max))
    inv_den = np.zeros((n_cls, m_max))
    for c in range(n_cls):
        m = n_cells[c]
        k = conductance[c]
        q_next = 0.0
        for i in range(m - 1, -1, -1):           # 0-based cell i, faces k[i] above, k[i+1] below
            den = cap_dt[c, i] + theta * (k[i] + k[i + 1])
            if i < m - 1:
                den -= theta * k[i + 1] * q_next
            inv_den[c, i] = 1.0 / den
            q[c, i] = theta * k[i] * inv_den[c, i]
            q_next = q[c, i]
    return cap_dt, q, inv_den


BLOCK = 64
"""Columns per block of the kernels: one class per block, the cell loops run across the
block's columns (independent chains: SIMD lanes and pipelining instead of one latency-bound
Thomas recurrence at a time)."""


_PARALLEL_MIN_BLOCKS = 32
"""Fewer blocks than this run on one thread (see :class:`_Stepper`)."""


def _blocks(class_index: np.ndarray, block: int = BLOCK) -> tuple:
    """Columns sorted by class (stable) and blocks ``(class, start, end)`` of that order, no
    block straddling two classes."""
    order = np.argsort(class_index, kind="stable")
    sorted_cls = class_index[order]
    rows = []
    start = 0
    n = len(order)
    while start < n:
        c = sorted_cls[start]
        end = start
        while end < n and end - start < block and sorted_cls[end] == c:
            end += 1
        rows.append((c, start, end))
        start = end
    return order.astype(np.int64), np.array(rows, dtype=np.int64).reshape(-1, 3)


def _step_blocks(temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta, emis, rs, tbot,
                sw, lw, ta, rh, pres, h, dt, out, sb_old, acc, acc_abs, imbalance, work):
    """One step of every column, blocks in parallel; the arithmetic of
    :func:`_step_reference`. ``temp`` (M + 1, N): surface node then cells, columns in the
    sorted order ``order`` (sorted position → column), updated in place. Inputs and outputs
    per column are in the caller's order; ``out`` (6, N): long-wave net, sensible, latent,
    ground, bottom flux, new surface temperature. ``work`` (11, N): scratch rows (no
    allocation inside the loop)."""
    for bk in prange(blocks.shape[0]):
        c = blocks[bk, 0]
        j0 = blocks[bk, 1]
        nb = blocks[bk, 2] - j0
        m = n_cells[c]
        col = order[j0:j0 + nb]
        tb = work[0, j0:j0 + nb]
        t_below_old = work[1, j0:j0 + nb]
        p_below = work[2, j0:j0 + nb]
        for jj in range(nb):
            tb[jj] = tbot[col[jj]]
            t_below_old[jj] = tb[jj]
            p_below[jj] = 0.0
        # upward elimination, temp[i] <- P_i (old values kept where still needed)
        for i in range(m, 0, -1):
            cd = cap_dt[c, i - 1]
            k_up = cond[c, i - 1]
            k_dn = cond[c, i]
            idn = inv_den[c, i - 1]
            c_bot = theta * k_dn if i == m else 0.0
            c_p = 0.0 if i == m else theta * k_dn
            row = temp[i, j0:j0 + nb]        # 1-D views: plain non-negative indices
            if theta < 1.0:
                above = temp[i - 1, j0:j0 + nb]
                for jj in range(nb):
                    ti = row[jj]
                    rhs = cd * ti + (1.0 - theta) * (k_up * (above[jj] - ti)
                                                     - k_dn * (ti - t_below_old[jj]))
                    p = (rhs + c_bot * tb[jj] + c_p * p_below[jj]) * idn
                    row[jj] = p
                    p_below[jj] = p
                    t_below_old[jj] = ti
            else:
                for jj in range(nb):
                    p = (cd * row[jj] + c_bot * tb[jj] + c_p * p_below[jj]) * idn
                    row[jj] = p
                    p_below[jj] = p
        # surface node: G(x) = k0 (x − P_1 − Q_1 x) = a x − b; Newton on the block together
        k0 = cond[c, 0]
        a = k0 * (1.0 - q[c, 0])
        latent = rs[col[0]] >= 0.0
        swb = work[3, j0:j0 + nb]
        lwb = work[4, j0:j0 + nb]
        tab = work[5, j0:j0 + nb]
        hb = work[6, j0:j0 + nb]
        eb = work[7, j0:j0 + nb]
        ce = work[8, j0:j0 + nb]
        ea = work[9, j0:j0 + nb]
        x = work[10, j0:j0 + nb]
        surface = temp[0, j0:j0 + nb]
        t1 = temp[1, j0:j0 + nb]
        for jj in range(nb):
            ce[jj] = 0.0
            ea[jj] = 0.0
            j = col[jj]
            swb[jj] = sw[j]
            lwb[jj] = lw[j]
            tab[jj] = ta[j]
            hb[jj] = h[j]
            eb[jj] = emis[j]
            x[jj] = surface[jj]
            if latent:
                rho_cp = 1013.0 * pres[j] / (1.01 * 287.0 * ta[j])
                gamma = 1013.0 * pres[j] / (0.622 * 2.45e6)
                ce[jj] = rho_cp / gamma * h[j] / (rho_cp + h[j] * rs[j])
                tca = ta[j] - 273.15
                ea[jj] = rh[j] / 100.0 * (610.8 * np.exp(17.27 * tca / (tca + 237.3)))
        for it in range(60):
            dmax = 0.0
            if latent:
                for jj in range(nb):
                    xj = x[jj]
                    x3 = xj * xj * xj
                    tc = xj - 273.15
                    es = 610.8 * np.exp(17.27 * tc / (tc + 237.3))
                    f = (swb[jj] + eb[jj] * (lwb[jj] - 5.670374419e-8 * x3 * xj)
                         - hb[jj] * (xj - tab[jj]) - (a * xj - k0 * t1[jj])
                         - ce[jj] * (es - ea[jj]))
                    df = (-4.0 * eb[jj] * 5.670374419e-8 * x3 - hb[jj] - a
                          - ce[jj] * es * (17.27 * 237.3) / ((tc + 237.3) * (tc + 237.3)))
                    dx = -f / df
                    x[jj] = xj + dx
                    dmax = max(dmax, abs(dx))
            else:
                for jj in range(nb):
                    xj = x[jj]
                    x3 = xj * xj * xj
                    f = (swb[jj] + eb[jj] * (lwb[jj] - 5.670374419e-8 * x3 * xj)
                         - hb[jj] * (xj - tab[jj]) - (a * xj - k0 * t1[jj]))
                    df = -4.0 * eb[jj] * 5.670374419e-8 * x3 - hb[jj] - a
                    dx = -f / df
                    x[jj] = xj + dx
                    dmax = max(dmax, abs(dx))
            if dmax < 1e-7:
                break
        # back substitution (temp[0] holds the new surface temperature, then each row the new
        # cell temperature: T_i = P_i + Q_i T_{i−1})
        for jj in range(nb):
            surface[jj] = x[jj]
        for i in range(1, m + 1):
            qi = q[c, i - 1]
            row = temp[i, j0:j0 + nb]
            above = temp[i - 1, j0:j0 + nb]
            for jj in range(nb):
                row[jj] = row[jj] + qi * above[jj]
        k_bot = cond[c, m]
        bottom = temp[m, j0:j0 + nb]
        for jj in range(nb):
            j = col[jj]
            xj = x[jj]
            x3 = xj * xj * xj
            lwn = eb[jj] * (lwb[jj] - 5.670374419e-8 * x3 * xj)
            sens = hb[jj] * (xj - tab[jj])
            lat = 0.0
            if latent:
                tc = xj - 273.15
                lat = ce[jj] * (610.8 * np.exp(17.27 * tc / (tc + 237.3)) - ea[jj])
            g = k0 * (xj - t1[jj])
            bot = k_bot * (bottom[jj] - tb[jj])
            s = swb[jj] + lwn - sens - lat
            out[0, j] = lwn
            out[1, j] = sens
            out[2, j] = lat
            out[3, j] = g
            out[4, j] = bot
            out[5, j] = xj
            acc[j] += dt * (theta * (s - bot) + (1.0 - theta) * sb_old[j])
            acc_abs[j] += dt * (abs(swb[jj]) + abs(lwn) + abs(sens) + abs(lat) + abs(bot))
            sb_old[j] = s - bot
            d = abs(s - g)
            if d > imbalance[j]:
                imbalance[j] = d


def _step_reference(temp, order, blocks, n_cells, cap_dt, cond, q, inv_den, theta, emis, rs,
                    tbot, sw, lw, ta, rh, pres, h, dt, out, sb_old, acc, acc_abs, imbalance,
                    work=None):
    """Plain numpy version of :func:`_step_numba`: the same blocks, the same arithmetic in the
    same order, vectorised over the columns of a block.

    For cell i (1-based, capacity C_i, faces K_{i−1} above and K_i below):
    ``C_i/Δt (T'_i − T_i) = θ [K_{i−1}(T'_{i−1} − T'_i) − K_i(T'_i − T'_{i+1})]
    + (1 − θ)[same at the old level]``, T_0 the surface node, T_{m+1} the bottom temperature.
    Eliminating from the bottom, T'_i = P_i + Q_i T'_{i−1}; the surface balance
    ``S(T_s) − K_0 (T_s − P_1 − Q_1 T_s) = 0`` is solved by Newton (all columns of a block
    iterate until the largest update is below :data:`_NEWTON_TOL`), then T' follows downward.
    Every term of that balance is concave and decreasing in T_s (−εσT⁴, −h T, −λE with e°
    convex, the linear conduction), so Newton converges from any start, monotonically from
    above after its first step.
    """
    for c, j0, j1 in blocks:
        sl = slice(j0, j1)
        col = order[sl]
        m = n_cells[c]
        tb = tbot[col]
        t_below_old = tb.copy()
        p_below = np.zeros(j1 - j0)
        for i in range(m, 0, -1):
            cd = cap_dt[c, i - 1]
            k_up = cond[c, i - 1]
            k_dn = cond[c, i]
            idn = inv_den[c, i - 1]
            c_bot = theta * k_dn if i == m else 0.0
            c_p = 0.0 if i == m else theta * k_dn
            ti = temp[i, sl].copy()
            if theta < 1.0:
                rhs = cd * ti + (1.0 - theta) * (k_up * (temp[i - 1, sl] - ti)
                                                 - k_dn * (ti - t_below_old))
                p = (rhs + c_bot * tb + c_p * p_below) * idn
                t_below_old = ti
            else:
                p = (cd * ti + c_bot * tb + c_p * p_below) * idn
            temp[i, sl] = p
            p_below = p
        k0 = cond[c, 0]
        a = k0 * (1.0 - q[c, 0])
        latent = rs[col[0]] >= 0.0
        swb, lwb, tab, hb, eb = sw[col], lw[col], ta[col], h[col], emis[col]
        ce = np.zeros(j1 - j0)
        ea = np.zeros(j1 - j0)
        if latent:
            rho_cp = 1013.0 * pres[col] / (1.01 * 287.0 * tab)
            gamma = 1013.0 * pres[col] / (0.622 * 2.45e6)
            ce = rho_cp / gamma * hb / (rho_cp + hb * rs[col])
            tca = tab - 273.15
            ea = rh[col] / 100.0 * (610.8 * np.exp(17.27 * tca / (tca + 237.3)))
        x = temp[0, sl].copy()
        t1 = temp[1, sl]
        for _ in range(_NEWTON_MAX):
            x3 = x * x * x
            f = swb + eb * (lwb - SIGMA * x3 * x) - hb * (x - tab) - (a * x - k0 * t1)
            df = -4.0 * eb * SIGMA * x3 - hb - a
            if latent:
                tc = x - 273.15
                es = 610.8 * np.exp(17.27 * tc / (tc + 237.3))
                f = f - ce * (es - ea)
                df = df - ce * es * (17.27 * 237.3) / ((tc + 237.3) * (tc + 237.3))
            dx = -f / df
            x = x + dx
            if np.max(np.abs(dx)) < _NEWTON_TOL:
                break
        temp[0, sl] = x
        for i in range(1, m + 1):
            temp[i, sl] = temp[i, sl] + q[c, i - 1] * temp[i - 1, sl]
        x3 = x * x * x
        lwn = eb * (lwb - SIGMA * x3 * x)
        sens = hb * (x - tab)
        lat = np.zeros(j1 - j0)
        if latent:
            tc = x - 273.15
            lat = ce * (610.8 * np.exp(17.27 * tc / (tc + 237.3)) - ea)
        g = k0 * (x - temp[1, sl])
        bot = cond[c, m] * (temp[m, sl] - tb)
        s = swb + lwn - sens - lat
        out[0, col] = lwn
        out[1, col] = sens
        out[2, col] = lat
        out[3, col] = g
        out[4, col] = bot
        out[5, col] = x
        acc[col] += dt * (theta * (s - bot) + (1.0 - theta) * sb_old[col])
        acc_abs[col] += dt * (np.abs(swb) + np.abs(lwn) + np.abs(sens) + np.abs(lat)
                              + np.abs(bot))
        sb_old[col] = s - bot
        imbalance[col] = np.maximum(imbalance[col], np.abs(s - g))


def _renamed(func, name: str):
    """A copy of a plain function under another name (numba caches compiled code per
    qualified name: the parallel and the serial build must not share an entry)."""
    copy = types.FunctionType(func.__code__, func.__globals__, name, func.__defaults__,
                              func.__closure__)
    copy.__qualname__ = name
    copy.__doc__ = func.__doc__
    return copy


_step_numba = njit(parallel=True, cache=True)(_renamed(_step_blocks, "_step_numba"))
_step_numba_serial = njit(cache=True)(_renamed(_step_blocks, "_step_numba_serial"))
"""The kernel of :func:`_step_blocks` compiled twice: blocks on numba's threads, and on the
calling thread alone for small problems (a parallel launch costs tens of µs per step, far
more while other processes hold the cores; same blocks, same arithmetic, same results)."""

_KERNELS = {"numba": _step_numba, "reference": _step_reference}


# ---------------------------------------------------------------------------------------------
# Time loop
# ---------------------------------------------------------------------------------------------
@dataclass
class _State:
    temp: np.ndarray          # (M+1, N) surface node + cells, columns in the sorted order
    sb_old: np.ndarray        # (N,) surface net − bottom flux at the last level [W m-2]
    acc: np.ndarray           # (N,) ∫ boundary fluxes [J m-2]
    acc_abs: np.ndarray
    imbalance: np.ndarray


class _Stepper:
    """Advances all columns step by step with one kernel and one convection model."""

    def __init__(self, columns: Columns, convection: Callable, theta: float, dt: float,
                 kernel: Callable):
        self.columns = columns
        self.convection = convection
        self.theta = theta
        self.dt = dt
        self.kernel = kernel
        self.n_cells, self.capacity, self.cond = columns.padded()
        self.cap_dt, self.q, self.inv_den = _factorise(self.n_cells, self.capacity, self.cond,
                                                       dt, theta)
        n = columns.n_columns
        self.out = np.zeros((6, n))
        self.work = np.zeros((11, n))
        self.order, self.blocks = _blocks(np.asarray(columns.class_index))
        if kernel is _step_numba and len(self.blocks) < _PARALLEL_MIN_BLOCKS:
            self.kernel = _step_numba_serial
        self.emis = np.ascontiguousarray(columns.emissivity)
        self.rs = np.ascontiguousarray(columns.surface_resistance)
        self.tbot = np.ascontiguousarray(columns.bottom_temperature)

    def surface(self, state: _State) -> np.ndarray:
        """Surface temperature in the columns' order."""
        ts = np.empty(self.columns.n_columns)
        ts[self.order] = state.temp[0]
        return ts

    def step(self, state: _State, sw, lw, ta, rh, pres, wind) -> np.ndarray:
        h = np.ascontiguousarray(np.broadcast_to(
            self.convection(self.surface(state), ta, wind), ta.shape), dtype=float)
        self.kernel(state.temp, self.order, self.blocks, self.n_cells, self.cap_dt, self.cond,
                    self.q, self.inv_den, self.theta, self.emis, self.rs, self.tbot, sw, lw, ta,
                    rh, pres, h, self.dt, self.out, state.sb_old, state.acc, state.acc_abs,
                    state.imbalance, self.work)
        return h

    def stored_energy(self, temp: np.ndarray) -> np.ndarray:
        """Σ ρ c Δz T per column [J m-2], in the columns' order."""
        cap = self.capacity[self.columns.class_index[self.order]]      # (N, M) sorted
        e_sorted = np.einsum("nm,mn->n", cap, np.nan_to_num(temp[1:]))
        e = np.empty_like(e_sorted)
        e[self.order] = e_sorted
        return e

    def cells(self, state: _State) -> np.ndarray:
        """(N, M) cell temperatures in the columns' order (NaN below a column's bottom)."""
        out = np.empty((self.columns.n_columns, state.temp.shape[0] - 1))
        out[self.order] = state.temp[1:].T
        return out


def _forcing_rows(forcing: SurfaceForcing):
    names = ("shortwave_absorbed", "longwave_down", "temp_air", "relative_humidity", "pressure",
             "wind_speed")
    return [forcing.field(name) for name in names]


def _initial_state(columns: Columns, stepper_steady: _Stepper, rows, day_index) -> _State:
    """Steady column under the day-mean forcing (backward Euler with Δt → ∞, i.e. no
    storage): four steady solves, the convective coefficient refreshed between them."""
    n = columns.n_columns
    m_max = columns.n_cells_max
    means = [np.ascontiguousarray(np.asarray(r[day_index], dtype=float).mean(axis=0))
             for r in rows]
    temp = np.full((m_max + 1, n), np.nan)
    cls_sorted = columns.class_index[stepper_steady.order]
    t_mean = means[2][stepper_steady.order]
    for c, mesh in enumerate(columns.meshes):
        sel = cls_sorted == c
        temp[:mesh.n_cells + 1, sel] = t_mean[sel]
    state = _State(temp, np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
    for _ in range(4):
        stepper_steady.step(state, *means)
    return state


_OUTPUTS = ("temp_surface", "shortwave_net", "longwave_net", "sensible", "latent", "ground",
            "h_convection")


class _Run:
    """The time loop's pieces over one forcing: an interval of substeps, a periodic day,
    the energy accounting; the outputs on the forcing grid."""

    def __init__(self, stepper: _Stepper, forcing: SurfaceForcing, substeps: int,
                 outputs=_OUTPUTS, dtype=np.float64):
        self.stepper = stepper
        self.rows = _forcing_rows(forcing)
        self.substeps = substeps
        self.n_day = int(round(DAY / forcing.time_step))
        self.outputs = {name: np.empty((forcing.n_times, forcing.n_columns), dtype)
                        for name in outputs}

    def interval(self, state: _State, k_from: int, k_to: int) -> None:
        """Substeps from forcing index ``k_from`` to ``k_to`` (forcing linear in between);
        the end values are stored at ``k_to``."""
        # (float32 forcing of a long record: rows in float64, as the kernel computes)
        r0 = [np.asarray(r[k_from], dtype=float) for r in self.rows]
        r1 = [np.asarray(r[k_to], dtype=float) for r in self.rows]
        for s in range(1, self.substeps + 1):
            w = s / self.substeps
            now = [np.ascontiguousarray(b if w == 1.0 else a + w * (b - a))
                   for a, b in zip(r0, r1)]
            h = self.stepper.step(state, *now)
        out, o = self.stepper.out, self.outputs
        for name, value in (("temp_surface", out[5]), ("shortwave_net", now[0]),
                            ("longwave_net", out[0]), ("sensible", out[1]),
                            ("latent", out[2]), ("ground", out[3]), ("h_convection", h)):
            if name in o:
                o[name][k_to] = value

    def periodic_day(self, state: _State) -> np.ndarray:
        """The first day of the forcing once, wrapping onto index 0; its surface temperature
        (n_day, N)."""
        for k in range(1, self.n_day + 1):
            self.interval(state, k - 1, k % self.n_day)
        return self.outputs["temp_surface"][:self.n_day].copy()

    def record(self, state: _State) -> None:
        """The whole forcing from index 0 (the state at index 0 given)."""
        for k in range(1, len(self.rows[0])):
            self.interval(state, k - 1, k)

    def start_accounting(self, state: _State) -> np.ndarray:
        """Zero the flux integrals; the stored energy now [J m-2]."""
        state.acc[:] = 0.0
        state.acc_abs[:] = 0.0
        state.imbalance[:] = 0.0
        return self.stepper.stored_energy(state.temp)


def _spin_up(run: _Run, state: _State, tolerance: float, min_days: int, max_days: int):
    """Periodic days until the largest day-to-day change of any column's surface temperature
    is below ``tolerance`` (and at least ``min_days``); returns (days, change (N,), stored
    energy at the start of the last day)."""
    previous = None
    change = np.full(state.temp.shape[1], np.inf)
    days = 0
    while days < max_days:
        energy_start = run.start_accounting(state)     # the last day's books: periodic mode
        day = run.periodic_day(state)
        days += 1
        if previous is not None:
            change = np.max(np.abs(day - previous), axis=0)
            if np.max(change) < tolerance and days >= min_days:
                break
        previous = day
    return days, change, energy_start


def _check_run(forcing: SurfaceForcing, columns: Columns, scheme: str, mode: str, backend: str,
               substeps, tolerance: float, min_days: int, max_days: int) -> None:
    forcing.validate()
    require(scheme in SCHEMES, "surface_energy.scheme", scheme,
            f"must be one of {', '.join(SCHEMES)}")
    require(mode in ("record", "periodic"), "surface_energy.mode", mode,
            "must be 'record' or 'periodic'")
    require(backend in _KERNELS, "surface_energy.backend", backend,
            f"must be one of {', '.join(_KERNELS)}")
    require(isinstance(substeps, (int, np.integer)) and substeps >= 1, "surface_energy.substeps",
            substeps, "must be an integer >= 1")
    check_range("surface_energy.tolerance", tolerance, 0.0, 10.0, "K", low_open=True)
    require(2 <= min_days <= max_days, "surface_energy.min_days", min_days,
            f"must lie in [2, max_days = {max_days}]")
    require(forcing.n_columns == columns.n_columns, "forcing.shortwave_absorbed",
            forcing.shortwave_absorbed.shape,
            f"must have one column per column ({columns.n_columns})")
    per_day = DAY / forcing.time_step
    require(abs(per_day - round(per_day)) < 1e-9, "forcing.time_step", forcing.time_step,
            "must divide a day (86400 s) into a whole number of steps")
    n_day = int(round(per_day))
    if mode == "periodic":
        require(forcing.n_times == n_day, "forcing.shortwave_absorbed",
                forcing.shortwave_absorbed.shape,
                f"must hold one day ({n_day} instants of {forcing.time_step:g} s) in "
                "periodic mode")
    else:
        require(forcing.n_times >= n_day, "forcing.shortwave_absorbed",
                forcing.shortwave_absorbed.shape,
                f"must hold at least one day ({n_day} instants) for the spin-up")
    for name in ("shortwave_absorbed", "longwave_down"):
        value = getattr(forcing, name)
        if not value.size or not (np.isfinite(np.min(value)) and np.isfinite(np.max(value))):
            check_finite(f"forcing.{name}", value)


def solve_surface_energy(forcing: SurfaceForcing, columns: Columns,
                         convection: Callable | str | None = None,
                         scheme: str = "backward_euler", substeps: int = 1,
                         mode: str = "record", tolerance: float = 0.01, max_days: int = 60,
                         min_days: int = 2, backend: str = "numba", outputs=None,
                         output_dtype=np.float64) -> SurfaceEnergyResult:
    """Surface temperature and energy balance of N columns.

    Parameters
    ----------
    forcing : SurfaceForcing
        On a uniform grid; a day must be a whole number of ``forcing.time_step``.
    columns : Columns
        From :func:`build_columns`.
    convection : callable, str or None
        ``h(temp_surface, temp_air, wind_speed) -> [W m-2 K-1]`` (vectorised over the
        columns), a model name of ``CONVECTION_MODELS`` (through
        :func:`convection_correlation`), or None for the project's default correlation on a
        horizontal ground pixel. :func:`convection_aerodynamic` is the log-law alternative.
        Evaluated once per step with the surface temperature at the start of the step.
    scheme : {'backward_euler', 'crank_nicolson'}
        Time scheme (:data:`SCHEMES`); backward Euler by default (L-stable: see the module
        notes).
    substeps : int
        Solver steps per forcing interval (forcing linearly interpolated in between).
    mode : {'record', 'periodic'}
        ``'periodic'``: the forcing is one design day, repeated until the largest change of
        any column's surface temperature from one day to the next is below ``tolerance``;
        the result is the last day. ``'record'``: the first day of the forcing is run
        periodically the same way (spin-up), then the whole record from its first instant.
    tolerance : float
        Day-to-day change that ends the spin-up [K].
    max_days : int
        Most spin-up days (the result reports the change reached).
    min_days : int
        Fewest spin-up days (≥ 2: a change needs two days). The surface temperature settles
        before the deep cells where the surface is pinned (a very large h): then set this
        from the column's slowest decay, exp(−α π² t / L²).
    backend : {'numba', 'reference'}
        The compiled kernel or the numpy reference (same arithmetic).
    outputs : sequence of str, optional
        The (n_t, N) results kept (default all; ``temp_surface`` always): the others are
        None. A year of 2 200 columns at 600 s holds 0.9 GB per float64 output.
    output_dtype : numpy dtype
        Storage of the kept outputs (float32 for a long record).

    Returns
    -------
    SurfaceEnergyResult

    Notes
    -----
    The spin-up starts from the steady column under the day-mean forcing, so only the
    diurnal wave and the nonlinearity's offset have to settle. In record mode index 0 of the
    result is the end of the spin-up (its periodic day wraps onto the record's first instant).
    """
    _check_run(forcing, columns, scheme, mode, backend, substeps, tolerance, min_days,
               max_days)
    if convection is None or isinstance(convection, str):
        convection = convection_correlation(convection or DEFAULT_CONVECTION_MODEL)
    require(callable(convection), "surface_energy.convection", type(convection).__name__,
            "must be a callable h(temp_surface, temp_air, wind_speed), a model name or None")
    kernel = _KERNELS[backend]
    stepper = _Stepper(columns, convection, SCHEMES[scheme], forcing.time_step / substeps,
                       kernel)
    keep = tuple(_OUTPUTS) if outputs is None else tuple(dict.fromkeys(("temp_surface",
                                                                         *outputs)))
    require(set(keep) <= set(_OUTPUTS), "surface_energy.outputs", list(keep),
            f"must name outputs of {', '.join(_OUTPUTS)}")
    run = _Run(stepper, forcing, int(substeps), keep, output_dtype)
    steady = _Stepper(columns, convection, 1.0, 1.0e30, kernel)
    state = _initial_state(columns, steady, run.rows, np.arange(run.n_day))
    days, change, energy_start = _spin_up(run, state, tolerance, min_days, max_days)
    if mode == "record":
        energy_start = run.start_accounting(state)
        run.record(state)
    energy_end = stepper.stored_energy(state.temp)
    return SurfaceEnergyResult(
        **{name: run.outputs.get(name) for name in _OUTPUTS}, temp_cells=stepper.cells(state),
        energy_residual=energy_end - energy_start - state.acc, energy_scale=state.acc_abs,
        surface_imbalance=state.imbalance.copy(), spinup_days=days, spinup_change=change,
        scheme=scheme, substeps=int(substeps))
