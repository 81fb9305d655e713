"""Ship meshes as CAD exports them: named parts, rule-based parts, all problems at once.

* :func:`load_named_parts` — parts from the names inside one file: OBJ groups / objects,
  the named meshes (scene nodes) of a GLB / glTF file;
* :func:`assign_parts` — for one unlabelled mesh, parts by rules: below the waterline
  ``hull`` (split into ``hull_wetted`` / ``hull_dry`` later), upward faces at deck level
  ``deck``, everything standing above the deck ``superstructure``, the rest (hull sides)
  ``hull``; :func:`part_ranges` turns the result into an editable part-map JSON;
* :func:`diagnose_surface` — every problem of a surface in one list, each with the
  scenario keys that fix it (:func:`problems_message` words them as one message);
* :func:`union_repair` — a fast robust repair of a soup of closed pieces: a boolean union
  (manifold3d) of the connected components, instead of a tetrahedral remesh.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from .parts import boundary_edges, face_areas, main_part, signed_volume
from .surface_ops import fix_winding

__all__ = ["SCENE_EXTENSIONS", "DECK_NORMAL_DEG", "DECK_TOLERANCE_FRAC", "MAX_REPAIR_CHANGE",
           "load_named_parts", "assign_parts", "part_ranges", "Problem", "diagnose_surface",
           "problems_message", "union_repair", "repair_change_check"]

SHIP_LENGTH_RANGE = (5.0, 500.0)
"""Plausible overall length of a ship [m] (harbour launches to the largest tankers, 458 m)."""

SCENE_EXTENSIONS = (".obj", ".glb", ".gltf")
"""Formats whose parts may come from names in the file (OBJ groups, glTF meshes)."""

DECK_NORMAL_DEG = 25.0
"""Rule-based parts: a face is 'upward' (a deck candidate) when its normal is within this
angle of vertical [deg] (ship decks: camber 1/50 of the beam and sheer are a few degrees;
hull flare and deckhouse walls are steeper than 65 deg from horizontal)."""

DECK_TOLERANCE_FRAC = 0.05
"""Rule-based parts: a face belongs to the deck level when it lies within this fraction of
the freeboard above the local deck height (0.25 m on a 5 m freeboard: more than the camber
rise over a frigate's half-beam, less than the lowest deckhouse)."""

MAX_REPAIR_CHANGE = 0.01
"""Largest relative change of surface area or enclosed volume a repair may make unless the
user raises ``ship.files.max_repair_change`` (1 %: merging coincident pieces and closing
slits changes far less; a repair that changes more has rebuilt the ship)."""

CHECK_COLOURS = {"hull_wetted": "#8b2d2d", "hull_dry": "#3f78b5", "deck": "#e0a830",
                 "superstructure": "#c4c9ce"}
"""Contrasting part colours of the picture that shows a rule-based part assignment."""

_NAME_SUFFIX = re.compile(r"\.\d+$")          # Blender-style duplicates: "deck.001"


# ---------------------------------------------------------------------------------------
# Named parts
# ---------------------------------------------------------------------------------------
def _normalise(name: str) -> str:
    n = _NAME_SUFFIX.sub("", str(name).strip()).lower()
    return re.sub(r"[\s\-]+", "_", n)


def _part_of(names) -> str | None:
    for n in names:
        n = _normalise(n)
        try:
            main_part(n)
            return n
        except InputError:
            continue
    return None


def load_named_parts(path, scale: float = 1.0):
    """Triangles of an OBJ / GLB / glTF file with a part per named group or mesh.

    Parameters
    ----------
    path : path
    scale : float
        Factor to metres.

    Returns
    -------
    (vertices, faces, labels, names), or ``None`` when the file holds a single unnamed
    mesh (then the caller needs a part map or the rules). Raises :class:`InputError` when
    the file holds no triangles, or when names are present but some name no known part
    (listing every such name).
    """
    import trimesh      # deferred: start-up cost (trimesh takes ~1.5 s to import)

    path = Path(path)
    try:
        scene = trimesh.load(path, force="scene", process=False, split_objects=True,
                             split_groups=True)
    except Exception:                              # a parser error: not a mesh file
        raise InputError("ship.files.mesh", path.name, f"cannot be read as "
                         f"{path.suffix[1:].upper()} (damaged, truncated or another format)",
                         "Export the ship again as a triangle mesh") from None
    items = []                                     # (names, vertices, faces)
    for node in scene.graph.nodes_geometry:
        transform, gname = scene.graph[node]
        geom = scene.geometry[gname]
        faces = np.asarray(getattr(geom, "faces", np.zeros((0, 3))), np.int64)
        if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
            continue
        v = np.asarray(geom.vertices, float)
        v = v @ np.asarray(transform)[:3, :3].T + np.asarray(transform)[:3, 3]
        items.append(((gname, node), v * scale, faces))
    if not items:
        raise InputError("ship.files.mesh", str(path), "holds no triangles",
                         "Export the ship surface as a triangle mesh (not points, lines "
                         "or an empty scene)")
    if len(items) == 1 and _part_of(items[0][0]) is None:
        return None
    parts = [_part_of(n) for n, _, _ in items]
    unknown = sorted({str(n[0]) for (n, _, _), p in zip(items, parts) if p is None})
    if unknown:
        raise InputError("ship.files.mesh", str(path),
                         f"names its groups/meshes {', '.join(repr(u) for u in unknown)}, "
                         "which are no ship parts (hull, hull_wetted, hull_dry, deck, "
                         "superstructure or <main>_<detail>)",
                         "Rename them in the CAD export, or give ship.files.part_map "
                         '(a JSON of face ranges, or "auto" to assign parts by rules)')
    names = list(dict.fromkeys(parts))
    vs, fs, labs, off = [], [], [], 0
    for (_, v, f), p in zip(items, parts):
        vs.append(v)
        fs.append(f + off)
        labs.append(np.full(len(f), names.index(p)))
        off += len(v)
    return np.concatenate(vs), np.concatenate(fs), np.concatenate(labs), tuple(names)


# ---------------------------------------------------------------------------------------
# Rule-based parts
# ---------------------------------------------------------------------------------------
def assign_parts(vertices, faces, n_stations: int = 60,
                 deck_normal_deg: float = DECK_NORMAL_DEG,
                 deck_tolerance_frac: float = DECK_TOLERANCE_FRAC):
    """Parts of an unlabelled ship surface by rules (waterline at z = 0, x along the ship).

    The ship is cut into ``n_stations`` stations along x. In each, the deck height is the
    lowest 'upward' face above the waterline reaching into the station (normal within ``deck_normal_deg`` of
    vertical, either sign, so inverted normals do not matter); stations without one take
    the height of their neighbours. Then per face:

    * centroid below the waterline → ``hull`` (split exactly into ``hull_wetted`` /
      ``hull_dry`` later);
    * upward, centroid within the tolerance of the deck height → ``deck``;
    * any vertex higher than the tolerance above the deck → ``superstructure``;
    * else (hull sides, transom, flare) → ``hull``.

    The tolerance is ``deck_tolerance_frac`` × the median deck height (the freeboard).

    Returns
    -------
    labels (M,) int into ``names``, names ``('hull', 'deck', 'superstructure')``, info
    dict (``deck_height`` per station, ``stations`` edges, the rule parameters).
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    p = v[f]
    c = p.mean(axis=1)
    nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    nlen = np.linalg.norm(nrm, axis=1)
    nz = np.abs(nrm[:, 2]) / np.where(nlen > 0, nlen, 1.0)
    up = (nz >= np.cos(np.radians(deck_normal_deg))) & (c[:, 2] > 0) & (nlen > 0)
    edges = np.linspace(v[:, 0].min(), v[:, 0].max(), n_stations + 1)
    st = np.clip(np.searchsorted(edges, c[:, 0], side="right") - 1, 0, n_stations - 1)
    # Every upward face counts for each station its x-extent covers (coarse CAD decks are
    # a few long triangles whose centroids miss most stations).
    lo = np.clip(np.searchsorted(edges, p[up, :, 0].min(axis=1), side="right") - 1, 0, n_stations - 1)
    hi = np.clip(np.searchsorted(edges, p[up, :, 0].max(axis=1), side="left") - 1, 0, n_stations - 1)
    hi = np.maximum(hi, lo)
    span = hi - lo + 1
    rows = np.repeat(np.arange(len(lo)), span)
    cover = lo[rows] + (np.arange(len(rows)) - np.repeat(np.cumsum(span) - span, span))
    deck = np.full(n_stations, np.inf)
    np.minimum.at(deck, cover, c[up, 2][rows])
    have = np.isfinite(deck)
    if not have.any():
        raise InputError("ship.files.part_map", "auto", "found no upward-facing surface above "
                         "the waterline (no deck)", "Check ship.files.draught / waterline_z, "
                         "or give a part map")
    mid = 0.5 * (edges[:-1] + edges[1:])
    deck = np.interp(mid, mid[have], deck[have])
    tol = deck_tolerance_frac * float(np.median(deck))
    z_deck = deck[st]
    top = p[:, :, 2].max(axis=1)
    labels = np.zeros(len(f), np.int64)                      # hull
    labels[up & (c[:, 2] <= z_deck + tol)] = 1               # deck
    labels[(labels == 0) & (top > z_deck + tol) & (c[:, 2] > 0)] = 2
    labels[up & (c[:, 2] > z_deck + tol)] = 2
    labels[c[:, 2] < 0] = 0
    info = dict(stations=edges.tolist(), deck_height=deck.tolist(), tolerance_m=tol,
                deck_normal_deg=deck_normal_deg, deck_tolerance_frac=deck_tolerance_frac)
    return labels, ("hull", "deck", "superstructure"), info


def part_ranges(labels, names) -> dict:
    """``{part: [[start, stop], ...]}`` face ranges (stop exclusive) of per-face labels, the
    part-map format of :func:`~.io.read_part_map`."""
    labels = np.asarray(labels)
    cut = np.flatnonzero(np.diff(labels)) + 1
    starts = np.r_[0, cut]
    stops = np.r_[cut, len(labels)]
    out: dict = {n: [] for n in names}
    for a, b in zip(starts, stops):
        out[names[int(labels[a])]].append([int(a), int(b)])
    return {n: r for n, r in out.items() if r}


# ---------------------------------------------------------------------------------------
# All problems at once
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Problem:
    """One problem of a mesh: what was found and the scenario settings that fix it."""

    kind: str          # 'scale', 'axes', 'degenerate', 'duplicate', 'open', 'nonmanifold',
    #                    'intersecting', 'winding', 'inward'
    text: str
    fix: str

    def __str__(self) -> str:
        return f"{self.text} (fix: {self.fix})"


FIXED_BY = {"degenerate": "clean", "duplicate": "clean", "winding": "fix_normals",
            "inward": "fix_normals", "open": "repair", "nonmanifold": "repair",
            "intersecting": "repair", "scale": "check_scale"}
"""Which option handles each kind of problem (``axes`` has none: rotate the export)."""


def _components(f: np.ndarray, n_vertices: int) -> np.ndarray:
    # deferred: start-up cost (scipy.sparse.csgraph takes ~1 s to import)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    e = f[:, [0, 1, 1, 2]].reshape(-1, 2)
    g = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n_vertices, n_vertices))
    return connected_components(g, directed=False)[1][f[:, 0]]


def _solid_pieces(f: np.ndarray) -> np.ndarray:
    """Piece of each triangle, joining triangles only across edges that exactly two
    triangles share (solids that touch along an edge or a face stay separate pieces)."""
    # deferred: start-up cost (scipy.sparse.csgraph takes ~1 s to import)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    m = len(f)
    e = np.sort(f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    key = e[:, 0] * (int(f.max()) + 1) + e[:, 1]
    owner = np.repeat(np.arange(m), 3)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    start = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    count = np.diff(np.r_[start, len(ks)])
    two = start[count == 2]
    a, b = owner[order[two]], owner[order[two + 1]]
    g = coo_matrix((np.ones(len(a)), (a, b)), shape=(m, m))
    return connected_components(g, directed=False)[1]


def diagnose_surface(vertices, faces, units: str = "m", *, check_scale: bool = True,
                     check_intersections: bool = True) -> list[Problem]:
    """Every problem of a ship surface, without changing it.

    Checks: plausible length (units), longest extent along x, zero-area and duplicate
    triangles, open and non-manifold edges, self-intersections (Embree ray casts),
    inconsistent winding, inward normals (closed surfaces only). Each problem names the
    scenario keys that fix it.
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    out: list[Problem] = []
    ext = np.ptp(v, axis=0)
    if int(np.argmax(ext)) != 0:
        out.append(Problem("axes", f"extent x {ext[0]:.4g} m, y {ext[1]:.4g} m, z {ext[2]:.4g} m: "
                           "the longest dimension must lie along x (x forward, y to port, z up)",
                           "rotate the mesh in the CAD export so the bow points to +x"))
    lo, hi = SHIP_LENGTH_RANGE
    length = float(ext.max())
    if check_scale and not lo <= length <= hi:
        if units == "m" and lo <= length / 1e3 <= hi:
            fix = 'ship.files.units = "mm" (it looks like millimetres)'
        elif units == "mm" and lo <= length * 1e3 <= hi:
            fix = 'ship.files.units = "m" (it looks like metres)'
        else:
            fix = "rescale the file to metres or millimetres"
        out.append(Problem("scale", f"a ship length of {length:.6g} m, outside the plausible "
                           f"{lo:g}–{hi:g} m", fix + ", or ship.files.check_scale = false for "
                           "a deliberate non-ship size"))
    scale = float(ext.max()) or 1.0
    area = face_areas(v, f)
    degenerate = ((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])
                  | (area <= 1e-14 * scale * scale))
    if degenerate.any():
        out.append(Problem("degenerate", f"{int(degenerate.sum())} zero-area triangles (first: "
                           f"face {int(np.argmax(degenerate))})", "ship.files.clean = true"))
    key = np.sort(f, axis=1)
    n_unique = len(np.unique(key, axis=0))
    if n_unique < len(f):
        out.append(Problem("duplicate", f"{len(f) - n_unique} duplicate triangles",
                           "ship.files.clean = true"))
    # Topology on the triangles with three distinct vertices (a zero-area "needle" at a
    # T-junction still closes the surface: clean flips it away), duplicates counted once.
    repeated = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])
    fu = f[~repeated]
    fu = fu[np.sort(np.unique(np.sort(fu, axis=1), axis=0, return_index=True)[1])] if len(fu) else fu
    open_e, nonman = boundary_edges(fu) if len(fu) else (np.zeros((0, 2)), np.zeros((0, 2)))
    comp = _components(fu, len(v)) if len(fu) else np.zeros(0, int)
    n_comp = int(comp.max()) + 1 if len(comp) else 0
    repair_fix = ('ship.files.repair = "union" (fast: unites closed pieces)' if not len(open_e)
                  else 'ship.files.repair = "tetwild" (closes gaps; slower)')
    if len(open_e):
        w = v[open_e[0]].mean(axis=0)
        out.append(Problem("open", f"{len(open_e)} open edges (used by one triangle; first near "
                           f"({w[0]:.3f}, {w[1]:.3f}, {w[2]:.3f}) m) in {n_comp} pieces: the "
                           "surface must be closed (watertight)",
                           repair_fix + ", or close the gap in CAD"))
    if len(nonman):
        w = v[nonman[0]].mean(axis=0)
        out.append(Problem("nonmanifold", f"{len(nonman)} edges shared by more than two "
                           f"triangles (first near ({w[0]:.3f}, {w[1]:.3f}, {w[2]:.3f}) m)",
                           repair_fix))
    if check_intersections and len(fu) and not len(open_e) and not len(nonman):
        try:    # deferred: the FV mesh package loads scipy (0.15 s), kept out of loading a scenario
            from ..mesh import find_self_intersections
            fa = fu[face_areas(v, fu) > 1e-14 * scale * scale]
            pairs = find_self_intersections(v, fa, max_report=1)
        except ImportError:                       # the FV mesh package is absent
            pairs = np.zeros((0, 2), int)
        if len(pairs):
            w = v[fa[int(pairs[0][0])]].mean(axis=0)
            what = (f"{n_comp} separate pieces that overlap" if n_comp > 1
                    else "the surface intersects itself")
            out.append(Problem("intersecting", f"{what} (first crossing near ({w[0]:.3f}, "
                               f"{w[1]:.3f}, {w[2]:.3f}) m)", repair_fix))
    if len(fu):
        directed = fu[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
        _, dcount = np.unique(directed, axis=0, return_counts=True)
        n_bad = int((dcount > 1).sum())
        if n_bad:
            out.append(Problem("winding", f"{n_bad} edges traversed twice in the same direction "
                               "(inconsistent winding)", "ship.files.fix_normals = true"))
        elif not len(open_e) and not len(nonman):
            vol = signed_volume(v, fu)
            if vol < 0:
                out.append(Problem("inward", f"signed volume {vol:.6g} m3 < 0: the normals "
                                   "point into the ship", "ship.files.fix_normals = true"))
    return out


def problems_message(path, problems: list[Problem]) -> InputError:
    """One :class:`InputError` listing every problem with its fix."""
    n = len(problems)
    listed = "; ".join(f"({k + 1}) {p}" for k, p in enumerate(problems))
    return InputError("ship.files.mesh", str(path), f"has {n} problem{'s' * (n > 1)}: {listed}",
                      "Each can be fixed in the CAD export instead; every repair is printed "
                      "with its change of area and volume")


# ---------------------------------------------------------------------------------------
# Repairs
# ---------------------------------------------------------------------------------------
def union_repair(vertices, faces, face_part):
    """Boolean union (manifold3d) of the connected pieces of a surface.

    For exports made of many closed pieces that touch or overlap (a deckhouse standing
    in the deck, a soup of solids): pieces are the triangles joined across edges shared
    by exactly two triangles (so solids touching along an edge or a face, e.g. stacked
    deckhouses, stay separate); each must be closed; the union removes the inner
    surfaces exactly. Parts follow the faces (manifold3d keeps each output
    triangle's source face). Pieces with inconsistent or inward winding are re-oriented
    first.

    Returns vertices, faces, face_part, report (area/volume before and after, their
    relative change, ``pieces``, ``seconds``).
    """
    # (manifold3d on use: loading a scenario reads this module's limits, not the union)
    from manifold3d import Manifold, Mesh64, OpType

    t0 = time.perf_counter()
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    lab = np.asarray(face_part)
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])
    f, lab = f[keep], lab[keep]
    comp = _solid_pieces(f)
    n = int(comp.max()) + 1
    pieces, src, total = [], [], 0
    order = np.argsort(comp, kind="stable")
    bounds = np.searchsorted(comp[order], np.arange(n + 1))
    bad = flat = 0
    tiny = 1e-12 * float(np.ptp(v, axis=0).max()) ** 3
    for k in range(n):
        rows = order[bounds[k]:bounds[k + 1]]
        fk, _ = fix_winding(f[rows])
        used, inv = np.unique(fk, return_inverse=True)
        vk, fk = v[used], inv.reshape(-1, 3)
        vol = signed_volume(vk, fk)
        if abs(vol) <= tiny:          # a face exported twice back to back: no solid
            flat += 1
            continue
        if vol < 0:
            fk = fk[:, ::-1]
        man = Manifold(Mesh64(vert_properties=vk, tri_verts=fk.astype(np.uint64),
                              face_id=np.arange(total, total + len(fk), dtype=np.uint64)))
        if man.status().name != "NoError":
            bad += 1
            continue
        pieces.append(man)
        src.append(rows)
        total += len(fk)
    if bad:
        raise InputError("ship.files.repair", "union", f"needs closed pieces: {bad} of {n} "
                         "pieces are open or not manifold",
                         'Use ship.files.repair = "tetwild" (closes gaps), or close them in CAD')
    out = Manifold.batch_boolean(pieces, OpType.Add).to_mesh64()
    nv = np.asarray(out.vert_properties, float)[:, :3]
    nf = np.asarray(out.tri_verts, np.int64)
    labels = lab[np.concatenate(src)][np.asarray(out.face_id, np.int64)]
    a0, a1 = float(face_areas(v, f).sum()), float(face_areas(nv, nf).sum())
    v0 = float(sum(abs(signed_volume(v, f[r])) for r in src))
    v1 = signed_volume(nv, nf)
    report = dict(method="union", pieces=n, flat_pieces_dropped=flat, area_before=a0, area_after=a1,
                  area_change=(a1 - a0) / a0, volume_before=v0, volume_after=v1,
                  volume_change=(v1 - v0) / v0 if v0 else float("inf"),
                  seconds=time.perf_counter() - t0)
    return nv, nf, labels, report


def repair_change_check(report: dict, limit: float) -> None:
    """Refuse a repair that changed the area or volume by more than ``limit`` (relative)."""
    worst = max(abs(report["area_change"]), abs(report["volume_change"]))
    if worst > limit:
        raise InputError("ship.files.max_repair_change", limit,
                         f"the {report.get('method', 'repair')} repair changed the area by "
                         f"{100 * report['area_change']:+.2f} % and the volume by "
                         f"{100 * report['volume_change']:+.2f} %, more than the "
                         f"{100 * limit:g} % accepted",
                         f"Check the mesh; to accept, set ship.files.max_repair_change = "
                         f"{np.ceil(worst * 100 + 1e-9) / 100:g} or more")
