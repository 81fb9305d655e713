"""Linear-algebra kernels of the solver against scipy/LAPACK, and the choice of backend."""

import sys

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import cho_solve_banded, cholesky_banded

from shipthermal._tridiagonal import (column_bounds, column_factor, tridiagonal_factor,
                                      tridiagonal_solve)
from shipthermal import linear
from shipthermal.errors import InputError
from shipthermal.linear import choose_backend, has_cholmod, make_preconditioner, measure_backends


def _columns(n, seed=0):
    """A diagonally dominant SPD tridiagonal matrix cut into plate columns."""
    rng = np.random.default_rng(seed)
    sup = -rng.uniform(0.1, 10.0, n - 1)
    sup[rng.random(n - 1) < 0.3] = 0.0               # column breaks
    diag = np.abs(np.concatenate([sup, [0.0]])) + np.abs(np.concatenate([[0.0], sup]))
    diag += rng.uniform(1e-3, 5.0, n)
    return diag, sup


def test_tridiagonal_ldlt_matches_lapack_banded_cholesky():
    diag, sup = _columns(5000)
    rhs = np.random.default_rng(1).normal(size=5000)
    ab = np.zeros((2, 5000))
    ab[1], ab[0, 1:] = diag, sup
    ref = cho_solve_banded((cholesky_banded(ab), False), rhs)
    x = tridiagonal_solve(tridiagonal_factor(diag, sup), rhs)
    # Both are backward stable on a diagonally dominant matrix: agreement to a few ulps of
    # the solution's scale (condition number ≤ max/min diagonal ratio ~1e4 here).
    np.testing.assert_allclose(x, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    a = sp.diags([sup, diag, sup], [-1, 0, 1])
    assert np.max(np.abs(a @ x - rhs)) < 1e-11 * np.abs(rhs).max()


def test_tridiagonal_rejects_indefinite():
    with pytest.raises(np.linalg.LinAlgError):
        tridiagonal_factor(np.array([1.0, 1.0]), np.array([2.0]))


def test_column_factor_reads_the_bands_from_the_value_array():
    """The factor built from a CSR value array (diagonal and (i, i + 1) positions, column
    cuts dropped) equals the factor of the bands taken with scipy."""
    diag, sup = _columns(200, seed=7)
    lateral = sp.random(200, 200, density=0.02, random_state=8)
    lateral = -(lateral + lateral.T) * 1e-2
    a = (sp.diags([sup, diag, sup], [-1, 0, 1]) + lateral).tocsr()
    a = (a + sp.diags(np.abs(lateral).sum(axis=1).A1)).tocsr()
    a.sort_indices()
    rows = np.repeat(np.arange(200), np.diff(a.indptr))
    keys = rows * 200 + a.indices
    diag_pos = np.searchsorted(keys, np.arange(200) * 201)
    want = np.arange(199) * 201 + 1
    pos = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
    sup_pos = np.where(keys[pos] == want, pos, -1)
    cut = sup == 0.0
    cut[::17] = True                                  # cuts where a coupling is stored too
    got = column_factor(a.data, diag_pos, sup_pos, cut)
    ref = tridiagonal_factor(a.diagonal(), np.where(cut, 0.0, a.diagonal(1)))
    np.testing.assert_array_equal(got[0], ref[0])
    np.testing.assert_array_equal(got[1], ref[1])


def _threads():
    """Thread counts to compare: one and as many as numba may use (at most 2)."""
    import numba

    return sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)})


def _with_threads(n, fn):
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(n)
    try:
        return fn()
    finally:
        numba.set_num_threads(before)


def test_tridiagonal_blocks_equal_one_sweep_bit_for_bit_on_any_threads():
    """Split at column boundaries, factor and solve give the very numbers of one sweep over
    all unknowns, on one thread or two."""
    diag, sup = _columns(20_000, seed=4)
    cut = sup == 0.0
    rhs = np.random.default_rng(5).normal(size=20_000)
    one = tridiagonal_factor(diag, sup)
    x_one = tridiagonal_solve(one, rhs)
    bounds = column_bounds(cut, 16)
    assert len(bounds) == 17 and bounds[0] == 0 and bounds[-1] == 20_000
    assert np.all(cut[bounds[1:-1] - 1])              # every block starts after a cut
    for n in _threads():
        blk = _with_threads(n, lambda: tridiagonal_factor(diag, sup, bounds))
        np.testing.assert_array_equal(blk[0], one[0])
        np.testing.assert_array_equal(blk[1], one[1])
        np.testing.assert_array_equal(_with_threads(n, lambda: tridiagonal_solve(blk, rhs)), x_one)


def test_pcg_kernels_agree_with_plain_numpy_and_do_not_depend_on_threads():
    """The numba PCG (fused product and updates, block-ordered dot products) takes the
    iterations of the plain numpy loop to round-off, and the same iterates, bit for bit,
    on one thread or two."""
    diag, sup = _columns(30_000, seed=6)
    rng = np.random.default_rng(7)
    lateral = sp.coo_matrix((rng.random(180_000), (rng.integers(0, 30_000, 180_000),
                                                     rng.integers(0, 30_000, 180_000))),
                            shape=(30_000, 30_000))
    lateral = -(lateral + lateral.T) * 0.5
    a = (sp.diags([sup, diag, sup], [-1, 0, 1]) + lateral).tocsr()
    a = (a + sp.diags(np.abs(lateral).sum(axis=1).A1)).tocsr()
    prec = make_preconditioner(a, "column", sup == 0.0)
    rhs = np.random.default_rng(8).normal(size=30_000)
    ref, it_ref, rel_ref = linear._pcg_generic(a, rhs, prec.apply, None, 1e-10, 200)
    runs = [_with_threads(n, lambda: linear.pcg(a, rhs, prec.apply, rtol=1e-10)) for n in _threads()]
    x, it, rel = runs[0]
    assert rel <= 1e-10 and abs(it - it_ref) <= 1
    np.testing.assert_allclose(x, ref, rtol=0, atol=1e-9 * np.abs(ref).max())
    assert np.max(np.abs(a @ x - rhs)) <= 1e-9 * np.linalg.norm(rhs)
    for other in runs[1:]:
        np.testing.assert_array_equal(other[0], x)
        assert other[1] == it


def test_column_preconditioner_is_the_tridiagonal_part():
    diag, sup = _columns(300, seed=2)
    lateral = sp.random(300, 300, density=0.01, random_state=3)
    lateral = -(lateral + lateral.T) * 1e-3
    a = sp.diags([sup, diag, sup], [-1, 0, 1]) + lateral
    a = a + sp.diags(np.abs(lateral).sum(axis=1).A1)           # keep it SPD
    brk = sup == 0.0
    prec = make_preconditioner(a.tocsr(), "column", brk)
    tri = sp.diags([np.where(brk, 0.0, a.diagonal(1)), a.diagonal(), np.where(brk, 0.0, a.diagonal(1))],
                   [-1, 0, 1])
    r = np.random.default_rng(4).normal(size=300)
    np.testing.assert_allclose(tri @ prec.apply(r), r, rtol=0, atol=1e-10 * np.abs(r).max())


def _plates(n_cols=4000, cells=3, slivers=0.03, seed=11):
    """Plate columns (stiff through the thickness) coupled sideways to random neighbours, a
    share of them slivers: tiny own stiffness (capacity and boundary) against their sideways
    couplings, like the small triangles at plate edges of a ship mesh. Returns the SPD
    matrix, the column cuts and the sliver columns."""
    rng = np.random.default_rng(seed)
    n = n_cols * cells
    col = np.repeat(np.arange(n_cols), cells)
    sup = np.where(np.arange(n - 1) % cells == cells - 1, 0.0, -rng.uniform(50.0, 100.0, n - 1))
    own = rng.uniform(20.0, 40.0, n_cols)
    sliver = rng.choice(n_cols, int(slivers * n_cols), replace=False)
    own[sliver] = 10.0 ** rng.uniform(-1.0, 1.0, len(sliver))
    # sideways: each column's middle cell to 3 others (nearby numbering, as on a mesh)
    i = np.repeat(np.arange(n_cols), 3)
    j = (i + rng.integers(1, 40, len(i))) % n_cols
    g = rng.uniform(0.1, 0.6, len(i))
    mid = cells // 2
    lat = sp.coo_matrix((-g, (i * cells + mid, j * cells + mid)), shape=(n, n))
    lat = (lat + lat.T).tocsr()
    diag = (np.abs(np.concatenate([sup, [0.0]])) + np.abs(np.concatenate([[0.0], sup]))
            - lat.sum(axis=1).A1)
    diag[np.arange(n_cols) * cells] += own          # capacity and boundary on the surface cell
    a = (sp.diags([sup, diag, sup], [-1, 0, 1]) + lat).tocsr()
    a.sort_indices()
    return a, sup == 0.0, np.sort(sliver)


def test_column_groups_take_the_slivers_and_solve_their_blocks_exactly():
    """Columns whose sideways couplings outweigh their own stiffness are grouped with their
    neighbours (slivers first, at most AGGREGATE_SHARE of the columns starting a group), and
    the preconditioner solves each group's block exactly and the other columns as before."""
    from shipthermal._aggregates import AGGREGATE_SHARE, column_aggregates
    from shipthermal._tridiagonal import ColumnSolve

    a, cut, sliver = _plates()
    groups = column_aggregates(a, cut)
    n_cols = int(cut.sum()) + 1
    assert 0 < groups.n_groups <= AGGREGATE_SHARE * n_cols + 1
    col = np.concatenate([[0], np.cumsum(cut)])
    grouped_cols = np.unique(col[groups.cells])
    assert np.isin(sliver, grouped_cols).mean() > 0.9
    groups.factor(a.data)
    factor = tridiagonal_factor(a.diagonal(), np.where(cut, 0.0, a.diagonal(1)),
                                column_bounds(cut))
    prec = ColumnSolve(factor, groups)
    rng = np.random.default_rng(12)
    r = rng.normal(size=a.shape[0])
    z = prec(r)
    for g in range(0, groups.n_groups, max(1, groups.n_groups // 25)):
        cells = groups.cells[groups.ptr[g]:groups.ptr[g + 1]]
        block = a[cells][:, cells].toarray()
        np.testing.assert_allclose(block @ z[cells], r[cells], rtol=0,
                                   atol=1e-12 * np.abs(r).max())
    alone = np.setdiff1d(np.arange(a.shape[0]), groups.cells)
    np.testing.assert_array_equal(z[alone], tridiagonal_solve(factor, r)[alone])


def test_column_groups_same_answer_on_any_threads():
    from shipthermal._aggregates import column_aggregates
    from shipthermal._tridiagonal import ColumnSolve

    a, cut, _ = _plates(seed=13)
    factor = tridiagonal_factor(a.diagonal(), np.where(cut, 0.0, a.diagonal(1)),
                                column_bounds(cut))
    groups = column_aggregates(a, cut)
    groups.factor(a.data)
    rhs = np.random.default_rng(14).normal(size=a.shape[0])
    x0, _, _ = linear.pcg(a, rhs, ColumnSolve(factor), rtol=1e-10)
    runs = [_with_threads(n, lambda: linear.pcg(a, rhs, ColumnSolve(factor, groups), rtol=1e-10))
            for n in _threads()]
    x, it, rel = runs[0]
    assert rel <= 1e-10
    np.testing.assert_allclose(x, x0, rtol=0, atol=1e-8 * np.abs(x0).max())
    for other in runs[1:]:
        np.testing.assert_array_equal(other[0], x)
        assert other[1] == it


def test_column_groups_cut_the_pcg_iterations_of_a_ship_day(monkeypatch):
    """A patrol boat's day at 3 m: the column groups take 45 % of the PCG iterations off
    (measured 5800 → 3202; frigate at 0.5 m: 5.4 → 3.9 a Newton pass), the answer the same
    to the Newton tolerance (the solver's own 1e-9 K a step, tighter than a diurnal run's;
    measured 3e-9 K over the day)."""
    from shipthermal import _aggregates, simulation
    from shipthermal.diurnal import DiurnalSettings, run_diurnal
    from shipthermal.environment import Environment, climate_day
    from shipthermal.geometry import patrol_boat

    ship = patrol_boat(edge_length=3.0)
    env = Environment.from_climate_day(climate_day("summer"), ship_heading=90.0)
    s = DiurnalSettings(time_step=300.0, output_interval=1800.0, rays_per_face=32,
                        samples_per_face=8, spinup_max_days=1, spinup_tolerance=1.0,
                        newton_tolerance=1e-9, energy_tolerance=1e-12, surface_tolerance=1e-11)
    grouped = run_diurnal(ship, env, s, progress=False)
    monkeypatch.setattr(simulation, "column_aggregates",
                        lambda m, cut: _aggregates.column_aggregates(m, cut, ratio=np.inf))
    alone = run_diurnal(ship, env, s, progress=False, traced=grouped.forcing.traced,
                        graph=grouped.graph)
    it_g = grouped.timings["solver_detail"]["linear_iterations"]
    it_a = alone.timings["solver_detail"]["linear_iterations"]
    d = np.max(np.abs(grouped.results.face_temperature - alone.results.face_temperature))
    print(f"PCG iterations: columns alone {it_a:.0f}, grouped {it_g:.0f}; faces within {d:.1e} K")
    assert it_g < 0.7 * it_a
    assert d < 1e-7
    assert grouped.energy.relative_imbalance <= 1e-11


@pytest.mark.skipif(not has_cholmod(), reason="kvxopt (CHOLMOD) not installed")
def test_cholmod_backend_solves_spd_system():
    diag, sup = _columns(400, seed=5)
    a = (sp.diags([sup, diag, sup], [-1, 0, 1]) + sp.eye(400)).tocsr()
    rhs = np.random.default_rng(6).normal(size=400)
    x = make_preconditioner(a, "cholmod").apply(rhs)
    assert np.max(np.abs(a @ x - rhs)) < 1e-12 * np.abs(rhs).max()


def _laplacian_3d(m):
    """7-point Laplacian of an m³ grid plus a heat-capacity diagonal: SPD, 3-D fill."""
    one = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
    eye = sp.eye(m)
    lap = (sp.kron(sp.kron(one, eye), eye) + sp.kron(sp.kron(eye, one), eye)
           + sp.kron(sp.kron(eye, eye), one))
    return (lap + 0.5 * sp.eye(m**3)).tocsr()


def test_auto_picks_the_least_predicted_cost_and_its_preconditioner_solves():
    a = _laplacian_3d(14)
    best, table, precs = measure_backends(a, ("direct", "amg"))
    assert set(table) == {"direct", "amg"}
    for b, (setup, solve, iterations, cost) in table.items():
        assert cost == pytest.approx(setup + linear.AUTO_SOLVES * solve)
        assert iterations >= 1
    cheapest = min(table, key=lambda b: table[b][3])
    if cheapest == "amg" and table["amg"][3] > linear.AUTO_AMG_MARGIN * table["direct"][3]:
        cheapest = "direct"
    assert best == cheapest
    assert table["direct"][2] == 1          # an exact factor: one PCG iteration
    prec = make_preconditioner(a, "auto")
    assert prec.backend in linear._candidates(a.shape[0]) and "auto →" in prec.note
    rhs = np.random.default_rng(7).normal(size=a.shape[0])
    x, _, rel = linear.pcg(a, rhs, prec.apply, rtol=1e-12)
    assert rel <= 1e-12 and np.max(np.abs(a @ x - rhs)) < 1e-10 * np.abs(rhs).max()
    # The choice is kept for the same pattern: a rebuild (new values) does not measure again.
    again = make_preconditioner((a + sp.eye(a.shape[0])).tocsr(), "auto")
    assert again.backend == prec.backend and again.note == ""


@pytest.fixture
def no_kvxopt(monkeypatch):
    """kvxopt made unimportable, as on an install without the wheel."""
    monkeypatch.setitem(sys.modules, "kvxopt", None)
    monkeypatch.setitem(sys.modules, "kvxopt.cholmod", None)


def test_without_kvxopt_auto_falls_back_to_superlu_or_amg(no_kvxopt):
    assert not has_cholmod()
    with pytest.raises(InputError, match="kvxopt"):
        choose_backend("cholmod", 1000, "tetrahedral")
    a = _laplacian_3d(10)
    assert linear._candidates(a.shape[0]) == ("direct", "amg")
    assert linear._candidates(linear.SUPERLU_MEASURE_LIMIT + 1) == ("amg",)
    prec = make_preconditioner(a, "auto")
    assert prec.backend in ("direct", "amg")
    rhs = np.ones(a.shape[0])
    x, _, rel = linear.pcg(a, rhs, prec.apply, rtol=1e-12)
    assert rel <= 1e-12


@pytest.mark.skipif(not has_cholmod(), reason="kvxopt (CHOLMOD) not installed")
def test_without_kvxopt_a_simulation_gives_the_cholmod_answer(monkeypatch):
    from shipthermal.conditions import Convection
    from shipthermal.mesh import build_dual_tet_graph
    from shipthermal.model import ThermalModel
    from shipthermal.simulation import Simulation
    from solver_meshes import box_tets

    g = box_tets((0.1, 0.1, 0.05), 0.01, builder=build_dual_tet_graph)
    m = ThermalModel(g, {"zmax": Convection(50.0, 280.0)}, initial_temperature=300.0)
    chol = Simulation(m, 60.0, 1200.0, linear_solver="cholmod").run()
    with monkeypatch.context() as mp:
        mp.setitem(sys.modules, "kvxopt", None)
        mp.setitem(sys.modules, "kvxopt.cholmod", None)
        fallback = Simulation(m, 60.0, 1200.0, linear_solver="auto").run()
    assert fallback.backend in ("direct", "amg")
    # Both converge each step to a 1e-9 K correction estimate.
    assert np.max(np.abs(fallback.cell_temperature - chol.cell_temperature)) < 1e-8


@pytest.mark.parametrize("duplicates", [False, True])
def test_jacobian_pattern_refill_equals_the_sparse_sum(duplicates):
    """``B + diag(d) + extras`` of the solver's Jacobian pattern, fresh or refilled in place
    (only the diagonal and the exchange positions rewritten), equals scipy's sum of the
    three; extras on the diagonal and several extras at one position included."""
    from shipthermal.linear import JacobianPattern

    rng = np.random.default_rng(11)
    n = 400
    b = sp.random(n, n, density=0.02, random_state=12)
    b = (b + b.T).tocsr()
    er = rng.integers(0, n, 900)
    ec = rng.integers(0, n, 900)
    er[:20] = ec[:20]                                   # on the diagonal
    if duplicates:
        er[20:60], ec[20:60] = er[60:100], ec[60:100]   # shared positions
    else:
        keep = np.unique(er * n + ec, return_index=True)[1]   # sorted by position
        er, ec = er[keep], ec[keep]
    pat = JacobianPattern(b, er, ec)
    for k in range(3):
        d = rng.normal(size=n)
        e = rng.normal(size=len(er))
        ref = (b + sp.diags(d) + sp.coo_matrix((e, (er, ec)), shape=(n, n))).toarray()
        got = pat.jacobian(d, e, fresh=(k == 0)).toarray()
        np.testing.assert_allclose(got, ref, rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(pat.diagonal(d, e), np.diag(ref), rtol=1e-14, atol=1e-14)
    assert pat._extra_plain is (not duplicates)     # both paths of the fill are covered


def test_gathered_conduction_flows_equal_minus_k_t_and_cancel():
    """The per-cell (threaded) conduction flows equal ``−K T`` of the assembled matrix to
    round-off of the products, and sum to round-off of the face fluxes (each face's flux is
    computed on both sides as exact negatives), on one thread or two."""
    from solver_meshes import box_tets

    from shipthermal.model import conduction_flows

    g = box_tets((0.4, 0.3, 0.2), 0.05)
    temp = 290.0 + 20.0 * np.random.default_rng(3).random(g.n_cells)
    flows = [_with_threads(n, lambda: conduction_flows(g, temp)) for n in _threads()]
    for f in flows[1:]:
        np.testing.assert_array_equal(f, flows[0])
    ref = -(g.conduction_matrix @ temp)
    scale = np.abs(g.conduction_matrix).sum(axis=1).A1 * temp      # |K| |T| per row
    assert np.max(np.abs(flows[0] - ref) / scale) < 1e-14
    face_flux = g.face_conductance * np.abs(temp[g.face_cells[:, 1]] - temp[g.face_cells[:, 0]])
    assert abs(np.sum(flows[0])) < 1e-13 * np.sum(face_flux)


def test_one_pass_reductions_equal_numpy_and_keep_nan():
    from shipthermal.model import _change_and_max
    from shipthermal._step_kernels import max_ratio

    rng = np.random.default_rng(21)
    a, b = rng.normal(size=5000), rng.uniform(0.5, 2.0, 5000)
    assert max_ratio(a, b) == np.max(np.abs(a) / b)
    new, old = 300.0 + rng.normal(size=5000), 300.0 + rng.normal(size=5000)
    assert _change_and_max(new, old) == (np.max(np.abs(new - old)), np.max(new))
    a[1234] = np.nan
    new[17] = np.nan
    assert np.isnan(max_ratio(a, b)) and np.isnan(_change_and_max(new, old)[0])
    assert _change_and_max(np.zeros(0), np.zeros(0)) == (0.0, 0.0)
