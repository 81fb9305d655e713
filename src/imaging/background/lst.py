"""Land surface temperature from TIRS band 10: the generalized single-channel algorithm.

Formulation (stated, with its coefficients):

* **Atmospheric functions** (Jiménez-Muñoz, Sobrino, Skoković, Mattar & Cristóbal 2014,
  "Land surface temperature retrieval methods from Landsat-8 Thermal Infrared Sensor data",
  IEEE GRSL 11(10):1840–1843, eq. 3 and Table I, TIRS band 10, GAPRI database)::

      [psi1]   [ 0.04019   0.02916   1.01523] [w^2]
      [psi2] = [-0.38333  -1.50294   0.20324] [w  ]
      [psi3]   [ 0.00918   1.36072  -0.27514] [1  ]

  with ``w`` the total column water vapour [g cm-2]; ``psi1 = 1/tau``,
  ``psi2 = -L_down - L_up/tau``, ``psi3 = L_down``.
* **Radiative transfer equation** (the same paper, eq. 1) for a Lambertian surface::

      L_sen = [eps * B(T_s) + (1 - eps) * L_down] * tau + L_up

* **Inversion**: ``B(T_s) = (psi1 * L_sen + psi2) / eps + psi3`` (eq. 2), then ``T_s`` from
  ``B`` by the band's Planck inversion with K1/K2 (``method="planck"``, default, exact for
  the band model) or by the paper's first-order expansion ``T_s = gamma*[...] + delta``
  with ``gamma = T_sen^2/(b_gamma L_sen)``, ``delta = T_sen - T_sen^2/b_gamma`` and
  ``b_gamma = 1324 K`` for band 10 (``method="taylor"``).
* **Emissivity** by the NDVI thresholds method (NDVI-THM; Sobrino, Jiménez-Muñoz & Paolini
  2004, RSE 90:434–440, §4.1): bare soil (NDVI < 0.2) ``eps = a + b rho_red``; full vegetation
  (NDVI > 0.5) ``eps = eps_v``; mixed ``eps = eps_v P_v + eps_s (1 - P_v) + C`` with
  ``P_v = ((NDVI - 0.2)/(0.5 - 0.2))^2`` and cavity term ``C = (1 - eps_s) eps_v F (1 - P_v)``,
  ``F = 0.55``. The coefficients are band-specific; named sets in
  :data:`EMISSIVITY_PARAMETERS`:

  - ``"tirs_b10"`` (default, TIRS band 10): soil ``eps = 0.973 - 0.047 rho_red`` (Skoković et
    al. 2014, ESA LPVE), ``eps_s = 0.9668``, ``eps_v = 0.9863`` (Yu, Guo & Wu 2014, Remote
    Sens. 6:9829, ASTER spectral library convolved with the band-10 response), as compiled
    by Sekertekin & Bonafoni 2020 (Remote Sens. 12:294);
  - ``"tm6_sobrino2004"``: the original Landsat-5 TM band-6 set, soil ``0.979 - 0.035
    rho_red``, ``eps_s = 0.97``, ``eps_v = 0.99`` (Sobrino et al. 2004). On TIRS band 10 it
    gives emissivities up to ~0.008 higher over bare soil (~0.5 K colder LST).

  Water (NDVI < 0) is not covered by the method; the usual value ``eps = 0.991`` (Sobrino et
  al. 2008, IEEE TGRS 46(2)) is used.

The psi fit is calibrated for ``w`` up to about 3 g cm-2 (errors grow above, JM2014 §IV);
values outside ``[0.2, 6]`` g cm-2 are rejected because the fit then gives unphysical
(negative) ``L_down``.

**Stated accuracy** (measured in ``tests/background/test_bg_lst.py``):

* the inversion itself (``method="planck"``) is exact for the band model; DN quantisation of
  band 10 adds ~2 mK; the Taylor form adds < 0.15 K for ``|T_s - T_sen| < 4 K``;
* the K1/K2 band model against spectral integration over 10.60–11.19 µm: 0.13–0.22 K;
* against an independent atmosphere (LOWTRAN 7 mid-latitude summer / winter with the
  paper's Navy maritime aerosol at 23 km, spectral forward model): psi(w) gives LST
  **2–3 K too cold** (summer -2.2 … -3.1 K, winter -1.7 … -2.2 K), because the JM2014 fit has
  no aerosol and a 12–15 % larger path radiance than LOWTRAN. JM2014 quote ~1–1.5 K for
  clear-sky ``w < 3`` g cm-2 against their own simulations. Treat the background LST as
  carrying a 2–3 K systematic uncertainty unless the water vapour and aerosol are known.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from shipthermal.errors import InputError, check_range

from .landsat.radiometry import brightness_temperature_to_radiance, radiance_to_brightness_temperature

__all__ = [
    "JIMENEZ_MUNOZ_2014_B10",
    "SOBRINO_2004",
    "EMISSIVITY_PARAMETERS",
    "DEFAULT_EMISSIVITY_MODEL",
    "AtmosphereB10",
    "atmospheric_functions",
    "ndvi",
    "emissivity_ndvi_threshold",
    "at_sensor_radiance",
    "lst_single_channel",
]

JIMENEZ_MUNOZ_2014_B10 = np.array([
    [0.04019, 0.02916, 1.01523],
    [-0.38333, -1.50294, 0.20324],
    [0.00918, 1.36072, -0.27514],
])
"""Coefficients c_ij of psi_i = c_i1 w^2 + c_i2 w + c_i3 for TIRS band 10 (JM2014, Table I)."""

B_GAMMA_B10 = 1324.0
"""b_gamma of the Taylor form for TIRS band 10 [K] (JM2014, eq. 2 text)."""

EMISSIVITY_PARAMETERS = {
    "tirs_b10": {
        "ndvi_soil": 0.2, "ndvi_veg": 0.5, "soil_a": 0.973, "soil_b": -0.047,
        "eps_soil": 0.9668, "eps_veg": 0.9863, "shape_factor": 0.55,
        "ndvi_water": 0.0, "eps_water": 0.991,
    },
    "tm6_sobrino2004": {
        "ndvi_soil": 0.2, "ndvi_veg": 0.5, "soil_a": 0.979, "soil_b": -0.035,
        "eps_soil": 0.97, "eps_veg": 0.99, "shape_factor": 0.55,
        "ndvi_water": 0.0, "eps_water": 0.991,
    },
}
"""NDVI-thresholds emissivity parameter sets by name (module docstring for the sources).

``tirs_b10``: TIRS band 10 (Skoković et al. 2014 soil line; Yu et al. 2014 soil and vegetation
emissivities). ``tm6_sobrino2004``: Landsat TM band 6 (Sobrino et al. 2004). Water: Sobrino et
al. 2008 for both."""

DEFAULT_EMISSIVITY_MODEL = "tirs_b10"

SOBRINO_2004 = EMISSIVITY_PARAMETERS["tm6_sobrino2004"]
"""The TM band-6 set of Sobrino et al. 2004 (kept under its historical name)."""

WATER_VAPOUR_RANGE = (0.2, 6.0)
"""Accepted total column water vapour [g cm-2]."""


@dataclass(frozen=True)
class AtmosphereB10:
    """Atmospheric quantities of TIRS band 10.

    Attributes
    ----------
    water_vapour : float
        Total column water vapour [g cm-2].
    psi : ndarray, shape (3,)
        Atmospheric functions psi1 [-], psi2 [W m-2 sr-1 um-1], psi3 [W m-2 sr-1 um-1].
    tau : float
        Surface-to-sensor transmittance [-].
    l_up : float
        Upwelling path radiance [W m-2 sr-1 um-1].
    l_down : float
        Downwelling hemispheric sky radiance / pi [W m-2 sr-1 um-1].
    """

    water_vapour: float
    psi: np.ndarray
    tau: float
    l_up: float
    l_down: float


def atmospheric_functions(water_vapour: float) -> AtmosphereB10:
    """TIRS band-10 atmospheric functions from water vapour (JM2014 eq. 3, Table I).

    Parameters
    ----------
    water_vapour : float
        Total column water vapour [g cm-2], in [0.2, 6].

    Returns
    -------
    AtmosphereB10
        psi1..psi3 and the equivalent tau, L_up, L_down.
    """
    check_range("water_vapour", water_vapour, *WATER_VAPOUR_RANGE, unit="g cm-2")
    w = float(water_vapour)
    psi = JIMENEZ_MUNOZ_2014_B10 @ np.array([w * w, w, 1.0])
    tau = 1.0 / psi[0]
    l_down = psi[2]
    l_up = -tau * (psi[1] + psi[2])
    return AtmosphereB10(w, psi, float(tau), float(l_up), float(l_down))


def ndvi(red, nir):
    """Normalised difference vegetation index ``(nir - red)/(nir + red)`` [-].

    Parameters
    ----------
    red, nir : array_like
        Reflectance of OLI band 4 and band 5 [-].
    """
    red = np.asarray(red, dtype=np.float64)
    nir = np.asarray(nir, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = (nir - red) / (nir + red)
    return np.where(np.isfinite(out), out, np.nan)


def emissivity_ndvi_threshold(ndvi_value, red, params: str | dict | None = None):
    """Band-10 surface emissivity by the NDVI thresholds method.

    Parameters
    ----------
    ndvi_value : array_like
        NDVI [-].
    red : array_like
        Red reflectance [-] (used on bare soil).
    params : str or dict, optional
        A name in :data:`EMISSIVITY_PARAMETERS` (default ``"tirs_b10"``), or a dict of
        overrides of the default set (same keys).

    Returns
    -------
    ndarray
        Emissivity [-].

    Notes
    -----
    Sobrino et al. 2004 (RSE 90), §4.1 "NDVI_THM", with the band-specific coefficients of the
    chosen set; water value from Sobrino et al. 2008.
    """
    p = _emissivity_parameters(params)
    v = np.asarray(ndvi_value, dtype=np.float64)
    red = np.asarray(red, dtype=np.float64)
    pv = np.clip((v - p["ndvi_soil"]) / (p["ndvi_veg"] - p["ndvi_soil"]), 0.0, 1.0) ** 2
    cavity = (1.0 - p["eps_soil"]) * p["eps_veg"] * p["shape_factor"] * (1.0 - pv)
    mixed = p["eps_veg"] * pv + p["eps_soil"] * (1.0 - pv) + cavity
    soil = p["soil_a"] + p["soil_b"] * red
    eps = np.where(v < p["ndvi_soil"], soil, np.where(v > p["ndvi_veg"], p["eps_veg"], mixed))
    eps = np.where(v < p["ndvi_water"], p["eps_water"], eps)
    return np.where(np.isfinite(v), eps, np.nan)


def _emissivity_parameters(params) -> dict:
    if params is None:
        params = DEFAULT_EMISSIVITY_MODEL
    if isinstance(params, str):
        if params not in EMISSIVITY_PARAMETERS:
            raise InputError("emissivity_model", params, f"must be one of {sorted(EMISSIVITY_PARAMETERS)}",
                             "or a dict of overrides of the default set")
        return dict(EMISSIVITY_PARAMETERS[params])
    p = dict(EMISSIVITY_PARAMETERS[DEFAULT_EMISSIVITY_MODEL])
    unknown = set(params) - set(p)
    if unknown:
        raise InputError("emissivity_params", sorted(unknown), f"keys must be among {sorted(p)}")
    p.update(params)
    return p


def at_sensor_radiance(temp_surface, emissivity, atmosphere: AtmosphereB10, k1: float, k2: float):
    """Forward model: TOA band-10 radiance of a surface (RTE, JM2014 eq. 1).

    Parameters
    ----------
    temp_surface : array_like
        Land surface temperature [K].
    emissivity : array_like
        Band emissivity [-].
    atmosphere : AtmosphereB10
    k1, k2 : float
        Band constants [W m-2 sr-1 um-1], [K]; ``B(T) = k1/(exp(k2/T) - 1)``.

    Returns
    -------
    ndarray
        At-sensor radiance [W m-2 sr-1 um-1].
    """
    eps = np.asarray(emissivity, dtype=np.float64)
    b = brightness_temperature_to_radiance(temp_surface, k1, k2)
    return (eps * b + (1.0 - eps) * atmosphere.l_down) * atmosphere.tau + atmosphere.l_up


def lst_single_channel(radiance, emissivity, atmosphere: AtmosphereB10, k1: float, k2: float,
                       method: str = "planck"):
    """Generalized single-channel LST retrieval for TIRS band 10.

    Parameters
    ----------
    radiance : array_like
        At-sensor band-10 radiance [W m-2 sr-1 um-1].
    emissivity : array_like
        Surface emissivity [-] in (0, 1].
    atmosphere : AtmosphereB10
        From :func:`atmospheric_functions`.
    k1, k2 : float
        Band constants from the MTL [W m-2 sr-1 um-1], [K].
    method : {"planck", "taylor"}
        ``"planck"`` inverts B(T_s) exactly with K1/K2; ``"taylor"`` is JM2014's
        ``gamma/delta`` linearisation around the brightness temperature.

    Returns
    -------
    ndarray
        Land surface temperature [K] (NaN where the radiance is NaN).

    Notes
    -----
    JM2014 eq. 2: ``T_s = gamma [ (psi1 L_sen + psi2)/eps + psi3 ] + delta``.
    """
    if method not in ("planck", "taylor"):
        raise InputError("lst_method", method, "must be 'planck' or 'taylor'")
    eps = np.asarray(emissivity, dtype=np.float64)
    finite_eps = eps[np.isfinite(eps)]
    if finite_eps.size and (finite_eps.min() <= 0 or finite_eps.max() > 1):
        bad = finite_eps[(finite_eps <= 0) | (finite_eps > 1)][0]
        raise InputError("emissivity", float(bad), "must lie in (0, 1]")
    rad = np.asarray(radiance, dtype=np.float64)
    psi1, psi2, psi3 = atmosphere.psi
    b_surface = (psi1 * rad + psi2) / eps + psi3
    if method == "planck":
        return radiance_to_brightness_temperature(b_surface, k1, k2)
    t_sen = radiance_to_brightness_temperature(rad, k1, k2)
    gamma = t_sen ** 2 / (B_GAMMA_B10 * rad)
    delta = t_sen - t_sen ** 2 / B_GAMMA_B10
    return gamma * b_surface + delta
