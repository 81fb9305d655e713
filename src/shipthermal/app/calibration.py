"""Calibration of unknown scenario quantities against measured surface temperatures.

Given measured temperatures of a ship (part area means or point values, at local times,
optionally with uncertainties; CSV format in ``docs/CALIBRATION.md``) and a list of unknown
scenario quantities with bounds (dotted scenario keys such as ``weather.cloud_cover_offset``
or ``ship.solar_absorptivity.deck``, optionally scoped to one case as
``summer:weather.cloud_cover_offset``), :func:`calibrate` estimates the unknowns by bounded
least squares (:func:`scipy.optimize.least_squares`, trust-region reflective) on the full
thermal model, and reports

* the values with 95 % intervals and the correlation matrix from the Jacobian at the
  solution (linearised covariance ``(JᵀWJ)⁻¹``, scaled by the residual variance when the
  measurements carry no uncertainty of their own);
* the residuals of the fitted rows and the errors on **held-out** rows (a named split, or
  leave-one-out refits warm-started from the full fit);
* flags: a value on a bound (the data want a value outside the bounds), a parameter the
  data do not determine (tiny singular value of the scaled Jacobian, or an interval wider
  than the bounds), strongly correlated pairs.

Cost: each model evaluation is a full diurnal run. The ship, its shell graph and its ray
tracing (sun-lit fractions and view factors, which depend on the geometry only) are built
once per case and reused by every evaluation; each run starts from the last converged state
of the same case (warm start), and a case is re-run only when one of *its* unknowns changed
(a season-scoped unknown does not re-run the other season). The calibration runs use a
coarse setting, :data:`CALIBRATION_SETTINGS` (4 m mesh, 64 rays, 900 s steps), whose deck
means differ from the 2 m / 300 s default by a few tenths of a kelvin; say ``settings={}``
to calibrate at the scenario's own resolution.

Nothing in the built-in scenarios changes: the fitted values are reported, not stored.
"""

from __future__ import annotations

import json
import math
import re
import time as _time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..diurnal import part_groups
from ..errors import InputError, require
from ..results import atomic_path
from ..units import ZERO_CELSIUS
from .chain import Simulation
from .paper import REFERENCE_DECK, crossover_rows
from .rundir import RunDir, scenario_inputs
from .scenario import default_scenario, load_scenario
from .thermal import run_scenario_thermal

__all__ = ["CALIBRATION_SETTINGS", "DEFAULT_SIGMA_K", "Unknown", "CalibrationResult",
           "read_measurements", "parse_unknown", "calibrate", "paper_calibration"]

#: Scenario changes of every calibration run: coarse mesh, fewer rays, 900 s steps (the
#: deck means move by < 0.05 K against 300 s steps on the same mesh), looser spin-up
#: tolerance (finite-difference steps change the fitted temperatures by ≳ 0.5 K).
CALIBRATION_SETTINGS = {"ship.edge_length": 4.0, "solver.rays_per_face": 64,
                        "solver.samples_per_face": 8, "solver.time_step": 900.0,
                        "solver.spinup_tolerance": 0.02}

#: Measurement uncertainty assumed when the CSV gives none [K]: a calibrated thermocouple or
#: IR radiometer on a painted plate, area-averaged (ASSUMPTION; give ``sigma_K`` per row).
DEFAULT_SIGMA_K = 1.0

#: Finite-difference step of the Jacobian, as a fraction of each unknown's bound range.
DIFF_STEP = 0.04

#: |correlation| above which a pair of unknowns is flagged as hard to separate.
CORRELATION_FLAG = 0.95

#: Relative singular value of the range-scaled Jacobian below which a direction of the
#: unknowns is flagged as not determined by the data.
IDENTIFIABILITY_RTOL = 1e-3

SPLITS = ("fit", "holdout")


# --------------------------------------------------------------------------- inputs -----
@dataclass(frozen=True)
class Unknown:
    """An unknown scenario quantity: dotted ``key`` (optionally ``case:key``), bounds and a
    start value (default: the scenario's own value, clipped into the bounds)."""

    key: str
    lower: float
    upper: float
    start: float | None = None
    case: str | None = None

    @property
    def label(self) -> str:
        return f"{self.case}:{self.key}" if self.case else self.key


def parse_unknown(text: str) -> Unknown:
    """``[case:]key=lower:upper[:start]`` → :class:`Unknown`."""
    fix = "write e.g. weather.cloud_cover_offset=-0.5:0.5 or summer:ship.solar_absorptivity.deck=0.2:0.95:0.7"
    if "=" not in text:
        raise InputError("--unknown", text, "must be KEY=LOWER:UPPER[:START]", fix)
    name, rng = text.split("=", 1)
    case = None
    if ":" in name:
        case, name = name.split(":", 1)
    nums = rng.split(":")
    try:
        vals = [float(v) for v in nums]
    except ValueError:
        raise InputError("--unknown", text, "bounds must be numbers LOWER:UPPER[:START]", fix)
    require(len(vals) in (2, 3), "--unknown", text, "must give LOWER:UPPER or LOWER:UPPER:START", fix)
    require(all(math.isfinite(v) for v in vals) and vals[0] < vals[1], "--unknown", text,
            "needs finite bounds with LOWER < UPPER", fix)
    if len(vals) == 3:
        require(vals[0] <= vals[2] <= vals[1], "--unknown", text, "START must lie within the bounds", fix)
    return Unknown(name.strip(), vals[0], vals[1], vals[2] if len(vals) == 3 else None,
                   case.strip() if case else None)


_CLOCK = re.compile(r"^(\d{1,3}):([0-5]\d)(?::([0-5]\d))?$")


def _hour(value, row) -> float:
    text = str(value).strip()
    allowed = ("must be HH:MM[:SS] local time (minutes and seconds 00-59) or decimal hours "
               "after local midnight of the scenario's day")
    try:
        if ":" in text:
            m = _CLOCK.match(text)
            if m is None:
                raise ValueError(text)
            h = int(m.group(1)) + int(m.group(2)) / 60.0 + int(m.group(3) or 0) / 3600.0
        else:
            h = float(text)
    except ValueError:
        raise InputError(f"measurements row {row}: time", text, allowed) from None
    require(math.isfinite(h) and h >= 0.0, f"measurements row {row}: time", text,
            "must be ≥ 00:00 (hours after local midnight)")
    return h


def read_measurements(path) -> pd.DataFrame:
    """Read a measurement CSV (``docs/CALIBRATION.md``) into a normalised table with
    columns case, hour, target, temperature_K, sigma_K, split."""
    path = Path(path)
    require(path.is_file(), "measurements", str(path), "must be an existing CSV file")
    try:
        df = pd.read_csv(path, comment="#", skipinitialspace=True, dtype=str)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError("measurements", str(path), f"must be a CSV table ({exc})".strip())
    df.columns = [c.strip() for c in df.columns]
    need = {"case", "time", "target"}
    missing = sorted(need - set(df.columns))
    has_t = [c for c in ("temperature_K", "temperature_C") if c in df.columns]
    if missing or not has_t:
        raise InputError("measurements", str(path), "needs columns case, time, target and "
                         "temperature_K (or temperature_C); optional sigma_K, split",
                         f"missing: {', '.join(missing + ([] if has_t else ['temperature_K']))}")
    require(len(df) > 0, "measurements", str(path), "holds no rows")
    rows = []
    for i, r in df.iterrows():
        n = i + 2                               # line number in the file (header = 1)
        col = has_t[0]
        try:
            t = float(r[col])
        except (TypeError, ValueError):
            raise InputError(f"measurements row {n}: {col}", r[col], "must be a number")
        t = t + ZERO_CELSIUS if col == "temperature_C" else t
        require(math.isfinite(t) and 150.0 < t < 500.0, f"measurements row {n}: {col}", r[col],
                "must be a surface temperature between 150 and 500 K",
                "temperature_K is in kelvin, temperature_C in degrees Celsius")
        sigma = DEFAULT_SIGMA_K
        if "sigma_K" in df.columns and isinstance(r["sigma_K"], str) and r["sigma_K"].strip():
            try:
                sigma = float(r["sigma_K"])
            except ValueError:
                raise InputError(f"measurements row {n}: sigma_K", r["sigma_K"], "must be a number")
            require(math.isfinite(sigma) and sigma > 0, f"measurements row {n}: sigma_K",
                    r["sigma_K"], "must be > 0 K")
        split = "fit"
        if "split" in df.columns and isinstance(r["split"], str) and r["split"].strip():
            split = r["split"].strip().lower()
            require(split in SPLITS, f"measurements row {n}: split", r["split"],
                    "must be 'fit' or 'holdout'")
        target = str(r["target"]).strip()
        if target.startswith("point:"):
            try:
                xyz = [float(v) for v in target[6:].replace(";", " ").replace(",", " ").split()]
            except ValueError:
                xyz = []
            require(len(xyz) == 3, f"measurements row {n}: target", target,
                    "a point is 'point:x y z' in ship coordinates [m]")
        rows.append({"case": str(r["case"]).strip(), "hour": _hour(r["time"], n),
                     "target": target, "temperature_K": t, "sigma_K": sigma, "split": split,
                     "line": n})
    out = pd.DataFrame(rows)
    out.attrs["source"] = str(path)
    out.attrs["sigma_given"] = "sigma_K" in df.columns
    return out


# --------------------------------------------------------------------------- model ------
class _Case:
    """One scenario: ship, graph and ray tracing built once; warm-started evaluations."""

    def __init__(self, name, scenario, rows: pd.DataFrame, progress=False):
        self.name = name
        self.scenario = scenario
        self.rows = rows
        self.ship = scenario.ship()
        self.parts = set(part_groups(self.ship.part_names).values())
        self.traced = None
        self.graph = None
        self.state = None
        self.memo: dict = {}
        self.runs = 0
        self.seconds = 0.0
        self.days: list = []
        self.progress = progress
        centres = self.ship.vertices[self.ship.faces].mean(axis=1)
        self.face_of_row = {}
        for idx, r in rows.iterrows():
            tgt = r["target"]
            if tgt.startswith("point:"):
                p = np.array([float(v) for v in tgt[6:].replace(";", " ").replace(",", " ").split()])
                d = np.linalg.norm(centres - p, axis=1)
                k = int(np.argmin(d))
                require(d[k] < 3.0 * float(scenario.ship.edge_length or 4.0), f"measurements line "
                        f"{r['line']}: target", tgt, "must lie on the ship's surface",
                        f"nearest surface face is {d[k]:.1f} m away")
                self.face_of_row[idx] = k
            else:
                require(tgt in self.parts, f"measurements line {r['line']}: target", tgt,
                        f"must be a part of this ship ({', '.join(sorted(self.parts))}) "
                        "or 'point:x y z'")

    def run(self, changes: dict):
        """The full diurnal result with these changes (warm-started, ray tracing reused)."""
        sc = self.scenario.updated(changes) if changes else self.scenario
        return run_scenario_thermal(sc, ship=self.ship, progress=False, traced=self.traced,
                                    graph=self.graph, initial_state=self.state)

    def predict(self, changes: dict) -> np.ndarray:
        key = tuple(sorted((k, round(float(v), 10)) for k, v in changes.items()))
        if key in self.memo:
            return self.memo[key]

        t0 = _time.perf_counter()
        sc = self.scenario.updated(changes) if changes else self.scenario
        res = run_scenario_thermal(sc, ship=self.ship, progress=False, traced=self.traced,
                                   graph=self.graph, initial_state=self.state)
        self.seconds += _time.perf_counter() - t0
        self.runs += 1
        self.days.append(int(res.days))
        if self.traced is None:
            self.traced = getattr(res.forcing, "traced", None)
            self.graph = res.graph
        self.state = res.results.cell_temperature[0]
        hmax = float(res.part_means.index.max())
        out = np.empty(len(self.rows))
        for j, (idx, r) in enumerate(self.rows.iterrows()):
            require(r["hour"] <= hmax + 1e-9, f"measurements line {r['line']}: time",
                    r["hour"], f"must lie within the simulated day(s) (0 … {hmax:g} h)")
            if idx in self.face_of_row:
                out[j] = res.face_temperature_at(r["hour"])[self.face_of_row[idx]]
            else:
                out[j] = res.part_mean_at(r["target"], r["hour"])
        self.memo[key] = out
        return out


#: settings where the larger value is the coarser (the others: the smaller)
_COARSER_IS_LARGER = ("ship.edge_length", "solver.time_step", "solver.spinup_tolerance")


def _coarsest(scenario, tweaks: dict) -> dict:
    """The calibration setting, but never finer than the scenario's own (a scenario that is
    already coarser keeps its values)."""
    out = {}
    for key, value in tweaks.items():
        own = _default_value(scenario, key)
        if own is None:
            out[key] = value
        elif key in _COARSER_IS_LARGER:
            out[key] = max(own, value)
        else:
            out[key] = min(own, value)
        if isinstance(value, int):
            out[key] = int(out[key])
    step = out.get("solver.time_step")
    interval = _default_value(scenario, "time.output_interval")
    if step is not None and interval is not None and abs(interval / step - round(interval / step)) > 1e-9:
        out.pop("solver.time_step")            # must divide the recording interval
    return out


def _default_value(scenario, key: str) -> float | None:
    """The scenario's current value of a dotted key (None when it has no plain number)."""
    if key.startswith("ship.solar_absorptivity."):
        return float(scenario.solar_absorptivity(key.rsplit(".", 1)[1]))
    if key.startswith("ship.longwave_emissivity."):
        return float(scenario.longwave_emissivity(key.rsplit(".", 1)[1]))
    node = scenario.to_dict()
    for p in key.split("."):
        if not isinstance(node, dict) or p not in node:
            return None
        node = node[p]
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        return None
    return float(node)


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
    from scipy import stats
    from scipy.optimize import least_squares

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
    unknowns = [parse_unknown(u) if isinstance(u, str) else u for u in unknowns]
    require(len(unknowns) > 0, "--unknown", None, "give at least one unknown KEY=LOWER:UPPER")
    labels = [u.label for u in unknowns]
    require(len(set(labels)) == len(labels), "--unknown", labels, "each unknown once")
    tweaks = dict(CALIBRATION_SETTINGS if settings is None else settings)
    if sigma_known is None:
        sigma_known = bool(attrs.get("sigma_given", False))

    fit_mask = (meas["split"] == "fit").to_numpy()
    require(fit_mask.any(), "measurements", "split", "needs at least one row with split 'fit'")

    cases = {}
    for name in dict.fromkeys(meas["case"]):
        sc = (scenarios or {}).get(name)
        if sc is None:
            if name in ("summer", "winter"):
                sc = default_scenario(name)
            else:
                p = Path(name)
                p = p if p.is_absolute() else Path(base_dir) / p
                require(p.is_file(), "measurements: case", name, "must be 'summer', 'winter' or "
                        "a scenario TOML file (relative to the CSV)")
                sc = load_scenario(p)
        sc = sc.updated(_coarsest(sc, tweaks)) if tweaks else sc
        cases[name] = _Case(name, sc, meas[meas["case"] == name], progress=False)
    for u in unknowns:
        require(u.case is None or u.case in cases, "--unknown", u.label,
                f"names a case without measurements (cases: {', '.join(cases)})")

    # start values and a check that each key is a number the scenario accepts
    starts, defaults = [], []
    for u in unknowns:
        targets = [cases[u.case]] if u.case else list(cases.values())
        d = _default_value(targets[0].scenario, u.key)
        if d is None:
            raise InputError("--unknown", u.label, "must be a numeric scenario key",
                             "see docs/SCENARIO.md, e.g. weather.wind_speed_offset, "
                             "ship.solar_absorptivity.deck, weather.cloud_cover_offset")
        for c in targets:
            for v in (u.lower, u.upper):
                try:
                    c.scenario.updated({u.key: v})
                except InputError as exc:
                    raise InputError("--unknown", u.label, f"bound {v:g} is not accepted by the "
                                     f"scenario ({exc.field} {exc.allowed})")
        defaults.append(d)
        starts.append(u.start if u.start is not None else min(max(d, u.lower), u.upper))
    lo = np.array([u.lower for u in unknowns])
    hi = np.array([u.upper for u in unknowns])
    span = hi - lo

    def changes_for(case, x):
        return {u.key: float(v) for u, v in zip(unknowns, x) if u.case in (None, case)}

    def predict_all(x):
        out = np.empty(len(meas))
        for name, c in cases.items():
            out[c.rows.index.to_numpy()] = c.predict(changes_for(name, x))
        return out

    meas_t = meas["temperature_K"].to_numpy()
    sig = meas["sigma_K"].to_numpy()

    def fit(mask, u0, nfev):
        def resid(u):
            x = lo + np.clip(u, 0.0, 1.0) * span
            return ((predict_all(x) - meas_t) / sig)[mask]

        return least_squares(resid, u0, bounds=(0.0, 1.0), method="trf", diff_step=DIFF_STEP,
                             x_scale=1.0, xtol=1e-3, ftol=1e-4, max_nfev=nfev)

    u0 = (np.array(starts) - lo) / span
    untuned_x = np.clip(np.array(defaults), lo, hi)
    say(f"calibration: {int(fit_mask.sum())} fitted rows, {len(unknowns)} unknowns, "
        f"{len(cases)} case(s)")
    untuned = predict_all(untuned_x)
    sol = fit(fit_mask, u0, max_nfev)
    u_hat = sol.x
    x_hat = lo + u_hat * span
    model = predict_all(x_hat)
    say(f"calibration: least squares {sol.message} ({sol.nfev} evaluations)")

    # covariance from the Jacobian at the solution (in x units)
    n_fit, p = int(fit_mask.sum()), len(unknowns)
    # Jacobian at the solution by one-sided steps into the interior (the optimiser's own
    # is not reported for unknowns held on a bound)
    r = ((model - meas_t) / sig)[fit_mask]
    jac_u = np.empty((n_fit, p))
    for j in range(p):
        step = DIFF_STEP if u_hat[j] <= 0.5 else -DIFF_STEP
        x_j = x_hat.copy()
        x_j[j] = lo[j] + (u_hat[j] + step) * span[j]
        jac_u[:, j] = (((predict_all(x_j) - meas_t) / sig)[fit_mask] - r) / step
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

    flags = []
    undetermined = set()
    if rank < p:
        for k in range(rank, p):
            comb = " + ".join(f"{vt[k, j]:+.2f}·{labels[j]}" for j in np.argsort(-abs(vt[k]))
                              if abs(vt[k, j]) > 0.2)
            flags.append(f"not identifiable: the measurements do not determine the combination "
                         f"{comb} (relative singular value {rel[k]:.1e}); fix one unknown or add "
                         "measurements at other times or parts")
            undetermined.update(labels[j] for j in range(p) if abs(vt[k, j]) > 0.2)
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
    for a in range(p):
        for b in range(a + 1, p):
            if np.isfinite(corr[a, b]) and abs(corr[a, b]) > CORRELATION_FLAG:
                flags.append(f"correlated {corr[a, b]:+.2f}: {labels[a]} and {labels[b]} "
                             "trade off against each other")

    res = pd.DataFrame({"case": meas["case"], "time": [_clock(h) for h in meas["hour"]],
                        "target": meas["target"], "split": meas["split"],
                        "measured_K": meas_t, "sigma_K": sig, "untuned_K": untuned,
                        "model_K": model, "residual_K": model - meas_t})
    summary = {"n_fit": n_fit, "n_holdout": int((~fit_mask).sum()), "covariance": how,
               "rms_fit_K": float(np.sqrt(np.mean((model - meas_t)[fit_mask] ** 2))),
               "rms_untuned_fit_K": float(np.sqrt(np.mean((untuned - meas_t)[fit_mask] ** 2))),
               "rms_holdout_K": (float(np.sqrt(np.mean((model - meas_t)[~fit_mask] ** 2)))
                                 if (~fit_mask).any() else None),
               "rms_untuned_holdout_K": (float(np.sqrt(np.mean((untuned - meas_t)[~fit_mask] ** 2)))
                                         if (~fit_mask).any() else None),
               "rms_loo_K": None, "rank": rank,
               "optimizer": f"{sol.message.rstrip('.')}; {sol.nfev} evaluations, "
                            f"{sol.njev} Jacobians (2-point, step {DIFF_STEP:g} of the range)",
               "settings": tweaks}
    if holdout == "loo":
        if n_fit - 1 < p:
            flags.append(f"leave-one-out skipped: {n_fit} fitted rows leave fewer than the "
                         f"{p} unknowns")
        else:
            loo = np.full(len(meas), np.nan)
            for i in np.flatnonzero(fit_mask):
                m = fit_mask.copy()
                m[i] = False
                say(f"leave-one-out: refit without line {meas['line'][i]}")
                s_i = fit(m, u_hat, max(4, max_nfev // 2))
                loo[i] = predict_all(lo + s_i.x * span)[i]
            res["loo_K"] = loo
            res["loo_error_K"] = loo - meas_t
            summary["rms_loo_K"] = float(np.sqrt(np.nanmean((loo - meas_t)[fit_mask] ** 2)))
    summary.update(model_runs=sum(c.runs for c in cases.values()),
                   runs_per_case={n: c.runs for n, c in cases.items()},
                   spinup_days_per_run={n: c.days for n, c in cases.items()},
                   seconds=_time.perf_counter() - t_start)
    corr_df = pd.DataFrame(corr, index=labels, columns=labels)
    return CalibrationResult(pd.DataFrame(rows), corr_df, res, flags, summary,
                             extra={"x": x_hat, "cov": cov, "cases": cases})


# --------------------------------------------------------------------------- paper ------
#: Solar absorptivity of ship paints, white to black: the bounds of the paper-case fit and
#: the plausibility range (ASSUMPTION: the usual span of white ≈ 0.2–0.3 to black ≈ 0.95
#: coatings; no source at hand).
PAINT_ABSORPTIVITY_RANGE = (0.2, 0.95)


def paper_measurements() -> pd.DataFrame:
    """The paper's reference deck means as a measurement table: the two noon moments are
    fitted, the two crossover moments (07:00 summer, 08:00 winter) held out."""
    rows = [{"case": s, "hour": h, "target": "deck", "temperature_K": t,
             "sigma_K": DEFAULT_SIGMA_K, "split": "fit" if h == 12.0 else "holdout",
             "line": i + 2} for i, ((s, h), t) in enumerate(REFERENCE_DECK.items())]
    df = pd.DataFrame(rows)
    df.attrs["sigma_given"] = False
    return df


def paper_variants() -> dict:
    """Two explanations of the reference, each with unknowns and bounds:

    * ``cloud`` — the weather: a cloud fraction per season (bounds: the whole 0 … 1 range,
      written as offsets from the climatology's derived mean cloud);
    * ``absorptivity`` — the coating: one deck solar absorptivity for both seasons (bounds
      :data:`PAINT_ABSORPTIVITY_RANGE`).
    """
    # lazy: shipthermal.environment loads pvlib (seconds, measured)
    from ..environment.climatology import climate_day

    cloud = []
    for s in ("summer", "winter"):
        c0 = climate_day(s).cloud_cover
        cloud.append(Unknown("weather.cloud_cover_offset", -c0, 1.0 - c0, 0.0, s))
    return {"cloud": cloud,
            "absorptivity": [Unknown("ship.solar_absorptivity.deck", *PAINT_ABSORPTIVITY_RANGE)]}


def plausibility(result: CalibrationResult) -> list:
    """Say, for each fitted unknown, what it means for Dalian against the climatology's
    sourced numbers."""
    # lazy: shipthermal.environment loads pvlib (seconds, measured)
    from ..environment.climatology import climate_day

    out = []
    for _, r in result.parameters.iterrows():
        case, _, key = r["unknown"].rpartition(":")
        if key == "weather.cloud_cover_offset" and case:
            day = climate_day(case)
            cc = float(np.clip(day.cloud_cover + r["estimate"], 0.0, 1.0))
            sun = (1.0 - cc) * day.day_length
            lo_cc = float(np.clip(day.cloud_cover + r["ci95_low"], 0, 1))
            hi_cc = float(np.clip(day.cloud_cover + r["ci95_high"], 0, 1))
            verdict = ("plausible as a single overcast day, not as the month's mean"
                       if sun < 0.5 * day.sunshine_hours else "plausible for the month")
            out.append(f"{case}: cloud fraction {cc:.2f} (95 % {lo_cc:.2f}–{hi_cc:.2f}; "
                       f"climatology {day.cloud_cover:.2f}) = {sun:.1f} h of sunshine vs the "
                       f"sourced monthly mean {day.sunshine_hours:.1f} h/day: {verdict}")
        elif key.startswith("ship.solar_absorptivity"):
            a0, a1 = PAINT_ABSORPTIVITY_RANGE
            a = r["estimate"]
            verdict = ("a light coating (white to light grey)" if a < 0.45 else
                       "a mid-tone coating" if a < 0.75 else "a dark coating")
            out.append(f"deck solar absorptivity {a:.2f} (95 % {r['ci95_low']:.2f}–"
                       f"{r['ci95_high']:.2f}; scenario default {r['untuned']:.2f}, paints "
                       f"{a0}–{a1}): {verdict}")
        elif key == "weather.wind_speed_offset" and case:
            day = climate_day(case)
            out.append(f"{case}: wind {day.wind_speed + r['estimate']:.1f} m/s (climatology "
                       f"{day.wind_speed:.1f} m/s, an ASSUMPTION)")
        elif key == "weather.temp_air_offset" and case:
            day = climate_day(case)
            out.append(f"{case}: daily maximum air {day.temp_max + r['estimate'] - ZERO_CELSIUS:.1f} "
                       f"degC vs the sourced mean maximum {day.temp_max - ZERO_CELSIUS:.1f} degC")
    return out


def paper_calibration(settings: dict | None = None, log=None, crossovers: bool = False) -> dict:
    """The paper's case: both variants of :func:`paper_variants` fitted to the noon
    reference values; the 07:00 / 08:00 values held out. Returns variant → result (each
    with ``extra['plausibility']``) and ``'table'``, the four moments side by side.

    ``crossovers``: also image each variant's fitted scenarios as ``shipthermal run
    --image`` does (:class:`~shipthermal.app.chain.Simulation`, every
    ``imaging.scr_interval``) and put the crossover moments beside the paper's
    (``'crossovers'``)."""
    meas = paper_measurements()
    scen = {s: default_scenario(s) for s in ("summer", "winter")}
    out = {}
    table = None
    for name, unknowns in paper_variants().items():
        res = calibrate(meas, unknowns, scen, holdout="split", settings=settings, log=log)
        res.extra["plausibility"] = plausibility(res)
        cases = res.extra.pop("cases", {})
        out[name] = res
        if crossovers:
            runs, fitted = {}, {}
            for season, c in cases.items():
                changes = {u.key: float(v) for u, v in zip(unknowns, res.extra["x"])
                           if u.case in (None, season)}
                fitted[season] = c.scenario.updated(changes)
                runs[season] = c.run(changes)
            # the fitted scenarios imaged by the chain of `shipthermal run --image`
            results = {s: Simulation(fitted[s], progress=False).result_from(runs[s])
                       for s in runs}
            rows = pd.DataFrame(crossover_rows(results, log))
            rows.insert(0, "variant", name)
            out["crossovers"] = pd.concat([out.get("crossovers"), rows], ignore_index=True)
        r = res.residuals
        if table is None:
            table = r[["case", "time", "split", "measured_K", "untuned_K"]].rename(
                columns={"measured_K": "reference_K"}).copy()
            table["untuned_diff_K"] = r["untuned_K"] - r["measured_K"]
        table[f"{name}_K"] = r["model_K"]
        table[f"{name}_diff_K"] = r["residual_K"]
    out["table"] = table
    return out


def paper_text(paper: dict) -> str:
    """The paper's case as text: the moments table, then each variant's fit."""
    lines = ["Paper case: deck means fitted at the two noon moments, 07:00 summer and 08:00 "
             "winter held out", "(untuned = the built-in Dalian design days; each variant "
             "explains the reference by one kind of condition)", "",
             paper["table"].to_string(index=False, float_format=lambda x: f"{x:.2f}")]
    for name, res in paper.items():
        if not isinstance(res, CalibrationResult):
            continue
        s = res.summary
        lines += ["", f"--- variant '{name}' ---", res.parameters[
            ["unknown", "untuned", "estimate", "std", "ci95_low", "ci95_high", "on_bound"]]
            .to_string(index=False, float_format=lambda x: f"{x:.3f}"),
            f"held-out RMS error {s['rms_holdout_K']:.2f} K (untuned {s['rms_untuned_holdout_K']:.2f} K); "
            f"fitted RMS {s['rms_fit_K']:.2f} K; {s['covariance']}"]
        lines += [f"plausibility: {p}" for p in res.extra.get("plausibility", [])]
        lines += [f"FLAG: {f}" for f in res.flags]
        lines.append(f"{s['model_runs']} model runs, {s['seconds']:.0f} s")
    if paper.get("crossovers") is not None:
        lines += ["", "Crossover moments with each variant's fitted conditions vs the paper", "",
                  paper["crossovers"].to_string(index=False)]
    return "\n".join(lines)


# --------------------------------------------------------------------------- command ----
def _measurement_inputs(path, meas: pd.DataFrame) -> list:
    """The files a calibration reads: the measurement CSV, the scenario files its cases
    name (relative to the CSV) and the files those scenarios name."""
    out = [str(path)]
    base = Path(path).parent
    for name in dict.fromkeys(meas["case"]):
        if name in ("summer", "winter"):
            continue
        p = Path(name) if Path(name).is_absolute() else base / name
        if p.is_file():
            out.append(str(p))
            try:
                out += scenario_inputs(load_scenario(p))
            except InputError:        # reported with its own message by the fit
                pass
    return out


def run_calibrate_command(args, con) -> int:
    """``shipthermal calibrate``: inputs checked first; products written only when the fit
    has finished (a user error leaves no folder behind)."""
    settings = {} if args.full else None
    if args.paper:
        require(not args.measurements and not args.unknown, "--paper", True,
                "takes no measurement file or --unknown (it fits the paper's reference values)")
        meas = unknowns = None
    else:
        require(bool(args.measurements), "measurements", None, "give a measurement CSV "
                "(docs/CALIBRATION.md) or --paper")
        meas = read_measurements(args.measurements)
        unknowns = [parse_unknown(u) for u in args.unknown]
        require(len(unknowns) > 0, "--unknown", None, "give at least one unknown "
                "[CASE:]KEY=LOWER:UPPER", "e.g. --unknown weather.cloud_cover_offset=-0.5:0.5")
    inputs = [] if args.paper else _measurement_inputs(args.measurements, meas)
    RunDir.check_target(Path(args.out), force=args.force, kind="calibrate", inputs=inputs)
    with RunDir(Path(args.out), force=args.force, command=args.argv, kind="calibrate",
                inputs=inputs) as run:
        with run.stage("calibration") as tmp:
            if args.paper:
                paper = paper_calibration(settings=settings, log=con.info,
                                          crossovers=args.crossovers)
                for name, res in paper.items():
                    if isinstance(res, CalibrationResult):
                        res.write(tmp / name)
                if paper.get("crossovers") is not None:
                    with atomic_path(tmp / "paper_crossovers.csv") as t:
                        paper["crossovers"].to_csv(t, index=False)
                with atomic_path(tmp / "paper_case.csv") as t:
                    paper["table"].to_csv(t, index=False, float_format="%.4f")
                text = paper_text(paper)
                with atomic_path(tmp / "paper_case.txt") as t:
                    t.write_text(text + "\n")
            else:
                res = calibrate(meas, unknowns, holdout=args.holdout, settings=settings,
                                log=con.info)
                res.write(tmp)
                text = res.text()
    con.out(text)
    return 0


# --------------------------------------------------------------------------- validate ---
def _variant_table(paper: dict) -> pd.DataFrame:
    rows = []
    for name, res in paper.items():
        if not isinstance(res, CalibrationResult):
            continue
        for _, r in res.parameters.iterrows():
            rows.append({"variant": name, **r.to_dict(),
                         "heldout_rms_K": res.summary["rms_holdout_K"],
                         "untuned_heldout_rms_K": res.summary["rms_untuned_holdout_K"],
                         "flags": " | ".join(res.flags)})
    return pd.DataFrame(rows)


def validation_text(calibration: dict) -> str:
    """The calibrated paper case and the anchor, for the validation printout."""
    lines = [paper_text({k: v for k, v in calibration.items() if k != "anchor"})]
    anchor = calibration.get("anchor")
    if anchor is not None and len(anchor):
        cols = ["surface", "time", "faces", "air_K", "irradiance_W_m2", "sol_air_K", "model_K",
                "model_minus_sol_air_K", "expected_low_K", "expected_high_K"]
        lines += ["", "Independent anchor: ASHRAE sol-air temperature (dark surface, "
                  "h_o = 17 W m-2 K-1) vs the model, clear-sky summer design day; expected: "
                  "below sol-air by the loss to the compartment (inside film 2.5-8 W m-2 K-1)",
                  "", anchor[cols].to_string(index=False, float_format=lambda x: f"{x:.1f}")]
    return "\n".join(lines)


def write_validation_tables(calibration: dict, out_dir) -> dict:
    """``validation_calibrated.csv`` (the four moments: reference, untuned, each variant),
    ``validation_calibrated_parameters.csv`` and ``validation_anchor.csv`` (the report
    shows every CSV of the validation folder)."""
    out = Path(out_dir)
    tables = {"validation_calibrated": calibration.get("table"),
              "validation_calibrated_parameters": _variant_table(calibration),
              "validation_anchor": calibration.get("anchor"),
              "validation_calibrated_crossovers": calibration.get("crossovers")}
    paths = {}
    for name, df in tables.items():
        if df is None:
            continue
        with atomic_path(out / f"{name}.csv") as tmp:
            df.to_csv(tmp, index=False, float_format="%.4f")
        paths[name] = out / f"{name}.csv"
    return paths
