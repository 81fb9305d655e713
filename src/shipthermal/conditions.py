"""Boundary conditions as data.

A boundary condition is a small frozen dataclass: a *kind* plus values. Each value may be

* a number (same on every face of the patch),
* an array with one entry per face of the patch,
* a function of time ``f(t) -> number or array`` with ``t`` in seconds since the start of
  the simulation.

All kinds compile to one per-face surface balance (:class:`FaceForcing`): the net heat flux
into the body through a face at surface temperature ``T_s`` is

    q(T_s) = q_0 + h (T_fluid − T_s) + ε (L_in − σ T_s⁴)            [W m-2]

with ``q_0`` the absorbed short-wave plus any prescribed flux, ``h`` a convection coefficient,
``ε`` the long-wave emissivity (= absorptivity, Kirchhoff) and ``L_in`` the incident long-wave
irradiance; or a fixed surface temperature.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Union

import numpy as np

from .errors import InputError, check_finite, require
from .units import SIGMA

__all__ = ["FixedTemperature", "HeatFlux", "Convection", "Radiation", "SurfaceBalance",
           "Adiabatic", "FaceForcing", "evaluate", "BoundaryCondition"]

Value = Union[float, np.ndarray, Callable[[float], Union[float, np.ndarray]]]


@dataclass(frozen=True)
class FixedTemperature:
    """Prescribed surface temperature ``temperature`` [K]."""

    temperature: Value


@dataclass(frozen=True)
class HeatFlux:
    """Prescribed heat flux into the body ``flux`` [W m-2] (negative: out of the body)."""

    flux: Value


@dataclass(frozen=True)
class Convection:
    """Convection to a fluid: ``h (temp_fluid − T_s)``; ``h`` [W m-2 K-1], ``temp_fluid`` [K]."""

    h: Value
    temp_fluid: Value


@dataclass(frozen=True)
class Radiation:
    """Grey long-wave exchange with black surroundings: ``ε σ (temp_env⁴ − T_s⁴)``.

    ``emissivity`` [-] in (0, 1], ``temp_env`` [K].
    """

    emissivity: Value
    temp_env: Value


@dataclass(frozen=True)
class SurfaceBalance:
    """Outdoor surface energy balance.

    ``q = absorbed_shortwave + h (temp_air − T_s) + ε (longwave_in − σ T_s⁴)``

    Parameters
    ----------
    absorbed_shortwave : absorbed solar flux (already × absorptivity) [W m-2]
    emissivity : long-wave emissivity ε [-]
    longwave_in : incident long-wave irradiance [W m-2] (sky, sea, surroundings weighted by
        view factors); give this or ``temp_env``
    temp_env : equivalent black-body temperature of the surroundings [K]
    h : convection coefficient [W m-2 K-1]
    temp_air : air temperature [K]
    """

    absorbed_shortwave: Value = 0.0
    emissivity: Value = 0.0
    longwave_in: Value | None = None
    temp_env: Value | None = None
    h: Value = 0.0
    temp_air: Value = 0.0


@dataclass(frozen=True)
class Adiabatic:
    """No heat flow through the face."""


BoundaryCondition = Union[FixedTemperature, HeatFlux, Convection, Radiation, SurfaceBalance,
                          Adiabatic]


@dataclass
class FaceForcing:
    """Per-boundary-face forcing at one time (all arrays of length b)."""

    fixed: np.ndarray        # bool: fixed temperature
    temp_fixed: np.ndarray   # [K]
    q0: np.ndarray           # [W m-2]
    h: np.ndarray            # [W m-2 K-1]
    temp_fluid: np.ndarray   # [K]
    emissivity: np.ndarray   # [-]
    longwave_in: np.ndarray  # [W m-2]

    @classmethod
    def zeros(cls, b: int) -> "FaceForcing":
        z = np.zeros(b)
        return cls(np.zeros(b, bool), z.copy(), z.copy(), z.copy(), z.copy(), z.copy(), z.copy())


def evaluate(value: Value, t: float, n: int, field: str) -> np.ndarray:
    """Evaluate a condition value at time ``t`` for a patch of ``n`` faces."""
    v = value(t) if callable(value) else value
    arr = np.asarray(v, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    require(arr.shape == (n,), field, arr.shape,
            f"must be a number or an array with one value per face of the patch ({n})")
    check_finite(field, arr)
    return arr


def fill(forcing: FaceForcing, idx: np.ndarray, bc: BoundaryCondition, t: float, field: str) -> None:
    """Write one patch's condition at time ``t`` into ``forcing`` (faces ``idx``)."""
    n = len(idx)

    def ev(name: str, value):
        return evaluate(value, t, n, f"{field}.{name}")

    if isinstance(bc, FixedTemperature):
        temp = ev("temperature", bc.temperature)
        require(bool(np.all(temp > 0)), f"{field}.temperature", float(temp.min()), "must be > 0 K")
        forcing.fixed[idx] = True
        forcing.temp_fixed[idx] = temp
    elif isinstance(bc, HeatFlux):
        forcing.q0[idx] += ev("flux", bc.flux)
    elif isinstance(bc, Convection):
        h = ev("h", bc.h)
        require(bool(np.all(h >= 0)), f"{field}.h", float(h.min()), "must be ≥ 0 W m-2 K-1")
        forcing.h[idx] = h
        forcing.temp_fluid[idx] = ev("temp_fluid", bc.temp_fluid)
    elif isinstance(bc, Radiation):
        eps = ev("emissivity", bc.emissivity)
        _check_emissivity(f"{field}.emissivity", eps)
        forcing.emissivity[idx] = eps
        forcing.longwave_in[idx] = SIGMA * ev("temp_env", bc.temp_env) ** 4
    elif isinstance(bc, SurfaceBalance):
        forcing.q0[idx] += ev("absorbed_shortwave", bc.absorbed_shortwave)
        eps = ev("emissivity", bc.emissivity)
        _check_emissivity(f"{field}.emissivity", eps, allow_zero=True)
        forcing.emissivity[idx] = eps
        if bc.longwave_in is not None and bc.temp_env is not None:
            raise InputError(f"{field}", "longwave_in and temp_env", "give one of them, not both")
        if bc.longwave_in is not None:
            forcing.longwave_in[idx] = ev("longwave_in", bc.longwave_in)
        elif bc.temp_env is not None:
            forcing.longwave_in[idx] = SIGMA * ev("temp_env", bc.temp_env) ** 4
        elif np.any(eps > 0):
            raise InputError(f"{field}.longwave_in", None,
                             "is needed when emissivity > 0 (or give temp_env)")
        h = ev("h", bc.h)
        require(bool(np.all(h >= 0)), f"{field}.h", float(h.min()), "must be ≥ 0 W m-2 K-1")
        forcing.h[idx] = h
        forcing.temp_fluid[idx] = ev("temp_air", bc.temp_air) if np.any(h > 0) else 0.0
    elif isinstance(bc, Adiabatic):
        pass
    else:
        raise InputError(field, type(bc).__name__,
                         "must be one of FixedTemperature, HeatFlux, Convection, Radiation, "
                         "SurfaceBalance, Adiabatic")


def _check_emissivity(field: str, eps: np.ndarray, allow_zero: bool = False) -> None:
    lo_ok = np.all(eps >= 0) if allow_zero else np.all(eps > 0)
    if not (lo_ok and np.all(eps <= 1)):
        bad = eps[(eps > 1) | ((eps < 0) if allow_zero else (eps <= 0))]
        raise InputError(field, float(bad[0]), f"must lie in {'[' if allow_zero else '('}0, 1]")
