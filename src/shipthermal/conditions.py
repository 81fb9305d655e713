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

A convection coefficient may depend on the surface temperature itself (natural convection):
a :class:`ConvectionLaw` beside ``h`` makes ``h`` the forced part and gives the natural part
as a law of ``ΔT = T_s − T_fluid``; the solver then evaluates the coefficient at the surface
temperature it solves for (:func:`law_h`), inside the surface balance's Newton iteration.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Union

import numpy as np
from numba import njit

from .errors import InputError, check_finite, require
from .units import SIGMA

__all__ = ["FixedTemperature", "HeatFlux", "Convection", "Radiation", "SurfaceBalance",
           "Adiabatic", "FaceForcing", "evaluate", "BoundaryCondition", "ConvectionLaw",
           "LAW_PARAMETERS", "law_h", "law_h_and_slope"]

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
    """Convection to a fluid: ``h (temp_fluid − T_s)``; ``h`` [W m-2 K-1], ``temp_fluid`` [K].

    With ``law`` (:class:`ConvectionLaw`), ``h`` is the forced part and the coefficient is
    evaluated at the solved surface temperature."""

    h: Value
    temp_fluid: Value
    law: "ConvectionLaw | None" = None


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
    h : convection coefficient [W m-2 K-1] (with ``law``: its forced part)
    temp_air : air temperature [K]
    law : ConvectionLaw, optional
        The coefficient's dependence on the surface temperature, evaluated by the solver at
        the surface temperature it solves for.
    """

    absorbed_shortwave: Value = 0.0
    emissivity: Value = 0.0
    longwave_in: Value | None = None
    temp_env: Value | None = None
    h: Value = 0.0
    temp_air: Value = 0.0
    law: "ConvectionLaw | None" = None


@dataclass(frozen=True)
class Adiabatic:
    """No heat flow through the face."""


# ---------------------------------------------------------------------------------------
# Temperature-dependent convection coefficients
# ---------------------------------------------------------------------------------------
LAW_PARAMETERS = ("c1", "p1", "c2", "p2", "a", "b")
"""Per face and side, the natural-convection law ``h_N(x) = max(c1 x^p1, c2 x^p2,
(a + b x^(1/6))²)`` of ``x = |ΔT|`` [K]: two power laws (horizontal plates, building
correlations) and the Churchill–Chu form of a vertical plate; unused terms are zero."""


@dataclass(frozen=True)
class ConvectionLaw:
    """The temperature dependence of a convection coefficient.

    With ``ΔT = T_s − T_fluid`` and ``x = |ΔT|``::

        h = h_N + R [(h_F^n + h_N^n)^(1/n) − h_N]
        h_N = max(c1 x^p1, c2 x^p2, (a + b x^(1/6))²)       (side: unstable or stable)

    ``h_F`` is the condition's ``h`` (the forced part), ``n`` the blending exponent, ``R`` a
    roughness multiplier of the forced part. ``n = 1, R = 1``: forced + natural (TARP);
    ``n = 2``: quadrature (MoWiTT; with ``R`` ≠ 1 the DOE-2 form); ``n = 3, R = 1``: Churchill
    (1977) mixed convection; a zero natural law leaves ``h = R h_F``.

    The side is *unstable* where the buoyant flow leaves the face freely, ``ΔT · normal_z >
    0`` (a hot face looking up, a cold face looking down), else *stable*; a vertical face
    (``normal_z = 0``) uses the unstable row for both.

    Parameters
    ----------
    natural : value
        ``(k, 2, 6)`` per face: rows [unstable, stable], columns :data:`LAW_PARAMETERS`
        ([W m-2 K-(1+p)], [-], …; ``a``, ``b`` in [W^½ m-1 K-½], [W^½ m-1 K-(½+1/6)]);
        a number, an array or ``f(t)``.
    blend : value
        ``n`` [-] (≥ 1) per face.
    multiplier : value
        ``R`` [-] (> 0) per face.
    normal_z : value
        Upward component of the unit normal pointing into the fluid [-].
    """

    natural: Value = 0.0
    blend: Value = 1.0
    multiplier: Value = 1.0
    normal_z: Value = 0.0


@njit(cache=True, inline="always")
def _power(x, p, r):
    """``x^p`` for ``x > 0`` given ``r = x^(1/3)``: the common exponents without ``pow``."""
    if p == 0.0:
        return 1.0
    if abs(p - 1.0 / 3.0) < 1e-15:
        return r
    if p == 0.25:
        return np.sqrt(np.sqrt(x))
    return x ** p


@njit(cache=True)
def law_h_and_slope(h_forced, blend, mult, nz, law, delta):
    """``(h, x ∂h/∂x)`` of a :class:`ConvectionLaw` at ``ΔT = delta`` [K] (``law`` the
    face's ``(2, 6)`` parameters). ``x ∂h/∂x`` (``x = |ΔT|``) is finite at ``ΔT = 0``: the
    convective flux ``h ΔT`` has the slope ``h + x ∂h/∂x`` there and everywhere."""
    x = abs(delta)
    side = 1 if delta * nz < 0.0 else 0      # ΔT = 0: both sides give the same h
    c1 = law[side, 0]
    c2 = law[side, 2]
    a = law[side, 4]
    b = law[side, 5]
    hn = 0.0
    gn = 0.0              # x ∂h_N/∂x
    if x > 0.0:
        r = np.cbrt(x)
        if c1 > 0.0:
            p1 = law[side, 1]
            hn = c1 * _power(x, p1, r)
            gn = p1 * hn
        if c2 > 0.0:
            p2 = law[side, 3]
            v = c2 * _power(x, p2, r)
            if v > hn:
                hn = v
                gn = p2 * v
        if b > 0.0:
            y = np.sqrt(r)
            s = a + b * y
            v = s * s
            if v > hn:
                hn = v
                gn = s * b * y / 3.0          # x d/dx (a + b x^(1/6))² = 2 s b y / 6
    if a * a > hn:
        hn = a * a
        gn = 0.0
    if hn == 0.0:
        return mult * h_forced, 0.0
    if h_forced <= 0.0:
        # no forced part: S = h_N, h = h_N whatever R and n
        return hn, gn
    if blend == 1.0:
        tot = h_forced + hn
        ratio = 1.0
    elif blend == 2.0:
        tot = np.sqrt(h_forced * h_forced + hn * hn)
        ratio = hn / tot
    elif blend == 3.0:
        tot = np.cbrt(h_forced * h_forced * h_forced + hn * hn * hn)
        q = hn / tot
        ratio = q * q
    else:
        tot = (h_forced ** blend + hn ** blend) ** (1.0 / blend)
        ratio = (hn / tot) ** (blend - 1.0)
    h = hn + mult * (tot - hn)
    # ∂S/∂h_N = (h_N / S)^(n−1)
    g = gn * (1.0 - mult + mult * ratio)
    return h, g


@njit(cache=True)
def _law_h_array(h_forced, blend, mult, nz, law, delta, out_h, out_g):
    for i in range(delta.shape[0]):
        h, g = law_h_and_slope(h_forced[i], blend[i], mult[i], nz[i], law[i], delta[i])
        out_h[i] = h
        out_g[i] = g


def law_h(h_forced, law: "ConvectionLaw", delta, return_slope: bool = False):
    """The coefficient of a :class:`ConvectionLaw` (evaluated, arrays) at ``ΔT = delta``
    [K]: the same function the solver evaluates per face (:func:`law_h_and_slope`).

    Parameters
    ----------
    h_forced : array_like
        Forced part ``h_F`` [W m-2 K-1].
    law : ConvectionLaw
        With array values (``natural`` of shape ``(..., 2, 6)``).
    delta : array_like
        ``T_s − T_fluid`` [K].
    return_slope : bool
        Also return ``x ∂h/∂x`` [W m-2 K-1].

    Returns
    -------
    numpy.ndarray
        h [W m-2 K-1], broadcast shape of the inputs.
    """
    d = np.asarray(delta, dtype=float)
    nat = np.asarray(law.natural, dtype=float)
    shape = np.broadcast_shapes(np.shape(h_forced), d.shape, np.shape(law.blend),
                                np.shape(law.multiplier), np.shape(law.normal_z),
                                nat.shape[:-2] if nat.ndim >= 2 else ())
    n = int(np.prod(shape)) if shape else 1
    def flat(v):
        return np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=float), shape)).reshape(n)
    if nat.ndim < 2:
        nat = np.zeros((2, 6)) + nat
    law_flat = np.ascontiguousarray(np.broadcast_to(nat, shape + (2, 6))).reshape(n, 2, 6)
    h = np.empty(n)
    g = np.empty(n)
    _law_h_array(flat(h_forced), flat(law.blend), flat(law.multiplier), flat(law.normal_z),
                 law_flat, flat(d), h, g)
    h, g = h.reshape(shape), g.reshape(shape)
    return (h, g) if return_slope else h


BoundaryCondition = Union[FixedTemperature, HeatFlux, Convection, Radiation, SurfaceBalance,
                          Adiabatic]


@dataclass
class FaceForcing:
    """Per-boundary-face forcing at one time (all arrays of length b).

    Faces with a :class:`ConvectionLaw` have ``law_index ≥ 0``: their ``h`` is the forced
    part and ``law_*[law_index]`` the law (compact: only those faces carry one)."""

    fixed: np.ndarray        # bool: fixed temperature
    temp_fixed: np.ndarray   # [K]
    q0: np.ndarray           # [W m-2]
    h: np.ndarray            # [W m-2 K-1]
    temp_fluid: np.ndarray   # [K]
    emissivity: np.ndarray   # [-]
    longwave_in: np.ndarray  # [W m-2]
    law_index: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))  # (b,)
    law_natural: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 6)))
    law_blend: np.ndarray = field(default_factory=lambda: np.zeros(0))
    law_multiplier: np.ndarray = field(default_factory=lambda: np.zeros(0))
    law_normal_z: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @classmethod
    def zeros(cls, b: int) -> "FaceForcing":
        z = np.zeros(b)
        return cls(np.zeros(b, bool), z.copy(), z.copy(), z.copy(), z.copy(), z.copy(), z.copy(),
                   law_index=np.full(b, -1, np.int64))

    @property
    def has_law(self) -> bool:
        """Whether some face's coefficient depends on its temperature."""
        return self.law_blend.shape[0] > 0

    def set_law(self, idx: np.ndarray, natural, blend, multiplier, normal_z) -> None:
        """Give the faces ``idx`` a law (arrays of ``len(idx)`` rows); :meth:`finish` joins
        the laws of all patches."""
        parts = self.__dict__.setdefault("_law_parts", [])
        start = sum(len(p[0]) for p in parts) + self.law_blend.shape[0]
        self.law_index[idx] = start + np.arange(len(idx))
        parts.append((natural, blend, multiplier, normal_z, idx))

    def finish(self) -> "FaceForcing":
        """Join the laws given by :meth:`set_law` (one copy instead of one per patch)."""
        parts = self.__dict__.pop("_law_parts", None)
        if parts:
            # every row from set_law, in order: its faces at hand (deriving them from
            # law_index takes 0.8 ms a step of the frigate at 0.5 m, this 0.02 ms)
            if self.law_blend.shape[0] == 0:
                self.__dict__["_law_faces"] = np.concatenate(
                    [np.asarray(p[4], np.int64) for p in parts])
            self.law_natural = np.concatenate([self.law_natural] + [p[0] for p in parts])
            self.law_blend = np.concatenate([self.law_blend] + [p[1] for p in parts])
            self.law_multiplier = np.concatenate([self.law_multiplier] + [p[2] for p in parts])
            self.law_normal_z = np.concatenate([self.law_normal_z] + [p[3] for p in parts])
        return self

    @property
    def law_faces(self) -> np.ndarray:
        """The face of every law row (``law_index``'s inverse): the solver's loops over
        the faces with a law take these, not every face (an even share per thread: the
        frigate's law faces are the first half of its boundary faces, the outer sides)."""
        faces = self.__dict__.get("_law_faces")
        if faces is None or faces.shape[0] != self.law_blend.shape[0]:
            has = self.law_index >= 0
            faces = np.empty(self.law_blend.shape[0], np.int64)
            faces[self.law_index[has]] = np.flatnonzero(has)
            self.__dict__["_law_faces"] = faces
        return faces


def evaluate(value: Value, t: float, n: int, field: str, check: bool = True) -> np.ndarray:
    """Evaluate a condition value at time ``t`` for a patch of ``n`` faces (``check``
    False: its finiteness is left to :func:`plausible` on the joined forcing)."""
    v = value(t) if callable(value) else value
    arr = np.asarray(v, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    require(arr.shape == (n,), field, arr.shape,
            f"must be a number or an array with one value per face of the patch ({n})")
    if check:
        check_finite(field, arr)
    return arr


def fill(forcing: FaceForcing, idx: np.ndarray, bc: BoundaryCondition, t: float, field: str,
         check: bool = True) -> None:
    """Write one patch's condition at time ``t`` into ``forcing`` (faces ``idx``).

    ``check`` False leaves out the per-value checks of finiteness and range (a model's
    steps: :func:`plausible` checks the joined forcing in one pass and the model fills it
    again with the checks when it fails, for their message); the checks of shape and of
    the condition's structure stay."""
    n = len(idx)

    def ev(name: str, value):
        return evaluate(value, t, n, f"{field}.{name}", check)

    if isinstance(bc, FixedTemperature):
        temp = ev("temperature", bc.temperature)
        if check:
            require(bool(np.all(temp > 0)), f"{field}.temperature", float(temp.min()),
                    "must be > 0 K")
        forcing.fixed[idx] = True
        forcing.temp_fixed[idx] = temp
    elif isinstance(bc, HeatFlux):
        forcing.q0[idx] += ev("flux", bc.flux)
    elif isinstance(bc, Convection):
        h = ev("h", bc.h)
        if check:
            require(bool(np.all(h >= 0)), f"{field}.h", float(h.min()), "must be ≥ 0 W m-2 K-1")
        forcing.h[idx] = h
        forcing.temp_fluid[idx] = ev("temp_fluid", bc.temp_fluid)
        if bc.law is not None:
            _fill_law(forcing, idx, bc.law, t, f"{field}.law", check)
    elif isinstance(bc, Radiation):
        eps = ev("emissivity", bc.emissivity)
        if check:
            _check_emissivity(f"{field}.emissivity", eps)
        forcing.emissivity[idx] = eps
        forcing.longwave_in[idx] = SIGMA * ev("temp_env", bc.temp_env) ** 4
    elif isinstance(bc, SurfaceBalance):
        forcing.q0[idx] += ev("absorbed_shortwave", bc.absorbed_shortwave)
        eps = ev("emissivity", bc.emissivity)
        if check:
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
        if check:
            require(bool(np.all(h >= 0)), f"{field}.h", float(h.min()), "must be ≥ 0 W m-2 K-1")
        forcing.h[idx] = h
        if bc.law is not None:
            forcing.temp_fluid[idx] = ev("temp_air", bc.temp_air)
            _fill_law(forcing, idx, bc.law, t, f"{field}.law", check)
        else:
            forcing.temp_fluid[idx] = ev("temp_air", bc.temp_air) if np.any(h > 0) else 0.0
    elif isinstance(bc, Adiabatic):
        pass
    else:
        raise InputError(field, type(bc).__name__,
                         "must be one of FixedTemperature, HeatFlux, Convection, Radiation, "
                         "SurfaceBalance, Adiabatic")


def plausible(forcing: FaceForcing) -> bool:
    """Whether a forcing filled without checks (:func:`fill` ``check=False``) passes what
    the checks test, in one pass over the joined arrays: every value finite, ``h ≥ 0``,
    emissivities in [0, 1], fixed temperatures > 0, law parameters ≥ 0, blends ≥ 1 and
    multipliers > 0. False may also mean a sum overflowed: the caller fills again with
    the checks, which then either name the bad value or find none."""
    f = forcing
    arrays = (f.temp_fixed, f.q0, f.h, f.temp_fluid, f.emissivity, f.longwave_in,
              f.law_natural, f.law_blend, f.law_multiplier, f.law_normal_z)
    with np.errstate(over="ignore", invalid="ignore"):
        if not np.isfinite(sum(float(np.sum(a)) for a in arrays)):
            return False
    if len(f.h) and (f.h.min() < 0.0 or f.emissivity.min() < 0.0 or f.emissivity.max() > 1.0):
        return False
    if f.fixed.any() and f.temp_fixed[f.fixed].min() <= 0.0:
        return False
    if f.law_blend.shape[0] and (f.law_natural.min() < 0.0 or f.law_blend.min() < 1.0
                                 or f.law_multiplier.min() <= 0.0):
        return False
    return True


def _fill_law(forcing: FaceForcing, idx: np.ndarray, law: ConvectionLaw, t: float,
              field: str, check: bool = True) -> None:
    n = len(idx)
    nat = law.natural(t) if callable(law.natural) else law.natural
    nat = np.asarray(nat, dtype=float)
    nat = np.broadcast_to(nat, (n, 2, len(LAW_PARAMETERS))) if nat.ndim <= 2 else nat
    require(nat.shape == (n, 2, len(LAW_PARAMETERS)), f"{field}.natural", nat.shape,
            f"must be ({n}, 2, {len(LAW_PARAMETERS)}): per face, [unstable, stable] × "
            f"{', '.join(LAW_PARAMETERS)}")
    if check:
        low = float(nat.min()) if nat.size else 0.0
        require(np.isfinite(nat.sum()) and low >= 0.0, f"{field}.natural", low,
                "must be finite and ≥ 0")
    blend = evaluate(law.blend, t, n, f"{field}.blend", check)
    if check:
        require(bool(np.all(blend >= 1)), f"{field}.blend", float(blend.min()), "must be ≥ 1")
    mult = evaluate(law.multiplier, t, n, f"{field}.multiplier", check)
    if check:
        require(bool(np.all(mult > 0)), f"{field}.multiplier", float(mult.min()),
                "must be > 0")
    nz = evaluate(law.normal_z, t, n, f"{field}.normal_z", check)
    forcing.set_law(idx, np.ascontiguousarray(nat), blend, mult, nz)


def _check_emissivity(field: str, eps: np.ndarray, allow_zero: bool = False) -> None:
    lo_ok = np.all(eps >= 0) if allow_zero else np.all(eps > 0)
    if not (lo_ok and np.all(eps <= 1)):
        bad = eps[(eps > 1) | ((eps < 0) if allow_zero else (eps <= 0))]
        raise InputError(field, float(bad[0]), f"must lie in {'[' if allow_zero else '('}0, 1]")
