"""LOWTRAN 7's published aerosol and model-atmosphere tables, and its aerosol defaults.

``data/lowtran7_aerosol.npz`` is extracted from ``lowtran7.f`` by
``scripts/make_atmosphere_tables.py`` (:mod:`._fortran_data`): the Navy maritime
aerosol's coefficients (``BLOCK DATA MARDTA``, Gathman 1983), the Shettle & Fenn aerosol
tables (``EXTDTA``), the aerosol profiles (``PRFDTA``) and the AFGL model atmospheres
(``MLATMB``: altitude, pressure, temperature, water vapour; Anderson et al. 1986). The
atmosphere itself runs LOWTRAN's own aerosol (``IHAZE=3``, :mod:`.lowtran_backend`); the
product reads the model profiles (:mod:`.models`) and the default winds below.

References
----------
Gathman, S.G. (1983), Optical properties of the marine aerosol as predicted by the
Navy aerosol model, Opt. Eng. 22, 57–62.
Kneizys, F.X. et al. (1988), Users guide to LOWTRAN 7, AFGL-TR-88-0177.
Anderson, G.P. et al. (1986), AFGL atmospheric constituent profiles (0-120 km),
AFGL-TR-86-0110.
"""

from __future__ import annotations

from importlib import resources

import numpy as np

__all__ = ["DEFAULT_WIND_SPEED", "DEFAULT_AIR_MASS", "load_aerosol_tables"]

#: LOWTRAN 7 MARINE defaults indexed by model atmosphere 0..7 (WSPD, m/s)
DEFAULT_WIND_SPEED = (6.9, 4.1, 4.1, 10.29, 6.69, 12.35, 7.2, 6.9)
#: LOWTRAN 7 ``ICSTL`` default (air-mass character, 1 open ocean .. 10 continental)
DEFAULT_AIR_MASS = 3


def load_aerosol_tables() -> dict[str, np.ndarray]:
    """The LOWTRAN 7 aerosol and model-atmosphere tables (see module docstring)."""
    ref = resources.files("imaging.atmosphere") / "data" / "lowtran7_aerosol.npz"
    with resources.as_file(ref) as path, np.load(path) as npz:
        return {k: npz[k] for k in npz.files}
