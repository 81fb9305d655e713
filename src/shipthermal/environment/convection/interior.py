"""Inner faces to compartment air: ISO 6946 constants or natural convection.

Temperatures in K, coefficients h in W m-2 K-1.
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError, check_positive
from shipthermal.units import SIGMA

from .fluids import air_properties
from .plates import h_natural


ISO6946_INTERIOR_CONVECTION = {"up": 5.0, "horizontal": 2.5, "down": 0.7}
"""Convective coefficient h_ci of internal surfaces by heat-flow direction [W m-2 K-1]:
ISO 6946:2017 Annex C, C.3."""


def h_interior_iso6946(temp_surface, temp_room, normal_z, include_radiation=False,
                       emissivity=0.9):
    """Interior surface coefficient by ISO 6946:2017 Annex C [W m-2 K-1].

    Parameters
    ----------
    temp_surface : array_like
        Inner face temperature [K].
    temp_room : array_like
        Compartment air temperature [K].
    normal_z : array_like
        Upward component of the unit normal pointing INTO the room [-].
    include_radiation : bool
        Add the linearised radiative part ``ε h_r0`` with ``h_r0 = 4 σ T_m³`` (ISO 6946
        eq. C.4) — only if the caller does not model interior radiation itself.
    emissivity : float
        Hemispherical emissivity of the inner face [-].

    Returns
    -------
    numpy.ndarray
        h_ci (5.0 upward, 2.5 horizontal, 0.7 downward heat flow), plus ``ε h_r0``
        when requested.

    Notes
    -----
    ISO 6946:2017 Annex C, C.2: heat flow is "horizontal" within ±30° of the
    horizontal plane. The heat-flow direction is from the warmer side to the colder:
    a floor (normal up) warmer than the room loses heat upward, etc. With radiation
    the standard's R_si values follow (1/(2.5 + 0.9·5.13) ≈ 0.14 ≈ 0.13 m²K/W).
    """
    ts = np.asarray(temp_surface, dtype=float)
    tr = np.asarray(temp_room, dtype=float)
    nz = np.asarray(normal_z, dtype=float)
    # heat-flow direction (vertical component): surface→room along +n if surface warmer
    flow_z = np.sign(ts - tr) * nz
    sin30 = 0.5
    hci_ = ISO6946_INTERIOR_CONVECTION
    hci = np.where(flow_z > sin30, hci_["up"],
                   np.where(flow_z < -sin30, hci_["down"], hci_["horizontal"]))
    if include_radiation:
        tm = 0.5 * (ts + tr)
        hci = hci + emissivity * 4.0 * SIGMA * (tm * tm * tm)
    return hci


def h_interior(temp_surface, temp_room, normal_z, length_vertical=None,
               length_horizontal=None, method: str = "iso6946"):
    """Interior face coefficient to compartment air [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_room : array_like
        [K].
    normal_z : array_like
        Upward component of the unit normal pointing into the room [-].
    length_vertical, length_horizontal : array_like, optional
        Needed for ``method='natural'`` [m].
    method : {'iso6946', 'natural'}
        ISO 6946 convective constants, or the natural-convection correlations of
        :func:`h_natural` in air at the film temperature.
    """
    if method == "iso6946":
        return h_interior_iso6946(temp_surface, temp_room, normal_z)
    if method == "natural":
        if length_vertical is None or length_horizontal is None:
            raise InputError("interior.length", None,
                             "method='natural' needs length_vertical and length_horizontal")
        check_positive("interior.length_vertical", length_vertical, "m")
        check_positive("interior.length_horizontal", length_horizontal, "m")
        ts = np.asarray(temp_surface, dtype=float)
        tr = np.asarray(temp_room, dtype=float)
        props = air_properties(0.5 * (ts + tr))
        return h_natural(ts, tr, normal_z, length_vertical, length_horizontal, props)
    raise InputError("interior.method", method, "must be 'iso6946' or 'natural'")
