"""Numba bounding-volume hierarchy and ray–triangle kernels (the independent fallback tracer).

The hierarchy is a binary tree over axis-aligned boxes built top-down with a binned surface
area heuristic (SAH, 16 bins on the longest centroid axis; Wald 2007), falling back to a
median split when the heuristic cannot separate the triangles. Children of a node are stored
next to each other (``right = left + 1``) so a node needs only one child index.

Traversal is an ordered stack walk (nearer child first, boxes beyond the current closest hit
skipped); the triangle test is Möller–Trumbore (1997) in float64 without back-face culling,
edges inclusive. ``prange`` runs over blocks of rays so each thread allocates one stack.

``brute_force_first`` tests every ray against every triangle with the same triangle test: it
is the plain reference the BVH is checked against.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_N_BINS = 16
_RAY_BLOCK = 256  # rays per parallel task; one traversal stack each
_DET_EPS = 1e-300  # rays exactly parallel to a triangle's plane cannot hit it


@njit(cache=True)
def _surface_area(lo, hi):
    dx = hi[0] - lo[0]
    dy = hi[1] - lo[1]
    dz = hi[2] - lo[2]
    if dx < 0.0:  # empty box
        return 0.0
    return 2.0 * (dx * dy + dy * dz + dz * dx)


@njit(cache=True)
def build_bvh(tri_min, tri_max, centroid, leaf_size):
    """Build the hierarchy.

    Returns (node_min, node_max, node_left, node_start, node_count, order, max_depth).

    ``node_left[i] == -1`` marks a leaf holding triangles
    ``order[node_start[i] : node_start[i] + node_count[i]]``.
    """
    n = centroid.shape[0]
    order = np.arange(n)
    max_nodes = max(2 * n - 1, 1)
    node_min = np.empty((max_nodes, 3))
    node_max = np.empty((max_nodes, 3))
    node_left = np.full(max_nodes, -1, np.int64)
    node_start = np.zeros(max_nodes, np.int64)
    node_count = np.zeros(max_nodes, np.int64)

    stack_node = np.empty(max_nodes, np.int64)
    stack_start = np.empty(max_nodes, np.int64)
    stack_end = np.empty(max_nodes, np.int64)
    stack_depth = np.empty(max_nodes, np.int64)
    max_depth = 0
    stack_depth[0] = 0
    stack_node[0] = 0
    stack_start[0] = 0
    stack_end[0] = n
    sp = 1
    n_nodes = 1

    bin_count = np.zeros(_N_BINS, np.int64)
    bin_lo = np.empty((_N_BINS, 3))
    bin_hi = np.empty((_N_BINS, 3))
    left_area = np.empty(_N_BINS)
    left_cnt = np.empty(_N_BINS, np.int64)
    lo = np.empty(3)
    hi = np.empty(3)
    clo = np.empty(3)
    chi = np.empty(3)

    while sp > 0:
        sp -= 1
        node = stack_node[sp]
        start = stack_start[sp]
        end = stack_end[sp]
        depth = stack_depth[sp]
        max_depth = max(max_depth, depth)
        count = end - start
        for k in range(3):
            lo[k] = np.inf
            hi[k] = -np.inf
            clo[k] = np.inf
            chi[k] = -np.inf
        for i in range(start, end):
            t = order[i]
            for k in range(3):
                lo[k] = min(lo[k], tri_min[t, k])
                hi[k] = max(hi[k], tri_max[t, k])
                clo[k] = min(clo[k], centroid[t, k])
                chi[k] = max(chi[k], centroid[t, k])
        for k in range(3):
            node_min[node, k] = lo[k]
            node_max[node, k] = hi[k]
        node_start[node] = start
        node_count[node] = count
        if count <= leaf_size:
            continue
        axis = 0
        ext = chi[0] - clo[0]
        for k in range(1, 3):
            if chi[k] - clo[k] > ext:
                ext = chi[k] - clo[k]
                axis = k
        if ext <= 0.0:
            continue  # all centroids coincide: cannot split, keep a (large) leaf

        # binned SAH along the longest centroid axis
        scale = _N_BINS * (1.0 - 1e-9) / ext
        for b in range(_N_BINS):
            bin_count[b] = 0
            for k in range(3):
                bin_lo[b, k] = np.inf
                bin_hi[b, k] = -np.inf
        for i in range(start, end):
            t = order[i]
            b = int((centroid[t, axis] - clo[axis]) * scale)
            bin_count[b] += 1
            for k in range(3):
                bin_lo[b, k] = min(bin_lo[b, k], tri_min[t, k])
                bin_hi[b, k] = max(bin_hi[b, k], tri_max[t, k])
        # sweep from the left: area and count of bins [0, b]
        for k in range(3):
            lo[k] = np.inf
            hi[k] = -np.inf
        c = 0
        for b in range(_N_BINS - 1):
            c += bin_count[b]
            for k in range(3):
                lo[k] = min(lo[k], bin_lo[b, k])
                hi[k] = max(hi[k], bin_hi[b, k])
            left_area[b] = _surface_area(lo, hi)
            left_cnt[b] = c
        best_cost = np.inf
        best_split = -1
        for k in range(3):
            lo[k] = np.inf
            hi[k] = -np.inf
        c = 0
        for b in range(_N_BINS - 1, 0, -1):
            c += bin_count[b]
            for k in range(3):
                lo[k] = min(lo[k], bin_lo[b, k])
                hi[k] = max(hi[k], bin_hi[b, k])
            if c == 0 or left_cnt[b - 1] == 0:
                continue
            cost = left_area[b - 1] * left_cnt[b - 1] + _surface_area(lo, hi) * c
            if cost < best_cost:
                best_cost = cost
                best_split = b  # bins [0, b) go left
        mid = start
        if best_split > 0:
            # in-place partition of order[start:end]
            i = start
            j = end - 1
            while i <= j:
                t = order[i]
                b = int((centroid[t, axis] - clo[axis]) * scale)
                if b < best_split:
                    i += 1
                else:
                    order[i] = order[j]
                    order[j] = t
                    j -= 1
            mid = i
        if mid <= start or mid >= end:
            # SAH failed to separate (e.g. all in one bin): median split on the axis
            keys = np.empty(count)
            for i in range(count):
                keys[i] = centroid[order[start + i], axis]
            perm = np.argsort(keys)
            tmp = order[start:end].copy()
            for i in range(count):
                order[start + i] = tmp[perm[i]]
            mid = start + count // 2
        left = n_nodes
        n_nodes += 2
        node_left[node] = left
        stack_node[sp] = left
        stack_start[sp] = start
        stack_end[sp] = mid
        stack_depth[sp] = depth + 1
        sp += 1
        stack_node[sp] = left + 1
        stack_start[sp] = mid
        stack_end[sp] = end
        stack_depth[sp] = depth + 1
        sp += 1

    return (node_min[:n_nodes].copy(), node_max[:n_nodes].copy(), node_left[:n_nodes].copy(),
            node_start[:n_nodes].copy(), node_count[:n_nodes].copy(), order, max_depth)


@njit(cache=True, inline="always")
def _hit_triangle(ox, oy, oz, dx, dy, dz, v0, e1, e2, t):
    """Möller–Trumbore distance along the ray, or inf for a miss (edges inclusive)."""
    e1x = e1[t, 0]
    e1y = e1[t, 1]
    e1z = e1[t, 2]
    e2x = e2[t, 0]
    e2y = e2[t, 1]
    e2z = e2[t, 2]
    px = dy * e2z - dz * e2y
    py = dz * e2x - dx * e2z
    pz = dx * e2y - dy * e2x
    det = e1x * px + e1y * py + e1z * pz
    if abs(det) < _DET_EPS:
        return np.inf
    inv = 1.0 / det
    tx = ox - v0[t, 0]
    ty = oy - v0[t, 1]
    tz = oz - v0[t, 2]
    u = (tx * px + ty * py + tz * pz) * inv
    if u < 0.0 or u > 1.0:
        return np.inf
    qx = ty * e1z - tz * e1y
    qy = tz * e1x - tx * e1z
    qz = tx * e1y - ty * e1x
    v = (dx * qx + dy * qy + dz * qz) * inv
    if v < 0.0 or u + v > 1.0:
        return np.inf
    return (e2x * qx + e2y * qy + e2z * qz) * inv


@njit(cache=True, inline="always")
def _box_entry(node_min, node_max, node, ox, oy, oz, ix, iy, iz, tmax):
    """Entry distance of the ray into a node's box, or inf if it misses within (0, tmax)."""
    t1 = (node_min[node, 0] - ox) * ix
    t2 = (node_max[node, 0] - ox) * ix
    tlo = min(t1, t2)
    thi = max(t1, t2)
    t1 = (node_min[node, 1] - oy) * iy
    t2 = (node_max[node, 1] - oy) * iy
    tlo = max(tlo, min(t1, t2))
    thi = min(thi, max(t1, t2))
    t1 = (node_min[node, 2] - oz) * iz
    t2 = (node_max[node, 2] - oz) * iz
    tlo = max(tlo, min(t1, t2))
    thi = min(thi, max(t1, t2))
    if thi < max(tlo, 0.0) or tlo > tmax:
        return np.inf
    return tlo


@njit(cache=True, inline="always")
def _inv(d):
    # a zero component gives a huge slope, not inf, so (bound - origin) * inv is never NaN
    if d == 0.0:
        return 1e300
    return 1.0 / d


@njit(parallel=True, cache=True)
def trace_bvh(node_min, node_max, node_left, node_start, node_count, order, v0, e1, e2,
              origins, directions, max_distance, any_hit, stack_size):
    """First hit (triangle index, -1 for none) of each ray with t in (0, max_distance).

    With ``any_hit`` the walk stops at the first triangle found (occlusion query); the index
    returned is then some hit triangle, not necessarily the nearest.
    """
    n = origins.shape[0]
    out = np.full(n, -1, np.int64)
    # one direction / one distance may be shared by all rays
    one_dir = 1 if directions.shape[0] == 1 else 0
    one_dist = 1 if max_distance.shape[0] == 1 else 0
    n_blocks = (n + _RAY_BLOCK - 1) // _RAY_BLOCK
    for blk in prange(n_blocks):
        # an ordered walk holds at most one pending sibling per level: depth + 1 entries
        stack = np.empty(stack_size, np.int64)
        r_end = min(n, (blk + 1) * _RAY_BLOCK)
        for r in range(blk * _RAY_BLOCK, r_end):
            ox = origins[r, 0]
            oy = origins[r, 1]
            oz = origins[r, 2]
            rd = r if one_dir == 0 else 0
            dx = directions[rd, 0]
            dy = directions[rd, 1]
            dz = directions[rd, 2]
            ix = _inv(dx)
            iy = _inv(dy)
            iz = _inv(dz)
            t_best = max_distance[r if one_dist == 0 else 0]
            best = -1
            if _box_entry(node_min, node_max, 0, ox, oy, oz, ix, iy, iz, t_best) == np.inf:
                continue
            sp = 0
            stack[0] = 0
            sp = 1
            done = False
            while sp > 0 and not done:
                sp -= 1
                node = stack[sp]
                left = node_left[node]
                if left < 0:
                    s = node_start[node]
                    for i in range(s, s + node_count[node]):
                        t = order[i]
                        th = _hit_triangle(ox, oy, oz, dx, dy, dz, v0, e1, e2, t)
                        if th > 0.0 and th < t_best:
                            t_best = th
                            best = t
                            if any_hit:
                                done = True
                                break
                    continue
                tl = _box_entry(node_min, node_max, left, ox, oy, oz, ix, iy, iz, t_best)
                tr = _box_entry(node_min, node_max, left + 1, ox, oy, oz, ix, iy, iz, t_best)
                # push the farther child first so the nearer one is walked first
                if tl <= tr:
                    if tr < np.inf:
                        stack[sp] = left + 1
                        sp += 1
                    if tl < np.inf:
                        stack[sp] = left
                        sp += 1
                else:
                    if tl < np.inf:
                        stack[sp] = left
                        sp += 1
                    stack[sp] = left + 1
                    sp += 1
            out[r] = best
    return out


@njit(parallel=True, cache=True)
def brute_force_first(v0, e1, e2, origins, directions, max_distance):
    """Reference: nearest hit of each ray over all triangles, same triangle test as the BVH."""
    n = origins.shape[0]
    m = v0.shape[0]
    out = np.full(n, -1, np.int64)
    step_dir = 0 if directions.shape[0] == 1 else 1
    step_dist = 0 if max_distance.shape[0] == 1 else 1
    for r in prange(n):
        rd = r * step_dir
        t_best = max_distance[r * step_dist]
        best = -1
        for t in range(m):
            th = _hit_triangle(origins[r, 0], origins[r, 1], origins[r, 2], directions[rd, 0],
                               directions[rd, 1], directions[rd, 2], v0, e1, e2, t)
            if th > 0.0 and th < t_best:
                t_best = th
                best = t
        out[r] = best
    return out
