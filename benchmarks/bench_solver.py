"""Thermal solver benchmarks: a transient tet problem against scikit-fem and FiPy, and a ship
shell day.

Run::

    python benchmarks/bench_solver.py box   [--edge 0.02] [--ours-dt 10,40,100,200] [--cell-dt 10,20,40]
    python benchmarks/bench_solver.py tets  [--edge 0.0075] [--cases 1,2] [--cell-centred-edge 0.015]
    python benchmarks/bench_solver.py shell [--edge 0.5] [--profile] [--linear-solver cholmod]

**box** — a steel box 1.0 × 0.5 × 0.2 m (k 50, ρ 7850, c 470), 293.15 K, the face x = 0
held at 373.15 K from t = 0, the others adiabatic; one pytetwild mesh (edge 0.02 m: ~125 k
tets, ~23 k vertices) for every solver; L2 error (weighted by each unknown's volume) against
the exact 1-D image series at 2000 s; one thread each. The peers run their own setups at
Δt = 10 s × 200: scikit-fem P1 (lumped mass, backward Euler, x = 0 vertices condensed, the
one matrix factorised once by the same CHOLMOD as ours); OpenFOAM ``laplacianFoam`` (Debian
package ``openfoam``, v1912; the tet mesh written as a polyMesh directly, Euler, ``Gauss
linear corrected`` with least-squares gradients, PCG/DIC to 1e-10, ``nNonOrthogonalCorrectors``
0 and 2; skipped with a note when not installed); FiPy 4 (cells, CG 1e-8; skipped when not
installed). Ours: the vertex-centred graph (BDF2, ``auto`` linear solver, several Δt: the
accuracy-matched comparison picks the largest Δt whose error is still at most the peer's)
and the cell-centred graph (non-orthogonal correction extrapolated per step, BDF2 and
backward Euler). Ratios are totals (meshing excluded, set-up and factorisation included)
measured in the same run.

**tets** — a steel cube (0.2 m side, pytetwild tetrahedra), initially uniform, cooling
through all six faces; 200 BDF2 steps (backward Euler first step) to Fo = α t/L² = 0.5, the
same mesh and time step for every solver:

* case 1, convection (h = 500 W m-2 K-1, Bi = 0.94, 400 K → 300 K): exact answer
  θ/θ_i = S(x) S(y) S(z), S the Carslaw–Jaeger convective slab series;
* case 2, radiation + convection (ε = 0.9 to 300 K surroundings, h = 50, 800 K start): the
  reference is our vertex-centred solver on the same mesh at 4× finer Δt (800 steps), so it
  measures time-stepping and nonlinear-solve error, not spatial error; FiPy's cell values
  are compared with the reference's P1 field at the cell centroids.

Solvers: ours on the vertex-centred graph (P1/CVFEM: one SPD solve per step; linear backend
``auto``, chosen by measurement; ``--all-backends`` adds CHOLMOD through kvxopt and, on small
meshes, SuperLU), scikit-fem
P1 (consistent and lumped mass; factorisations reused: SuperLU with the ``MMD_AT_PLUS_A``
ordering — scipy's default COLAMD is several times slower on 3-D meshes —, plus a row with
the same CHOLMOD as ours to separate discretisation from linear algebra; case 2 with lumped
mass and boundary terms, radiation by a chord Newton that reuses the factorisation of the
first step's Jacobian), FiPy 4 on the tet cells (cell-centred two-point fluxes, no
non-orthogonal correction; ``LinearCGSolver(tolerance=1e-8)``; convection/radiation as
implicit sources through the boundary faces' two-point conductances, radiation re-linearised
by sweeps) and — on a coarser mesh — our cell-centred graph (deferred non-orthogonal
correction, extrapolated per step). The vertex-centred unknowns are the mesh vertices (≈ tets/5.5); FiPy's and
the cell-centred ones are the tets.

**shell** — the default frigate surface at its default size through the default layups
(multilayer shells, cells = faces × layers), one simulated day with a synthetic sun, sky
and air (callables of time, no ray tracing), reporting time per step, preconditioner
set-up, Newton / PCG iterations and the energy imbalance; ``--profile`` adds a cProfile
of the day.

Not tests. Other jobs share the 2 cores of this machine: timings vary by ±30 % between runs;
BLAS is limited to one thread for every solver.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

HALF = 0.1                      # half side of the cube L [m]
STEPS = 200
FO_END = 0.5
CASES = {
    1: dict(name="convection", temp_init=400.0, temp_amb=300.0, h=500.0, emissivity=0.0),
    2: dict(name="radiation+convection", temp_init=800.0, temp_amb=300.0, h=50.0, emissivity=0.9),
}


# ------------------------------------------------------------------ problem ----------------
def steel():
    from shipthermal.materials import MATERIALS

    return MATERIALS["mild_steel"]


def end_time() -> float:
    return FO_END * HALF**2 / steel().diffusivity


def slab_series(x_over_l, fourier, biot, n_terms=80):
    """Carslaw & Jaeger (1959) §3.11 eq. (4): θ/θ_i of a convecting plane wall."""
    from scipy.optimize import brentq

    z = np.array([brentq(lambda s: s * np.tan(s) - biot, n * np.pi + 1e-12, n * np.pi + np.pi / 2 - 1e-12)
                  for n in range(n_terms)])
    c = 4 * np.sin(z) / (2 * z + np.sin(2 * z))
    x = np.clip(np.asarray(x_over_l), -1.0, 1.0)     # pytetwild may leave vertices ~1e-4 outside
    return np.einsum("n,np->p", c * np.exp(-z**2 * fourier), np.cos(z[:, None] * x[None, :]))


def exact_case1(points: np.ndarray) -> np.ndarray:
    c = CASES[1]
    biot = c["h"] * HALF / steel().conductivity
    theta = np.ones(len(points))
    for ax in range(3):
        theta *= slab_series(points[:, ax] / HALF, FO_END, biot)
    return c["temp_amb"] + (c["temp_init"] - c["temp_amb"]) * theta


def cube_mesh(edge: float):
    import trimesh

    from shipthermal.mesh import tetrahedralize_surface

    box = trimesh.creation.box(extents=(2 * HALF,) * 3)
    t0 = time.perf_counter()
    pts, tets = tetrahedralize_surface(box.vertices, box.faces, edge_length=edge)
    return pts, tets, time.perf_counter() - t0


def errors(values, exact, weights):
    e = values - exact
    return float(np.sqrt(np.sum(weights * e**2) / np.sum(weights))), float(np.max(np.abs(e)))


# -------------------------------------------------------------------- ours ----------------
def run_ours(pts, tets, case, builder="dual", backend="auto", steps=STEPS):
    from shipthermal.conditions import Convection, SurfaceBalance
    from shipthermal.mesh import build_dual_tet_graph, build_tet_graph
    from shipthermal.model import ThermalModel
    from shipthermal.simulation import Simulation

    c = CASES[case]
    t0 = time.perf_counter()
    build = build_dual_tet_graph if builder == "dual" else build_tet_graph
    g = build(pts, tets, material=steel())
    if c["emissivity"] > 0:
        bc = SurfaceBalance(emissivity=c["emissivity"], temp_env=c["temp_amb"], h=c["h"],
                            temp_air=c["temp_amb"])
    else:
        bc = Convection(c["h"], c["temp_amb"])
    m = ThermalModel(g, {"boundary": bc}, initial_temperature=c["temp_init"])
    t_end = end_time()
    sim = Simulation(m, t_end / steps, t_end, scheme="bdf2", output_times=[t_end],
                     linear_solver=backend)
    t1 = time.perf_counter()
    res = sim.run()
    t2 = time.perf_counter()
    tim = res.timing
    return dict(setup=t1 - t0, factor=tim["setup"], stepping=t2 - t1 - tim["setup"],
                values=res.final_temperature, points=g.cell_centroid, weights=g.cell_volume,
                info=f"{res.backend}; Newton {tim['newton_iterations'] / steps:.2f}/step, "
                     f"linear {tim['linear_iterations'] / steps:.2f}/step, "
                     f"energy {res.energy.relative_imbalance:.1e}", n=g.n_cells)


# ---------------------------------------------------------------- scikit-fem --------------
def _factor(matrix, how):
    if how == "cholmod":
        from shipthermal.linear import _cholmod_factor

        return _cholmod_factor(matrix)
    return spla.splu(sp.csc_matrix(matrix), permc_spec="MMD_AT_PLUS_A",
                     options=dict(SymmetricMode=True)).solve


def run_skfem(pts, tets, case, lumped=True, how="splu", steps=STEPS):
    """P1 Galerkin, BDF2 (BE start), the two matrices factorised once."""
    from skfem import Basis, ElementTetP1, FacetBasis, MeshTet, asm
    from skfem.models.poisson import laplace, mass

    from shipthermal.units import SIGMA

    c = CASES[case]
    mat = steel()
    t0 = time.perf_counter()
    mesh = MeshTet(np.ascontiguousarray(pts.T), np.ascontiguousarray(tets.T))
    basis = Basis(mesh, ElementTetP1())
    stiff = mat.conductivity * asm(laplace, basis)
    cap = mat.volumetric_heat_capacity * asm(mass, basis)
    bmass = asm(mass, FacetBasis(mesh, ElementTetP1()))         # ∫_∂Ω φ_i φ_j
    if lumped:
        cap = sp.diags(np.asarray(cap.sum(axis=1)).ravel())
        bmass = sp.diags(np.asarray(bmass.sum(axis=1)).ravel())
    cap, bmass, stiff = cap.tocsr(), bmass.tocsr(), stiff.tocsr()
    barea = np.asarray(bmass.sum(axis=1)).ravel()               # lumped boundary area per node
    t1 = time.perf_counter()
    dt = end_time() / steps
    eps, tamb = c["emissivity"], c["temp_amb"]
    h_lin = c["h"] + 4 * eps * SIGMA * c["temp_init"] ** 3      # chord slope (case 2)
    base = stiff + h_lin * bmass
    solves = [_factor(base + cap / dt, how), _factor(base + 1.5 * cap / dt, how)]
    t2 = time.perf_counter()
    t_old = np.full(len(pts), c["temp_init"])
    t_now = None
    iters = 0
    for k in range(steps):
        if k == 0:
            a, hist, solve = 1.0, t_old, solves[0]
        else:
            a, hist, solve = 1.5, 2.0 * t_now - 0.5 * t_old, solves[1]
        if eps == 0.0:
            temp = solve(cap @ hist / dt + c["h"] * tamb * barea)
            iters += 1
        else:
            # Chord Newton on M(aT − hist)/Δt + K T + B (h (T − T∞) + εσ (T⁴ − T∞⁴)) = 0 with
            # the factorised first Jacobian; stop at a 1e-9 K correction (our tolerance).
            temp = (t_old if k == 0 else 2.0 * t_now - t_old).copy()
            for _ in range(200):
                resid = (cap @ (a * temp - hist) / dt + stiff @ temp
                         + barea * (c["h"] * (temp - tamb) + eps * SIGMA * (temp**4 - tamb**4)))
                delta = solve(-resid)
                temp += delta
                iters += 1
                if np.max(np.abs(delta)) <= 1e-9:
                    break
        t_old, t_now = (t_now if t_now is not None else t_old), temp
    t3 = time.perf_counter()
    w = np.asarray(asm(mass, basis).sum(axis=1)).ravel()
    return dict(setup=t1 - t0, factor=t2 - t1, stepping=t3 - t2, values=t_now, points=pts,
                weights=w, info=f"{'lumped' if lumped else 'consistent'} mass, {how}; "
                                f"solves {iters / steps:.2f}/step", n=len(pts))


# ---------------------------------------------------------------------- FiPy --------------
def fipy_mesh(pts, tets):
    """FiPy's general mesh from arrays: unique triangles, 4 per cell."""
    from fipy.meshes.mesh import Mesh

    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
    tri = tets[:, local].reshape(-1, 3)
    n = len(pts)
    s = np.sort(tri, axis=1)
    key = (s[:, 0] * n + s[:, 1]) * n + s[:, 2]
    _, first, inv = np.unique(key, return_index=True, return_inverse=True)
    faces = tri[first]
    return Mesh(vertexCoords=pts.T.copy(), faceVertexIDs=faces.T.copy(),
                cellFaceIDs=inv.reshape(-1, 4).T.copy())


def run_fipy(pts, tets, case, steps=STEPS):
    import fipy

    from shipthermal.units import SIGMA

    c = CASES[case]
    mat = steel()
    t0 = time.perf_counter()
    mesh = fipy_mesh(pts, tets)
    vol = np.asarray(mesh.cellVolumes)
    # Boundary faces' two-point conductance to the surface: γ A = k A / d (d: centroid to
    # face plane), in series with the surface's own h (+ linearised radiation).
    ext = np.asarray(mesh.exteriorFaces.value)
    fcell = np.asarray(mesh.faceCellIDs.filled(-1))[0][ext]
    area = np.asarray(mesh._faceAreas)[ext]
    normal = np.asarray(mesh.faceNormals)[:, ext].T
    fcen = np.asarray(mesh.faceCenters)[:, ext].T
    ccen = np.asarray(mesh.cellCenters).T
    d = np.abs(np.einsum("ij,ij->i", fcen - ccen[fcell], normal))
    gamma = mat.conductivity / d
    ncell = mesh.numberOfCells
    temp = fipy.CellVariable(mesh=mesh, value=c["temp_init"], hasOld=True)
    prev = fipy.CellVariable(mesh=mesh, value=c["temp_init"])
    sink = fipy.CellVariable(mesh=mesh, value=0.0)       # Σ ∂Q/∂T_P / V  [W m-3 K-1]
    inflow = fipy.CellVariable(mesh=mesh, value=0.0)     # explicit part [W m-3]
    rc = mat.volumetric_heat_capacity
    dt = end_time() / steps
    eq_be = (fipy.TransientTerm(coeff=rc) == fipy.DiffusionTerm(coeff=mat.conductivity)
             + inflow - fipy.ImplicitSourceTerm(coeff=sink))
    hist = fipy.CellVariable(mesh=mesh, value=0.0)       # BDF2 history ½ ρc (Tⁿ − Tⁿ⁻¹)/Δt
    eq_bdf2 = (fipy.TransientTerm(coeff=1.5 * rc) == fipy.DiffusionTerm(coeff=mat.conductivity)
               + inflow - fipy.ImplicitSourceTerm(coeff=sink) + hist)
    solver = fipy.LinearCGSolver(tolerance=1e-8)
    tf = np.full(len(fcell), c["temp_init"])

    def linearise(tp):
        """Surface balances of the boundary faces at cell temperatures tp (Newton per face),
        returned as an implicit sink and an explicit inflow per cell (Newton linearisation)."""
        nonlocal tf
        tc = tp[fcell]
        ts = tf.copy()
        for _ in range(50):
            f = gamma * (tc - ts) - c["h"] * (ts - c["temp_amb"]) - c["emissivity"] * SIGMA * (ts**4 - c["temp_amb"]**4)
            df = -gamma - c["h"] - 4 * c["emissivity"] * SIGMA * ts**3
            step = f / df
            ts -= step
            if np.max(np.abs(step)) < 1e-12 * 1000:
                break
        tf = ts
        kappa = c["h"] + 4 * c["emissivity"] * SIGMA * ts**3
        dq = area * gamma * kappa / (gamma + kappa)          # ∂(loss)/∂T_P [W K-1]
        loss = area * gamma * (tc - ts)                       # heat out [W]
        s = np.bincount(fcell, dq, ncell) / vol
        q = np.bincount(fcell, dq * tc - loss, ncell) / vol
        return s, q

    t1 = time.perf_counter()
    sweeps = 0
    for k in range(steps):
        eq = eq_be if k == 0 else eq_bdf2
        if k > 0:
            hist.setValue(0.5 * rc * (np.asarray(temp.old.value) - np.asarray(prev.value)) / dt)
        prev.setValue(np.asarray(temp.old.value))
        for _ in range(30):
            s, q = linearise(np.asarray(temp.value))
            sink.setValue(s)
            inflow.setValue(q)
            before = np.asarray(temp.value).copy()
            eq.solve(var=temp, dt=dt, solver=solver)
            sweeps += 1
            if c["emissivity"] == 0.0 or np.max(np.abs(np.asarray(temp.value) - before)) < 1e-6:
                break
        temp.updateOld()
    t2 = time.perf_counter()
    return dict(setup=t1 - t0, factor=0.0, stepping=t2 - t1, values=np.asarray(temp.value).copy(),
                points=ccen, weights=vol, info=f"CG 1e-8, sweeps {sweeps / steps:.2f}/step",
                n=ncell)


# ------------------------------------------------------------------ driver ----------------
def _has_fipy() -> bool:
    try:
        import fipy  # noqa: F401
    except ImportError:
        return False
    return True


def tets_benchmark(args):
    from threadpoolctl import threadpool_limits

    print(next(p for p in __doc__.split("\n\n") if p.startswith("**tets**")))
    cases = [] if args.cases in ("", "none") else [int(x) for x in args.cases.split(",")]
    if cases:
        pts, tets, t_mesh = cube_mesh(args.edge)
        print(f"\nmesh: edge {args.edge} m → {len(tets)} tets, {len(pts)} vertices "
              f"(pytetwild {t_mesh:.1f} s); dt = {end_time() / STEPS:.3f} s, {STEPS} steps, "
              f"t_end = {end_time():.1f} s")
    from shipthermal.linear import has_cholmod

    with threadpool_limits(limits=1, user_api="blas"):
        for case in cases:
            c = CASES[case]
            print(f"\n=== case {case}: {c['name']} (T_i {c['temp_init']} K, h {c['h']}, "
                  f"ε {c['emissivity']}) ===")
            if case == 1:
                reference = exact_case1
                ref_label = "exact (Carslaw–Jaeger product)"
            else:
                t0 = time.perf_counter()
                ref = run_ours(pts, tets, case, steps=4 * STEPS)
                print(f"reference: ours (vertex-centred) with 4×{STEPS} steps, "
                      f"{time.perf_counter() - t0:.1f} s")
                tet_mean = tets
                ref_vals = ref["values"]

                def reference(p, _vals=ref_vals):
                    if len(p) == len(pts):
                        return _vals
                    return _vals[tet_mean].mean(axis=1)      # P1 field at the tet centroids
                ref_label = "ours at Δt/4"
            rows = []
            runs = [("ours vertex-centred (auto)", lambda: run_ours(pts, tets, case))]
            if args.all_backends:
                if has_cholmod():
                    runs += [("ours vertex-centred (cholmod)",
                              lambda: run_ours(pts, tets, case, backend="cholmod"))]
                if len(pts) < 40_000:
                    runs += [("ours vertex-centred (splu)", lambda: run_ours(pts, tets, case, backend="direct"))]
            if case == 1:
                runs += [("scikit-fem P1 consistent, splu", lambda: run_skfem(pts, tets, case, lumped=False))]
            runs += [("scikit-fem P1 lumped, splu", lambda: run_skfem(pts, tets, case))]
            if has_cholmod():
                runs += [("scikit-fem P1 lumped, cholmod", lambda: run_skfem(pts, tets, case, how="cholmod"))]
            if not args.no_fipy and _has_fipy():
                runs += [("FiPy 4 (cells, CG 1e-8)", lambda: run_fipy(pts, tets, case))]
            for label, fn in runs:
                r = fn()
                l2, mx = errors(r["values"], reference(r["points"]), r["weights"])
                total = r["setup"] + r["factor"] + r["stepping"]
                rows.append((label, r, l2, mx, total))
                print(f"  done: {label:34s} total {total:7.1f} s", flush=True)
            ours_total = rows[0][4]
            print(f"\nerrors vs {ref_label}; times [s]; ratio = ours (auto) total / this total")
            print(f"{'solver':34s} {'unknowns':>9s} {'setup':>7s} {'factor':>7s} {'steps':>7s} "
                  f"{'total':>7s} {'ratio':>6s} {'L2 [K]':>9s} {'max [K]':>9s}  notes")
            for label, r, l2, mx, total in rows:
                print(f"{label:34s} {r['n']:9d} {r['setup']:7.2f} {r['factor']:7.2f} "
                      f"{r['stepping']:7.2f} {total:7.2f} {ours_total / total:6.2f} "
                      f"{l2:9.2e} {mx:9.2e}  {r['info']}")

        if args.cell_centred_edge:
            pts2, tets2, _ = cube_mesh(args.cell_centred_edge)
            print(f"\n=== case 1 on a coarser mesh ({len(tets2)} tets, {len(pts2)} vertices): "
                  "cell-centred vs vertex-centred graph ===")
            for label, fn in (("ours vertex-centred", lambda: run_ours(pts2, tets2, 1)),
                              ("ours cell-centred", lambda: run_ours(pts2, tets2, 1, builder="cells")),
                              ("FiPy 4 (cells, CG 1e-8)", lambda: run_fipy(pts2, tets2, 1)),
                              ("scikit-fem P1 lumped, splu", lambda: run_skfem(pts2, tets2, 1))):
                if label.startswith("FiPy") and (args.no_fipy or not _has_fipy()):
                    print(f"{label:28s} skipped (--no-fipy or not installed)")
                    continue
                r = fn()
                l2, mx = errors(r["values"], exact_case1(r["points"]), r["weights"])
                total = r["setup"] + r["factor"] + r["stepping"]
                print(f"{label:28s} unknowns {r['n']:7d}  setup {r['setup']:6.2f}  factor "
                      f"{r['factor']:6.2f}  steps {r['stepping']:7.2f}  total {total:7.2f} s  "
                      f"L2 {l2:.2e} K  max {mx:.2e} K  {r['info']}", flush=True)


# ============================================================= box: the conduction race ====
# A steel box, one face suddenly heated (the problem of the project's solver comparison):
# every solver on the same pytetwild mesh, one thread each, errors against the exact series.
BOX = (1.0, 0.5, 0.2)                      # [m]
BOX_T0, BOX_HOT = 293.15, 373.15           # initial, face x = 0 [K]
BOX_T_END = 2000.0                         # [s]
BOX_DT_PEER = 10.0                         # the comparison's step for the peers [s]
# Boundary faces facing −x with their centroid within this of x = 0 form the heated face [m]
# (pytetwild may leave surface vertices slightly off the input planes).
BOX_FACE_TOL = 1e-3


def box_material():
    from shipthermal.materials import Material

    return Material("box_steel", 7850.0, 470.0, 50.0, "round figures of a carbon steel")


def exact_box(points: np.ndarray, t: float = BOX_T_END) -> np.ndarray:
    """x = 0 held at T_hot from t = 0, x = L adiabatic, the rest adiabatic: the 1-D image
    series (Carslaw & Jaeger 1959, §2.5) θ/θ₀ = Σₙ (−1)ⁿ [erfc((2nL + x)/2√(αt)) +
    erfc((2(n+1)L − x)/2√(αt))]."""
    from scipy.special import erfc

    length = BOX[0]
    s = 2.0 * np.sqrt(box_material().diffusivity * t)
    x = np.clip(points[:, 0], 0.0, length)
    theta = np.zeros(len(points))
    for n in range(6):
        theta += (-1) ** n * (erfc((2 * n * length + x) / s) + erfc((2 * (n + 1) * length - x) / s))
    return BOX_T0 + (BOX_HOT - BOX_T0) * theta


def box_mesh(edge: float):
    import trimesh

    from shipthermal.mesh import tetrahedralize_surface

    box = trimesh.creation.box(extents=BOX)
    box.apply_translation(np.asarray(BOX) / 2.0)
    t0 = time.perf_counter()
    pts, tets = tetrahedralize_surface(box.vertices, box.faces, edge_length=edge)
    return pts, tets, time.perf_counter() - t0


def _box_hot_vertices(pts, tets):
    """Vertices of the boundary triangles of the heated face (as :func:`_box_patches`)."""
    from shipthermal.mesh.tets import orient_tets, tet_faces

    *_, btri = tet_faces(orient_tets(pts, np.asarray(tets, np.int64)))
    p0, p1, p2 = (pts[btri[:, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return np.unique(btri[_box_patches((p0 + p1 + p2) / 3.0, normal) == "hot"])


def _box_patches(centroid, normal):
    return np.where((normal[:, 0] < -0.99) & (centroid[:, 0] < BOX_FACE_TOL), "hot", "walls")


def box_ours(pts, tets, builder="dual", scheme="bdf2", dt=BOX_DT_PEER, backend="auto",
             treatment="extrapolated"):
    from shipthermal.conditions import Adiabatic, FixedTemperature
    from shipthermal.mesh import build_dual_tet_graph, build_tet_graph
    from shipthermal.model import ThermalModel
    from shipthermal.simulation import Simulation

    t0 = time.perf_counter()
    if builder == "dual":
        g = build_dual_tet_graph(pts, tets, material=box_material(), patches=_box_patches)
    else:
        g = build_tet_graph(pts, tets, material=box_material(), patches=_box_patches,
                            correction_treatment=treatment)
    m = ThermalModel(g, {"hot": FixedTemperature(BOX_HOT), "walls": Adiabatic()},
                     initial_temperature=BOX_T0)
    steps = int(round(BOX_T_END / dt))
    sim = Simulation(m, dt, BOX_T_END, scheme=scheme, output_times=[BOX_T_END],
                     linear_solver=backend)
    t1 = time.perf_counter()
    res = sim.run()
    t2 = time.perf_counter()
    tim = res.timing
    return dict(total=t2 - t0, values=res.final_temperature, points=g.cell_centroid,
                weights=g.cell_volume, n=g.n_cells,
                info=f"{scheme} Δt {dt:g} s; {res.backend}; set-up {t1 - t0:.1f} s, factor "
                     f"{tim['setup']:.1f} s; Newton {tim['newton_iterations'] / steps:.2f}/step; "
                     f"energy {res.energy.relative_imbalance:.0e}")


def box_skfem(pts, tets, dt=BOX_DT_PEER, how="cholmod"):
    """scikit-fem P1, lumped mass, backward Euler, x = 0 vertices condensed (Dirichlet), the
    one matrix factorised once (CHOLMOD through kvxopt, as ours)."""
    from skfem import Basis, ElementTetP1, MeshTet, asm
    from skfem.models.poisson import laplace, mass

    mat = box_material()
    t0 = time.perf_counter()
    mesh = MeshTet(np.ascontiguousarray(pts.T), np.ascontiguousarray(tets.T))
    basis = Basis(mesh, ElementTetP1())
    stiff = (mat.conductivity * asm(laplace, basis)).tocsr()
    lumped = mat.volumetric_heat_capacity * np.asarray(asm(mass, basis).sum(axis=1)).ravel()
    hot = _box_hot_vertices(pts, tets)
    free = np.setdiff1d(np.arange(len(pts)), hot)
    a = (stiff + sp.diags(lumped / dt)).tocsr()
    a_ff = a[free][:, free]
    a_fd = a[free][:, hot]
    solve = _factor(a_ff, how)
    temp = np.full(len(pts), BOX_T0)
    temp[hot] = BOX_HOT
    lift = a_fd @ temp[hot]
    c_f = lumped[free] / dt
    steps = int(round(BOX_T_END / dt))
    for _ in range(steps):
        temp[free] = solve(c_f * temp[free] - lift)
    t1 = time.perf_counter()
    return dict(total=t1 - t0, values=temp, points=pts, weights=lumped, n=len(pts),
                info=f"P1 lumped mass, backward Euler Δt {dt:g} s, {how} factor reused")


def _foam_header(cls, obj, location):
    return ("FoamFile\n{\n    version 2.0;\n    format ascii;\n    class " + cls + ";\n"
            f"    location \"{location}\";\n    object {obj};\n}}\n")


def write_foam_case(case, pts, tets, dt, alpha, n_nonorth=0, grad="leastSquares", tol=1e-10):
    """An OpenFOAM case of the tet mesh: polyMesh written directly (upper-triangular face
    order, owner < neighbour, boundary faces grouped by patch), laplacianFoam settings."""
    from pathlib import Path

    case = Path(case)
    poly = case / "constant" / "polyMesh"
    poly.mkdir(parents=True, exist_ok=True)
    (case / "system").mkdir(exist_ok=True)
    (case / "0").mkdir(exist_ok=True)
    from shipthermal.mesh.tets import orient_tets, tet_faces

    own, nei, ftri, bown, btri = tet_faces(orient_tets(pts, np.asarray(tets, np.int64)))
    swap = own > nei
    own, nei = np.where(swap, nei, own), np.where(swap, own, nei)
    ftri = np.where(swap[:, None], ftri[:, [0, 2, 1]], ftri)
    o = np.lexsort((nei, own))
    own, nei, ftri = own[o], nei[o], ftri[o]
    p0, p1, p2 = (pts[btri[:, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    label = _box_patches((p0 + p1 + p2) / 3.0, normal)
    patches = ["hot", "walls"]
    bo = np.lexsort((bown, np.array([patches.index(x) for x in label])))
    btri, bown, label = btri[bo], bown[bo], label[bo]

    def write(name, cls, body):
        (poly / name).write_text(_foam_header(cls, name, "constant/polyMesh") + body)

    write("points", "vectorField", f"{len(pts)}\n(\n"
          + "\n".join(f"({x:.12g} {y:.12g} {z:.12g})" for x, y, z in pts) + "\n)\n")
    faces = np.vstack([ftri, btri])
    write("faces", "faceList", f"{len(faces)}\n(\n"
          + "\n".join(f"3({i} {j} {k})" for i, j, k in faces) + "\n)\n")
    write("owner", "labelList", f"{len(faces)}\n(\n" + "\n".join(map(str, np.concatenate([own, bown])))
          + "\n)\n")
    write("neighbour", "labelList", f"{len(nei)}\n(\n" + "\n".join(map(str, nei)) + "\n)\n")
    start = len(ftri)
    body = f"{len(patches)}\n(\n"
    for p in patches:
        nf = int(np.sum(label == p))
        body += f"{p}\n{{\n    type patch;\n    nFaces {nf};\n    startFace {start};\n}}\n"
        start += nf
    write("boundary", "polyBoundaryMesh", body + ")\n")
    steps = int(round(BOX_T_END / dt))
    (case / "system" / "controlDict").write_text(_foam_header("dictionary", "controlDict", "system") + f"""
application laplacianFoam;
startFrom startTime;
startTime 0;
stopAt endTime;
endTime {BOX_T_END:g};
deltaT {dt:g};
writeControl timeStep;
writeInterval {steps};
purgeWrite 0;
writeFormat ascii;
writePrecision 12;
writeCompression off;
timeFormat general;
timePrecision 8;
runTimeModifiable false;
""")
    (case / "system" / "fvSchemes").write_text(_foam_header("dictionary", "fvSchemes", "system") + f"""
ddtSchemes {{ default Euler; }}
gradSchemes {{ default {grad}; }}
divSchemes {{ default none; }}
laplacianSchemes {{ default Gauss linear corrected; }}
interpolationSchemes {{ default linear; }}
snGradSchemes {{ default corrected; }}
""")
    (case / "system" / "fvSolution").write_text(_foam_header("dictionary", "fvSolution", "system") + f"""
solvers {{ T {{ solver PCG; preconditioner DIC; tolerance {tol:g}; relTol 0; }} }}
SIMPLE {{ nNonOrthogonalCorrectors {n_nonorth}; }}
""")
    (case / "constant" / "transportProperties").write_text(
        _foam_header("dictionary", "transportProperties", "constant") + f"DT {alpha:.12g};\n")
    (case / "0" / "T").write_text(_foam_header("volScalarField", "T", "0") + f"""
dimensions [0 0 0 1 0 0 0];
internalField uniform {BOX_T0};
boundaryField
{{
    hot {{ type fixedValue; value uniform {BOX_HOT}; }}
    walls {{ type zeroGradient; }}
}}
""")
    a_, b_, c_, d_ = (pts[tets[:, k]] for k in range(4))
    vol = np.einsum("ij,ij->i", np.cross(b_ - a_, c_ - a_), d_ - a_) / 6.0
    return (a_ + b_ + c_ + d_) / 4.0, vol


DEBIAN_FOAM_DIR = "/usr/share/openfoam"    # the Debian package's project directory


def box_openfoam(pts, tets, dt=BOX_DT_PEER, n_nonorth=0):
    import os
    import shutil
    import subprocess
    import tempfile

    exe = shutil.which("laplacianFoam")
    if exe is None:
        return None
    with tempfile.TemporaryDirectory(prefix="foam_box_") as case:
        centroids, vol = write_foam_case(case, pts, tets, dt, box_material().diffusivity, n_nonorth)
        env = dict(os.environ, OMP_NUM_THREADS="1")
        if "WM_PROJECT_DIR" not in env and os.path.isdir(DEBIAN_FOAM_DIR):
            env["WM_PROJECT_DIR"] = DEBIAN_FOAM_DIR     # where it finds etc/controlDict
        t0 = time.perf_counter()
        out = subprocess.run([exe, "-case", case], capture_output=True, text=True, env=env)
        t1 = time.perf_counter()
        if out.returncode != 0:
            raise RuntimeError("laplacianFoam failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
        txt = open(f"{case}/{BOX_T_END:g}/T").read()
        body = txt[txt.index("internalField"):]
        n = int(body.split("\n")[1])
        start = body.index("(") + 1
        vals = np.array(body[start:body.index(")", start)].split(), dtype=float)
        assert len(vals) == n == len(tets)
    return dict(total=t1 - t0, values=vals, points=centroids, weights=vol, n=len(tets),
                info=f"Euler Δt {dt:g} s, Gauss linear corrected, leastSquares gradients, "
                     "PCG/DIC 1e-10; run time of the solver process")


def box_benchmark(args):
    from threadpoolctl import threadpool_limits

    pts, tets, t_mesh = box_mesh(args.edge)
    mat = box_material()
    print(f"box {BOX} m, k {mat.conductivity}, ρ {mat.density}, c {mat.specific_heat}; "
          f"{BOX_T0} K, x = 0 held at {BOX_HOT} K from t = 0, other faces adiabatic; error vs "
          f"the exact erfc series at {BOX_T_END:g} s (L2 weighted by each unknown's volume)")
    print(f"mesh: edge {args.edge} m → {len(tets)} tets, {len(pts)} vertices (pytetwild "
          f"{t_mesh:.1f} s)")
    ours_dt = [float(x) for x in args.ours_dt.split(",")]
    cell_dt = [float(x) for x in args.cell_dt.split(",")]
    runs = [("scikit-fem P1 + CHOLMOD", lambda: box_skfem(pts, tets))]
    runs += [(f"ours vertex-centred BDF2 Δt {d:g}", lambda d=d: box_ours(pts, tets, dt=d))
             for d in ours_dt]
    if args.be:
        runs += [("ours vertex-centred BE", lambda: box_ours(pts, tets, scheme="backward_euler"))]
    for nc in (int(x) for x in args.foam_correctors.split(",")):
        runs += [(f"OpenFOAM laplacianFoam nNonOrth {nc}", lambda nc=nc: box_openfoam(pts, tets, n_nonorth=nc))]
    if not args.no_cells:
        runs += [(f"ours cell-centred BDF2 Δt {d:g}", lambda d=d: box_ours(pts, tets, "cells", dt=d))
                 for d in cell_dt]
        runs += [("ours cell-centred BE", lambda: box_ours(pts, tets, "cells",
                                                           scheme="backward_euler"))]
        if args.cell_iterated:
            runs += [("ours cell-centred BE iterated", lambda: box_ours(
                pts, tets, "cells", scheme="backward_euler", treatment="iterated"))]
    has_fipy = _has_fipy()
    if has_fipy and not args.no_fipy:
        runs += [("FiPy 4 (cells, CG 1e-8)", lambda: box_fipy(pts, tets))]
    rows = []
    with threadpool_limits(limits=1, user_api="blas"):
        for label, fn in runs:
            r = fn()
            if r is None:
                print(f"  {label}: not installed (Debian package 'openfoam'), skipped", flush=True)
                continue
            l2, mx = errors(r["values"], exact_box(r["points"]), r["weights"])
            rows.append((label, r, l2, mx))
            print(f"  done: {label:36s} {r['total']:7.1f} s  L2 {l2:.4f} K", flush=True)
    if not has_fipy:
        print("  FiPy: not installed, skipped")
    peers = {lab: r for lab, r, *_ in rows if not lab.startswith("ours")}

    def short(label):
        return {"scikit-fem": "skfem", "OpenFOAM": "OF" + label.split()[-1], "FiPy": "FiPy"}[label.split()[0]]
    print(f"\n{'solver':36s} {'unknowns':>9s} {'total s':>8s} {'L2 K':>8s} {'max K':>7s} "
          + " ".join(f"{'/' + short(p):>8s}" for p in peers) + "  notes")
    for label, r, l2, mx in rows:
        ratios = " ".join(f"{r['total'] / pr['total']:8.2f}" for pr in peers.values())
        print(f"{label:36s} {r['n']:9d} {r['total']:8.1f} {l2:8.4f} {mx:7.3f} {ratios}  {r['info']}")
    print("(ratio columns: this total / the peer's total, all measured in this run)")


def box_fipy(pts, tets, dt=BOX_DT_PEER):
    import fipy

    mat = box_material()
    t0 = time.perf_counter()
    mesh = fipy_mesh(pts, tets)
    temp = fipy.CellVariable(mesh=mesh, value=BOX_T0)
    fc = np.asarray(mesh.faceCenters).T
    hot = mesh.exteriorFaces & (fc[:, 0] <= BOX_FACE_TOL)
    temp.constrain(BOX_HOT, where=hot)
    eq = fipy.TransientTerm(coeff=mat.volumetric_heat_capacity) == fipy.DiffusionTerm(coeff=mat.conductivity)
    solver = fipy.LinearCGSolver(tolerance=1e-8)
    for _ in range(int(round(BOX_T_END / dt))):
        eq.solve(var=temp, dt=dt, solver=solver)
    t1 = time.perf_counter()
    return dict(total=t1 - t0, values=np.asarray(temp.value).copy(),
                points=np.asarray(mesh.cellCenters).T, weights=np.asarray(mesh.cellVolumes),
                n=mesh.numberOfCells, info=f"backward Euler Δt {dt:g} s, CG 1e-8")


# ------------------------------------------------------------------- shell day -------------
def shell_benchmark(args):
    from shipthermal.conditions import SurfaceBalance
    from shipthermal.geometry import build_ship_mesh, frigate
    from shipthermal.model import ThermalModel
    from shipthermal.simulation import Simulation
    from shipthermal.units import DAY, HOUR

    t0 = time.perf_counter()
    ship = frigate()
    graph, report = build_ship_mesh(ship, edge_length=args.edge)
    t_mesh = time.perf_counter() - t0
    print(f"frigate: {ship.n_faces if args.edge is None else report['n_surface_faces']} surface "
          f"triangles → {graph.n_cells} shell cells, {graph.n_bfaces} boundary faces "
          f"(ship + graph {t_mesh:.1f} s)")

    # A synthetic clear day at sea: sun as a cosine bell from 06 to 18 h on faces turned to
    # it, sky radiating at 255–265 K, air 288–296 K lagging the sun by 2 h, wind h = 12;
    # inner faces see compartment air at 295 K with h = 3.
    omega = 2 * np.pi / DAY
    bf = graph.bface_normal

    def sun_direction(t):
        elev = np.maximum(np.sin(omega * (t - 6 * HOUR)), 0.0) * np.radians(60)
        az = omega * t
        return np.array([np.cos(elev) * np.cos(az), np.cos(elev) * np.sin(az), np.sin(elev)]), elev

    conds = {}
    for name in graph.patch_names:
        idx = graph.patch_faces(name)
        if name.endswith(":inner"):
            conds[name] = SurfaceBalance(h=3.0, temp_air=295.0)
            continue
        n = bf[idx]

        def absorbed(t, n=n):
            s, elev = sun_direction(t)
            return 0.7 * 900.0 * np.sin(elev) ** 0.3 * np.maximum(n @ s, 0.0) if elev > 0 else 0.0 * n[:, 0]

        conds[name] = SurfaceBalance(
            absorbed_shortwave=absorbed, emissivity=0.9,
            temp_env=lambda t: 260.0 + 5.0 * np.sin(omega * (t - 9 * HOUR)),
            h=12.0, temp_air=lambda t: 292.0 + 4.0 * np.sin(omega * (t - 9 * HOUR)))
    model = ThermalModel(graph, conds, initial_temperature=293.0)
    dt = args.dt
    span = args.hours * HOUR
    steps = int(round(span / dt))
    first = None
    for backend in args.linear_solver.split(","):
        sim = Simulation(model, dt, span, scheme="bdf2", output_interval=HOUR,
                         linear_solver=backend)
        t1 = time.perf_counter()
        if args.profile:
            import cProfile
            import pstats

            prof = cProfile.Profile()
            prof.enable()
            res = sim.run(progress=False)
            prof.disable()
        else:
            res = sim.run(progress=False)
        t2 = time.perf_counter()
        tim = res.timing
        print(f"\n== {args.hours:g} h of the frigate: {graph.n_cells} cells, Δt {dt:.0f} s, {steps} "
              f"BDF2 steps, linear solver {backend} → {res.backend} ==")
        print(f"time loop        {t2 - t1:8.1f} s  = {(t2 - t1) / steps * 1e3:.0f} ms/step")
        print(f"   forcing f(t) {tim['forcing']:6.1f} s, boundary balances {tim['boundary']:6.1f} s, "
              f"assembly {tim['assembly']:6.1f} s, linear solves {tim['solve']:6.1f} s, "
              f"preconditioner set-up {tim['setup']:6.2f} s ({tim['preconditioner_builds']} builds)")
        print(f"   Newton iterations/step {tim['newton_iterations'] / steps:.2f}, "
              f"PCG iterations/Newton {tim['linear_iterations'] / max(tim['newton_iterations'], 1):.2f}")
        if first is None:
            first = (backend, t2 - t1, res.final_temperature)
        else:
            print(f"   vs {first[0]}: time ratio {(t2 - t1) / first[1]:.2f}, final temperatures "
                  f"differ by at most {np.max(np.abs(res.final_temperature - first[2])):.1e} K")
    e = res.energy
    print(f"energy: relative imbalance {e.relative_imbalance:.2e} (max step "
          f"{e.max_step_imbalance:.2e}); heat moved {e.gross.sum():.3e} J")
    means = res.part_mean("outer")
    print("outer part means at 00, 06, 12, 18, 24 h [K]:")
    print(means.iloc[::6].round(2).to_string())
    if args.profile:
        print("\ncProfile of the day (top 20 by internal time):")
        pstats.Stats(prof).sort_stats("tottime").print_stats(20)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="what", required=True)
    t = sub.add_parser("tets", help="cube vs scikit-fem and FiPy")
    t.add_argument("--edge", type=float, default=0.0075, help="pytetwild edge length [m]")
    t.add_argument("--cases", default="1,2", help="comma-separated, or 'none'")
    t.add_argument("--no-fipy", action="store_true")
    t.add_argument("--all-backends", action="store_true",
                   help="also our CHOLMOD (and, below 40 k vertices, SuperLU) rows")
    t.add_argument("--cell-centred-edge", type=float, default=None,
                   help="also compare the cell-centred graph on a mesh of this edge [m]")
    b = sub.add_parser("box", help="a suddenly heated steel box vs scikit-fem, OpenFOAM, FiPy")
    b.add_argument("--edge", type=float, default=0.02, help="pytetwild edge length [m]")
    b.add_argument("--ours-dt", default="10,40,100,200", help="our vertex-centred BDF2 steps [s]")
    b.add_argument("--cell-dt", default="10,20,40", help="our cell-centred BDF2 steps [s]")
    b.add_argument("--foam-correctors", default="0,2",
                   help="OpenFOAM nNonOrthogonalCorrectors, one run each")
    b.add_argument("--be", action="store_true", help="also our vertex-centred backward Euler")
    b.add_argument("--no-cells", action="store_true", help="skip the cell-centred graph")
    b.add_argument("--cell-iterated", action="store_true",
                   help="also the cell-centred graph with the correction iterated in every step")
    b.add_argument("--no-fipy", action="store_true")
    s = sub.add_parser("shell", help="one day of the frigate's shells")
    s.add_argument("--edge", type=float, default=None, help="surface edge length [m] (default: the ship's)")
    s.add_argument("--dt", type=float, default=300.0)
    s.add_argument("--hours", type=float, default=24.0, help="simulated span [h]")
    s.add_argument("--linear-solver", default="auto",
                   help="comma-separated backends, each run in turn (e.g. auto,cholmod)")
    s.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    if args.what == "tets":
        tets_benchmark(args)
    elif args.what == "box":
        box_benchmark(args)
    else:
        shell_benchmark(args)


if __name__ == "__main__":
    main()
