"""The parametric hull: an analytic hull form and its closed hull, deck and transom surface.

``s`` ∈ [0, 1] runs from the transom (0) to the stem (1). Below the waterline each section
is a superellipse (full, round-bilged midships, V-shaped forward), above it the topsides
flare linearly out to the deck edge; the keel rises towards the transom and the forefoot
is cut up towards the stem; the deck rises towards the bow (sheer). Every section carries a
vertex exactly on ``z = 0`` so the waterline split is exact.
"""

from __future__ import annotations

import math

import numpy as np

from .grids import grid_faces, merge_vertices
from .parameters import ShipParameters

__all__ = ["HullForm", "hull_surface"]


class HullForm:
    """Analytic hull form: half-breadths and heights as functions of (s, z).

    ``s`` ∈ [0, 1] runs from the transom (0) to the stem (1).
    """

    def __init__(self, p: ShipParameters):
        self.p = p
        self.half = 0.5 * p.length
        self.s_bow = 1.0 - p.bow_fraction
        self.hb_max = 0.5 * p.beam
        self.hb_wl_max = self.hb_max - p.freeboard * math.tan(math.radians(p.flare_deg))
        self.rake = math.tan(math.radians(p.stem_rake_deg))

    def x_deck(self, s):
        return -self.half + s * self.p.length

    def z_deck(self, s):
        x = self.x_deck(s)
        x0 = 0.5 * self.half * 0.3   # sheer starts a bit forward of amidships
        u = np.clip((x - x0) / (self.half - x0), 0.0, 1.0)
        return self.p.freeboard + self.p.sheer_bow * u ** 2

    def _bow_u(self, s):
        return np.clip((s - self.s_bow) / (1.0 - self.s_bow), 0.0, 1.0)

    def _stern_u(self, s):
        if self.p.stern_fraction <= 0:
            return np.zeros_like(s)
        return np.clip((self.p.stern_fraction - s) / self.p.stern_fraction, 0.0, 1.0)

    def hb_deck(self, s):
        """Deck half-breadth: fuller than the waterline forward (bow flare)."""
        ub, ua = self._bow_u(s), self._stern_u(s)
        f = (1.0 - ub ** 2) ** 0.6 * (1.0 - (1.0 - self.p.transom_width) * ua ** 2)
        return self.hb_max * np.maximum(f, 0.0)

    def hb_waterline(self, s):
        ub, ua = self._bow_u(s), self._stern_u(s)
        f = (1.0 - ub ** 1.7) ** 1.1 * (1.0 - (1.0 - self.p.transom_width) * ua ** 2)
        return self.hb_wl_max * np.maximum(f, 0.0)

    def draught_local(self, s):
        ua = self._stern_u(s)
        ub = self._bow_u(s)
        return self.p.draught * (1.0 - self.p.keel_rise * ua ** 2) * (1.0 - self.p.forefoot * ub ** 3)

    def section_exponent(self, s):
        ub = self._bow_u(s)
        return self.p.section_mid + (self.p.section_bow - self.p.section_mid) * ub ** 1.5

    def x_at(self, s, z):
        """x of the station ``s`` at height ``z``: the stem rakes aft with depth below the deck."""
        shift = (self.z_deck(s) - z) * self.rake * self._bow_u(s)
        return self.x_deck(s) - shift


def _resample_polyline(pts: np.ndarray, n: int) -> np.ndarray:
    """``n + 1`` points equally spaced by arc length along a polyline (ends kept)."""
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    if arc[-1] <= 0:
        return np.repeat(pts[:1], n + 1, axis=0)
    t = np.linspace(0.0, arc[-1], n + 1)
    return np.stack([np.interp(t, arc, pts[:, k]) for k in range(pts.shape[1])], axis=1)


def _zipper(upper, lower, y_upper, y_lower) -> list[tuple[int, int, int]]:
    """Triangulate the strip between two chains of vertex indices running port → starboard.

    Both chains are monotone in y; the zipper advances along whichever chain is behind in
    normalised position. The winding matches :func:`.grids.grid_faces` with ``upper`` as
    row i and ``lower`` as row i+1 (outward, -x, on the transom).
    """
    p, q = len(upper) - 1, len(lower) - 1

    def norm(y):
        span = y[0] - y[-1]
        return (y[0] - y) / span if span > 0 else np.linspace(0.0, 1.0, len(y))

    ta, tb = norm(np.asarray(y_upper)), norm(np.asarray(y_lower))
    i = k = 0
    out = []
    while i < p or k < q:
        if i == p or (k < q and tb[k + 1] < ta[i + 1]):
            out.append((upper[i], lower[k], lower[k + 1]))
            k += 1
        else:
            out.append((upper[i], lower[k], upper[i + 1]))
            i += 1
    return out


def hull_surface(form: HullForm, h: float):
    """Closed hull+deck surface: (vertices, faces, is_deck)."""
    p = form.p
    # Station and deck-row counts are deliberately a little off round spacings, so that
    # superstructure walls (usually placed at round positions) never run exactly along a
    # grid line: coincident edges make the boolean produce zero-area triangles.
    ns = max(8, int(math.ceil(1.0137 * p.length / h)))
    s = np.linspace(0.0, 1.0, ns + 1)
    ring, m = _hull_rings(form, s, h)
    hull_v = ring.reshape(-1, 3)
    hull_f = grid_faces(ns, 2 * m)
    deck, deck_f, nk = _deck_surface(form, s, ring, h, len(hull_v))
    tr, tr_f = _transom_surface(ring, m, nk, h, len(hull_v) + len(deck), hull_v[:, 1])

    v = np.concatenate([hull_v, deck, tr.reshape(-1, 3)])
    f = np.concatenate([hull_f, deck_f, tr_f])
    is_deck = np.zeros(len(f), bool)
    is_deck[len(hull_f):len(hull_f) + len(deck_f)] = True
    v, f, ok = merge_vertices(v, f, tol=1e-6 * p.length)
    return v, f, is_deck[ok]


def _hull_rings(form: HullForm, s: np.ndarray, h: float):
    """Hull sections at the stations ``s``, each a ring from the port deck edge down to the
    keel and up to the starboard deck edge: ``(ring (ns+1, 2m+1, 3), m)`` with ``m`` the
    segments of a half-ring."""
    p = form.p
    # Points per half-section from the midship section, so spacing is ≈ h amidships.
    n_top = max(2, int(math.ceil(p.freeboard / h)))
    mid_bottom = _section_bottom(form.hb_waterline(np.array(0.5)), form.p.draught,
                                 form.section_exponent(np.array(0.5)), 400)
    bottom_len = float(np.linalg.norm(np.diff(mid_bottom, axis=0), axis=1).sum())
    n_bot = max(3, int(math.ceil(bottom_len / h)))

    m = n_top + n_bot                                         # half-ring segments
    ring = np.empty((len(s), 2 * m + 1, 3))
    zd = form.z_deck(s)
    hbd = form.hb_deck(s)
    hbw = form.hb_waterline(s)
    for i in range(len(s)):
        zt = zd[i] * (1.0 - np.arange(n_top + 1) / n_top)      # deck edge → waterline
        yt = hbw[i] + (hbd[i] - hbw[i]) * zt / zd[i]
        bot = _section_bottom(hbw[i], form.draught_local(s[i]), form.section_exponent(s[i]), 400)
        bot = _resample_polyline(bot, n_bot)                   # (y, z) waterline → keel
        y_half = np.concatenate([yt, bot[1:, 0]])
        z_half = np.concatenate([zt, bot[1:, 1]])
        z_half[n_top] = 0.0                                    # exact waterline vertex
        y_half[-1] = 0.0
        y = np.concatenate([y_half, -y_half[-2::-1]])
        z = np.concatenate([z_half, z_half[-2::-1]])
        ring[i, :, 0] = form.x_at(np.full_like(z, s[i]), z)
        ring[i, :, 1] = y
        ring[i, :, 2] = z
    return ring, m


def _deck_surface(form: HullForm, s: np.ndarray, ring: np.ndarray, h: float, off_d: int):
    """Deck rows between the deck edges of the hull rings, vertices numbered from
    ``off_d``: ``(points, faces, points in the aft row)``."""
    zd = form.z_deck(s)
    hbd = form.hb_deck(s)
    ns = len(s) - 1
    # Deck: rows across from the port deck edge to the starboard one, with as many points
    # as each row's width needs (odd counts: no centreline row), zipped station to station;
    # rows shrink towards the stem without making slivers.
    deck_pts, deck_rows, count = [], [], 0
    row_n = np.where(hbd > 0, 2 * np.ceil(1.0137 * hbd / h).astype(int) + 1, 1)
    for i in range(ns + 1):
        n_i = int(row_n[i])
        fr = 1.0 - 2.0 * np.arange(n_i + 1) / n_i
        pts = np.column_stack([np.full(n_i + 1, form.x_deck(s[i])), hbd[i] * fr,
                               np.full(n_i + 1, zd[i])])
        pts[0], pts[-1] = ring[i, 0], ring[i, -1]
        deck_pts.append(pts)
        deck_rows.append(off_d + count + np.arange(n_i + 1))
        count += n_i + 1
    deck = np.concatenate(deck_pts)
    deck_y = deck[:, 1]
    deck_f = np.array([t for i in range(ns) for t in
                       _zipper(deck_rows[i], deck_rows[i + 1], deck_y[deck_rows[i] - off_d],
                               deck_y[deck_rows[i + 1] - off_d])], dtype=np.int64)[:, ::-1]
    return deck, deck_f, int(row_n[0])       # the transom's top row matches the deck's aft row


def _transom_surface(ring: np.ndarray, m: int, nk: int, h: float, off_t: int,
                     hull_y: np.ndarray):
    """Transom rows between the port and starboard halves of the aft ring, its top row of
    ``nk`` segments matching the deck's aft row; new vertices numbered from ``off_t``:
    ``(points, faces)``."""
    # Transom (a plane x = -L/2): horizontal rows across from the port to the starboard
    # half of the aft ring, at ring points at least ~h/2 apart in height (rows closer than
    # that would make slivers where the bottom is flat); the ring points between two rows
    # join the lower chain, and consecutive chains are zipped into triangles.
    port = ring[0, :m + 1]
    ring_idx = np.arange(2 * m + 1)             # indices into the aft ring (station 0)
    levels = [0]
    for j in range(1, m + 1):
        if port[levels[-1], 2] - port[j, 2] >= 0.5 * h and port[j, 1] > 0.5 * h:
            levels.append(j)
    tr_pts, chains, count = [], [], 0
    for j in levels:
        nrow = nk if j == 0 else int(min(nk, max(1, math.ceil(2 * port[j, 1] / h))))
        fr = 1.0 - 2.0 * np.arange(nrow + 1) / nrow
        pts = np.column_stack([np.full(nrow + 1, port[j, 0]), port[j, 1] * fr,
                               np.full(nrow + 1, port[j, 2])])
        # Row ends are the ring points themselves; only the interior points are new.
        tr_pts.append(pts[1:-1])
        idx = np.concatenate([[ring_idx[j]], off_t + count + np.arange(nrow - 1),
                              [ring_idx[2 * m - j]]])
        count += nrow - 1
        chains.append(idx)
    bounds = levels + [m]
    tr = np.concatenate(tr_pts) if tr_pts else np.zeros((0, 3))

    def y_of(idx):
        idx = np.asarray(idx)
        return np.where(idx < off_t, hull_y[np.minimum(idx, len(hull_y) - 1)],
                        tr[np.clip(idx - off_t, 0, max(len(tr) - 1, 0)), 1] if len(tr) else 0.0)

    tri = []
    for r in range(len(levels)):
        j1, j2 = bounds[r], bounds[r + 1]
        upper = chains[r]
        if r + 1 < len(levels):
            lower = np.concatenate([ring_idx[j1 + 1:j2], chains[r + 1],
                                    ring_idx[2 * m - j2 + 1:2 * m - j1]])
        else:                                   # last strip: down to the keel and up again
            lower = ring_idx[j1 + 1:2 * m - j1]
        if len(lower) == 0:
            continue
        tri += _zipper(upper, lower, y_of(upper), y_of(lower))
    tr_f = np.array(tri, dtype=np.int64)
    return tr, tr_f


def _section_bottom(hb: float, depth: float, n: float, k: int) -> np.ndarray:
    """Superellipse quadrant from the waterline (hb, 0) to the keel (0, -depth) as (y, z)."""
    phi = np.linspace(0.0, 0.5 * np.pi, k + 1)
    y = hb * np.cos(phi) ** (2.0 / n)
    z = -depth * np.sin(phi) ** (2.0 / n)
    return np.stack([y, z], axis=1)
