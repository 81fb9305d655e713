"""Does the ship float where it is moored? Its footprint against the port's class map.

A ship placed over a pier or the quay is rendered as if the pier were not there and its
local SCR window measures land: the answer is wrong without any error. The footprint (the
plan-view outline of the hull) is laid onto the class map at the mooring position and
heading, and the part of it that lies on land, vegetation, buildings or outside the scene
is measured:

* :func:`hull_outline` — the convex plan-view outline of a ship's hull in the ship frame;
* :func:`footprint_overlap` — area and depth [m] of the footprint outside the water;
* :func:`clear_shift` — the smallest sideways shift (towards port or starboard) that puts
  the whole footprint on water, to suggest in a message.

The class map's pixels are squares of ``resolution_m``; the footprint is sampled on a
1 m lattice, so areas are exact to about a metre of outline and depths to a metre.
"""

from __future__ import annotations

import numpy as np

from .parameters import CLASS_NAMES
from .scene import ShipPlacement

__all__ = ["SAMPLE_STEP_M", "hull_outline", "footprint_overlap", "clear_shift"]

SAMPLE_STEP_M = 1.0
"""Lattice step of the footprint samples [m] (a fender is about a metre)."""


def hull_outline(vertices, faces, face_part, part_names) -> np.ndarray:
    """Convex plan-view outline (x forward, y to port) [m] of a ship's hull: the convex
    hull of the vertices of its hull parts (all vertices when it has none), counter-clockwise.

    Returns
    -------
    (k, 2) float array of corners.
    """
    from scipy.spatial import ConvexHull

    v = np.asarray(vertices, float)
    f = np.asarray(faces)
    hull = [k for k, n in enumerate(part_names) if str(n).startswith("hull")]
    sel = np.isin(np.asarray(face_part), hull)
    pts = v[np.unique(f[sel])] if sel.any() else v
    h = ConvexHull(pts[:, :2])
    return pts[h.vertices, :2]


def _samples(outline: np.ndarray, step: float):
    """Lattice points inside a convex counter-clockwise polygon and their distance to its
    boundary [m]."""
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    xs = np.arange(lo[0] + 0.5 * step, hi[0], step)
    ys = np.arange(lo[1] + 0.5 * step, hi[1], step)
    p = np.stack(np.meshgrid(xs, ys, indexing="xy"), axis=-1).reshape(-1, 2)
    a = outline
    b = np.roll(outline, -1, axis=0)
    e = b - a
    length = np.linalg.norm(e, axis=1)
    inward = np.stack([-e[:, 1], e[:, 0]], axis=1) / length[:, None]    # left normal
    dist = ((p[:, None, :] - a[None]) * inward[None]).sum(axis=2).min(axis=1)
    keep = dist >= 0
    return p[keep], dist[keep]


def _classes_under(cm, resolution_m, placement, pts):
    """Class code under each ship-frame point (0 outside the scene)."""
    ny, nx = cm.shape
    scene = placement.to_scene(np.column_stack([pts, np.zeros(len(pts))]))
    col = np.floor(scene[:, 0] / resolution_m).astype(np.int64)
    row = np.floor((ny * resolution_m - scene[:, 1]) / resolution_m).astype(np.int64)
    inside = (col >= 0) & (col < nx) & (row >= 0) & (row < ny)
    cls = np.zeros(len(pts), np.int64)
    cls[inside] = cm[row[inside], col[inside]]
    return cls


def footprint_overlap(class_map, resolution_m: float, placement: ShipPlacement,
                      outline_xy, step_m: float = SAMPLE_STEP_M) -> dict:
    """How much of a ship's footprint lies outside the water.

    Parameters
    ----------
    class_map : (ny, nx) int
        1 water, 2 vegetation, 3 land, 4 building (row 0 = north edge).
    resolution_m : float
        Pixel side [m].
    placement : ShipPlacement
        Ship-frame origin in scene metres (east and north of the south-west corner) and
        heading.
    outline_xy : (k, 2) array
        Convex footprint in the ship frame [m] (:func:`hull_outline`).
    step_m : float
        Sample lattice step [m].

    Returns
    -------
    dict
        ``area_m2`` of the footprint, ``dry_m2`` outside the water (land classes and
        outside the scene), ``depth_m``: the widest dry cut across the ship at one station
        along it (how far a pier reaches into the beam), ``classes``: area per class name
        (and ``"outside the scene"``).
    """
    cm = np.asarray(class_map)
    pts, _ = _samples(np.asarray(outline_xy, float), step_m)
    cls = _classes_under(cm, resolution_m, placement, pts)
    dry = cls != 1
    cell = step_m * step_m
    classes = {}
    for code in np.unique(cls[dry]):
        name = CLASS_NAMES.get(int(code), "outside the scene") if code else "outside the scene"
        classes[name] = float((cls[dry] == code).sum() * cell)
    depth = 0.0
    if dry.any():          # the widest dry cut across the ship, per 1-step station along it
        station = np.floor(pts[dry, 0] / step_m).astype(np.int64)
        depth = float(np.bincount(station - station.min()).max() * step_m)
    return {"area_m2": float(len(pts) * cell), "dry_m2": float(dry.sum() * cell),
            "depth_m": depth, "classes": classes}


def clear_shift(class_map, resolution_m: float, placement: ShipPlacement, outline_xy,
                max_shift_m: float = 300.0, step_m: float = SAMPLE_STEP_M):
    """The smallest shift towards port (+) or starboard (-) [m] that puts the whole
    footprint on water, and the placement it gives; ``(None, None)`` when none within
    ``max_shift_m``."""
    h = np.radians(placement.heading_deg)
    port = np.array([-np.cos(h), np.sin(h)])
    cm = np.asarray(class_map)
    pts, _ = _samples(np.asarray(outline_xy, float), step_m)
    for s in np.arange(step_m, max_shift_m + step_m, step_m):
        for sign in (1.0, -1.0):
            x, y = np.array([placement.x_m, placement.y_m]) + sign * s * port
            moved = ShipPlacement(float(x), float(y), placement.heading_deg)
            if (_classes_under(cm, resolution_m, moved, pts) == 1).all():
                return float(sign * s), moved
    return None, None
