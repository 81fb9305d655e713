"""Physical constants and unit helpers (SI throughout, kelvin for temperature)."""

SIGMA = 5.670374419e-8
"""Stefan–Boltzmann constant [W m-2 K-4] (CODATA 2018, exact)."""

ZERO_CELSIUS = 273.15
"""0 °C in kelvin [K]."""

MINUTE = 60.0
HOUR = 3600.0
DAY = 86400.0
"""Durations [s]."""


def celsius_to_kelvin(temp_c):
    """Convert °C to K."""
    return temp_c + ZERO_CELSIUS


def kelvin_to_celsius(temp_k):
    """Convert K to °C."""
    return temp_k - ZERO_CELSIUS
