"""Isotropic remeshing of a user ship surface to a target edge length, finer or coarser.

CAD exports come with long slivers and edge lengths unrelated to the thermal model's
needs. :func:`isotropic_remesh` rebuilds the triangulation with edges near the target
length (Botsch & Kobbelt's split / collapse / flip / tangential-relaxation remeshing, as
implemented by MeshLab through ``pymeshlab``, optional extra ``cad``), keeping creases
sharper than :data:`FEATURE_ANGLE_DEG` (deck edge, deckhouse corners, where the parts
meet). Parts are carried over from the nearest input triangle; the hull is re-split
exactly at the waterline (hull vertices closer to it than :data:`WATERLINE_SNAP` × the
edge length are first moved onto it, so the cut leaves no slivers; on steep topsides that
moves no surface, where the hull is nearly level at the waterline, e.g. a transom just
immersed, it is flattened onto the waterline by up to that distance).

The result must meet the quality floor :data:`QUALITY_FLOOR` (≥ 99 % of triangles with a
smallest angle ≥ 20°). Where the target is too coarse for the ship's details the remesher
cannot meet it; the edge length is then reduced step by step (× :data:`SHRINK`) until it
does, and the report says so.
"""

from __future__ import annotations

import time

import numpy as np

from ..errors import InputError, check_positive
from .parts import face_areas, main_part, signed_volume, split_at_waterline
from .surface_ops import surface_quality

__all__ = ["FEATURE_ANGLE_DEG", "QUALITY_FLOOR", "WATERLINE_SNAP", "SHRINK", "have_remesher",
           "isotropic_remesh", "meets_floor"]

FEATURE_ANGLE_DEG = 30.0
"""Creases sharper than this dihedral angle [deg] are kept as feature lines (MeshLab's
default; ship hull curvature between neighbouring triangles stays far below it)."""

QUALITY_FLOOR = (0.99, 20.0)
"""(fraction of triangles, smallest angle [deg]): the remeshed surface must have at least
this fraction of triangles whose smallest angle is at least this angle."""

WATERLINE_SNAP = 0.3
"""Hull vertices closer to the waterline than this × the edge length are moved onto it
before the exact waterline cut (a cut closer to a vertex than that leaves a sliver)."""

SHRINK = 0.85
"""Factor applied to the edge length when the quality floor is not met (at most
:data:`MAX_TRIES` times: down to 0.85**9 = 0.23 of the target)."""

MAX_TRIES = 10
ITERATIONS = 10
"""Remeshing passes (MeshLab's default; quality figures stop changing after ~6)."""


def have_remesher() -> bool:
    """True when ``pymeshlab`` (optional extra ``cad``) is installed."""
    try:
        import pymeshlab  # noqa: F401
    except ImportError:
        return False
    return True


def meets_floor(quality: dict, floor=QUALITY_FLOOR) -> bool:
    """Whether :func:`~.remesh.surface_quality` figures meet the floor."""
    frac, angle = floor
    if angle != 20.0:
        raise ValueError("surface_quality reports the fraction below 20 deg only")
    return 1.0 - quality["frac_min_angle_below_20"] >= frac


def _remesh_once(v, f, h, feature_deg):
    import pymeshlab as ml      # optional extra 'cad' (see have_remesher)

    ms = ml.MeshSet()
    ms.add_mesh(ml.Mesh(np.asarray(v, float), np.asarray(f, np.int32)))
    ms.meshing_isotropic_explicit_remeshing(iterations=ITERATIONS, targetlen=ml.PureValue(h),
                                            featuredeg=feature_deg, checksurfdist=True,
                                            maxsurfdist=ml.PureValue(0.1 * h))
    m = ms.current_mesh()
    return np.asarray(m.vertex_matrix(), float), np.asarray(m.face_matrix(), np.int64)


def isotropic_remesh(vertices, faces, face_part, part_names, edge_length: float,
                     feature_deg: float = FEATURE_ANGLE_DEG, floor=QUALITY_FLOOR):
    """Remesh a closed ship surface (waterline at z = 0) to ``edge_length`` [m].

    Returns
    -------
    vertices, faces, face_part, report
        ``report``: target and final edge length, ``tries``, quality before and after
        (:func:`~.remesh.surface_quality`), area and volume before and after and their
        relative change, ``seconds``.
    """
    import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

    check_positive("edge_length", edge_length, "m")
    if not have_remesher():
        raise InputError("ship.edge_length", edge_length, "remeshing a user ship to another "
                         "edge length needs pymeshlab",
                         "pip install 'shipthermal[cad]' (or pymeshlab), or leave "
                         "ship.edge_length out to keep the file's triangles")
    t0 = time.perf_counter()
    v0 = np.asarray(vertices, float)
    f0 = np.asarray(faces, np.int64)
    lab0 = np.asarray(face_part)
    names = tuple(part_names)
    q0 = surface_quality(v0, f0)
    # Faces of the remeshed surface take the part of the input triangle closest to their
    # centroid (at a crease the centroid lies a third of an edge off it, on its own side).
    src = trimesh.Trimesh(v0, f0, process=False, validate=False)
    hull_ids = [k for k, n in enumerate(names) if main_part(n) in ("hull_wetted", "hull_dry")]
    wet = next((k for k in hull_ids if main_part(names[k]) == "hull_wetted"), None)
    dry = next((k for k in hull_ids if main_part(names[k]) == "hull_dry"), None)
    h = float(edge_length)
    for tries in range(1, MAX_TRIES + 1):
        v, f = _remesh_once(v0, f0, h, feature_deg)
        lab = lab0[trimesh.proximity.closest_point(src, v[f].mean(axis=1))[2]]
        if hull_ids:
            # Exact waterline: snap hull vertices near it, cut, re-label by side.
            on_hull = np.zeros(len(v), bool)
            on_hull[f[np.isin(lab, hull_ids)].ravel()] = True
            snap = on_hull & (np.abs(v[:, 2]) < WATERLINE_SNAP * h)
            v = v.copy()
            v[snap, 2] = 0.0
            v, f, lab, _ = split_at_waterline(v, f, lab, 0.0, tol=1e-9 * h)
            zc = v[f, 2].mean(axis=1)
            hull = np.isin(lab, hull_ids)
            if wet is not None:
                lab[hull & (zc < 0)] = wet
            if dry is not None:
                lab[hull & (zc >= 0)] = dry
        q = surface_quality(v, f)
        if meets_floor(q, floor):
            break
        h *= SHRINK
    a0, a1 = float(face_areas(v0, f0).sum()), float(face_areas(v, f).sum())
    vol0, vol1 = signed_volume(v0, f0), signed_volume(v, f)
    report = dict(target_edge_length=float(edge_length), edge_length=h, tries=tries,
                  floor_met=meets_floor(q, floor), quality_before=q0, quality_after=q,
                  area_before=a0, area_after=a1, area_change=(a1 - a0) / a0,
                  volume_before=vol0, volume_after=vol1, volume_change=(vol1 - vol0) / vol0,
                  seconds=time.perf_counter() - t0)
    return v, f, lab, report
