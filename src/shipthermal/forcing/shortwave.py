"""Absorbed short-wave of the outer faces at the table times: the direct beam with the
traced self-shadowing, the isotropic diffuse sky through the sky view factor, the
sea-reflected short-wave through the sea view factor, and the first diffuse bounce off
the other ship faces.
"""

from __future__ import annotations

import numpy as np

from .convection import AirFaces


def absorbed_shortwave(state, rows, sun, lit, air: AirFaces, traced, alpha, n_out,
                       ship_reflection):
    """Absorbed short-wave of every outer face at the table rows [W m-2]: direct (traced
    shadows), diffuse sky, sea-reflected, and the first diffuse bounce off the ship."""
    a_ = air.cols
    F_sky, F_sea = traced.view.F_sky, traced.view.F_sea
    incident = np.zeros((rows.stop - rows.start, n_out))
    cos_inc = np.clip(sun[rows] @ air.normals.T, 0.0, None)
    incident[:, a_] = (state.dni[rows, None] * cos_inc * lit[rows]
                       + state.dhi[rows, None] * F_sky[a_]
                       + state.sea_shortwave_up[rows, None] * F_sea[a_])
    if ship_reflection:
        # first diffuse bounce off the ship: E1 = F (1 − α) E0
        bounce = (traced.view.F_faces @ ((1.0 - alpha)[:, None] * incident.T)).T
        incident[:, a_] += bounce[:, a_]
    return alpha * incident
