"""A messy ship export made from a built-in ship, for the mesh checks.

Real CAD exports of whole ships arrive as soups of pieces: cracks between pieces that
should meet, patches of triangles wound the wrong way, closed pieces inside the hull
(tanks, holds) and separate pieces exported inside-out. :func:`messy_cargo_ship` builds
such a file from the built-in cargo ship, with each defect in a known place, so what the
reader finds and removes can be counted:

* ``crack``: the superstructure is a separate piece lifted by 2 mm (open edges along its
  foot: only a repair closes them);
* ``flipped_patch``: the deck triangles within 20 m of amidships wound the wrong way;
* ``inner_box``: a closed box inside the hull (120 x 24 x 12.5 m, keel + 2 m to 0.5 m
  below the deck), inside-out (normals into the box, as a subtracted volume is exported):
  36 % of the file's area;
* ``inside_out``: a closed container (12 x 2.5 x 2.6 m) standing 0.5 m above the deck
  between the deckhouse and amidships, inside-out.

Coordinates: metres, keel at z = 0 (draught 10 m), x from the bow... as the built-in
ship, shifted up by its draught.
"""

from __future__ import annotations

import numpy as np
import trimesh

from shipthermal.geometry import cargo_ship

DRAUGHT = 10.0
"""Keel depth of the built-in cargo ship [m] (the file's waterline is z = 10 m)."""


def _box(extent, centre, subdivide=0, inside_out=False):
    b = trimesh.creation.box(extent)
    b.apply_translation(centre)
    for _ in range(subdivide):
        b = b.subdivide()
    f = np.asarray(b.faces)
    return np.asarray(b.vertices, float), (f[:, ::-1] if inside_out else f)


def messy_cargo_ship(edge_length=4.0, crack=True, flipped_patch=True, inner_box=True,
                     inside_out=True):
    """Vertices [m], triangles and a dict of what was done (face counts and areas [m2]);
    the reference built-in ship as the fourth item."""
    ship = cargo_ship(edge_length=edge_length)
    v, f, lab = ship.vertices.copy(), ship.faces.copy(), ship.face_part.copy()
    names = ship.part_names
    info = {}
    if crack:
        sup = np.isin(lab, [k for k, n in enumerate(names) if n.startswith("superstructure")])
        used = np.unique(f[sup])
        remap = np.full(len(v), -1)
        remap[used] = len(v) + np.arange(len(used))
        v = np.vstack([v, v[used] + [0.0, 0.0, 0.002]])
        f[sup] = remap[f[sup]]
        info["crack_faces"] = int(sup.sum())
    if flipped_patch:
        c = v[f].mean(axis=1)
        patch = (lab == names.index("deck")) & (np.abs(c[:, 0]) < 20.0)
        f[patch] = f[patch][:, ::-1]
        info["flipped_patch_faces"] = int(patch.sum())
    extra = []
    if inner_box:
        extra.append(("inner_box", _box((120.0, 24.0, 12.5), (0.0, 0.0, -1.75), 3, True)))
    if inside_out:
        extra.append(("inside_out", _box((12.0, 2.5, 2.6), (-40.0, 0.0, 5.5 + 0.5 + 1.3), 1,
                                         True)))
    for key, (bv, bf) in extra:
        f = np.vstack([f, bf + len(v)])
        v = np.vstack([v, bv])
        p = bv[bf]
        info[f"{key}_faces"] = int(len(bf))
        info[f"{key}_area"] = float(0.5 * np.linalg.norm(
            np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum())
    return v + [0.0, 0.0, DRAUGHT], f, info, ship


def write_messy_cargo_ship(path, **kw) -> dict:
    """Write :func:`messy_cargo_ship` as a binary STL; returns its info dict."""
    v, f, info, _ = messy_cargo_ship(**kw)
    trimesh.Trimesh(v, f, process=False, validate=False).export(path)
    return info
