"""Ray tracers over a triangle mesh: Embree (embreex) and an independent numba BVH.

Both backends answer the same two queries on the same rays:

* ``intersects_first(origins, directions, max_distance=inf)`` → index of the nearest triangle
  hit with distance in (0, max_distance), ``-1`` for a miss;
* ``any_hit(origins, directions, max_distance=inf)`` → bool, the ray is blocked before
  ``max_distance`` (occlusion query, cheaper: the walk stops at the first triangle found).

Neither culls back faces. Directions need not be unit length on input; they are normalised,
so ``max_distance`` is a length [m].

Precision. Embree stores the scene and the rays in float32. Coordinates are first shifted to
the centre of the bounding box (in float64) so their magnitude is at most half the diagonal
``scale``; float32 spacing there is ``2**-24 * scale`` ≈ 6e-8·scale. A ray leaving a surface
must start clear of that surface by many such spacings or it may hit the face it starts on,
or miss a neighbour it touches: :func:`ray_offset` returns ``RAY_OFFSET_FACTOR * scale`` with
``RAY_OFFSET_FACTOR = 1e-5`` (≈ 170 float32 spacings; 1 mm on a 100 m ship — well below a
plate thickness, so no real occluder is skipped). The numba tracer is float64 throughout but
uses the same offsets so the two backends see the same rays.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from shipthermal._threads import thread_map
from shipthermal.errors import InputError, require
from shipthermal.raytrace import _bvh

__all__ = ["RAY_OFFSET_FACTOR", "Tracer", "EmbreeTracer", "NumbaTracer", "make_tracer",
           "ray_offset", "has_embree", "batch_threads"]

RAY_OFFSET_FACTOR = 1e-5
"""Ray origin offset from a surface as a fraction of the model's bounding-box diagonal [-]."""

_FLOAT32_TFAR_MAX = 1e37  # "infinite" distance that still fits in float32
_PARALLEL_MIN_RAYS = 65536  # below this, splitting an Embree call over threads is not worth it


def has_embree() -> bool:
    """True when embreex can be imported."""
    try:
        import embreex.rtcore_scene  # noqa: F401
    except ImportError:
        return False
    return True


def ray_offset(scale: float) -> float:
    """Origin offset [m] for rays leaving a surface of a model of diagonal ``scale`` [m]."""
    return RAY_OFFSET_FACTOR * float(scale)


class Tracer(Protocol):
    """What the sampling functions need from a tracer (both backends implement it)."""

    vertices: np.ndarray  # (n_vertices, 3) float64 [m]
    faces: np.ndarray  # (n_faces, 3) int64
    scale: float  # bounding-box diagonal [m]
    offset: float  # ray origin offset from surfaces [m]

    def intersects_first(self, origins, directions, max_distance=np.inf, *,
                         validate: bool = True) -> np.ndarray: ...

    def any_hit(self, origins, directions, max_distance=np.inf, *,
                validate: bool = True) -> np.ndarray: ...


def _check_mesh(vertices, faces):
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    require(vertices.ndim == 2 and vertices.shape[1] == 3 and len(vertices) >= 3, "vertices",
            vertices, "must be an (n, 3) array of at least 3 points [m]")
    require(faces.ndim == 2 and faces.shape[1] == 3 and len(faces) >= 1, "faces", faces,
            "must be an (m, 3) integer array of at least one triangle")
    require(np.issubdtype(faces.dtype, np.integer), "faces.dtype", faces.dtype,
            "must be an integer type")
    require(bool(np.isfinite(vertices).all()), "vertices", vertices,
            "must be finite (no NaN or inf)")
    require(int(faces.min()) >= 0 and int(faces.max()) < len(vertices), "faces", faces,
            f"indices must lie in [0, {len(vertices) - 1}]")
    vertices = vertices.copy()
    faces = faces.astype(np.int64)
    vertices.flags.writeable = False
    faces.flags.writeable = False
    return vertices, faces


def _check_rays(origins, directions, max_distance, validate=True):
    """Rays as float64 arrays: origins (n, 3); unit directions (n, 3) or (1, 3) for one
    direction shared by all rays; distances (n,) or (1,)."""
    origins = np.asarray(origins, dtype=np.float64)
    directions = np.asarray(directions, dtype=np.float64)
    if directions.ndim == 1:
        directions = directions[None]
    dist = np.asarray(max_distance, dtype=np.float64).reshape(-1)
    if not validate:
        return origins, directions, dist
    require(origins.ndim == 2 and origins.shape[1] == 3, "origins", origins,
            "must be an (n, 3) array [m]")
    require(directions.ndim == 2 and directions.shape[1] == 3
            and len(directions) in (1, len(origins)), "directions", directions,
            f"must be (3,) or have the shape of origins {origins.shape}")
    norm = np.linalg.norm(directions, axis=1)
    require(bool((norm > 0).all() and np.isfinite(norm).all()), "directions", directions,
            "must be finite, non-zero vectors")
    directions = directions / norm[:, None]
    require(len(dist) in (1, len(origins)), "max_distance", max_distance,
            "must be a number or one per ray")
    require(bool((dist > 0).all()), "max_distance", max_distance, "must be > 0 [m]")
    require(bool(np.isfinite(origins).all()), "origins", origins, "must be finite")
    return origins, directions, dist


class _MeshTracer:
    """Geometry shared by both backends (immutable after construction)."""

    def __init__(self, vertices, faces):
        self.vertices, self.faces = _check_mesh(vertices, faces)
        lo = self.vertices.min(axis=0)
        hi = self.vertices.max(axis=0)
        self.center = 0.5 * (lo + hi)
        self.scale = float(np.linalg.norm(hi - lo))
        require(self.scale > 0, "vertices", self.vertices, "must not all coincide")
        self.offset = ray_offset(self.scale)

    def __repr__(self):
        return (f"{type(self).__name__}({len(self.faces)} triangles, scale={self.scale:.4g} m, "
                f"offset={self.offset:.3g} m)")


class EmbreeTracer(_MeshTracer):
    """Embree (embreex, float32) tracer.

    Parameters
    ----------
    vertices : (n, 3) array_like
        Vertex coordinates [m].
    faces : (m, 3) array_like of int
        Triangle vertex indices.
    n_threads : int, optional
        Python threads each running part of a large batch (embreex releases the GIL while
        tracing), from the process's persistent pool (:mod:`shipthermal._threads`).
        Default: numba's thread count (the CPUs, or what a sweep pins a case to).

    Notes
    -----
    Uses embreex's scene directly rather than ``trimesh.ray.ray_pyembree``: trimesh copies the
    rays twice (float32 → float64 → shift and scale → float32) on every call and exposes no
    occlusion query nor ``max_distance``; ``benchmarks/bench_raytrace.py`` measures the
    difference. Coordinates are shifted to the bounding-box centre in float64 before the
    float32 cast (see the module notes on precision).
    """

    def __init__(self, vertices, faces, n_threads: int | None = None):
        super().__init__(vertices, faces)
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        if not n_threads:
            import numba

            n_threads = numba.get_num_threads()
        self.n_threads = int(n_threads)
        require(self.n_threads >= 1, "n_threads", n_threads, "must be >= 1")
        self._scene = rtcore_scene.EmbreeScene()
        # the TriangleMesh object only registers the buffers with the scene; keep a reference
        self._mesh = TriangleMesh(
            scene=self._scene,
            vertices=np.ascontiguousarray(self.vertices - self.center, dtype=np.float32),
            indices=np.ascontiguousarray(self.faces, dtype=np.int32))
        # commit now (the first query would otherwise) so builds are timed with construction
        self._scene.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))

    def __reduce__(self):
        # the Embree scene is a C object: pickle the mesh and rebuild (for dask workers)
        return (type(self), (self.vertices, self.faces, self.n_threads))

    def single_threaded(self) -> "EmbreeTracer":
        """This tracer (the same committed scene) answering each call in the calling
        thread: for callers that run several batches at once on their own threads (Embree's
        queries on a committed scene are thread-safe)."""
        import copy

        one = copy.copy(self)
        one.n_threads = 1
        return one

    def _run(self, origins, directions, max_distance, query, validate):
        origins, directions, dist = _check_rays(origins, directions, max_distance, validate)
        n = len(origins)
        if n == 0:
            return np.zeros(0, np.int64)
        # shift and cast in one pass (no float64 temporary)
        o32 = np.empty((n, 3), np.float32)
        np.subtract(origins, self.center, out=o32, casting="same_kind")
        d32 = np.ascontiguousarray(directions, dtype=np.float32)
        t32 = np.empty(n, np.float32)
        t32[:] = np.minimum(dist, _FLOAT32_TFAR_MAX)
        if self.n_threads == 1 or n < _PARALLEL_MIN_RAYS:
            return self._scene.run(o32, d32, dists=t32, query=query).astype(np.int64)
        bounds = np.linspace(0, n, self.n_threads + 1).astype(int)
        one_dir = len(d32) == 1

        def part(k):
            sl = slice(bounds[k], bounds[k + 1])
            return self._scene.run(o32[sl], d32 if one_dir else d32[sl], dists=t32[sl],
                                   query=query)

        parts = thread_map(part, range(self.n_threads), self.n_threads)
        return np.concatenate(parts).astype(np.int64)

    def intersects_first(self, origins, directions, max_distance=np.inf, *,
                         validate: bool = True) -> np.ndarray:
        """Nearest triangle hit by each ray within ``max_distance``; -1 for a miss.

        Parameters
        ----------
        origins : (n, 3) array_like
            Ray origins [m].
        directions : (n, 3) or (3,) array_like
            Ray directions (one shared direction allowed) [-]; normalised here.
        max_distance : float or (n,) array_like
            Largest hit distance along the ray [m].
        validate : bool
            Check shapes and normalise directions. Internal callers passing unit
            directions and valid arrays set False to save a pass over the rays.

        Returns
        -------
        (n,) int64
            Triangle index, -1 for no hit.
        """
        return self._run(origins, directions, max_distance, "INTERSECT", validate)

    def any_hit(self, origins, directions, max_distance=np.inf, *,
                validate: bool = True) -> np.ndarray:
        """True where the ray meets any triangle before ``max_distance`` [m] (same
        parameters as :meth:`intersects_first`)."""
        # embreex's occlusion query returns the geometry id (0) when blocked, -1 otherwise
        return self._run(origins, directions, max_distance, "OCCLUDED", validate) >= 0


class NumbaTracer(_MeshTracer):
    """Independent float64 tracer: numba SAH bounding-volume hierarchy, parallel over rays.

    Parameters
    ----------
    vertices : (n, 3) array_like
        Vertex coordinates [m].
    faces : (m, 3) array_like of int
        Triangle vertex indices.
    leaf_size : int
        Largest number of triangles in a leaf of the hierarchy.

    Notes
    -----
    Build: binned SAH (Wald 2007), see :mod:`shipthermal.raytrace._bvh`. Triangle test:
    Möller & Trumbore (1997), edges inclusive. Intended for cross-checking Embree and for
    machines without embreex; on 10^5 triangles it is several times slower than Embree.
    """

    def __init__(self, vertices, faces, leaf_size: int = 4):
        super().__init__(vertices, faces)
        require(int(leaf_size) >= 1, "leaf_size", leaf_size, "must be >= 1")
        # same centring as Embree so both backends do arithmetic on the same numbers
        v = self.vertices - self.center
        tri = v[self.faces]
        self._v0 = np.ascontiguousarray(tri[:, 0])
        self._e1 = np.ascontiguousarray(tri[:, 1] - tri[:, 0])
        self._e2 = np.ascontiguousarray(tri[:, 2] - tri[:, 0])
        (self._node_min, self._node_max, self._node_left, self._node_start, self._node_count,
         self._order, depth) = _bvh.build_bvh(tri.min(axis=1), tri.max(axis=1),
                                              tri.mean(axis=1), int(leaf_size))
        self.depth = int(depth)

    def _run(self, origins, directions, max_distance, any_hit, validate):
        origins, directions, dist = _check_rays(origins, directions, max_distance, validate)
        return _bvh.trace_bvh(
            self._node_min, self._node_max, self._node_left, self._node_start,
            self._node_count, self._order, self._v0, self._e1, self._e2,
            np.ascontiguousarray(origins - self.center), np.ascontiguousarray(directions),
            np.ascontiguousarray(dist), any_hit, self.depth + 2)

    def intersects_first(self, origins, directions, max_distance=np.inf, *,
                         validate: bool = True) -> np.ndarray:
        """Nearest triangle hit by each ray within ``max_distance`` [m]; -1 for a miss
        (parameters as :meth:`EmbreeTracer.intersects_first`)."""
        return self._run(origins, directions, max_distance, False, validate)

    def any_hit(self, origins, directions, max_distance=np.inf, *,
                validate: bool = True) -> np.ndarray:
        """True where the ray meets any triangle before ``max_distance`` [m]."""
        return self._run(origins, directions, max_distance, True, validate) >= 0

    def brute_force_first(self, origins, directions, max_distance=np.inf) -> np.ndarray:
        """Same answer as :meth:`intersects_first` by testing every triangle (reference)."""
        origins, directions, dist = _check_rays(origins, directions, max_distance)
        return _bvh.brute_force_first(
            self._v0, self._e1, self._e2, np.ascontiguousarray(origins - self.center),
            np.ascontiguousarray(directions), np.ascontiguousarray(dist))


def batch_threads(tracer, n_batches: int) -> tuple:
    """``(tracer, threads)`` for a caller with ``n_batches`` independent batches of rays:
    on Embree with several threads and batches, a single-threaded view of the tracer and
    one batch per thread (each thread then also does its batch's own set-up and
    bookkeeping, which otherwise run on one thread between the parallel traces); else the
    tracer itself, batches one after the other (the numba tracer is parallel inside a call
    and not safe for concurrent ones)."""
    threads = getattr(tracer, "n_threads", 1)
    if hasattr(tracer, "single_threaded") and threads > 1 and n_batches > 1:
        return tracer.single_threaded(), threads
    return tracer, 1


_BACKENDS = ("auto", "embree", "numba")


def make_tracer(vertices, faces, backend: str = "auto", **options) -> EmbreeTracer | NumbaTracer:
    """Build a tracer: ``"embree"``, ``"numba"`` or ``"auto"`` (Embree when installed).

    ``options`` go to the backend's constructor (``n_threads`` for Embree, ``leaf_size``
    for numba).
    """
    require(backend in _BACKENDS, "backend", backend, f"must be one of {_BACKENDS}")
    if backend == "auto":
        backend = "embree" if has_embree() else "numba"
    if backend == "embree":
        if not has_embree():
            raise InputError("backend", backend, "needs the embreex package",
                             "pip install embreex, or use backend='numba'")
        return EmbreeTracer(vertices, faces, **options)
    return NumbaTracer(vertices, faces, **options)
