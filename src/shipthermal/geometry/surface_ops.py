"""Triangle-surface quality and sliver clean-up that moves no surface.

* :func:`surface_quality` — edge lengths, aspect ratios and angles.
* :func:`collapse_short_edges`, :func:`flip_coplanar_edges` — sliver clean-up that moves
  no surface (areas, volume, part boundaries unchanged); used by the built-in ship
  builder (:mod:`.ship`) and by :func:`~.remesh.remesh_ship`.
* :func:`fix_winding` — consistent triangle orientation per connected component (reading
  user meshes: :mod:`.io`, :mod:`.cad`).
* :func:`fix_winding` — consistent triangle orientation per connected component (reading
  user meshes: :mod:`.io`, :mod:`.cad`).
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from .parts import face_areas

__all__ = ["surface_quality", "flip_coplanar_edges", "collapse_short_edges", "fix_winding"]


def surface_quality(vertices: np.ndarray, faces: np.ndarray) -> dict:
    """Quality figures of a triangulation.

    Returns
    -------
    dict
        ``n_faces``, ``n_vertices``; edge length ``edge_min/mean/max`` [m]; aspect ratio
        ``aspect_mean/p99/max`` (longest edge over the altitude to it, × √3/2, so 1 for
        an equilateral triangle); smallest angle ``min_angle_min/p1/median`` [deg];
        ``frac_min_angle_below_10`` and ``_below_20`` (fractions of triangles).
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    p = v[f]                                           # (M, 3, 3)
    e = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]], axis=1)
    length = np.linalg.norm(e, axis=2)                 # (M, 3)
    area = face_areas(v, f)
    lmax = length.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        aspect = np.where(area > 0, lmax * lmax * (math.sqrt(3) / 4.0) / area, np.inf)
        # Angle at each vertex between its two edges.
        cosang = np.stack([
            -np.einsum("ij,ij->i", e[:, 2], e[:, 0]) / (length[:, 2] * length[:, 0]),
            -np.einsum("ij,ij->i", e[:, 0], e[:, 1]) / (length[:, 0] * length[:, 1]),
            -np.einsum("ij,ij->i", e[:, 1], e[:, 2]) / (length[:, 1] * length[:, 2])], axis=1)
    ang = np.degrees(np.arccos(np.clip(np.nan_to_num(cosang, nan=1.0), -1, 1)))
    amin = ang.min(axis=1)
    return dict(n_faces=int(len(f)), n_vertices=int(len(np.unique(f))),
                edge_min=float(length.min()), edge_mean=float(length.mean()),
                edge_max=float(length.max()),
                aspect_mean=float(np.mean(aspect)), aspect_p99=float(np.percentile(aspect, 99)),
                aspect_max=float(np.max(aspect)),
                min_angle_min=float(amin.min()), min_angle_p1=float(np.percentile(amin, 1)),
                min_angle_median=float(np.median(amin)),
                frac_min_angle_below_10=float(np.mean(amin < 10.0)),
                frac_min_angle_below_20=float(np.mean(amin < 20.0)))


def _quantize(x: np.ndarray, rel: float = 1e-9) -> np.ndarray:
    """Values rounded to ``rel`` of their largest magnitude, so that values equal up to
    round-off (mirror-image edges, last-bit differences between SIMD code paths) sort as
    exact ties and are ordered by the explicit tie-breakers of the caller."""
    x = np.asarray(x, float)
    unit = rel * (float(np.abs(x).max()) if len(x) else 1.0) or rel
    return np.round(x / unit)


def _angles(p0, p1, p2):
    """Interior angles at p0, p1, p2 of triangles (rows) [rad]."""
    def ang(o, u, w):
        a, b = u - o, w - o
        cos = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        return np.arccos(np.clip(np.nan_to_num(cos, nan=1.0), -1.0, 1.0))
    return ang(p0, p1, p2), ang(p1, p2, p0), ang(p2, p0, p1)


def flip_coplanar_edges(vertices, faces, face_part, max_passes: int = 30,
                        coplanar_tol: float = 1e-10):
    """Improve triangle shapes by flipping edges inside flat regions of one part.

    An edge shared by two triangles of the same part whose normals agree to
    ``1 - n1·n2 < coplanar_tol`` is flipped when that raises the smaller of the two
    triangles' minimum angles (Lawson-type flips). Geometry, areas, volume, closedness,
    orientation and part boundaries are unchanged: only the triangulation of planes
    (deck, deckhouse walls) is, which removes most slivers a boolean leaves along
    intersection lines.

    Returns the new faces (same count) and the number of flips.
    """
    v = np.asarray(vertices, float)
    f = np.array(faces, dtype=np.int64, copy=True)
    lab = np.asarray(face_part)
    n_flips = 0
    for _ in range(max_passes):
        e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        face_of = np.tile(np.arange(len(f)), 3)
        opp = np.concatenate([f[:, 2], f[:, 0], f[:, 1]])
        # Pair the two half-edges of each interior edge through a scalar edge key (a 1-D
        # sort is an order of magnitude faster than np.unique over rows).
        key = np.minimum(e[:, 0], e[:, 1]) * len(v) + np.maximum(e[:, 0], e[:, 1])
        order = np.argsort(key, kind="stable")
        ks = key[order]
        start = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
        count = np.diff(np.r_[start, len(ks)])
        two = start[count == 2]
        i1, i2 = order[two], order[two + 1]
        f1, f2 = face_of[i1], face_of[i2]
        a, b, c, d = e[i1, 0], e[i1, 1], opp[i1], opp[i2]
        ok = (lab[f1] == lab[f2]) & (e[i2, 0] == b) & (c != d)
        p = v[f]
        nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        nlen = np.linalg.norm(nrm, axis=1)
        unit = nrm / np.where(nlen > 0, nlen, 1.0)[:, None]
        ok &= 1.0 - np.einsum("ij,ij->i", unit[f1], unit[f2]) < coplanar_tol
        ok &= (nlen[f1] > 0) & (nlen[f2] > 0)
        if not ok.any():
            break
        a, b, c, d, f1, f2 = a[ok], b[ok], c[ok], d[ok], f1[ok], f2[ok]
        old = np.minimum(np.min(_angles(v[a], v[b], v[c]), axis=0), np.min(_angles(v[b], v[a], v[d]), axis=0))
        new = np.minimum(np.min(_angles(v[a], v[d], v[c]), axis=0), np.min(_angles(v[d], v[b], v[c]), axis=0))
        # The new pair must keep the orientation (convex quadrilateral).
        n_new1 = np.cross(v[d] - v[a], v[c] - v[a])
        n_new2 = np.cross(v[b] - v[d], v[c] - v[d])
        same = ((np.einsum("ij,ij->i", n_new1, unit[f1]) > 0)
                & (np.einsum("ij,ij->i", n_new2, unit[f1]) > 0))
        good = np.flatnonzero(same & (new > old + 1e-9))
        if len(good) == 0:
            break
        # Largest gain first; ties (a symmetric hull has many) broken by the edge's
        # vertices, so the result does not depend on the sort algorithm numpy picks for
        # the CPU (an unstable sort orders ties differently on AVX2 and AVX-512 machines).
        gain = _quantize(new - old)[good]
        good = good[np.lexsort((b[good], a[good], -gain))]
        used = np.zeros(len(f), bool)
        chosen = []
        for g in good:                      # independent set: a face flips once per pass
            if not used[f1[g]] and not used[f2[g]]:
                used[f1[g]] = used[f2[g]] = True
                chosen.append(g)
        chosen = np.asarray(chosen)
        f[f1[chosen]] = np.stack([a[chosen], d[chosen], c[chosen]], 1)
        f[f2[chosen]] = np.stack([d[chosen], b[chosen], c[chosen]], 1)
        n_flips += len(chosen)
    return f, n_flips


def collapse_short_edges(vertices, faces, face_part, min_length: float, plane_tol: float,
                         max_passes: int = 5):
    """Remove edges shorter than ``min_length`` [m] where that changes no geometry.

    Vertex ``q`` is moved onto its neighbour ``p`` only if ``p`` lies (within ``plane_tol``
    [m]) in the plane of every triangle around ``q`` that survives, no triangle flips or
    degenerates, the collapse keeps the surface manifold (link condition), and part
    boundaries stay where they are (across a part boundary only along a straight boundary
    line). Areas, volume, part areas and closedness are therefore unchanged; the slivers a
    boolean leaves where two grids meet (short edges along the intersection lines) go.

    Returns ``(vertices, faces, face_part, n_collapsed)`` with unused vertices removed.
    """
    v = np.asarray(vertices, float)
    f = np.array(faces, dtype=np.int64, copy=True)
    lab = np.array(face_part, copy=True)
    alive = np.ones(len(f), bool)
    n_done = 0
    for _ in range(max_passes):
        e = np.sort(np.concatenate([f[alive][:, [0, 1]], f[alive][:, [1, 2]], f[alive][:, [2, 0]]]), axis=1)
        key = np.unique(e[:, 0] * len(v) + e[:, 1])
        e = np.stack(np.divmod(key, len(v)), axis=1)
        length = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
        short = length < min_length
        cand = e[short]
        # Shortest first; equal lengths (mirror-image edges) in vertex order: deterministic
        # whatever sort numpy uses on this CPU.
        cand = cand[np.lexsort((cand[:, 1], cand[:, 0], _quantize(length[short])))]
        if len(cand) == 0:
            break
        # vertex -> alive faces (CSR)
        ids = np.flatnonzero(alive)
        fv = f[ids].ravel()
        order = np.argsort(fv, kind="stable")
        starts = np.searchsorted(fv[order], np.arange(len(v) + 1))
        owner = np.repeat(ids, 3)[order]
        def faces_of(x):
            return owner[starts[x]:starts[x + 1]]
        locked = np.zeros(len(v), bool)
        done_pass = 0
        for p0, q0 in cand:
            if locked[p0] or locked[q0]:
                continue
            for p, q in ((p0, q0), (q0, p0)):
                fq = [F for F in faces_of(q) if alive[F]]
                fp = [F for F in faces_of(p) if alive[F]]
                shared = [F for F in fq if p in f[F]]
                if len(shared) != 2:
                    break
                others = [F for F in fq if F not in shared]
                opp = {int(x) for F in shared for x in f[F] if x != p and x != q}
                nq = {int(x) for F in fq for x in f[F]} - {q}
                np_ = {int(x) for F in fp for x in f[F]} - {p}
                if (nq & np_) != opp:
                    continue
                ok = True
                for F in others:
                    a, b, c = v[f[F]]
                    n = np.cross(b - a, c - a)
                    nn = np.linalg.norm(n)
                    if nn == 0 or abs(np.dot(n / nn, v[p] - v[q])) > plane_tol:
                        ok = False
                        break
                    tri = np.where(f[F] == q, p, f[F])
                    a2, b2, c2 = v[tri]
                    n2 = np.cross(b2 - a2, c2 - a2)
                    if np.dot(n2, n) <= 1e-3 * nn * nn:
                        ok = False
                        break
                if not ok:
                    continue
                labels_q = {int(lab[F]) for F in fq}
                if len(labels_q) > 1:
                    if lab[shared[0]] == lab[shared[1]] or len(labels_q) > 2:
                        continue
                    # q's other boundary edge (q, r) must continue the line p-q.
                    bnd = []
                    for r in nq - {p}:
                        fr = [F for F in fq if r in f[F]]
                        if len(fr) == 2 and lab[fr[0]] != lab[fr[1]]:
                            bnd.append(r)
                    if len(bnd) != 1:
                        continue
                    d1, d2 = v[p] - v[q], v[bnd[0]] - v[q]
                    if (np.linalg.norm(np.cross(d1, d2)) > plane_tol * np.linalg.norm(d2)
                            or np.dot(d1, d2) >= 0):
                        continue
                for F in shared:
                    alive[F] = False
                for F in others:
                    f[F] = np.where(f[F] == q, p, f[F])
                locked[list(nq | np_ | {p, q})] = True
                done_pass += 1
                break
        n_done += done_pass
        if done_pass == 0:
            break
    f, lab = f[alive], lab[alive]
    used, inv = np.unique(f, return_inverse=True)
    return v[used], inv.reshape(-1, 3), lab, n_done


def fix_winding(f: np.ndarray):
    """Make the winding consistent by breadth-first search over edge neighbours.

    Each connected component keeps the orientation of its majority (fewest flips); the
    caller then fixes the global sign from the signed volume. Returns the new faces and a
    mask of flipped triangles.
    """
    m = len(f)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    face_of = np.tile(np.arange(m), 3)
    key = np.sort(e, axis=1)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    order = np.argsort(inv, kind="stable")
    starts = np.searchsorted(inv[order], np.arange(inv.max() + 2))
    # same[i]: directed edge i runs the same way as its key (u < v).
    same = e[:, 0] < e[:, 1]
    flip = np.zeros(m, bool)
    seen = np.zeros(m, bool)
    for seed in range(m):
        if seen[seed]:
            continue
        comp = [seed]
        seen[seed] = True
        queue = deque([seed])
        while queue:
            t = queue.popleft()
            for k in range(3):
                i = t + k * m
                g = inv[i]
                for j in order[starts[g]:starts[g + 1]]:
                    u = face_of[j]
                    if u == t or seen[u]:
                        continue
                    # Consistent neighbours traverse the shared edge in opposite directions.
                    flip[u] = flip[t] ^ (same[i] == same[j])
                    seen[u] = True
                    comp.append(u)
                    queue.append(u)
        comp = np.asarray(comp)
        if flip[comp].sum() * 2 > len(comp):
            flip[comp] = ~flip[comp]
    out = f.copy()
    out[flip] = out[flip][:, ::-1]
    return out, flip
