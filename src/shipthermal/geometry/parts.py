"""Named parts of a ship surface and the exact waterline split.

Every surface triangle belongs to exactly one part. The four main parts are

* ``hull_wetted`` — hull below the waterline (z < 0), facing the sea;
* ``hull_dry``    — hull above the waterline (topsides, transom above water);
* ``deck``        — the weather deck;
* ``superstructure`` — deckhouses, funnel, mast, gun house …

Sub-parts are allowed and named ``<main>_<detail>`` (``superstructure_funnel``); they map to
their main part through :func:`main_part`. The hull is split at the waterline plane
``z = 0`` *exactly*: triangles that cross it are cut along the plane (the new vertices lie
on it and are shared by both sides, so a closed surface stays closed).
"""

from __future__ import annotations

from typing import Mapping, Optional, Sequence

import numpy as np

from ..errors import InputError

__all__ = ["MAIN_PARTS", "HULL_PARTS", "main_part", "part_keys", "part_key", "part_value",
           "split_at_waterline", "label_hull_by_side",
           "face_areas", "part_areas", "boundary_edges", "signed_volume"]

MAIN_PARTS: tuple[str, ...] = ("hull_wetted", "hull_dry", "deck", "superstructure")
"""Main part names; every part name is one of these or ``<main>_<detail>``."""

HULL_PARTS: tuple[str, ...] = ("hull_wetted", "hull_dry")


def main_part(name: str) -> str:
    """Main part of a (sub-)part name: ``'superstructure_funnel'`` → ``'superstructure'``.

    ``'hull'`` (an unsplit hull) maps to itself. Raises :class:`InputError` for names that
    are neither a main part nor ``<main>_<detail>``.
    """
    if name in MAIN_PARTS or name == "hull":
        return name
    for main in ("superstructure", "deck", "hull_wetted", "hull_dry"):
        if name.startswith(main + "_") and len(name) > len(main) + 1:
            return main
    raise InputError("part name", name,
                     f"must be one of {', '.join(MAIN_PARTS)}, 'hull' (split at the waterline "
                     "automatically) or a sub-part '<main>_<detail>' such as 'superstructure_funnel'")


def part_keys(name: str) -> tuple[str, ...]:
    """Keys a (sub-)part's value may be given under, most specific first: the part, its main
    part, and ``'hull'`` for the parts of the hull (``hull_wetted``, ``hull_dry`` and their
    sub-parts).

    The one lookup policy of per-part values (scenario tables, user overrides, the
    parameter sets of :mod:`shipthermal.parameters` keyed by main part and ``'hull'``).
    """
    main = main_part(name)
    keys = [name, main] + (["hull"] if main in HULL_PARTS else [])
    return tuple(dict.fromkeys(keys))


def part_key(table: Mapping, name: str) -> Optional[str]:
    """The key of ``table`` that holds the value of part ``name`` (the first of
    :func:`part_keys` in it), or None when it holds none."""
    for key in part_keys(name):
        if key in table:
            return key
    return None


def part_value(table: Mapping, name: str, what: str = "value"):
    """The value of part ``name`` in ``table`` (looked up by :func:`part_key`).

    Raises
    ------
    InputError
        Naming the part, ``what`` it lacks and the parts with a value.
    """
    key = part_key(table, name)
    if key is None:
        raise InputError("part", name, f"has no {what}; parts with a value: {', '.join(table)}")
    return table[key]


def face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Triangle areas [m2]."""
    p0, p1, p2 = (vertices[faces[:, k]] for k in range(3))
    return 0.5 * np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)


def part_areas(vertices, faces, face_part, part_names: Sequence[str]) -> dict[str, float]:
    """Area of each part [m2]."""
    a = np.bincount(face_part, weights=face_areas(vertices, faces), minlength=len(part_names))
    return {name: float(x) for name, x in zip(part_names, a)}


def signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed enclosed volume [m3] (divergence theorem); > 0 when normals point outward."""
    p0, p1, p2 = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", p0, np.cross(p1, p2)).sum() / 6.0)


def boundary_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edges used by one triangle only (open boundary) and by more than two (non-manifold).

    Returns ``(open_edges (k, 2), nonmanifold_edges (j, 2))`` as sorted vertex pairs.
    """
    e = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    uniq, counts = np.unique(e, axis=0, return_counts=True)
    return uniq[counts == 1], uniq[counts > 2]


def split_at_waterline(vertices: np.ndarray, faces: np.ndarray, face_part: np.ndarray,
                       z_waterline: float = 0.0, tol: float = 0.0):
    """Cut every triangle crossing the plane ``z = z_waterline`` along the plane.

    Parameters
    ----------
    vertices : (N, 3) float [m]
    faces : (M, 3) int
    face_part : (M,) int
        Labels carried over to the pieces of each cut triangle.
    z_waterline : float
        Height of the cutting plane [m].
    tol : float
        Vertices closer than this to the plane [m] are snapped onto it first, so no
        sliver triangles thinner than ``tol`` are created.

    Returns
    -------
    vertices, faces, face_part, parent
        ``parent[i]`` is the input triangle of output triangle ``i``. New vertices are shared
        between the two triangles of each cut edge (a closed surface stays closed) and every
        piece keeps its parent's orientation.
    """
    v = np.array(vertices, dtype=float, copy=True)
    f = np.asarray(faces, dtype=np.int64)
    lab = np.asarray(face_part)
    if tol > 0:
        near = np.abs(v[:, 2] - z_waterline) <= tol
        v[near, 2] = z_waterline
    side = np.sign(v[:, 2] - z_waterline).astype(np.int8)
    s = side[f]
    cross = (s.max(axis=1) > 0) & (s.min(axis=1) < 0)
    if not cross.any():
        return v, f.copy(), lab.copy(), np.arange(len(f))
    cf = f[cross]
    cs = s[cross]
    # Rotate each crossing triangle (keeping its cyclic order) so that vertex 0 is the
    # "apex": the vertex on the plane if there is one, else the one alone on its side.
    has_zero = (cs == 0).any(axis=1)
    apex = np.where(has_zero, np.argmax(cs == 0, axis=1),
                    np.argmax(cs == -np.sign(cs.sum(axis=1, keepdims=True)), axis=1))
    roll = (apex[:, None] + np.arange(3)[None, :]) % 3
    cf = np.take_along_axis(cf, roll, axis=1)
    a, b, c = cf[:, 0], cf[:, 1], cf[:, 2]

    # Cut edges: (a,b) and (c,a) for a lone apex, (b,c) when the apex lies on the plane.
    lone = ~has_zero
    cut_edges = np.concatenate([np.stack([a[lone], b[lone]], 1), np.stack([c[lone], a[lone]], 1),
                                np.stack([b[has_zero], c[has_zero]], 1)])
    key = np.sort(cut_edges, axis=1)
    uniq, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    p, q = v[uniq[:, 0]], v[uniq[:, 1]]
    t = (z_waterline - p[:, 2]) / (q[:, 2] - p[:, 2])
    newp = p + t[:, None] * (q - p)
    newp[:, 2] = z_waterline
    new_index = len(v) + np.arange(len(uniq))
    v = np.vstack([v, newp])
    nl = int(lone.sum())
    m_ab = new_index[inv[:nl]]
    m_ca = new_index[inv[nl:2 * nl]]
    m_bc = new_index[inv[2 * nl:]]

    al, bl, cl = a[lone], b[lone], c[lone]
    az, bz, cz = a[has_zero], b[has_zero], c[has_zero]
    pieces = np.concatenate([
        np.stack([al, m_ab, m_ca], 1), np.stack([m_ab, bl, cl], 1), np.stack([m_ab, cl, m_ca], 1),
        np.stack([az, bz, m_bc], 1), np.stack([az, m_bc, cz], 1)])
    src = np.flatnonzero(cross)
    src_l, src_z = src[lone], src[has_zero]
    piece_parent = np.concatenate([src_l, src_l, src_l, src_z, src_z])
    keep = np.flatnonzero(~cross)
    out_f = np.concatenate([f[keep], pieces])
    parent = np.concatenate([keep, piece_parent])
    return v, out_f, lab[parent], parent


def label_hull_by_side(vertices: np.ndarray, faces: np.ndarray, is_hull: np.ndarray,
                       z_waterline: float = 0.0) -> np.ndarray:
    """For hull triangles (after :func:`split_at_waterline`): True where wetted (below).

    A triangle is wetted when its centroid lies below the plane; after the split no hull
    triangle has vertices on both sides, so this is exact.
    """
    zc = vertices[faces, 2].mean(axis=1)
    return is_hull & (zc < z_waterline)
