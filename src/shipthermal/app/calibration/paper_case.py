"""The paper's case: its reference deck means fitted by two explanations (cloud, deck
absorptivity), what the fitted values mean for Dalian, and the validation's tables of it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...environment.climatology import climate_day
from ...results import atomic_path
from ...units import ZERO_CELSIUS
from ..chain import Simulation
from ..paper import REFERENCE_DECK, crossover_rows
from ..scenario import default_scenario
from .fit import CalibrationResult, calibrate
from .measurements import DEFAULT_SIGMA_K, Unknown
from .model import case_changes


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
    cloud = []
    for s in ("summer", "winter"):
        c0 = climate_day(s).cloud_cover
        cloud.append(Unknown("weather.cloud_cover_offset", -c0, 1.0 - c0, 0.0, s))
    return {"cloud": cloud,
            "absorptivity": [Unknown("ship.solar_absorptivity.deck", *PAINT_ABSORPTIVITY_RANGE)]}


def plausibility(result: CalibrationResult) -> list:
    """Say, for each fitted unknown, what it means for Dalian against the climatology's
    sourced numbers."""
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
                changes = case_changes(unknowns, season, res.extra["x"])
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
