"""Ray tracing of a ship's outer surface: the tracer, the view factors (sky, sea, other
faces; reciprocity imposed) and the lit fraction of every sun-receiving face, traced once
per sun direction and cached (:class:`TracedShip`), reusable across environments.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..errors import require
from ..parameters import SUN_SAMPLES_PER_FACE, VIEW_RAYS_PER_FACE
from ..raytrace import make_tracer, sun_lit_fraction, symmetrize, view_factors
from ..raytrace.viewfactors import ViewFactors

@dataclass(eq=False)
class TracedShip:
    """The outer surface of a ship with its tracer, view factors and a lit-fraction cache.

    Build it with :func:`trace_ship`. Reusable across environments (sensitivity runs): the
    view factors do not depend on the environment and lit fractions are cached per sun
    direction (same date and place ⇒ same directions, nothing is traced again).

    Attributes
    ----------
    vertices : (N, 3) float [m]
    faces : (K, 3) int
        Outer triangles (right-hand normal points out of the ship).
    receivers : (k,) int
        Faces that receive sun (air faces); lit fractions are stored for these.
    normals, areas, centroids : arrays
        Per face [-], [m²], [m].
    tracer : EmbreeTracer or NumbaTracer
    view : ViewFactors
        Over all K faces (reciprocity imposed); F_faces columns index ``faces``.
    shooters : (m,) int
        Faces that shot view-factor rays (all but those entirely under the sea, which see
        only the sea); ray sample k of ``faces[shooters][i]`` is that of face i of
        :func:`~shipthermal.raytrace.view_factors` called on ``faces[shooters]``.
    samples_per_face : int
    seed : int
    n_rays : dict
        Rays traced so far: ``{'sun': …, 'view': …}`` (view: rays shot; the few that start
        under the sea, from faces touching the waterline, count as sea without tracing).
    seconds : dict
        Wall time spent [s]: ``{'build': …, 'sun': …, 'view': …}``.
    """

    vertices: np.ndarray
    faces: np.ndarray
    receivers: np.ndarray
    normals: np.ndarray
    areas: np.ndarray
    centroids: np.ndarray
    tracer: object
    view: ViewFactors
    samples_per_face: int
    seed: int
    shooters: np.ndarray
    n_rays: dict = field(default_factory=dict)
    seconds: dict = field(default_factory=dict)
    _lit: dict = field(default_factory=dict, repr=False)

    @staticmethod
    def _key(direction) -> tuple:
        # 1e-12 of a unit vector: directions equal to round-off are one cache entry
        return tuple(np.round(np.asarray(direction, dtype=float), 12) + 0.0)

    def lit_fractions(self, sun_dirs, progress=None) -> np.ndarray:
        """Lit fraction of each receiver for each sun direction, traced once per direction.

        Parameters
        ----------
        sun_dirs : (n, 3) array_like
            Unit vectors towards the sun in the ship frame [-]; directions below the horizon
            give 0.
        progress : bool, optional
            tqdm bar for the rays traced.

        Returns
        -------
        (n, k) float32
            Lit fraction [-].
        """
        sun = np.atleast_2d(np.asarray(sun_dirs, dtype=float))
        keys = [self._key(s) for s in sun]
        missing = {}
        for k, s in zip(keys, sun):
            if k not in self._lit and k not in missing and s[2] > 0.0:
                missing[k] = s
        if missing:
            t0 = _time.perf_counter()
            res = sun_lit_fraction(self.tracer, self.vertices, self.faces[self.receivers],
                                   np.array(list(missing.values())),
                                   samples_per_face=self.samples_per_face, seed=self.seed,
                                   sea_level_z=0.0, progress=progress)
            for col, k in enumerate(missing):
                self._lit[k] = res.face[:, col].astype(np.float32)
            self.n_rays["sun"] = self.n_rays.get("sun", 0) + res.n_rays
            self.seconds["sun"] = self.seconds.get("sun", 0.0) + _time.perf_counter() - t0
        out = np.zeros((len(sun), len(self.receivers)), np.float32)
        for row, k in enumerate(keys):
            if k in self._lit:
                out[row] = self._lit[k]
        return out

    def clear_lit_cache(self) -> None:
        """Forget the cached lit fractions (a weather record's window of tables keeps its
        own copy; over a year the cache would hold every sun direction of the record:
        26 000 directions × the receivers in float32, 6 GB for the frigate at 0.5 m).
        A direction asked for again is traced again, to the same values (the sample points
        do not depend on the directions traced with them)."""
        self._lit.clear()


def _merge_triangles(tri: np.ndarray):
    """(K, 3, 3) corner coordinates → shared vertices and faces (exact duplicates merged)."""
    flat = tri.reshape(-1, 3)
    verts, inv = np.unique(flat, axis=0, return_inverse=True)
    return verts, inv.reshape(-1, 3).astype(np.int64)


def trace_ship(vertices, faces, receivers=None, *, samples_per_face: int = SUN_SAMPLES_PER_FACE,
               rays_per_face: int = VIEW_RAYS_PER_FACE, seed: int = 0, backend: str = "auto",
               progress=None) -> TracedShip:
    """Build the tracer over a ship's outer surface and trace its view factors.

    Parameters
    ----------
    vertices : (N, 3) array_like
        Vertex coordinates in the ship frame (x bow, y port, z up, z = 0 the sea) [m].
    faces : (K, 3) array_like of int
        Outer triangles, normals out of the ship by the right-hand rule.
    receivers : (k,) array_like of int, optional
        Faces that receive sun (default: every face with its centroid above the sea).
    samples_per_face : int
        Sun-ray sample points per face.
    rays_per_face : int
        View-factor rays per face (binomial SE of a fraction F: sqrt(F(1−F)/rays)).
    seed : int
        Seed of every sample; results are a deterministic function of it.
    backend : {'auto', 'embree', 'numba'}
        Tracer (:func:`~shipthermal.raytrace.make_tracer`).
    progress : bool, optional
        tqdm bars.

    Returns
    -------
    TracedShip
    """
    require(int(samples_per_face) >= 1, "samples_per_face", samples_per_face, "must be >= 1")
    require(int(rays_per_face) >= 1, "rays_per_face", rays_per_face, "must be >= 1")
    t0 = _time.perf_counter()
    tracer = make_tracer(vertices, faces, backend=backend)
    v, f = tracer.vertices, tracer.faces
    tri = v[f]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    twice = np.linalg.norm(cross, axis=1)
    normals = cross / np.where(twice > 0, twice, 1.0)[:, None]
    centroids = tri.mean(axis=1)
    if receivers is None:
        receivers = np.flatnonzero(centroids[:, 2] > 0.0)
    receivers = np.asarray(receivers, dtype=np.int64)
    t1 = _time.perf_counter()
    # Faces entirely under the sea see only the sea (F_sea = 1): they shoot no rays; the
    # others shoot against the whole mesh, and their rows are embedded in the square
    # matrix reciprocity needs.
    shooters = np.flatnonzero(tri[:, :, 2].max(axis=1) > 0.0)
    sub = view_factors(tracer, v, f[shooters], rays_per_face=int(rays_per_face),
                       seed=int(seed), sea_level_z=0.0, reciprocity=False, progress=progress)
    n_faces = len(f)
    embed = sp.csr_matrix((np.ones(len(shooters)), (shooters, np.arange(len(shooters)))),
                          shape=(n_faces, len(shooters)))

    def full(values, fill):
        out = np.full(n_faces, fill, dtype=float)
        out[shooters] = values
        return out

    view = symmetrize(ViewFactors(
        F_sky=full(sub.F_sky, 0.0), F_sea=full(sub.F_sea, 1.0),
        F_faces=(embed @ sub.F_faces).tocsr(), se_sky=full(sub.se_sky, 0.0),
        se_sea=full(sub.se_sea, 0.0), rays_per_face=sub.rays_per_face, areas=0.5 * twice))
    t2 = _time.perf_counter()
    n_view = len(shooters) * int(rays_per_face)
    return TracedShip(vertices=v, faces=f, receivers=receivers, normals=normals,
                      areas=0.5 * twice, centroids=centroids, tracer=tracer, view=view,
                      samples_per_face=int(samples_per_face), seed=int(seed),
                      shooters=shooters, n_rays={"sun": 0, "view": n_view},
                      seconds={"build": t1 - t0, "view": t2 - t1, "sun": 0.0})


def outer_triangles(graph, outer_bfaces) -> np.ndarray:
    """(K, 3, 3) corners of the outer faces, wound along the graph's outward normals."""
    tri = graph.points[graph.bface_vertices[outer_bfaces]]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", cross, graph.bface_normal[outer_bfaces]) < 0
    tri[flip] = tri[flip][:, ::-1]
    return tri


def outer_surface_tracer(traced, tri, surface, samples_per_face, rays_per_face, seed, backend,
                         progress):
    """The tracer of the outer surface (``tri``: :func:`outer_triangles` of the
    :class:`~shipthermal.forcing.surface.SurfaceProperties` ``surface``): a new one, or
    ``traced`` checked against it."""
    if traced is None:
        verts, faces = _merge_triangles(tri)
        return trace_ship(verts, faces, np.flatnonzero(surface.outer_is_air),
                          samples_per_face=samples_per_face, rays_per_face=rays_per_face,
                          seed=seed, backend=backend, progress=progress)
    n = len(surface.outer_bfaces)
    require(isinstance(traced, TracedShip) and len(traced.faces) == n,
            "traced", type(traced).__name__,
            f"must be the TracedShip of this graph's {n} outer faces")
    require(np.allclose(traced.centroids, tri.mean(axis=1)), "traced", "centroids",
            "must come from the same graph (outer face centroids differ)")
    return traced
