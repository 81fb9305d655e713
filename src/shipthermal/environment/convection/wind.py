"""The wind a ship's face feels: the apparent wind of a moving ship, and the wind speed at a
height above the sea by the neutral logarithmic profile.

Speeds in m/s, directions in degrees, heights in m.
"""

from __future__ import annotations

import numpy as np


def relative_wind(wind_speed, wind_direction, ship_speed=0.0, ship_heading=0.0):
    """Apparent wind felt on a moving ship.

    Parameters
    ----------
    wind_speed : array_like
        True wind speed over ground [m s-1].
    wind_direction : array_like
        True wind direction, meteorological convention: where the wind blows FROM,
        clockwise from north [deg].
    ship_speed : array_like
        Ship speed over ground [m s-1].
    ship_heading : array_like
        Ship heading, clockwise from north [deg].

    Returns
    -------
    speed : numpy.ndarray
        Apparent wind speed [m s-1].
    direction : numpy.ndarray
        Apparent wind direction, where it blows FROM, clockwise from north [deg, 0–360).
    angle_off_bow : numpy.ndarray
        Apparent wind direction relative to the bow, clockwise (0 = from dead ahead,
        90 = from starboard beam) [deg, 0–360).

    Notes
    -----
    Velocity triangle: v_apparent = v_wind − v_ship, with the air velocity
    (−U sin φ, −U cos φ) in East-North components for a wind from φ.
    """
    u = np.asarray(wind_speed, dtype=float)
    phi = np.radians(np.asarray(wind_direction, dtype=float))
    v = np.asarray(ship_speed, dtype=float)
    psi = np.radians(np.asarray(ship_heading, dtype=float))
    ax = -u * np.sin(phi) - v * np.sin(psi)
    ay = -u * np.cos(phi) - v * np.cos(psi)
    speed = np.sqrt(ax * ax + ay * ay)
    direction = np.degrees(np.arctan2(-ax, -ay)) % 360.0
    off_bow = (direction - np.degrees(psi)) % 360.0
    return speed, direction, off_bow


SEA_ROUGHNESS_LENGTH = 2.0e-4
"""Aerodynamic roughness length of open sea [m] (Wieringa 1992, J. Wind Eng. Ind.
Aerodyn. 41, 357–368, Table 1: "open sea, fetch at least 5 km", z0 = 0.0002 m)."""


def wind_speed_at_height(wind_speed, height, reference_height=10.0,
                         roughness_length=SEA_ROUGHNESS_LENGTH):
    """Wind speed at ``height`` from a speed measured at ``reference_height`` (neutral
    logarithmic profile over the sea).

    The one home of the wind profile: the forcing takes the 10 m wind to each face's height,
    the station readers take an anemometer's wind to 10 m (``height=10.0,
    reference_height=<anemometer height>``).

    Parameters
    ----------
    wind_speed : array_like
        Wind speed measured at ``reference_height`` [m s-1].
    height : array_like
        Height above the sea surface the speed is wanted at [m].
    reference_height : array_like
        Height above the sea surface the speed was measured at [m] (10 m: the weather's).
    roughness_length : float
        Aerodynamic roughness length of the sea [m] (:data:`SEA_ROUGHNESS_LENGTH`).

    Returns
    -------
    numpy.ndarray
        ``u(z_ref) ln(z / z0) / ln(z_ref / z0)`` [m s-1]; both heights are clipped below at
        10 roughness lengths (the log law's lower end: a face at the waterline takes the
        wind there). Anemometer heights are validated at the input
        (``weather.wind_height``).

    Notes
    -----
    Neutral surface layer, u(z) = (u*/κ) ln(z / z0) (Stull 1988, An Introduction to
    Boundary Layer Meteorology, eq. 9.7.5c); stability and the ship's own flow
    disturbance are ignored.
    """
    z0 = float(roughness_length)
    z = np.maximum(np.asarray(height, dtype=float), 10.0 * z0)
    z_ref = np.maximum(np.asarray(reference_height, dtype=float), 10.0 * z0)
    return np.asarray(wind_speed, dtype=float) * np.log(z / z0) / np.log(z_ref / z0)
