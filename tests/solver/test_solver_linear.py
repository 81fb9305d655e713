"""Linear-algebra kernels of the solver against scipy/LAPACK."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.linalg import cho_solve_banded, cholesky_banded

from shipthermal._tridiagonal import tridiagonal_factor, tridiagonal_solve
from shipthermal.linear import has_cholmod, make_preconditioner


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


@pytest.mark.skipif(not has_cholmod(), reason="kvxopt (CHOLMOD) not installed")
def test_cholmod_backend_solves_spd_system():
    diag, sup = _columns(400, seed=5)
    a = (sp.diags([sup, diag, sup], [-1, 0, 1]) + sp.eye(400)).tocsr()
    rhs = np.random.default_rng(6).normal(size=400)
    x = make_preconditioner(a, "cholmod").apply(rhs)
    assert np.max(np.abs(a @ x - rhs)) < 1e-12 * np.abs(rhs).max()
