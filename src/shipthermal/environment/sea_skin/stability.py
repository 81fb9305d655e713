"""Monin–Obukhov stability functions of the atmospheric surface layer over the sea (COARE).

References in brackets: :mod:`shipthermal.environment.sea_skin`.
"""

from __future__ import annotations

import math

import numpy as np

from .constants import _ZETA_CAP


def _psi_blend(zeta, kansas, convective):
    f = zeta * zeta / (1.0 + zeta * zeta)
    return (1.0 - f) * kansas + f * convective


def _psi_convective(x):
    return (1.5 * np.log((x * x + x + 1.0) / 3.0) - math.sqrt(3.0)
            * np.arctan((2.0 * x + 1.0) / math.sqrt(3.0)) + math.pi / math.sqrt(3.0))


def psi_wind(zeta, stable_a=0.7, kansas=15.0, convective=10.15):
    """Integrated stability function of wind speed ψ_u(ζ) [-], ζ = z/L.

    Parameters
    ----------
    zeta : array_like
        Stability parameter z/L [-].
    stable_a, kansas, convective : float
        The coefficient a of the stable form and the Kansas and free-convection constants of
        the unstable form (defaults: COARE 3.5/3.6, [C36]; the COARE first guess uses
        a = 1, 18, 10).

    Notes
    -----
    Unstable (ζ < 0): the Kansas form with ``x = (1 − 15ζ)^(1/4)`` blended with the
    free-convection form with ``y = (1 − 10.15ζ)^(1/3)`` by ``ζ²/(1 + ζ²)`` ([F96a], [G00]).
    Stable: ``−(a ζ + b (ζ − c/d) exp(−d ζ) + b c/d)``, b = 3/4, c = 5, d = 0.35 ([BH91],
    whose a = 1 COARE 3.5/3.6 lowers to 0.7, [C36]); d ζ capped at 50.
    """
    z = np.asarray(zeta, dtype=float)
    zs = np.maximum(z, 0.0)
    dz = np.minimum(0.35 * zs, _ZETA_CAP)
    stable = -(stable_a * zs + 0.75 * (zs - 5.0 / 0.35) * np.exp(-dz) + 0.75 * 5.0 / 0.35)
    zu = np.minimum(z, 0.0)
    x = (1.0 - kansas * zu) ** 0.25
    psik = 2.0 * np.log((1.0 + x) / 2.0) + np.log((1.0 + x * x) / 2.0) - 2.0 * np.arctan(x) \
        + 0.5 * math.pi
    psic = _psi_convective((1.0 - convective * zu) ** (1.0 / 3.0))
    return np.where(z < 0.0, _psi_blend(zu, psik, psic), stable)


def psi_temperature(zeta):
    """Integrated stability function of temperature and humidity ψ_t(ζ) [-], ζ = z/L.

    Notes
    -----
    Unstable: Kansas ``2 ln((1 + x)/2)``, ``x = (1 − 15ζ)^(1/2)``, blended with the
    free-convection form, ``y = (1 − 34.15ζ)^(1/3)``, by ``ζ²/(1 + ζ²)`` ([F96a], [G00]).
    Stable: ``−((1 + 2/3 a ζ)^(3/2) + b (ζ − c/d) exp(−d ζ) + b c/d − 1)``, a = 1, b = 2/3,
    c = 5, d = 0.35 ([BH91]); as [C36].
    """
    z = np.asarray(zeta, dtype=float)
    zs = np.maximum(z, 0.0)
    dz = np.minimum(0.35 * zs, _ZETA_CAP)
    b = 2.0 / 3.0
    stable = -((1.0 + 2.0 / 3.0 * zs) ** 1.5 + b * (zs - 5.0 / 0.35) * np.exp(-dz)
               + b * 5.0 / 0.35 - 1.0)
    zu = np.minimum(z, 0.0)
    psik = 2.0 * np.log((1.0 + np.sqrt(1.0 - 15.0 * zu)) / 2.0)
    psic = _psi_convective((1.0 - 34.15 * zu) ** (1.0 / 3.0))
    return np.where(z < 0.0, _psi_blend(zu, psik, psic), stable)
