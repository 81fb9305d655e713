"""A parametric ship from its parameters: hull and superstructure united, triangles labelled
by part, slivers of the boolean removed, layups and compartment temperatures attached."""

from __future__ import annotations

from typing import Mapping

import numpy as np

from ...errors import check_range
from ..layups import compartment_temperatures, default_layups, outer_media
from ..limits import builtin_area_bound, check_surface_size
from ..parts import signed_volume, split_at_waterline
from ..ship_geometry import ShipGeometry
from ..surface_ops import collapse_short_edges, flip_coplanar_edges
from .hull import HullForm, hull_surface
from .parameters import DEFAULT_EDGE_LENGTH, ShipParameters
from .superstructure import block_meshes, unite

__all__ = ["build_ship"]


def build_ship(params: ShipParameters, edge_length: float | None = None,
               layups: Mapping | None = None, compartment_temperature: Mapping | None = None,
               superstructure_material: str = "mild_steel", improve: bool = True) -> ShipGeometry:
    """Generate a parametric ship surface with parts and layups.

    Parameters
    ----------
    params : ShipParameters
    edge_length : float, optional
        Target surface edge length [m]; default :data:`DEFAULT_EDGE_LENGTH` scaled with the
        length (0.5 m for a 132 m frigate).
    layups : mapping, optional
        Layup overrides per part (see :func:`~.layups.default_layups`).
    compartment_temperature : mapping, optional
        Inside air temperature overrides per part [K].
    superstructure_material : str
        ``'mild_steel'`` (default) or ``'aluminium_5083'``.
    improve : bool
        Remove the boolean's slivers (short-edge collapses and edge flips that move no
        surface); off only to measure their effect.
    """
    params.validate()
    if edge_length is None:
        edge_length = DEFAULT_EDGE_LENGTH * params.length / 132.0
    check_range("ship.edge_length", edge_length, 1e-4 * params.length, 0.1 * params.length, "m")
    check_surface_size(builtin_area_bound(params.length, params.beam, params.draught,
                                          params.freeboard), edge_length)
    form = HullForm(params)
    hv, hf, is_deck = hull_surface(form, edge_length)
    blocks, block_part = block_meshes(form, edge_length)
    if blocks:
        v, f, src_mesh, src_face = unite([(hv, hf)] + blocks)
    else:
        v, f = hv, hf
        src_mesh, src_face = np.zeros(len(f), int), np.arange(len(f))
    names, label = _label_faces(is_deck, block_part, src_mesh, src_face)

    # Exact waterline split (a no-op on the built-in hull, whose sections have a vertex on
    # z = 0, but it also catches triangles the boolean may have re-cut).
    v, f, label, _ = split_at_waterline(v, f, label, 0.0, tol=1e-9 * params.length)
    zc = v[f, 2].mean(axis=1)
    label[(label == 1) & (zc < 0)] = 0
    order, face_part = _order_parts(names, label)

    if signed_volume(v, f) < 0:           # never expected; kept as a guard for edits
        f = f[:, ::-1]
    if improve:
        v, f, face_part = _remove_slivers(v, f, face_part, edge_length, params.length)
    return ShipGeometry(
        vertices=v, faces=f, face_part=face_part, part_names=tuple(order),
        layups=default_layups(order, layups, superstructure_material),
        compartment_temperature=compartment_temperatures(order, compartment_temperature),
        outer_medium=outer_media(order),
        length=params.length, beam=params.beam, draught=params.draught, freeboard=params.freeboard,
        name=params.name, provenance=params.provenance, edge_length=float(edge_length),
        parameters=params)


def _label_faces(is_deck, block_part, src_mesh, src_face):
    """Part labels from each united triangle's source mesh (0: the hull, k: block k-1) and
    its face there: hull triangles are hull (``hull_dry``) or deck, blocks by part.
    Returns ``(names, label)``."""
    names = ["hull_wetted", "hull_dry", "deck"]
    for pname in block_part:
        if pname not in names:
            names.append(pname)
    label = np.empty(len(src_mesh), np.int64)
    from_hull = src_mesh == 0
    label[from_hull] = np.where(is_deck[src_face[from_hull]], 2, 1)
    block_label = np.array([names.index(pn) for pn in block_part] or [0])
    label[~from_hull] = block_label[src_mesh[~from_hull] - 1]
    return names, label


def _order_parts(names, label):
    """Order the part names: main parts first, then sub-parts; drop empty parts.
    Returns ``(order, face_part)`` with ``face_part`` indexing ``order``."""
    order = [n for n in ("hull_wetted", "hull_dry", "deck", "superstructure") if n in names]
    order += sorted(n for n in names if n not in order)
    counts = np.bincount(label, minlength=len(names))
    order = [n for n in order if counts[names.index(n)] > 0]
    remap = np.full(len(names), -1)
    for k, n in enumerate(order):
        remap[names.index(n)] = k
    return order, remap[label]


def _remove_slivers(v, f, face_part, edge_length: float, length: float):
    """The boolean leaves slivers where the deck grid meets the deckhouse grids: collapse
    the short edges that can go without moving any surface, then re-triangulate the flat
    regions (deck, deckhouse walls). Both keep areas, volume and part boundaries."""
    f, _ = flip_coplanar_edges(v, f, face_part, max_passes=4)
    v, f, face_part, _ = collapse_short_edges(v, f, face_part, 0.25 * edge_length,
                                              1e-9 * length)
    f, _ = flip_coplanar_edges(v, f, face_part, max_passes=4)
    return v, f, face_part
