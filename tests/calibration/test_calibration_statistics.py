"""The statistics of `calibrate` (`fit_unknowns`) on a model whose answer is known in closed
form: a linear response of each measurement to the unknowns stands in for the thermal model,
so the estimate, its covariance, the leave-one-out errors and the flags can be checked
against ordinary weighted least squares computed independently with numpy (fast: no
thermal run)."""

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.calibration import Problem, fit_unknowns, parse_unknown

KEYS = ("ship.solar_absorptivity.deck", "weather.wind_speed_offset")
DEFAULTS = np.array([0.85, 0.0])


class _Linear:
    """y = c + A x for every row (x = the unknowns in KEYS order)."""

    A = None
    c = None


def _table(n, sigma, split=None):
    return pd.DataFrame({"case": "summer", "hour": np.arange(n, dtype=float) + 6.0,
                         "target": "deck", "temperature_K": 0.0, "sigma_K": sigma,
                         "split": split or ["fit"] * n, "line": np.arange(n) + 2})


def _fit(rows, unknowns, holdout="split"):
    """`fit_unknowns` on the linear model, started as `calibrate` starts (the defaults,
    clipped into the bounds)."""
    unknowns = [parse_unknown(u) for u in unknowns]
    lo = np.array([u.lower for u in unknowns])
    hi = np.array([u.upper for u in unknowns])
    starts = [min(max(d, u.lower), u.upper) for d, u in zip(DEFAULTS, unknowns)]
    problem = Problem(lambda x: _Linear.c + _Linear.A @ x, rows["temperature_K"].to_numpy(),
                      rows["sigma_K"].to_numpy(), lo, hi)
    return fit_unknowns(problem, rows, unknowns, starts, list(DEFAULTS),
                        (rows["split"] == "fit").to_numpy(), holdout=holdout,
                        sigma_known=bool(rows.attrs.get("sigma_given", False)))


@pytest.fixture
def linear():
    rng = np.random.default_rng(3)
    n = 7
    _Linear.A = np.column_stack([rng.uniform(20, 40, n), rng.uniform(-4, -1, n)])
    _Linear.c = rng.uniform(290, 300, n)
    return n, rng


def test_estimate_covariance_and_loo_match_weighted_least_squares(linear):
    n, rng = linear
    sigma = np.full(n, 0.7)
    truth = np.array([0.6, 1.0])
    y = _Linear.c + _Linear.A @ truth + rng.normal(0, 0.7, n)
    rows = _table(n, sigma)
    rows["temperature_K"] = y
    rows.attrs["sigma_given"] = True
    res = _fit(rows, [f"{KEYS[0]}=0.2:0.95", f"{KEYS[1]}=-3:3"], holdout="loo")
    # independent: weighted least squares with numpy
    W = 1.0 / sigma
    X, b = _Linear.A * W[:, None], (y - _Linear.c) * W
    x_ls = np.linalg.lstsq(X, b, rcond=None)[0]
    cov = np.linalg.inv(X.T @ X)
    p = res.parameters
    # within the optimiser's step tolerance (xtol 1e-3 of each bound range)
    assert np.all(np.abs(p["estimate"].to_numpy() - x_ls) <= 2e-3 * np.array([0.75, 6.0])), \
        (p["estimate"].to_numpy(), x_ls)
    np.testing.assert_allclose(p["std"], np.sqrt(np.diag(cov)), rtol=1e-3)
    np.testing.assert_allclose(res.correlation.to_numpy()[0, 1],
                               cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1]), atol=1e-3)
    # leave-one-out of a linear fit: e_i / (1 - h_ii) exactly
    H = X @ cov @ X.T
    e = (X @ x_ls - b) / W
    loo = e / (1.0 - np.diag(H))
    np.testing.assert_allclose(res.residuals["loo_error_K"], loo, atol=0.02)
    # this design's two columns are strongly correlated: flagged exactly when |r| > 0.95
    r_ls = cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1])
    assert [f for f in res.flags if "correlated" in f] == ([res.flags[0]] if abs(r_ls) > 0.95 else [])
    assert not [f for f in res.flags if "correlated" not in f]


def test_unscaled_sigma_uses_residual_variance(linear):
    n, rng = linear
    y = _Linear.c + _Linear.A @ np.array([0.6, 1.0]) + rng.normal(0, 2.0, n)
    rows = _table(n, 1.0)
    rows["temperature_K"] = y
    res = _fit(rows, [f"{KEYS[0]}=0.2:0.95", f"{KEYS[1]}=-3:3"])
    X, b = _Linear.A, y - _Linear.c
    x_ls = np.linalg.lstsq(X, b, rcond=None)[0]
    s2 = np.sum((X @ x_ls - b) ** 2) / (n - 2)
    np.testing.assert_allclose(res.parameters["std"], np.sqrt(np.diag(s2 * np.linalg.inv(X.T @ X))),
                               rtol=1e-3)
    assert "residual variance" in res.summary["covariance"]


def test_flags_bound_and_unidentifiable(linear):
    n, _ = linear
    # both unknowns act only through their sum: not identifiable; truth far outside bounds
    _Linear.A = np.column_stack([np.full(n, 10.0), np.full(n, 10.0)])
    rows = _table(n, 1.0)
    rows["temperature_K"] = _Linear.c + 10.0 * 5.0
    rows.attrs["sigma_given"] = True
    res = _fit(rows, [f"{KEYS[0]}=0.2:0.95", f"{KEYS[1]}=-3:3"])
    text = " ".join(res.flags)
    assert "on its upper bound" in text
    assert "not identifiable" in text or "correlated" in text
