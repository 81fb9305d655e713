"""Benchmark: meshing the default frigate at two sizes, against peers on the same surface.

Ours: generate the ship surface at the target edge length (structured hull + manifold3d
union + exact waterline split) and build the multilayer shell cell graph.

Peers measured in the same run, on the same geometry:
* trimesh ``subdivide_to_size`` refining the coarse surface to the fine edge length
  (pure surface remeshing, no parts, no FV mesh);
* manifold3d ``refine_to_length`` doing the same;
* pytetwild (fTetWild) tetrahedralising the coarse surface at the coarse edge length
  (the robust-remeshing route: what a solid mesh of the ship costs).

The machine has 2 cores shared with other agents: timings are noisy (±20 % is common).
Usage: ``python benchmarks/bench_geometry.py``
"""

import time

import numpy as np


def timed(fn, *args, repeat=1, **kwargs):
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*args, **kwargs)
        best = min(best, time.perf_counter() - t0)
    return best, out


def main():
    import pytetwild
    import trimesh
    from manifold3d import Manifold, Mesh64

    from shipthermal.geometry import frigate
    from shipthermal.geometry.remesh import build_ship_mesh, surface_quality

    sizes = (1.0, 0.5)
    ships = {}
    print("ours: frigate surface generation + shell cell graph")
    for h in sizes:
        t_gen, ship = timed(frigate, h, repeat=2)
        t_graph, (graph, rep) = timed(build_ship_mesh, ship, repeat=2)
        q = surface_quality(ship.vertices, ship.faces)
        ships[h] = (ship, t_gen, t_graph)
        print(f"  edge {h:4.2f} m: {ship.n_faces:7d} triangles, {graph.n_cells:8d} cells; "
              f"surface {t_gen:6.2f} s, cell graph {t_graph:6.2f} s; "
              f"min angle median {q['min_angle_median']:.1f}°, p1 {q['min_angle_p1']:.1f}°, "
              f"{100 * q['frac_min_angle_below_10']:.1f} % below 10°")

    from shipthermal.geometry.ship import build_ship, frigate_parameters

    t_raw, _ = timed(build_ship, frigate_parameters(), sizes[1], improve=False, repeat=2)
    print(f"  of which sliver clean-up (collapses + flips) at {sizes[1]} m: "
          f"{ships[sizes[1]][1] - t_raw:.2f} s (surface without it {t_raw:.2f} s)")

    coarse, t_gen_c, _ = ships[sizes[0]]
    fine, t_gen_f, _ = ships[sizes[1]]
    v = np.array(coarse.vertices)
    f = np.array(coarse.faces)

    t_tm, (v2, f2) = timed(trimesh.remesh.subdivide_to_size, v, f, sizes[1], max_iter=20, repeat=2)
    print(f"peer trimesh.subdivide_to_size {sizes[0]} -> {sizes[1]} m: {t_tm:.2f} s, {len(f2)} triangles; "
          f"ours (regenerate at {sizes[1]} m) / peer = {t_gen_f / t_tm:.2f}")

    man = Manifold(Mesh64(vert_properties=v, tri_verts=f.astype(np.uint64)))
    t_mf, refined = timed(lambda: man.refine_to_length(sizes[1]).to_mesh64(), repeat=2)
    print(f"peer manifold3d.refine_to_length {sizes[0]} -> {sizes[1]} m: {t_mf:.2f} s, "
          f"{len(refined.tri_verts)} triangles; ours / peer = {t_gen_f / t_mf:.2f}")

    h_tet = 2.0
    t_tw, (pts, tets) = timed(pytetwild.tetrahedralize, v, f.astype(np.int32),
                              edge_length_abs=h_tet, vtk_ordering=True)
    print(f"peer pytetwild.tetrahedralize of the {sizes[0]} m surface at {h_tet} m edge: "
          f"{t_tw:.2f} s, {len(tets)} tets; ours ({sizes[0]} m surface) / peer = {t_gen_c / t_tw:.3f}")


if __name__ == "__main__":
    main()
