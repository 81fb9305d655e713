"""The parametric superstructure: convex blocks placed on the deck or stacked on each other,
gridded at the target edge length, and united with the hull by an exact mesh boolean
(manifold3d), which keeps a closed, consistently oriented surface and the identity of
every triangle's source.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ...errors import require
from .grids import grid_faces, merge_vertices
from .hull import HullForm
from .parameters import Block

__all__ = ["block_meshes", "block_surface", "unite"]


def block_meshes(form: HullForm, edge_length: float):
    """Surfaces of the superstructure blocks of ``form.p``, each standing on the deck or on
    the highest earlier block under its centre: ``(meshes [(vertices, faces)], parts)``."""
    params = form.p
    meshes = []
    block_part = []
    block_top = []                       # top height of each block, for stacking
    for i, b in enumerate(params.blocks):
        s_lo = (b.x_aft + form.half) / params.length
        s_hi = (b.x_fore + form.half) / params.length
        ss = np.linspace(s_lo, s_hi, 33)
        deck_lo, deck_hi = float(form.z_deck(ss).min()), float(form.z_deck(ss).max())
        if b.base == 0:
            half_room = float(form.hb_deck(ss).min())
            require(0.5 * b.width < half_room, f"{params.name}.blocks[{i}].width", b.width,
                    f"must fit on the deck: the deck is only {2 * half_room:.2f} m wide there")
            z_foot = deck_lo
            # Ensure the footprint stands everywhere on or above the deck (sheer).
            require(deck_hi - deck_lo < b.height, f"{params.name}.blocks[{i}]", b,
                    "the deck rises more than the block height over its footprint")
        else:
            # Stacked: stand on the highest earlier block under this block's centre.
            xc = 0.5 * (b.x_aft + b.x_fore)
            below = [top for top, lb in zip(block_top, params.blocks[:i])
                     if lb.x_aft <= xc <= lb.x_fore and 0.5 * lb.width >= 0]
            z_foot = max(below) if below else deck_lo + b.base
        meshes.append(block_surface(form, b, z_foot, edge_length))
        block_part.append(b.part)
        block_top.append(z_foot + b.height)
    return meshes, block_part


def block_surface(form: HullForm, b: Block, z_foot: float, h: float):
    """Closed gridded frustum of a block, outward oriented: (vertices, faces)."""
    shrink = b.height * math.tan(math.radians(b.incline_deg))
    # The footprint is sunk into what it stands on so the union overlaps (no coplanar faces).
    sink = 0.5 if b.base == 0 else 0.25
    z0, z1 = z_foot - sink, z_foot + b.height
    ext = sink * math.tan(math.radians(b.incline_deg))
    lo = np.array([[b.x_aft - ext, -0.5 * b.width - ext], [b.x_fore + ext, -0.5 * b.width - ext],
                   [b.x_fore + ext, 0.5 * b.width + ext], [b.x_aft - ext, 0.5 * b.width + ext]])
    hi = np.array([[b.x_aft + shrink + b.top_shift_x, -0.5 * b.width + shrink],
                   [b.x_fore - shrink + b.top_shift_x, -0.5 * b.width + shrink],
                   [b.x_fore - shrink + b.top_shift_x, 0.5 * b.width - shrink],
                   [b.x_aft + shrink + b.top_shift_x, 0.5 * b.width - shrink]])
    B = np.column_stack([lo, np.full(4, z0)])
    T = np.column_stack([hi, np.full(4, z1)])
    nx = max(1, int(math.ceil((b.x_fore - b.x_aft) / h)))
    ny = max(1, int(math.ceil(b.width / h)))
    nz = max(1, int(math.ceil(np.linalg.norm(T[0] - B[0]) / h)))
    quads = [(B[0], B[1], B[2], B[3], nx, ny), (T[0], T[1], T[2], T[3], nx, ny),
             (B[0], B[1], T[1], T[0], nx, nz), (B[3], B[2], T[2], T[3], nx, nz),
             (B[0], B[3], T[3], T[0], ny, nz), (B[1], B[2], T[2], T[1], ny, nz)]
    centre = np.concatenate([B, T]).mean(axis=0)
    vs, fs, off = [], [], 0
    for c00, c10, c11, c01, nu, nv in quads:
        u = np.linspace(0.0, 1.0, nu + 1)[:, None, None]
        w = np.linspace(0.0, 1.0, nv + 1)[None, :, None]
        pts = ((1 - u) * (1 - w) * c00 + u * (1 - w) * c10 + u * w * c11 + (1 - u) * w * c01)
        tri = grid_faces(nu, nv)
        pts = pts.reshape(-1, 3)
        # Convex block: orient each wall away from the block centre.
        n = np.cross(pts[tri[0, 1]] - pts[tri[0, 0]], pts[tri[0, 2]] - pts[tri[0, 0]])
        if np.dot(n, pts[tri[0]].mean(axis=0) - centre) < 0:
            tri = tri[:, ::-1]
        vs.append(pts)
        fs.append(tri + off)
        off += len(pts)
    v, f, _ = merge_vertices(np.concatenate(vs), np.concatenate(fs), tol=1e-6 * form.p.length)
    return v, f


def unite(meshes: Sequence[tuple[np.ndarray, np.ndarray]]):
    """Boolean union with manifold3d; returns (vertices, faces, source_mesh, source_face)."""
    # (manifold3d on use: loading a scenario reads the ship builder's limits, not the union)
    from manifold3d import Manifold, Mesh64, OpType

    ids = []
    total = 0
    parts = []
    for k, (v, f) in enumerate(meshes):
        fid = np.arange(total, total + len(f), dtype=np.uint32)
        man = Manifold(Mesh64(vert_properties=np.asarray(v, np.float64),
                              tri_verts=np.asarray(f, np.uint64), face_id=fid.astype(np.uint64)))
        if man.status().name != "NoError":
            raise RuntimeError(f"mesh {k} is not a closed manifold for the union: {man.status()}")
        parts.append(man)
        ids.append(np.full(len(f), k))
        total += len(f)
    result = Manifold.batch_boolean(parts, OpType.Add)
    out = result.to_mesh64()
    src_face = np.asarray(out.face_id, dtype=np.int64)
    src_mesh = np.concatenate(ids)[src_face]
    offsets = np.cumsum([0] + [len(f) for _, f in meshes])
    local = src_face - offsets[src_mesh]
    return (np.asarray(out.vert_properties, float)[:, :3], np.asarray(out.tri_verts, np.int64),
            src_mesh, local)
