"""Diffuse view factors of every face to the sky, the sea and the other faces.

Each face i shoots ``rays_per_face`` rays from points spread uniformly over it, with
directions cosine-weighted about its outward normal (density cos θ/π). For such rays the
fraction that first reaches a surface X is the diffuse view factor F_iX (e.g. Howell,
Mengüç & Siegel, *Thermal Radiation Heat Transfer*, 7th ed., §7.4: Monte Carlo view
factors). A ray ends

* on face j when the tracer's first hit is j and it is nearer than the sea surface;
* on the sea when it heads down (d_z < 0) and meets the plane ``z = sea_level_z`` first;
* in the sky otherwise (it escapes upward, or sideways without ever meeting the sea).

Rays starting below the sea surface (wetted hull) are counted as sea without tracing.
With ``sea_level_z=None`` there is no sea and every escaping ray counts as sky.

Each row of counts is a multinomial sample, so F_sky, F_sea and each F_ij carry the binomial
standard error sqrt(F (1 - F) / N). The samples are randomised quasi-Monte Carlo
(:mod:`~shipthermal.raytrace.sampling`): unbiased, and their true error is usually below
the binomial figure, which is reported as a conservative estimate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numba import njit
from tqdm.auto import tqdm

from shipthermal._threads import thread_map
from shipthermal.errors import require
from shipthermal.parameters import VIEW_RAYS_PER_FACE
from shipthermal.raytrace import _raygen
from shipthermal.raytrace.sampling import unit_samples
from shipthermal.raytrace.tracers import batch_threads

__all__ = ["ViewFactors", "view_factors", "view_factor_rays", "symmetrize"]

_DEFAULT_CHUNK = 1 << 18  # rays per tracer call: ~10 MB of rays, stays in cache-friendly sizes


@dataclass(frozen=True)
class ViewFactors:
    """Diffuse view factors of each face [-].

    Attributes
    ----------
    F_sky : (n_faces,) float
        Fraction of the face's diffuse emission reaching the sky.
    F_sea : (n_faces,) float
        Fraction reaching the sea surface.
    F_faces : scipy.sparse.csr_matrix (n_faces, n_tracer_faces)
        F_faces[i, j]: fraction of face i's emission reaching triangle j of the tracer's
        mesh first (square when the faces are the tracer's own mesh, the usual case).
        ``F_sky + F_sea + F_faces.sum(axis=1)`` is 1 for every face.
    se_sky, se_sea : (n_faces,) float
        Binomial standard errors of F_sky and F_sea (conservative for the quasi-random
        samples used).
    rays_per_face : int
        Rays shot per face.
    areas : (n_faces,) float
        Face areas [m²].
    symmetric : bool
        True when reciprocity was imposed (:func:`symmetrize`).
    """

    F_sky: np.ndarray
    F_sea: np.ndarray
    F_faces: sp.csr_matrix
    se_sky: np.ndarray
    se_sea: np.ndarray
    rays_per_face: int
    areas: np.ndarray
    symmetric: bool = False

    def standard_error(self, fraction):
        """Binomial standard error of any fraction estimated from these rays [-]."""
        f = np.asarray(fraction, dtype=np.float64)
        return np.sqrt(np.clip(f * (1.0 - f), 0.0, None) / self.rays_per_face)

    @property
    def row_sums(self) -> np.ndarray:
        """F_sky + F_sea + Σ_j F_ij per face (1 up to round-off)."""
        return self.F_sky + self.F_sea + np.asarray(self.F_faces.sum(axis=1)).ravel()


def view_factor_rays(tracer, vertices, faces, face_index, rays_per_face: int, seed: int):
    """Origins and cosine-weighted directions of the rays of the faces in ``face_index``.

    Deterministic for a given ``seed`` whatever the chunking: the base quasi-random set and
    the per-face shifts are drawn once for the whole mesh.

    Returns
    -------
    origins, directions : (len(face_index), rays_per_face, 3) float
        Ray origins [m] (offset ``tracer.offset`` along the normal) and unit directions.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    base, shift = unit_samples(len(faces), int(rays_per_face), 4, seed)
    frames = _Frames(vertices, faces)
    idx = np.asarray(face_index, dtype=np.int64)
    o, d = frames.rays(idx, base, shift, tracer.offset)
    return o.reshape(len(idx), -1, 3), d.reshape(len(idx), -1, 3)


class _Frames:
    """Per-face corner, edges and orthonormal frame, computed once per mesh."""

    def __init__(self, vertices, faces):
        # fused numba version of sampling.face_geometry + face_frames (tests compare them)
        (self.v0, self.e1, self.e2, self.normals, self.areas, self.t1,
         self.t2) = _raygen.face_frames(np.ascontiguousarray(vertices, dtype=np.float64),
                                        np.ascontiguousarray(faces, dtype=np.int64))

    def rays(self, idx, base, shift, offset, kernel=_raygen.face_rays):
        # fused numba version of sampling.triangle_points + cosine_hemisphere
        return kernel(self.v0, self.e1, self.e2, self.normals, self.t1, self.t2, base, shift,
                      idx, float(offset), True)


@njit(cache=True, nogil=True)
def _sea_distances(o, d, z):
    t = np.empty(o.shape[0])
    under = np.empty(o.shape[0], np.bool_)
    for r in range(o.shape[0]):
        under[r] = o[r, 2] < z
        t[r] = (z - o[r, 2]) / d[r, 2] if d[r, 2] < 0.0 else np.inf
    return t, under


def _sea_distance(o, d, sea_level_z):
    """Distance along each ray to the sea plane (inf for rays going up, or without a sea)
    and whether its origin is under the sea."""
    if sea_level_z is None:
        return np.full(len(o), np.inf), np.zeros(len(o), bool)
    return _sea_distances(o, d, float(sea_level_z))


@njit(cache=True, nogil=True)
def _tally(hit, submerged, t_sea, k, n_faces):
    """Per face of a chunk (rays ``k`` by ``k``): rays to the sea (from under it, or
    meeting it before any face), to the sky, and the (face, hit face) pairs of the rest."""
    sea = np.zeros(n_faces, np.int64)
    sky = np.zeros(n_faces, np.int64)
    rows = np.empty(hit.shape[0], np.int64)
    cols = np.empty(hit.shape[0], np.int64)
    m = 0
    for r in range(hit.shape[0]):
        f = r // k
        if submerged[r] or (hit[r] < 0 and np.isfinite(t_sea[r])):
            sea[f] += 1
        elif hit[r] < 0:
            sky[f] += 1
        else:
            rows[m] = f
            cols[m] = hit[r]
            m += 1
    return sea, sky, rows[:m], cols[:m]


def view_factors(tracer, vertices, faces, rays_per_face: int = VIEW_RAYS_PER_FACE, seed: int = 0,
                 sea_level_z: float | None = 0.0, reciprocity: bool = False,
                 chunk_rays: int = _DEFAULT_CHUNK, progress: bool | None = None) -> ViewFactors:
    """Monte-Carlo view factors of every face to the sky, the sea and the other faces.

    Parameters
    ----------
    tracer : EmbreeTracer or NumbaTracer
        Tracer built on the same ``vertices`` and ``faces``.
    vertices : (n, 3) array_like
        Vertex coordinates [m].
    faces : (m, 3) array_like of int
        Triangles that shoot rays; the outward normal follows the right-hand rule on the
        vertex order. Usually the tracer's own mesh; may be a subset (e.g. outer faces only),
        then the columns of F_faces still index the tracer's triangles.
    rays_per_face : int
        Rays per face; the standard error of a fraction F is sqrt(F(1-F)/rays_per_face).
    seed : int
        Seed; the result is a deterministic function of it.
    sea_level_z : float or None
        Height of the sea plane [m]; None for no sea (escaping rays all count as sky).
    reciprocity : bool
        Impose A_i F_ij = A_j F_ji with :func:`symmetrize`.
    chunk_rays : int
        Rays per tracer call (memory bound).
    progress : bool, optional
        Show a tqdm bar (None: only on a terminal).

    Returns
    -------
    ViewFactors
    """
    require(int(rays_per_face) >= 1, "rays_per_face", rays_per_face, "must be >= 1")
    require(int(chunk_rays) >= 1, "chunk_rays", chunk_rays, "must be >= 1")
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    n_faces = len(faces)
    n_cols = len(tracer.faces)  # hits are indices into the tracer's triangles
    k = int(rays_per_face)
    base, shift = unit_samples(n_faces, k, 4, seed)
    frames = _Frames(vertices, faces)
    areas = frames.areas

    face_chunk = max(1, int(chunk_rays) // k)
    starts = range(0, n_faces, face_chunk)
    # Embree: one chunk of faces per thread, each making its rays in its own thread
    # (frigate, 10.3 M rays: 1.9 → 1.3 s)
    tr, threads = batch_threads(tracer, len(starts))
    make_rays = _raygen.face_rays_serial if threads > 1 else _raygen.face_rays
    with tqdm(total=n_faces * k, unit="ray", unit_scale=True, desc="view-factor rays",
              disable=(not progress) if progress is not None else None) as bar:

        def chunk(start):
            """Rays of faces ``start …``: their sky and sea counts and their face hits (one
            CSR block of rows: chunks are disjoint row ranges)."""
            idx = np.arange(start, min(n_faces, start + face_chunk))
            o, d = frames.rays(idx, base, shift, tracer.offset, make_rays)
            t_sea, submerged = _sea_distance(o, d, sea_level_z)
            if submerged.any():
                traced = ~submerged
                hit = np.full(len(o), -1, np.int64)
                hit[traced] = tr.intersects_first(o[traced], d[traced], t_sea[traced],
                                                  validate=False)
            else:
                hit = tr.intersects_first(o, d, t_sea, validate=False)
            sea, sky, rows, cols = _tally(hit, submerged, t_sea, k, len(idx))
            # COO -> CSR sums the duplicate (i, j) pairs in linear time, no sort
            block = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(idx), n_cols))
            bar.update(len(o))
            return sea, sky, block

        parts = thread_map(chunk, starts, threads)   # in the order of the chunks
    n_sea, n_sky, blocks = (list(p) for p in zip(*parts))
    n_sea, n_sky = np.concatenate(n_sea), np.concatenate(n_sky)

    F_faces = sp.vstack(blocks, format="csr") / k
    F_faces.sum_duplicates()
    F_sky = n_sky / k
    F_sea = n_sea / k
    se = lambda f: np.sqrt(f * (1.0 - f) / k)  # noqa: E731
    vf = ViewFactors(F_sky=F_sky, F_sea=F_sea, F_faces=F_faces, se_sky=se(F_sky),
                     se_sea=se(F_sea), rays_per_face=k, areas=areas)
    return symmetrize(vf) if reciprocity else vf


def symmetrize(vf: ViewFactors) -> ViewFactors:
    """Impose reciprocity A_i F_ij = A_j F_ji and keep every row summing to 1.

    Notes
    -----
    The exchange areas G = A_i F_ij are replaced by (G + Gᵀ)/2, the average of the two
    independent estimates of the same quantity, so the noise of G drops by up to √2 and
    long-wave exchange between faces conserves energy exactly. Rows then no longer sum to 1:
    the remainder 1 − Σ_j F_ij is given back to the environment, split between sky and sea
    in the ratio of the traced F_sky : F_sea (all to sky when both are 0). Where the
    remainder would be negative (a face whose neighbours saw it more than it saw them) the
    row of F_ij is scaled down to sum to 1 with no environment share, which breaks
    reciprocity for that row only; this happens only when the estimates are very noisy.
    Zero-area faces keep their traced rows.
    """
    require(vf.F_faces.shape[0] == vf.F_faces.shape[1], "vf.F_faces.shape", vf.F_faces.shape,
            "must be square (faces = the tracer's mesh) to impose reciprocity")
    A = vf.areas
    G = sp.diags(A) @ vf.F_faces
    G = 0.5 * (G + G.T)
    inv_a = np.divide(1.0, A, out=np.zeros_like(A), where=A > 0)
    F = (sp.diags(inv_a) @ G).tocsr()
    zero = A <= 0
    if zero.any():
        keep = sp.diags(zero.astype(float)) @ vf.F_faces
        F = (sp.diags((~zero).astype(float)) @ F + keep).tocsr()
    row = np.asarray(F.sum(axis=1)).ravel()
    env_old = vf.F_sky + vf.F_sea
    rest = 1.0 - row
    over = rest < 0
    if over.any():
        F = (sp.diags(np.where(over, 1.0 / np.where(over, row, 1.0), 1.0)) @ F).tocsr()
        rest = np.where(over, 0.0, rest)
    share_sky = np.divide(vf.F_sky, env_old, out=np.ones_like(env_old), where=env_old > 0)
    F_sky = rest * share_sky
    F_sea = rest - F_sky
    F.sum_duplicates()
    return ViewFactors(F_sky=F_sky, F_sea=F_sea, F_faces=F, se_sky=vf.se_sky, se_sea=vf.se_sea,
                       rays_per_face=vf.rays_per_face, areas=vf.areas, symmetric=True)
