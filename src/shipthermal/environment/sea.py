"""The sea as a radiating, reflecting boundary of the ship: SST, long-wave up, albedo.

Sea surface temperature with a small diurnal warming cycle, long-wave leaving the sea
(emitted + reflected sky) and short-wave reflected by the sea (albedo for direct and diffuse
light, Taylor et al. 1996). The sea's emissivity (flat: Fresnel with water's complex index;
wind-roughened: the imaging's Cox-Munk model) is optics both stages share:
:mod:`shipthermal.optics`.

Temperatures in K, irradiance in W m-2, angles in degrees.
"""

from __future__ import annotations

import numpy as np

from shipthermal.parameters import SEA_EMISSIVITY
from shipthermal.units import SIGMA

__all__ = [
    "SEA_EMISSIVITY",
    "sst_diurnal",
    "sea_longwave_up",
    "sea_albedo_direct",
    "SEA_ALBEDO_DIFFUSE",
    "sea_reflected_shortwave",
]

SEA_ALBEDO_DIFFUSE = 0.06
"""Sea albedo for diffuse (sky) short-wave [-]: Payne (1972), J. Atmos. Sci. 29,
959–970 (≈ 0.06 for overcast skies), the value adopted by Taylor et al. (1996)."""


def sst_diurnal(hour_local, temp_sea_mean, amplitude=0.15, hour_peak=14.0):
    """Sea surface temperature with a sinusoidal diurnal cycle.

    Parameters
    ----------
    hour_local : array_like
        Local solar-ish clock time [h] (any real number; the cycle is 24 h periodic).
    temp_sea_mean : array_like
        Daily mean bulk SST [K].
    amplitude : array_like
        Half the diurnal range [K].
    hour_peak : float
        Local time of the daily maximum [h].

    Returns
    -------
    numpy.ndarray
        ``T_mean + A cos(2π (h − h_peak) / 24)`` [K].

    Notes
    -----
    Kawai & Wada (2007), "Diurnal sea surface temperature variation and its impact on
    the atmosphere and ocean: a review", J. Oceanogr. 63, 721–744: the bulk-SST
    diurnal range is typically a few tenths of a kelvin, with the maximum in the early
    afternoon (≈ 13–15 LT); it reaches > 1–3 K only under calm, sunny conditions. The
    shape here is the first harmonic only (the real curve rises faster than it falls).
    The default amplitude 0.15 K (range 0.3 K) is an ASSUMPTION within that range.
    """
    h = np.asarray(hour_local, dtype=float)
    return np.asarray(temp_sea_mean, dtype=float) + np.asarray(amplitude, dtype=float) * \
        np.cos(2.0 * np.pi * (h - hour_peak) / 24.0)


def sea_longwave_up(temp_sea, longwave_down_wm2, emissivity=SEA_EMISSIVITY):
    """Long-wave irradiance leaving the sea surface [W m-2].

    Parameters
    ----------
    temp_sea : array_like
        Sea skin temperature [K].
    longwave_down_wm2 : array_like
        Downwelling sky long-wave irradiance [W m-2].
    emissivity : array_like
        Sea emissivity [-].

    Returns
    -------
    numpy.ndarray
        ``ε σ T_sea^4 + (1 − ε) L_down`` (emitted + reflected sky; Kirchhoff) [W m-2].
        Divide by σ and take the 4th root for the sea's effective radiating
        temperature seen by a ship face.
    """
    eps = np.asarray(emissivity, dtype=float)
    return eps * SIGMA * np.asarray(temp_sea, dtype=float) ** 4 + \
        (1.0 - eps) * np.asarray(longwave_down_wm2, dtype=float)


def sea_albedo_direct(zenith):
    """Sea albedo for the direct solar beam, Taylor et al. (1996).

    Parameters
    ----------
    zenith : array_like
        Solar zenith angle [deg].

    Returns
    -------
    numpy.ndarray
        ``0.037 / (1.1 μ^1.4 + 0.15)`` with μ = cos(zenith) (μ clipped at 0) [-].

    Notes
    -----
    Taylor, J. P., Edwards, J. M., Glew, M. D., Hignett, P. & Slingo, A. (1996),
    "Studies with a flexible new radiation code. II: Comparisons with aircraft
    short-wave observations", Q. J. R. Meteorol. Soc. 122, 839–861; a fit to
    Payne's (1972) measured albedos. Values: 0.0296 at μ = 1, 0.247 at μ = 0.
    """
    mu = np.clip(np.cos(np.radians(np.asarray(zenith, dtype=float))), 0.0, 1.0)
    return 0.037 / (1.1 * mu ** 1.4 + 0.15)


def sea_reflected_shortwave(dni, dhi, zenith, albedo_diffuse=SEA_ALBEDO_DIFFUSE):
    """Short-wave irradiance reflected upward by the sea [W m-2].

    Parameters
    ----------
    dni : array_like
        Direct normal irradiance [W m-2].
    dhi : array_like
        Diffuse horizontal irradiance [W m-2].
    zenith : array_like
        Solar zenith angle [deg].
    albedo_diffuse : float
        Albedo for diffuse light [-].

    Returns
    -------
    numpy.ndarray
        ``α_dir(Z) DNI cos Z + α_dif DHI`` [W m-2], to be treated as isotropic upward
        radiance ``/π`` by the face loading (specular glint is the imaging stage's job).
    """
    z = np.asarray(zenith, dtype=float)
    mu = np.clip(np.cos(np.radians(z)), 0.0, 1.0)
    return sea_albedo_direct(z) * np.asarray(dni, dtype=float) * mu + \
        albedo_diffuse * np.asarray(dhi, dtype=float)
