"""Physical constants and unit helpers (SI throughout, kelvin for temperature)."""

SIGMA = 5.670374419e-8
"""Stefan–Boltzmann constant [W m-2 K-4] (CODATA 2018, exact)."""

PLANCK = 6.62607015e-34
"""Planck constant h [J s] (SI 2019, exact)."""
SPEED_OF_LIGHT = 299792458.0
"""Speed of light in vacuum c [m s-1] (SI, exact)."""
BOLTZMANN = 1.380649e-23
"""Boltzmann constant k [J K-1] (SI 2019, exact)."""

PLANCK_C1 = 2.0 * PLANCK * SPEED_OF_LIGHT ** 2 * 1e24
"""First radiation constant for spectral radiance, 2 h c² = 1.191042972e8
[W µm4 m-2 sr-1] (from the exact SI constants; the paper's eq. 2 rounds it to 1.191e8)."""
PLANCK_C2 = PLANCK * SPEED_OF_LIGHT / BOLTZMANN * 1e6
"""Second radiation constant, h c / k = 1.438776877e4 [µm K] (from the exact SI constants;
the paper's eq. 2 rounds it to 1.4388e4)."""

ZERO_CELSIUS = 273.15
"""0 °C in kelvin [K]."""

MINUTE = 60.0
HOUR = 3600.0
DAY = 86400.0
"""Durations [s]."""
