"""The fit: bounded least squares of the unknowns on the model, their covariance, flags and
held-out errors (:func:`calibrate`), and its tables (:class:`CalibrationResult`)."""

from __future__ import annotations

import json
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

from ...errors import require
from ...results import atomic_path
from .measurements import DEFAULT_SIGMA_K, parse_unknown, read_measurements
from .model import CALIBRATION_SETTINGS, build_cases, predict_rows, start_values


#: Finite-difference step of the Jacobian, as a fraction of each unknown's bound range.
DIFF_STEP = 0.04

#: |correlation| above which a pair of unknowns is flagged as hard to separate.
CORRELATION_FLAG = 0.95

#: Relative singular value of the range-scaled Jacobian below which a direction of the
#: unknowns is flagged as not determined by the data.
IDENTIFIABILITY_RTOL = 1e-3


# --------------------------------------------------------------------------- result -----
@dataclass
class CalibrationResult:
    """Tables of :func:`calibrate` (temperatures in K)."""

    parameters: pd.DataFrame
    correlation: pd.DataFrame
    residuals: pd.DataFrame
    flags: list
    summary: dict
    extra: dict = field(default_factory=dict)

    def text(self) -> str:
        fmt = lambda x: f"{x:.3f}"   # noqa: E731
        s = self.summary
        lines = [f"Calibration: {s['n_fit']} fitted and {s['n_holdout']} held-out measurements, "
                 f"{len(self.parameters)} unknowns ({s['covariance']})", "",
                 self.parameters.to_string(index=False, float_format=fmt), ""]
        if len(self.correlation) > 1:
            lines += ["Correlation of the estimates", "",
                      self.correlation.to_string(float_format=lambda x: f"{x:+.2f}"), ""]
        cols = [c for c in ("case", "time", "target", "split", "measured_K", "untuned_K",
                            "model_K", "residual_K", "loo_K", "loo_error_K")
                if c in self.residuals.columns]
        lines += ["Residuals (model - measured)", "",
                  self.residuals[cols].to_string(index=False, float_format=lambda x: f"{x:.2f}"), ""]
        lines.append(f"RMS residual, fitted rows: {s['rms_fit_K']:.2f} K")
        if s.get("rms_holdout_K") is not None:
            lines.append(f"RMS error, held-out rows (split): {s['rms_holdout_K']:.2f} K")
        if s.get("rms_loo_K") is not None:
            lines.append(f"RMS error, leave-one-out: {s['rms_loo_K']:.2f} K")
        for f in self.flags:
            lines.append(f"FLAG: {f}")
        if not self.flags:
            lines.append("flags: none (no value on a bound, every unknown determined, no "
                         f"|correlation| > {CORRELATION_FLAG})")
        lines.append(f"{s['model_runs']} model runs ({s['seconds']:.0f} s; settings "
                     f"{s['settings']}); least squares: {s['optimizer']}")
        return "\n".join(lines)

    def write(self, out_dir) -> dict:
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        paths = {}
        for name, df, idx in (("calibration_parameters", self.parameters, False),
                              ("calibration_correlation", self.correlation, True),
                              ("calibration_residuals", self.residuals, False)):
            with atomic_path(out / f"{name}.csv") as tmp:
                df.to_csv(tmp, index=idx, float_format="%.5g")
            paths[name] = out / f"{name}.csv"
        with atomic_path(out / "calibration.txt") as tmp:
            tmp.write_text(self.text() + "\n")
        paths["text"] = out / "calibration.txt"
        with atomic_path(out / "calibration.json") as tmp:
            tmp.write_text(json.dumps({"parameters": self.parameters.to_dict(orient="records"),
                                       "correlation": self.correlation.to_dict(),
                                       "residuals": self.residuals.to_dict(orient="records"),
                                       "flags": self.flags, "summary": self.summary},
                                      indent=2, default=str))
        paths["json"] = out / "calibration.json"
        return paths


def _clock(h: float) -> str:
    m = int(round(h * 60))
    return f"{m // 60:02d}:{m % 60:02d}"


# --------------------------------------------------------------------------- fit --------
@dataclass(frozen=True)
class Problem:
    """The weighted least-squares problem of a calibration: ``predict(x)`` gives the model
    temperature of every measurement row for the unknowns ``x``, which are fitted in the
    unit box ``x = lo + u * span`` (:meth:`fit`)."""

    predict: Callable
    measured: np.ndarray
    sigma: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    @property
    def span(self) -> np.ndarray:
        return self.hi - self.lo

    def fit(self, mask, u0, nfev):
        """Least squares (trust-region reflective) of the ``mask`` rows from ``u0``."""
        # lazy: scipy.optimize takes half a second to import (measured)
        from scipy.optimize import least_squares

        lo, span, meas_t, sig = self.lo, self.span, self.measured, self.sigma

        def resid(u):
            x = lo + np.clip(u, 0.0, 1.0) * span
            return ((self.predict(x) - meas_t) / sig)[mask]

        return least_squares(resid, u0, bounds=(0.0, 1.0), method="trf", diff_step=DIFF_STEP,
                             x_scale=1.0, xtol=1e-3, ftol=1e-4, max_nfev=nfev)


def calibrate(measurements, unknowns, scenarios: dict | None = None, *, holdout: str = "split",
              settings: dict | None = None, sigma_known: bool | None = None,
              max_nfev: int = 20, log=None, base_dir=None) -> CalibrationResult:
    """Estimate unknown scenario quantities from measured temperatures.

    Parameters
    ----------
    measurements : DataFrame or path
        :func:`read_measurements` table (or its CSV).
    unknowns : list of Unknown or str
        ``[case:]key=lower:upper[:start]``.
    scenarios : dict case → Scenario, optional
        Scenarios of the cases; a case not given is loaded by name ('summer', 'winter') or as
        a scenario TOML path (relative to ``base_dir``, default the CSV's folder).
    holdout : str
        ``'split'`` — fit the ``fit`` rows, report errors on the ``holdout`` rows;
        ``'loo'`` — also refit without each fitted row in turn (warm-started from the full
        fit) and report its prediction error; ``'none'``.
    settings : dict, optional
        Scenario changes of every run (default :data:`CALIBRATION_SETTINGS`).
    sigma_known : bool, optional
        Whether the ``sigma_K`` are true standard uncertainties (covariance unscaled). Default:
        True when the CSV had a ``sigma_K`` column, else the covariance is scaled by the
        residual variance (needs more fitted rows than unknowns).
    max_nfev : int
        Most least-squares iterations (function evaluations, Jacobians excluded).
    """
    say = log or (lambda m: None)
    t_start = _time.perf_counter()
    if not isinstance(measurements, pd.DataFrame):
        measurements = read_measurements(measurements)
    attrs = dict(measurements.attrs)
    meas = measurements.reset_index(drop=True)
    if base_dir is None:
        src = attrs.get("source")
        base_dir = Path(src).parent if src else Path.cwd()
    require(holdout in ("split", "loo", "none"), "--holdout", holdout, "must be split, loo or none")
    unknowns = checked_unknowns(unknowns)
    tweaks = dict(CALIBRATION_SETTINGS if settings is None else settings)
    if sigma_known is None:
        sigma_known = bool(attrs.get("sigma_given", False))
    fit_mask = (meas["split"] == "fit").to_numpy()
    require(fit_mask.any(), "measurements", "split", "needs at least one row with split 'fit'")
    cases = build_cases(meas, unknowns, scenarios, tweaks, base_dir)
    starts, defaults = start_values(unknowns, cases)
    problem = Problem(lambda x: predict_rows(cases, unknowns, x, len(meas)),
                      meas["temperature_K"].to_numpy(), meas["sigma_K"].to_numpy(),
                      np.array([u.lower for u in unknowns]), np.array([u.upper for u in unknowns]))
    say(f"calibration: {int(fit_mask.sum())} fitted rows, {len(unknowns)} unknowns, "
        f"{len(cases)} case(s)")
    result = fit_unknowns(problem, meas, unknowns, starts, defaults, fit_mask, holdout=holdout,
                          sigma_known=sigma_known, max_nfev=max_nfev, settings=tweaks, log=say)
    result.summary.update(model_runs=sum(c.runs for c in cases.values()),
                          runs_per_case={n: c.runs for n, c in cases.items()},
                          spinup_days_per_run={n: c.days for n, c in cases.items()},
                          seconds=_time.perf_counter() - t_start)
    result.extra["cases"] = cases
    return result


def checked_unknowns(unknowns) -> list:
    """The unknowns as :class:`Unknown` (parsed from ``[case:]key=lower:upper[:start]``
    text), at least one, each once."""
    unknowns = [parse_unknown(u) if isinstance(u, str) else u for u in unknowns]
    require(len(unknowns) > 0, "--unknown", None, "give at least one unknown KEY=LOWER:UPPER")
    labels = [u.label for u in unknowns]
    require(len(set(labels)) == len(labels), "--unknown", labels, "each unknown once")
    return unknowns


def fit_unknowns(problem: Problem, meas: pd.DataFrame, unknowns: list, starts, defaults,
                 fit_mask: np.ndarray, *, holdout: str = "split", sigma_known: bool = False,
                 max_nfev: int = 20, settings: dict | None = None,
                 log=None) -> CalibrationResult:
    """The statistics of a calibration on any model: the fit from ``starts``, the
    temperatures with the ``defaults`` (untuned), the covariance and intervals, the flags,
    the residuals and the held-out errors (``holdout`` as in :func:`calibrate`)."""
    say = log or (lambda m: None)
    lo, span = problem.lo, problem.span
    u0 = (np.array(starts) - lo) / span
    untuned_x = np.clip(np.array(defaults), lo, problem.hi)
    untuned = problem.predict(untuned_x)
    sol = problem.fit(fit_mask, u0, max_nfev)
    u_hat = sol.x
    x_hat = lo + u_hat * span
    model = problem.predict(x_hat)
    say(f"calibration: least squares {sol.message} ({sol.nfev} evaluations)")
    unc = _uncertainty(problem, u_hat, x_hat, model, fit_mask, sigma_known)
    labels = [u.label for u in unknowns]
    flags = _identifiability_flags(unc, labels)
    rows = _parameter_rows(unknowns, defaults, sol, x_hat, unc, span, flags)
    flags += _correlation_flags(unc["corr"], labels)
    res, summary = _residuals(meas, problem, untuned, model, fit_mask, unc, sol, settings)
    if holdout == "loo":
        _leave_one_out(problem, meas, fit_mask, u_hat, max_nfev, res, summary, flags, say)
    corr_df = pd.DataFrame(unc["corr"], index=labels, columns=labels)
    return CalibrationResult(pd.DataFrame(rows), corr_df, res, flags, summary,
                             extra={"x": x_hat, "cov": unc["cov"]})


def _uncertainty(problem: Problem, u_hat, x_hat, model, fit_mask, sigma_known: bool) -> dict:
    """Covariance, standard deviations, correlations and the rank of the unknowns from the
    Jacobian at the solution (in x units), and the quantile of their 95 % intervals."""
    # lazy: scipy.stats takes over a second to import (measured)
    from scipy import stats

    lo, span, meas_t, sig = problem.lo, problem.span, problem.measured, problem.sigma
    n_fit, p = int(fit_mask.sum()), len(u_hat)
    # Jacobian at the solution by one-sided steps into the interior (the optimiser's own
    # is not reported for unknowns held on a bound)
    r = ((model - meas_t) / sig)[fit_mask]
    jac_u = np.empty((n_fit, p))
    for j in range(p):
        step = DIFF_STEP if u_hat[j] <= 0.5 else -DIFF_STEP
        x_j = x_hat.copy()
        x_j[j] = lo[j] + (u_hat[j] + step) * span[j]
        jac_u[:, j] = (((problem.predict(x_j) - meas_t) / sig)[fit_mask] - r) / step
    jac = jac_u / span                             # d(residual/sigma)/dx
    dof = n_fit - p
    _, sv, vt = np.linalg.svd(jac_u, full_matrices=False)     # range-scaled Jacobian
    rel = sv / sv[0] if sv.size and sv[0] > 0 else np.zeros_like(sv)
    rank = int(np.sum(rel > IDENTIFIABILITY_RTOL))
    cov = np.linalg.pinv(jac.T @ jac, rcond=IDENTIFIABILITY_RTOL ** 2)
    if sigma_known:
        scale, quant, how = 1.0, stats.norm.ppf(0.975), "covariance from the given uncertainties"
    elif dof > 0:
        scale = float(r @ r / dof)
        quant = stats.t.ppf(0.975, dof)
        how = f"covariance scaled by the residual variance, {dof} degrees of freedom"
    else:
        scale, quant = 1.0, stats.norm.ppf(0.975)
        how = (f"no spare measurement to estimate the scatter; intervals assume σ = "
               f"{DEFAULT_SIGMA_K} K per row")
    cov = cov * scale
    std = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(std, std)
    corr = np.where(np.isfinite(corr), corr, np.nan)
    return {"n_fit": n_fit, "p": p, "rel": rel, "vt": vt, "rank": rank, "cov": cov,
            "std": std, "corr": corr, "quant": quant, "how": how}


def _identifiability_flags(unc: dict, labels: list) -> list:
    """A flag per direction of the unknowns that the measurements do not determine."""
    flags = []
    rank, p, vt, rel = unc["rank"], unc["p"], unc["vt"], unc["rel"]
    if rank < p:
        for k in range(rank, p):
            comb = " + ".join(f"{vt[k, j]:+.2f}·{labels[j]}" for j in np.argsort(-abs(vt[k]))
                              if abs(vt[k, j]) > 0.2)
            flags.append(f"not identifiable: the measurements do not determine the combination "
                         f"{comb} (relative singular value {rel[k]:.1e}); fix one unknown or add "
                         "measurements at other times or parts")
    return flags


def _undetermined(unc: dict, labels: list) -> set:
    """The unknowns taking part in a direction that the measurements do not determine."""
    out = set()
    rank, p, vt = unc["rank"], unc["p"], unc["vt"]
    if rank < p:
        for k in range(rank, p):
            out.update(labels[j] for j in range(p) if abs(vt[k, j]) > 0.2)
    return out


def _parameter_rows(unknowns, defaults, sol, x_hat, unc: dict, span, flags: list) -> list:
    """One row per unknown (estimate, standard deviation, 95 % interval, bound held); a
    value on a bound and an interval wider than the bounds are added to ``flags``."""
    undetermined = _undetermined(unc, [u.label for u in unknowns])
    u_hat, quant, std = sol.x, unc["quant"], unc["std"]
    rows = []
    for j, u in enumerate(unknowns):
        half = quant * std[j]
        on = None
        if u_hat[j] <= 1e-3 or sol.active_mask[j] < 0:
            on = "lower"
        elif u_hat[j] >= 1 - 1e-3 or sol.active_mask[j] > 0:
            on = "upper"
        if on:
            flags.append(f"{u.label} = {x_hat[j]:.4g} sits on its {on} bound: the data want a "
                         "value beyond it (the interval is not meaningful)")
        if u.label not in undetermined and 2 * half > span[j]:
            flags.append(f"poorly determined: {u.label}'s 95 % interval ±{half:.3g} is wider "
                         f"than its bounds ({u.lower:g} … {u.upper:g})")
        rows.append({"unknown": u.label, "untuned": defaults[j], "estimate": x_hat[j],
                     "std": std[j], "ci95_low": x_hat[j] - half, "ci95_high": x_hat[j] + half,
                     "lower_bound": u.lower, "upper_bound": u.upper, "on_bound": on or ""})
    return rows


def _correlation_flags(corr, labels: list) -> list:
    """A flag per pair of unknowns correlated beyond :data:`CORRELATION_FLAG`."""
    flags = []
    p = len(labels)
    for a in range(p):
        for b in range(a + 1, p):
            if np.isfinite(corr[a, b]) and abs(corr[a, b]) > CORRELATION_FLAG:
                flags.append(f"correlated {corr[a, b]:+.2f}: {labels[a]} and {labels[b]} "
                             "trade off against each other")
    return flags


def _residuals(meas, problem: Problem, untuned, model, fit_mask, unc: dict, sol,
               settings) -> tuple:
    """The residual table of every row and the summary of the fit (RMS errors of the
    fitted and held-out rows, with the untuned ones)."""
    meas_t, sig = problem.measured, problem.sigma
    res = pd.DataFrame({"case": meas["case"], "time": [_clock(h) for h in meas["hour"]],
                        "target": meas["target"], "split": meas["split"],
                        "measured_K": meas_t, "sigma_K": sig, "untuned_K": untuned,
                        "model_K": model, "residual_K": model - meas_t})
    summary = {"n_fit": unc["n_fit"], "n_holdout": int((~fit_mask).sum()),
               "covariance": unc["how"],
               "rms_fit_K": float(np.sqrt(np.mean((model - meas_t)[fit_mask] ** 2))),
               "rms_untuned_fit_K": float(np.sqrt(np.mean((untuned - meas_t)[fit_mask] ** 2))),
               "rms_holdout_K": (float(np.sqrt(np.mean((model - meas_t)[~fit_mask] ** 2)))
                                 if (~fit_mask).any() else None),
               "rms_untuned_holdout_K": (float(np.sqrt(np.mean((untuned - meas_t)[~fit_mask] ** 2)))
                                         if (~fit_mask).any() else None),
               "rms_loo_K": None, "rank": unc["rank"],
               "optimizer": f"{sol.message.rstrip('.')}; {sol.nfev} evaluations, "
                            f"{sol.njev} Jacobians (2-point, step {DIFF_STEP:g} of the range)",
               "settings": settings}
    return res, summary


def _leave_one_out(problem: Problem, meas, fit_mask, u_hat, max_nfev: int, res, summary: dict,
                   flags: list, say) -> None:
    """Refit without each fitted row in turn (warm-started from the full fit) and add its
    prediction error to ``res`` and ``summary`` (a flag when too few rows are left)."""
    n_fit, p = int(fit_mask.sum()), len(u_hat)
    meas_t = problem.measured
    if n_fit - 1 < p:
        flags.append(f"leave-one-out skipped: {n_fit} fitted rows leave fewer than the "
                     f"{p} unknowns")
        return
    loo = np.full(len(meas), np.nan)
    for i in np.flatnonzero(fit_mask):
        m = fit_mask.copy()
        m[i] = False
        say(f"leave-one-out: refit without line {meas['line'][i]}")
        s_i = problem.fit(m, u_hat, max(4, max_nfev // 2))
        loo[i] = problem.predict(problem.lo + s_i.x * problem.span)[i]
    res["loo_K"] = loo
    res["loo_error_K"] = loo - meas_t
    summary["rms_loo_K"] = float(np.sqrt(np.nanmean((loo - meas_t)[fit_mask] ** 2)))
