"""Remeshing a ship surface to a target edge length and building its finite-volume mesh.

* :func:`refine_surface` — conforming refinement: every edge longer than the target is
  bisected at one shared midpoint (``trimesh.remesh.subdivide_to_size``), so a closed
  surface stays closed; each new triangle keeps its parent's part. Refinement only: a mesh
  finer than the target is left as it is.
* :func:`tetwild_surface` — robust remeshing through pytetwild: tetrahedralise the
  (possibly messy) surface, take the boundary of the tet mesh, and carry the parts over by
  the closest input triangle; reports the change of area and volume.
* :func:`~.surface_ops.surface_quality`, :func:`~.surface_ops.collapse_short_edges`,
  :func:`~.surface_ops.flip_coplanar_edges` (in :mod:`.surface_ops`) — quality and sliver
  clean-up;
* :func:`remesh_ship` / :func:`build_ship_mesh` — the same on a :class:`ShipGeometry`
  (built-in ships are regenerated at the target size), then the cell graph of
  :mod:`shipthermal.mesh`: shells, all tetrahedra, or solid parts as tetrahedra coupled
  to the shells (:mod:`.mixed`).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Sequence

import numpy as np

from ..errors import InputError, check_positive, require
from . import isoremesh
from .limits import check_surface_size
from .parts import boundary_edges, face_areas, signed_volume, split_at_waterline
from .ship.build import build_ship
from .surface_ops import collapse_short_edges, flip_coplanar_edges, surface_quality

__all__ = ["refine_surface", "tetwild_surface", "remesh_ship", "build_ship_mesh",
           "TETWILD_ATTEMPTS"]

TETWILD_ATTEMPTS = 3
"""How many times :func:`tetwild_surface` runs fTetWild before it gives up on a pinched
result. fTetWild is not deterministic: on a 100 x 12 x 10 m box with two lid triangles
missing, 1 repair in 300 came back with two parts of the solid touching along one edge
(an edge of four boundary triangles) and the next repair was clean."""


def refine_surface(vertices, faces, face_part, edge_length: float):
    """Bisect edges until none is longer than ``edge_length`` [m]; parts are inherited.

    Returns ``(vertices, faces, face_part, parent)``; ``parent`` is the input triangle of
    each output triangle.
    """
    from trimesh.remesh import subdivide_to_size    # deferred: start-up cost (~1.5 s)

    check_positive("edge_length", edge_length, "m")
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    lmax = float(np.linalg.norm(v[f] - v[np.roll(f, 1, axis=1)], axis=2).max())
    n_iter = max(1, int(math.ceil(math.log2(max(lmax / edge_length, 1.0)))) + 2)
    require(lmax / edge_length < 2 ** 14, "edge_length", edge_length,
            f"is too small for this surface (longest edge {lmax:.3g} m)", "Use a larger edge length")
    v2, f2, parent = subdivide_to_size(v, f, max_edge=edge_length, max_iter=n_iter, return_index=True)
    return v2, np.asarray(f2, np.int64), np.asarray(face_part)[parent], np.asarray(parent)


def tetwild_surface(vertices, faces, face_part, edge_length: float | None = None,
                    edge_length_fac: float | None = None):
    """Robust remeshing: pytetwild tetrahedralisation, then the boundary of the tet mesh.

    Gaps and self-intersections of the input are resolved by fTetWild's winding-number
    inside/outside test (an open surface is *closed*: check it is what you want — the
    report says how much area and volume changed). Parts are carried over from the closest
    input triangle.

    Returns
    -------
    vertices, faces, face_part, report
        ``report`` holds ``area_before/after`` [m2], ``volume_before/after`` [m3] (signed,
        before as given), their relative changes, ``n_tets``, ``attempts`` (fTetWild runs
        until one gave a surface without pinched edges, at most :data:`TETWILD_ATTEMPTS`)
        and ``seconds``.
    """
    # deferred: the FV mesh package loads scipy (0.15 s) and trimesh takes 0.45 s (measured);
    # loading a scenario imports neither (test_load_is_lazy)
    from ..mesh.tets import orient_tets, tet_faces, tetwild as _tetwild
    import trimesh

    v = np.array(vertices, dtype=float)           # writable copies for the fTetWild binding
    f = np.array(faces, dtype=np.int64)
    t0 = time.perf_counter()
    kwargs = {}
    if edge_length is not None:
        kwargs["edge_length_abs"] = float(edge_length)
    elif edge_length_fac is not None:
        kwargs["edge_length_fac"] = float(edge_length_fac)
    for attempt in range(1, TETWILD_ATTEMPTS + 1):
        pts, tets = _tetwild(v, f.astype(np.int32), vtk_ordering=True, **kwargs)
        if len(tets) == 0:
            raise InputError("surface", f"{len(f)} triangles", "pytetwild found no enclosed volume",
                             "The surface is flat or has no inside; check the file")
        pts = np.asarray(pts, float)
        tets = orient_tets(pts, np.asarray(tets, np.int64))
        # the boundary triangles, outward from their tets, on the vertices they use
        used, inv = np.unique(tet_faces(tets)[4], return_inverse=True)
        nv, nf = pts[used], inv.reshape(-1, 3)
        if signed_volume(nv, nf) < 0:        # outward by construction; checked, not trusted
            nf = nf[:, ::-1]
        # two parts of the solid touching along an edge: edges of more than two triangles
        pinched = len(boundary_edges(nf)[1])
        if not pinched:
            break
    else:
        raise InputError("surface", f"{len(f)} triangles",
                         f"each of {TETWILD_ATTEMPTS} pytetwild repairs came back with edges "
                         f"shared by more than two triangles (the last: {pinched}), a pinched "
                         "solid the solver cannot mesh",
                         "Close the gaps in CAD, or set another tet size "
                         "(ship.files.repair_edge_length)")
    src = trimesh.Trimesh(v, f, process=False, validate=False)
    cen = nv[nf].mean(axis=1)
    _, _, tri_id = trimesh.proximity.closest_point(src, cen)
    labels = np.asarray(face_part)[tri_id]
    a0, a1 = float(face_areas(v, f).sum()), float(face_areas(nv, nf).sum())
    v0, v1 = signed_volume(v, f), signed_volume(nv, nf)
    report = dict(area_before=a0, area_after=a1, area_change=(a1 - a0) / a0,
                  volume_before=v0, volume_after=v1,
                  volume_change=(v1 - v0) / abs(v0) if v0 != 0 else float("inf"),
                  n_tets=int(len(tets)), attempts=attempt, seconds=time.perf_counter() - t0)
    return nv, nf, labels, report


def remesh_ship(ship, edge_length: float, improve: bool = True, return_report: bool = False):
    """The ship at a target edge length [m].

    Built-in ships (``ship.parameters`` set) are regenerated at that size with the same
    layups and compartment temperatures. User surfaces are remeshed isotropically, finer
    or coarser, with a quality floor (:func:`.isoremesh.isotropic_remesh`, needs
    ``pymeshlab``); without it they are refined by edge bisection only, the waterline split
    is redone exactly and (``improve``) slivers are cleaned up without moving the surface.
    With ``return_report`` returns ``(ship, report)`` (``{}`` unless remeshed
    isotropically).
    """
    check_positive("ship.edge_length", edge_length, "m")
    if ship.parameters is not None:
        new = build_ship(ship.parameters, edge_length)
        require(new.part_names == ship.part_names, "ship.part_names", ship.part_names,
                "changed on regeneration")
        new = replace(new, layups=dict(ship.layups),
                      compartment_temperature=dict(ship.compartment_temperature),
                      outer_medium=dict(ship.outer_medium))
        return (new, {}) if return_report else new
    check_surface_size(float(face_areas(ship.vertices, ship.faces).sum()), edge_length)
    if isoremesh.have_remesher():
        v, f, lab, rep = isoremesh.isotropic_remesh(ship.vertices, ship.faces, ship.face_part,
                                                    ship.part_names, edge_length)
        new = replace(ship, vertices=v, faces=f, face_part=lab, edge_length=rep["edge_length"])
        return (new, rep) if return_report else new
    v, f, lab, _ = refine_surface(ship.vertices, ship.faces, ship.face_part, edge_length)
    v, f, lab, _ = split_at_waterline(v, f, lab, 0.0)
    if improve:
        # Geometry-preserving clean-up: collapses of short edges that move no surface, then
        # flips inside flat regions (see the two functions).
        v, f, lab, _ = collapse_short_edges(v, f, lab, 0.25 * edge_length, 1e-9 * ship.length)
        f, _ = flip_coplanar_edges(v, f, lab, max_passes=4)
    new = replace(ship, vertices=v, faces=f, face_part=lab, edge_length=float(edge_length))
    return (new, {}) if return_report else new


def build_ship_mesh(ship, edge_length: float | None = None, solid_parts: Sequence[str] | str = (),
                    layups=None):
    """Remesh a ship and build its finite-volume cell graph.

    Parameters
    ----------
    ship : ShipGeometry
    edge_length : float, optional
        Target surface edge length [m]; default: as the ship is.
    solid_parts : sequence of str or 'all'
        Parts meshed as solid tetrahedra instead of plate shells. ``'all'``: the whole
        closed ship becomes one tetrahedral solid (verification). A subset: tets for those
        parts, shells for the rest, coupled along the rim where they meet
        (:mod:`.mixed`).
    layups : mapping, optional
        Layup overrides for this mesh (otherwise ``ship.layups``).

    Returns
    -------
    graph : shipthermal.mesh.CellGraph
    report : dict
        Nominal ``edge_length`` and measured ``edge_median`` [m], surface face counts (total
        and per part), cell counts per part, surface quality (:func:`surface_quality`),
        timings [s]; ``note`` when a user surface is much finer than the target (it is
        refined to the target, never coarsened).
    """
    # deferred: the FV mesh package loads scipy (0.15 s, measured), kept out of loading a scenario
    from .. import mesh as fvmesh

    t0 = time.perf_counter()
    remesh_report = {}
    if edge_length is not None and not (abs(edge_length - ship.edge_length) <= 1e-12 * edge_length):
        ship, remesh_report = remesh_ship(ship, edge_length, return_report=True)
    t_remesh = time.perf_counter() - t0
    if layups is not None:
        ship = ship.with_layups(layups)
    if isinstance(solid_parts, str):
        require(solid_parts == "all", "solid_parts", solid_parts, "must be 'all' or a list of part names")
        solid_parts = ship.part_names
    solid = tuple(solid_parts)
    for name in solid:
        ship.part_index(name)
    quality = surface_quality(ship.vertices, ship.faces)
    edges = np.linalg.norm(ship.vertices[ship.faces] - ship.vertices[np.roll(ship.faces, 1, axis=1)], axis=2)
    report = dict(edge_length=float(ship.edge_length), edge_median=float(np.median(edges)),
                  n_surface_faces=ship.n_faces,
                  surface_faces_per_part={n: int(np.sum(ship.face_part == k))
                                          for k, n in enumerate(ship.part_names)},
                  quality=quality, seconds_remesh=t_remesh)
    if remesh_report:
        report["remesh"] = {k: x for k, x in remesh_report.items() if k != "quality_after"}
    # User surfaces are refined, never coarsened: say so when the mesh is much finer than
    # asked (fTetWild does not coarsen either: its surface resolution follows its envelope;
    # a 5120-triangle ellipsoid at a 2 m target came back with 2378 triangles of 0.7 m mean
    # edge in 13 s).
    if (ship.parameters is None and not remesh_report
            and report["edge_median"] < 0.5 * ship.edge_length):
        report["note"] = (f"the surface is finer than the target ({report['edge_median']:.3g} m median "
                          f"edge vs {ship.edge_length:.3g} m): refinement only, it was not coarsened; "
                          "coarsen it in CAD to save cells")
    t1 = time.perf_counter()
    if not solid:
        graph = fvmesh.build_shell_graph(ship.vertices, ship.faces, ship.face_part,
                                         ship.part_names, dict(ship.layups))
        report["kind"] = "shell"
    elif set(solid) == set(ship.part_names):
        graph = _solid_ship_graph(ship, fvmesh)
        report["kind"] = "tetrahedral"
    else:
        # deferred: the mixed graph imports the FV mesh package and scipy.sparse (as above)
        from .mixed import mixed_ship_graph

        graph, info = mixed_ship_graph(ship, solid, fvmesh)
        report["kind"] = "mixed"
        report.update(info)
    report["seconds_graph"] = time.perf_counter() - t1
    report["n_cells"] = graph.n_cells
    report["cells_per_part"] = {n: int(c) for n, c in zip(
        graph.part_names, np.bincount(graph.cell_part, minlength=len(graph.part_names)))}
    return graph, report


def _solid_ship_graph(ship, fvmesh):
    """Whole closed ship as tetrahedra; each tet takes the structural material of the part
    of its nearest surface triangle, boundary faces are patched ``{part}:outer``."""
    from scipy.spatial import cKDTree      # deferred: start-up cost (~1 s to import)

    # Writable copies: the wrapped fTetWild rejects read-only numpy arrays.
    pts, tets = fvmesh.tetrahedralize_surface(np.array(ship.vertices), np.array(ship.faces),
                                              edge_length=ship.edge_length, field="ship")
    tree = cKDTree(ship.face_centroids)
    names = ship.part_names
    # Structural material of each part: its thickest layer.
    mats = []
    part_mat = []
    for n in names:
        lay = ship.layups[n]
        k = int(np.argmax([l.thickness for l in lay.layers]))
        m = lay.materials[k]
        if m.name not in [x.name for x in mats]:
            mats.append(m)
        part_mat.append([x.name for x in mats].index(m.name))
    cen = pts[tets].mean(axis=1)
    _, near = tree.query(cen)
    cell_mat = np.asarray(part_mat)[ship.face_part[near]]

    def rule(face_centroid, face_normal):
        _, i = tree.query(face_centroid)
        return np.array([f"{names[p]}:outer" for p in ship.face_part[i]])

    return fvmesh.build_tet_graph(pts, tets, material=mats, cell_material=cell_mat,
                                  patches=rule, part_name="ship")
