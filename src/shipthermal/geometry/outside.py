"""Which side of each triangle is the outside: ray casting, and what follows from it.

A ship surface is right when every triangle's normal points to the outside: into the air
or the sea, where a ray can leave to infinity. Winding and the signed volume cannot tell
this for a soup of pieces or after a repair (a closed piece exported inside-out inside
the hull, the walls of a cavity left by a remesh, a separate deckhouse turned inside-out:
each is consistently wound and the total volume stays positive). The outside can: from a
triangle's front side some ray into its half-space must escape without meeting the ship.

* :func:`outside_visibility` — for each triangle, how many of a fixed fan of rays leave
  its front (normal side) and its back without hitting the surface;
* :func:`classify_pieces` — per connected piece, the share of its area that faces out,
  faces in (the back sees out, the front does not) or is enclosed (neither side sees
  out): whole pieces that are enclosed are interior shells, whole pieces that face in are
  inside-out;
* :func:`part_sense` — parts that make no physical sense: a deck that is mostly not
  facing the sky, a hull with no wetted part, a superstructure that lies below the deck;
* :func:`sliver_share` — the share of needle triangles and the edge length that would
  remesh them.

The rays are deterministic (a spherical Fibonacci fan, no random numbers), so the same
surface always gets the same answer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .parts import face_areas, main_part

__all__ = ["OUTSIDE_RAYS", "OUTSIDE_RAYS_RETRY", "ENCLOSED_PIECE_SHARE",
           "INWARD_PIECE_SHARE", "DECK_SKY_NORMAL_DEG", "DECK_SKY_MIN_SHARE",
           "SLIVER_ANGLE_DEG", "SLIVER_WARN_SHARE", "hemisphere_fan", "outside_visibility",
           "PieceReport", "classify_pieces", "part_sense", "sliver_share"]

OUTSIDE_RAYS = 32
"""Rays per triangle side in the first pass. A triangle on the open outside of a ship
sees at least a quarter of its hemisphere (a deck beside a wall: half; a corner between
a deck and two walls: a quarter), which holds 8 of 32 fan directions, so one pass decides
nearly every outer triangle."""

OUTSIDE_RAYS_RETRY = 512
"""Rays per side for the triangles whose first pass found no escape (deep pockets: the
floor of a hold, a recess between deckhouses). With 512 fan directions a pocket that opens
to the sky through a cone of 5 deg half-angle (solid angle 0.024 sr of 2 pi) still gets
about 2 rays out."""

ENCLOSED_PIECE_SHARE = 0.9
"""A connected piece is an interior shell when at least this share of its area sees out
from neither side (an inside shell sees out nowhere; 0.9 leaves room for a few triangles
that touch the outer surface through a crack)."""

INWARD_PIECE_SHARE = 0.5
"""A connected piece is inside-out when more of its area sees out from the back only
than from the front, and that share is at least this."""

DECK_SKY_NORMAL_DEG = 45.0
"""A deck triangle faces the sky when its outward normal lies within this angle of the
vertical [deg] (camber, sheer and the deck edge rounding stay well inside it)."""

DECK_SKY_MIN_SHARE = 0.5
"""Least share of the deck area that must face the sky: a weather deck is mostly
horizontal and upward; less means the deck label lies on hull sides, an inside shell or
downward faces."""

SLIVER_ANGLE_DEG = 10.0
"""A triangle is a sliver when its smallest angle is below this [deg] (the view factors
and the finite-volume fluxes of such needles are poorly resolved)."""

SLIVER_WARN_SHARE = 0.2
"""Share of sliver triangles above which reading a ship warns and names the remesh key."""


# ---------------------------------------------------------------------------------------
# Rays
# ---------------------------------------------------------------------------------------
def hemisphere_fan(n: int) -> np.ndarray:
    """``n`` unit directions spread evenly over the upper hemisphere (z > 0).

    A spherical Fibonacci lattice: equal solid angle per direction, heights
    ``z_k = 1 - (k + 1/2) / n``, azimuths by the golden angle. Deterministic.

    Returns
    -------
    (n, 3) float array.
    """
    k = np.arange(n)
    z = 1.0 - (k + 0.5) / n
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = k * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def _frames(normals: np.ndarray):
    """Two tangents per unit normal (any orthonormal frame)."""
    helper = np.where(np.abs(normals[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(normals, t1)
    return t1, t2


def _escapes(tracer, centroids, normals, faces_idx, n_rays: int, side: float,
             chunk: int = 2_000_000) -> np.ndarray:
    """Rays of the fan that leave each given triangle's ``side`` (+1 front, -1 back)
    without meeting the surface (count per triangle)."""
    fan = hemisphere_fan(n_rays)
    out = np.zeros(len(faces_idx), np.int64)
    per = max(1, chunk // n_rays)
    for a in range(0, len(faces_idx), per):
        idx = faces_idx[a:a + per]
        nrm = side * normals[idx]
        t1, t2 = _frames(nrm)
        dirs = (fan[None, :, 0:1] * t1[:, None, :] + fan[None, :, 1:2] * t2[:, None, :]
                + fan[None, :, 2:3] * nrm[:, None, :]).reshape(-1, 3)
        org = np.repeat(centroids[idx] + tracer.offset * nrm, n_rays, axis=0)
        hit = tracer.any_hit(org, dirs, validate=False).reshape(len(idx), n_rays)
        out[a:a + per] = n_rays - hit.sum(axis=1)
    return out


def outside_visibility(vertices, faces, backend: str = "auto", n_rays: int = OUTSIDE_RAYS,
                       n_retry: int = OUTSIDE_RAYS_RETRY):
    """Rays that leave each triangle's front and back sides to infinity.

    Parameters
    ----------
    vertices : (N, 3) [m]
    faces : (M, 3)
    backend : {'auto', 'embree', 'numba'}
        Ray tracer (:func:`shipthermal.raytrace.make_tracer`).
    n_rays, n_retry : int
        Fan sizes of the first pass and of the retry of undecided triangles.

    Returns
    -------
    front, back : (M,) int
        Escaping rays from the front (normal side) and from the back. The back is traced
        only where the front found none (elsewhere ``back`` is 0); undecided triangles
        are traced again with ``n_retry`` rays on each side.
    """
    # deferred: the ray tracers load numba and scipy (0.85 s, measured); loading a scenario
    # imports neither (test_load_is_lazy)
    from ..raytrace import make_tracer

    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    p = v[f]
    nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    length = np.linalg.norm(nrm, axis=1)
    nrm = nrm / np.where(length > 0, length, 1.0)[:, None]
    cen = p.mean(axis=1)
    tracer = make_tracer(v, f, backend)
    every = np.arange(len(f))
    front = _escapes(tracer, cen, nrm, every, n_rays, 1.0)
    back = np.zeros(len(f), np.int64)
    blocked = np.flatnonzero(front == 0)
    if len(blocked):
        back[blocked] = _escapes(tracer, cen, nrm, blocked, n_rays, -1.0)
        undecided = blocked[back[blocked] == 0]
        if len(undecided) and n_retry > n_rays:
            front[undecided] = _escapes(tracer, cen, nrm, undecided, n_retry, 1.0)
            still = undecided[front[undecided] == 0]
            if len(still):
                back[still] = _escapes(tracer, cen, nrm, still, n_retry, -1.0)
    return front, back


# ---------------------------------------------------------------------------------------
# Pieces
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PieceReport:
    """What the rays found per connected piece of a surface.

    Attributes
    ----------
    piece : (M,) int
        Connected piece of each triangle (triangles sharing a vertex are connected).
    outward, inward, enclosed : (M,) bool
        Per triangle: the front sees out; only the back sees out; neither side sees out.
    interior_pieces, inverted_pieces : tuple of int
        Pieces that are interior shells (:data:`ENCLOSED_PIECE_SHARE` of their area
        enclosed) and pieces that are inside-out (:data:`INWARD_PIECE_SHARE`).
    stray_inward, stray_enclosed : int
        Triangles of the other pieces that face in, or see out from neither side.
    """

    piece: np.ndarray
    outward: np.ndarray
    inward: np.ndarray
    enclosed: np.ndarray
    interior_pieces: tuple
    inverted_pieces: tuple
    stray_inward: int
    stray_enclosed: int

    @property
    def interior_faces(self) -> np.ndarray:
        """Triangles of the interior shells (bool per triangle)."""
        return np.isin(self.piece, self.interior_pieces)

    @property
    def inverted_faces(self) -> np.ndarray:
        """Triangles of the inside-out pieces (bool per triangle)."""
        return np.isin(self.piece, self.inverted_pieces)


def _pieces(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    # deferred: start-up cost (scipy.sparse.csgraph takes ~1 s to import)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    e = faces[:, [0, 1, 1, 2]].reshape(-1, 2)
    g = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n_vertices, n_vertices))
    return connected_components(g, directed=False)[1][faces[:, 0]]


def classify_pieces(vertices, faces, backend: str = "auto") -> PieceReport:
    """Interior shells and inside-out pieces of a surface, found by ray casting.

    Parameters
    ----------
    vertices : (N, 3) [m]
    faces : (M, 3)
    backend : str
        Ray tracer.

    Returns
    -------
    PieceReport
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    front, back = outside_visibility(v, f, backend)
    outward = front > 0
    inward = ~outward & (back > 0)
    enclosed = ~outward & ~inward
    piece = _pieces(f, len(v))
    area = face_areas(v, f)
    n = int(piece.max()) + 1 if len(piece) else 0
    total = np.bincount(piece, weights=area, minlength=n)
    share_in = np.bincount(piece, weights=area * inward, minlength=n) / np.maximum(total, 1e-300)
    share_out = np.bincount(piece, weights=area * outward, minlength=n) / np.maximum(total, 1e-300)
    share_enc = np.bincount(piece, weights=area * enclosed, minlength=n) / np.maximum(total, 1e-300)
    interior = tuple(int(k) for k in np.flatnonzero(share_enc >= ENCLOSED_PIECE_SHARE))
    inverted = tuple(int(k) for k in np.flatnonzero((share_in >= INWARD_PIECE_SHARE)
                                                     & (share_in > share_out)))
    rest = ~np.isin(piece, interior + inverted)
    return PieceReport(piece=piece, outward=outward, inward=inward, enclosed=enclosed,
                       interior_pieces=interior, inverted_pieces=inverted,
                       stray_inward=int((inward & rest).sum()),
                       stray_enclosed=int((enclosed & rest).sum()))


# ---------------------------------------------------------------------------------------
# Parts that make sense
# ---------------------------------------------------------------------------------------
def part_sense(vertices, faces, face_part, part_names, freeboard: float) -> tuple[list, list]:
    """Parts that contradict what they name (waterline at z = 0, normals outward).

    Parameters
    ----------
    vertices : (N, 3) [m]
    faces : (M, 3)
    face_part : (M,) int
    part_names : sequence of str
    freeboard : float
        Deck height amidships [m] (NaN when unknown).

    Returns
    -------
    refusals, warnings : list of str
        Each a sentence saying what was found. Refusals: the deck is mostly not facing
        the sky (:data:`DECK_SKY_MIN_SHARE`), the hull has no wetted part. Warnings: most
        of the superstructure lies below the deck.
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    lab = np.asarray(face_part)
    mains = np.array([main_part(n) for n in part_names])[lab]
    p = v[f]
    nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    area = 0.5 * np.linalg.norm(nrm, axis=1)
    nz = nrm[:, 2] / np.maximum(2.0 * area, 1e-300)
    zc = p[:, :, 2].mean(axis=1)
    refusals, warnings = [], []
    deck = mains == "deck"
    if deck.any():
        a = area[deck].sum()
        sky = area[deck & (nz >= np.cos(np.radians(DECK_SKY_NORMAL_DEG)))].sum() / a
        if sky < DECK_SKY_MIN_SHARE:
            down = area[deck & (nz <= -np.cos(np.radians(DECK_SKY_NORMAL_DEG)))].sum() / a
            refusals.append(f"only {100 * sky:.0f} % of the deck's area faces the sky (normal "
                            f"within {DECK_SKY_NORMAL_DEG:g} deg of up; {100 * down:.0f} % faces "
                            f"down): the deck label lies on hull sides, an inside shell or "
                            f"inward faces")
    if not (mains == "hull_wetted").any():
        refusals.append("no triangle belongs to the wetted hull (below the waterline): the "
                        "ship would not touch the sea")
    sup = mains == "superstructure"
    if sup.any() and np.isfinite(freeboard):
        below = area[sup & (zc < freeboard - 0.05 * max(freeboard, 1.0))].sum() / area[sup].sum()
        if below > 0.5:
            warnings.append(f"{100 * below:.0f} % of the superstructure's area lies below the "
                            f"deck (freeboard {freeboard:.2f} m): are the parts swapped?")
    return refusals, warnings


def sliver_share(vertices, faces) -> tuple[float, float]:
    """Share of sliver triangles (smallest angle below :data:`SLIVER_ANGLE_DEG`) and the
    edge length of equilateral triangles of the same count and total area [m] (the
    resolution a remesh would keep)."""
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    p = v[f]
    e = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]], axis=1)
    length = np.linalg.norm(e, axis=2)
    area = face_areas(v, f)
    # the smallest angle is opposite the shortest edge: sin = 2 A / (product of the others)
    k = np.argmin(length, axis=1)
    rows = np.arange(len(f))
    others = length.prod(axis=1) / np.maximum(length[rows, k], 1e-300)
    sin_min = np.clip(2.0 * area / np.maximum(others, 1e-300), 0.0, 1.0)
    share = float(np.mean(sin_min < np.sin(np.radians(SLIVER_ANGLE_DEG))))
    return share, float(np.sqrt(4.0 * area.mean() / np.sqrt(3.0)))
