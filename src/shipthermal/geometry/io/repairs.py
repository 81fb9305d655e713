"""The repairs of a read ship: a surface repair computed once and then reused from the cache,
and the ray-cast outside test (interior shells removed, inside-out pieces turned)."""

from __future__ import annotations

from typing import Mapping

import numpy as np

from ...errors import InputError
from ..cad import Problem, problems_message, union_repair
from ..outside import classify_pieces
from ..parts import face_areas
from ..remesh import tetwild_surface
from ..repair_cache import load_repaired, repair_key, save_repaired

__all__ = ["repair_once", "outside_checked"]


def repair_once(v, f, labels, method: str, edge_length, lines: list):
    """A repair (:func:`..cad.union_repair` or :func:`..remesh.tetwild_surface`), computed
    once per input and settings and reused from the cache afterwards
    (:mod:`..repair_cache`: fTetWild is not deterministic, so every read of the same file
    must get the first repair's surface)."""
    key = repair_key(v, f, labels, method, edge_length=edge_length)
    cached = load_repaired(key)
    if cached is not None:
        nv, nf, nl, rep, path = cached
        rep = dict(rep, cache=str(path), reused=True)
        lines.append(f"repair ({method}): the repaired surface of this file computed before, "
                     f"reused from the cache ({path.name})")
        return nv, nf, nl, rep
    if method == "union":
        nv, nf, nl, rep = union_repair(v, f, labels)
    else:
        nv, nf, nl, rep = tetwild_surface(v, f, labels, edge_length=edge_length)
        rep["method"] = "tetwild"
    path, why = save_repaired(key, nv, nf, nl, rep)
    rep = dict(rep, cache=str(path) if path else None, reused=False)
    if path is None:
        lines.append(f"repair ({method}): the repaired surface could not be cached ({why}); "
                     "another read of this file may repair it differently")
    return nv, nf, nl, rep


def outside_checked(v, f, labels, fix_normals: bool, source, lines: list):
    """Ray-cast outside test (:func:`..outside.classify_pieces`): interior shells are
    removed (reported), inside-out pieces are turned with ``fix_normals`` or refused,
    stray inward or enclosed triangles above 1 % of the area are refused."""
    rep = classify_pieces(v, f)
    area = face_areas(v, f)
    total = float(area.sum())
    out = {"pieces": int(rep.piece.max()) + 1 if len(rep.piece) else 0,
           "interior_pieces": len(rep.interior_pieces),
           "inverted_pieces": len(rep.inverted_pieces),
           "stray_inward_faces": rep.stray_inward, "stray_enclosed_faces": rep.stray_enclosed}
    where = source if not isinstance(source, Mapping) else ", ".join(
        str(x) for x in source.values())
    inverted = rep.inverted_faces
    if inverted.any():
        if not fix_normals:
            c = v[f[np.flatnonzero(inverted)[0]]].mean(axis=0)
            raise problems_message(where, [Problem(
                "inverted_piece", f"{len(rep.inverted_pieces)} separate piece(s) "
                f"({int(inverted.sum())} triangles, {100 * area[inverted].sum() / total:.1f} % "
                f"of the area; first near ({c[0]:.3f}, {c[1]:.3f}, {c[2]:.3f}) m) are "
                "inside-out: their normals point into themselves (ray casting: only the back "
                "of their triangles sees the outside)", "ship.files.fix_normals = true")])
        f = f.copy()
        f[inverted] = f[inverted][:, ::-1]
        lines.append(f"fix_normals: {len(rep.inverted_pieces)} inside-out piece(s) turned "
                     f"({int(inverted.sum())} triangles; ray casting)")
        out["inverted_faces_turned"] = int(inverted.sum())
    interior = rep.interior_faces
    if interior.any():
        if interior.all():
            raise InputError("ship.files.mesh", str(where), "has no outer surface: no "
                             "triangle sees the outside (ray casting)", "Check the file")
        a_int = float(area[interior].sum())
        lines.append(f"interior shells removed: {len(rep.interior_pieces)} closed piece(s) "
                     f"inside the ship ({int(interior.sum())} triangles, {a_int:.6g} m2 = "
                     f"{100 * a_int / total:.1f} % of the area; no ray from either side of "
                     "them reaches the outside)")
        out["interior_faces_removed"] = int(interior.sum())
        out["interior_area_removed_m2"] = a_int
        keep = ~interior
        f, labels = f[keep], np.asarray(labels)[keep]
        used, inv = np.unique(f, return_inverse=True)
        v, f = v[used], inv.reshape(-1, 3)
    stray = ~rep.interior_faces & ~rep.inverted_faces & (rep.inward | rep.enclosed)
    a_stray = float(area[stray].sum()) / total if stray.any() else 0.0
    out["stray_area_share"] = a_stray
    if a_stray > 0.01:
        raise problems_message(where, [Problem(
            "inward", f"{int(stray.sum())} triangles ({100 * a_stray:.1f} % of the area) of the "
            "outer surface face into the ship or see the outside from neither side (ray "
            "casting)", 'ship.files.repair = "tetwild", or fix the normals in CAD')])
    return v, f, labels, out
