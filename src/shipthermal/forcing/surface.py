"""Which faces the forcing drives and their optics: the forced patches of the graph
(``'{part}:outer'`` in air or sea, ``'{part}:inner'``), the part and medium of every
boundary face, the solar absorptivity and long-wave emissivity per part and face, and the
per-part values and choices from defaults and user overrides.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..errors import check_range, require
from ..geometry.parts import MAIN_PARTS, part_key, part_value
from ..parameters import LONGWAVE_EMISSIVITY, SOLAR_ABSORPTIVITY


def part_values(part_names, defaults: Mapping[str, float], overrides, field_name: str,
                low: float, high: float, low_open: bool = False) -> dict[str, float]:
    """A value per part from per-main-part defaults and user overrides.

    Parameters
    ----------
    part_names : sequence of str
        Parts of the ship (``'superstructure_funnel'`` …).
    defaults : mapping
        Value per main part (``'hull'`` for both hull parts, as in
        :mod:`shipthermal.parameters`).
    overrides : float or mapping or None
        One number for every part, or ``{part: value}`` where a key may be a part, a main
        part (applies to its sub-parts unless they are given too) or ``'hull'`` (both hull
        parts).
    field_name : str
        Name used in error messages (``'absorptivity'``).
    low, high : float
        Allowed range [-].
    low_open : bool
        Exclude ``low``.

    Returns
    -------
    dict
        Part name → value.
    """
    if overrides is None:
        overrides = {}
    if not isinstance(overrides, Mapping):
        check_range(field_name, overrides, low, high, low_open=low_open)
        return {n: float(overrides) for n in part_names}
    allowed = set(part_names) | set(MAIN_PARTS) | {"hull"}
    for key, value in overrides.items():
        require(key in allowed, f"{field_name}[{key!r}]", key,
                f"unknown part; parts are {', '.join(part_names)} (or a main part / 'hull')")
        check_range(f"{field_name}[{key!r}]", value, low, high, low_open=low_open)
    out = {}
    for name in part_names:
        key = part_key(overrides, name)
        out[name] = float(overrides[key] if key is not None
                          else part_value(defaults, name, field_name))
    return out


def part_choices(part_names, default, overrides, field_name: str, check,
                 defaults: Mapping | None = None) -> dict:
    """A name per part from a default (or per-main-part ``defaults``) and user overrides
    (one name, or ``{part: name}`` with parts, main parts or ``'hull'``); every name passes
    ``check(name, field) -> name``."""
    if overrides is None:
        overrides = {}
    if not isinstance(overrides, Mapping):
        one = check(overrides, field_name)
        return {n: one for n in part_names}
    allowed = set(part_names) | set(MAIN_PARTS) | {"hull"}
    for key, value in overrides.items():
        require(key in allowed, f"{field_name}[{key!r}]", key,
                f"unknown part; parts are {', '.join(part_names)} (or a main part / 'hull')")
        check(value, f"{field_name}[{key!r}]")
    out = {}
    for name in part_names:
        key = part_key(overrides, name)
        if key is not None:
            out[name] = overrides[key]
        else:
            out[name] = default if defaults is None else part_value(defaults, name, field_name)
    return out


@dataclass(eq=False)
class SurfaceProperties:
    """Stage 1: which boundary faces are forced, their part, medium and optics.

    Attributes
    ----------
    part_names : tuple of str
    patch_part : dict
        Patch → (part, ``'outer'`` | ``'inner'``).
    unforced : tuple of str
        Patches that are neither (left to the caller).
    outer_bfaces, inner_bfaces : (K,), (M,) int
        Boundary faces of the outer / inner patches (increasing).
    bpart : (n_bfaces,) int
        Part index of every boundary face (-1: unforced).
    outer_part : (K,) int
    outer_is_air : (K,) bool
    absorptivity, emissivity : dict
        Per part [-].
    alpha, epsilon : (K,) float
        Per outer face [-].
    """

    part_names: tuple
    patch_part: dict
    unforced: tuple
    outer_bfaces: np.ndarray
    inner_bfaces: np.ndarray
    bpart: np.ndarray
    outer_part: np.ndarray
    outer_is_air: np.ndarray
    absorptivity: dict
    emissivity: dict
    alpha: np.ndarray
    epsilon: np.ndarray


def surface_properties(ship, graph, absorptivity=None, emissivity=None) -> SurfaceProperties:
    """Stage 1: forced patches of ``graph`` and the optics of their faces.

    ``absorptivity`` and ``emissivity`` as in
    :class:`~shipthermal.forcing.build.ForcingSettings` (defaults
    :data:`~shipthermal.parameters.SOLAR_ABSORPTIVITY` and
    :data:`~shipthermal.parameters.LONGWAVE_EMISSIVITY`).
    """
    names = tuple(ship.part_names)
    alpha_part = part_values(names, SOLAR_ABSORPTIVITY, absorptivity, "absorptivity", 0.0, 1.0)
    eps_part = part_values(names, LONGWAVE_EMISSIVITY, emissivity, "emissivity", 0.0, 1.0,
                           low_open=True)
    is_outer = np.zeros(graph.n_bfaces, bool)
    is_inner = np.zeros(graph.n_bfaces, bool)
    patch_part = {}
    unforced = []
    for name in graph.patch_names:
        part, _, side = name.rpartition(":")
        if side not in ("outer", "inner") or not part:
            unforced.append(name)
            continue
        require(part in names, f"graph patch {name!r}", part,
                f"must name a part of the ship ({', '.join(names)})",
                "Build the graph from this ship (geometry.build_ship_mesh(ship))")
        patch_part[name] = (part, side)
        (is_outer if side == "outer" else is_inner)[graph.patch_faces(name)] = True
    outer_bfaces = np.flatnonzero(is_outer)
    require(len(outer_bfaces) > 0, "graph.patch_names", graph.patch_names,
            "must contain '{part}:outer' patches")
    part_index = {n: i for i, n in enumerate(names)}
    bpart = np.full(graph.n_bfaces, -1)
    for name, (part, _) in patch_part.items():
        bpart[graph.patch_faces(name)] = part_index[part]
    outer_part = bpart[outer_bfaces]
    medium = np.array([ship.outer_medium[n] for n in names])
    return SurfaceProperties(
        part_names=names, patch_part=patch_part, unforced=tuple(unforced),
        outer_bfaces=outer_bfaces, inner_bfaces=np.flatnonzero(is_inner), bpart=bpart,
        outer_part=outer_part, outer_is_air=medium[outer_part] == "air",
        absorptivity=alpha_part, emissivity=eps_part,
        alpha=np.array([alpha_part[n] for n in names])[outer_part],
        epsilon=np.array([eps_part[n] for n in names])[outer_part])


@dataclass(eq=False)
class Patch:
    """A forced patch of the graph: its part, medium and faces."""

    name: str
    part: str
    kind: str            # 'air' | 'sea' | 'inner'
    bfaces: np.ndarray   # boundary-face indices, graph.patch_faces order
    cols: np.ndarray     # columns into the outer-face arrays (air/sea) or inner arrays


def forced_patches(graph, surface: SurfaceProperties, ship) -> dict:
    """Patch name → :class:`Patch` of every forced patch of ``graph``."""
    out = {}
    for name, (part, side) in surface.patch_part.items():
        bf = graph.patch_faces(name)
        if side == "outer":
            cols = np.searchsorted(surface.outer_bfaces, bf)
            kind = "air" if ship.outer_medium[part] == "air" else "sea"
        else:
            cols = np.searchsorted(surface.inner_bfaces, bf)
            kind = "inner"
        out[name] = Patch(name=name, part=part, kind=kind, bfaces=bf, cols=cols)
    return out

