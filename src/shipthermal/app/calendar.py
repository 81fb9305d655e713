"""``shipthermal calendar``: the ship's detectability at the overpasses of a weather record.

The steps, each a function of its own:

1. :func:`calendar_overpasses` — the overpasses over the record's span: the named satellites
   of ``[calendar]`` on their reference ground tracks, the user's two-line elements, the
   listed instants (:mod:`imaging.overpass`);
2. the thermal run of the record (:func:`shipthermal.app.pipeline.thermal_case`) and its port
   background, which follows the same record (the physical background);
3. :func:`imaging.calendar.image_overpasses` at every overpass, each from its own direction,
   and :func:`imaging.calendar.image_dense` every ``calendar.dense_step`` of every day;
4. :func:`write_calendar` — ``calendar/``: ``overpasses.csv`` (one row per overpass and
   band), ``monthly.csv`` (fraction under the clutter per month), ``crossovers.csv`` (every
   crossover of the dense series) and ``crossover_months.csv`` (their median and 5-95 %
   range of clock time per month), ``calendar_<band>.png`` (day × local-time SCR with the
   overpasses marked, monthly bars), ``summary.json``.
"""

from __future__ import annotations

import json
import time as _time
from pathlib import Path

import pandas as pd

from imaging.calendar import (crossover_table, image_dense, image_overpasses, monthly_table,
                              plot_calendar)
from imaging.overpass import (listed_overpasses, satellite, satellite_overpasses,
                              tle_overpasses)

from ..errors import InputError
from .pipeline import (build_background, check_imaging_bands, imaging_scenario, load_history,
                       record_span_s, thermal_case)
from .rundir import atomic_write_text

__all__ = ["calendar_inputs", "calendar_overpasses", "calendar_span_s", "run_calendar",
           "write_calendar"]


def calendar_overpasses(scenario, end_s: float) -> list:
    """Every overpass of ``[calendar]`` inside ``[start, start + end_s]``."""
    cal, loc = calendar_inputs(scenario), scenario.location
    start = scenario.start
    t0, t1 = start.tz_convert("UTC"), (start + pd.Timedelta(seconds=end_s)).tz_convert("UTC")
    out = []
    for name in cal["satellites"]:
        out += satellite_overpasses(name, loc.latitude, loc.longitude, t0, t1)
    flying = [n for n in cal["satellites"]
              if pd.Timestamp(satellite(n).launched, tz="UTC") <= t1]
    if cal["satellites"] and not flying and cal["tle"] is None and not cal["times"]:
        launched = ", ".join(f"{n} {satellite(n).launched}" for n in cal["satellites"])
        raise InputError("calendar.satellites", list(cal["satellites"]), "none of them flies "
                         f"during the record ({t0:%Y-%m-%d} … {t1:%Y-%m-%d}); launched: "
                         f"{launched}",
                         "Give the elements of a satellite flying then (calendar.tle with "
                         "calendar.swath), or list the overpass times (calendar.times)")
    if cal["tle"] is not None:
        try:
            text = Path(cal["tle"]).read_text(encoding="utf-8", errors="strict")
        except (OSError, UnicodeDecodeError) as exc:
            raise InputError("calendar.tle", cal["tle"], "must be a readable text file "
                             f"({type(exc).__name__})",
                             "Save the two-line elements as plain text") from None
        out += tle_overpasses(text, loc.latitude, loc.longitude, t0, t1,
                              swath_m=cal["swath_m"], source=Path(cal["tle"]).name)
    if cal["times"]:
        listed = listed_overpasses(cal["times"], scenario.imaging.sensor.view_zenith_deg,
                                   scenario.imaging.sensor.view_azimuth_deg)
        out += [o for o in listed if t0 <= o.time_utc <= t1]
        outside = [str(o.time_utc) for o in listed if not t0 <= o.time_utc <= t1]
        if outside:
            raise InputError("calendar.times", outside[0], f"must lie within the record "
                             f"({t0:%Y-%m-%d %H:%M} … {t1:%Y-%m-%d %H:%M} UTC)",
                             "Drop it, or extend weather.days")
    return sorted(out, key=lambda o: o.time_utc)


def calendar_inputs(scenario) -> dict:
    """What the calendar receives from a scenario besides the stages it runs: the overpass
    sources and the thresholds of ``[calendar]``."""
    cal = scenario.calendar
    return {"satellites": tuple(cal.satellites), "tle": cal.tle, "swath_m": cal.swath,
            "times": tuple(cal.times), "threshold": cal.threshold,
            "dense_step_s": cal.dense_step}


def calendar_span_s(scenario) -> float:
    """The record's span [s]; a periodic day is refused (overpasses fall on real dates)."""
    end_s = record_span_s(scenario)
    if end_s is None:
        raise InputError("weather.day", scenario.weather.day, "must be 'record' for a calendar "
                         "(overpasses fall on real dates of a weather record)",
                         "Set weather.day = 'record' with a weather file covering the days")
    check_imaging_bands(scenario)
    return end_s


def run_calendar(scenario, run, *, progress: bool = True, log=None, ship=None,
                 overpasses=None) -> dict:
    """The calendar of a scenario into ``run`` (a RunDir): thermal stage, background,
    overpass and dense imaging, tables and pictures (``overpasses`` found before, or found
    here). Returns the summary."""
    say = log or (lambda m: None)
    end_s = calendar_span_s(scenario)
    if overpasses is None:
        overpasses = calendar_overpasses(scenario, end_s)
    say(f"calendar: {len(overpasses)} overpasses in {end_s / 86400:.0f} days "
        f"({', '.join(sorted({o.satellite for o in overpasses})) or 'none'})")
    case = scenario.name
    summary = thermal_case(scenario, run, case, progress=progress, log=say, ship=ship)
    history = load_history(run.path / "thermal" / case)
    t0 = _time.perf_counter()
    background = build_background(scenario, progress=progress)
    img = imaging_scenario(scenario, background, history)
    bands = scenario.bands
    say(f"calendar: background ({_time.perf_counter() - t0:.1f} s); imaging the overpasses")
    t0 = _time.perf_counter()
    op = image_overpasses(history, img, overpasses, scenario.start, bands,
                          scenario.calendar.threshold, progress=progress)
    t_op = _time.perf_counter() - t0
    dense = {}
    if scenario.calendar.dense_step > 0:
        say(f"calendar: every {scenario.calendar.dense_step / 60:g} min of every day")
        t0 = _time.perf_counter()
        dense = image_dense(history, img, end_s, scenario.calendar.dense_step, bands,
                            progress=progress)
        t_dense = _time.perf_counter() - t0
    else:
        t_dense = 0.0
    with run.stage("calendar") as tmp:
        files = write_calendar(tmp, scenario, op, dense, background)
    out = {"overpasses": len(overpasses), "frames_overpass": int(len(op)),
           "seconds_overpass_imaging": round(t_op, 2),
           "seconds_dense_imaging": round(t_dense, 2), "files": sorted(files),
           "thermal": {k: summary.get(k) for k in ("days", "converged", "surface_faces")}}
    run.manifest["settings"]["calendar"] = out
    run.save_manifest()
    return out


def write_calendar(out_dir, scenario, overpass_df: pd.DataFrame, dense: dict,
                   background) -> dict:
    """The calendar's products in ``out_dir`` (module docstring)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cal = scenario.calendar
    start = scenario.start
    files = {}
    monthly = monthly_table(overpass_df, cal.threshold)
    every, months = crossover_table(dense, start)

    def csv(name, df):
        path = out / name
        tmp = path.with_name(f".{name}.tmp")
        df.to_csv(tmp, index=False, float_format="%.6g")
        tmp.replace(path)
        files[name] = path

    table = overpass_df.copy()
    if len(table):
        table["time_utc"] = table["time_utc"].astype(str)
    csv("overpasses.csv", table.rename(columns={
        "hours": "hours_after_start_h", "contrast": "contrast_W_m-2_sr-1",
        "std_background": "std_background_W_m-2_sr-1"}))
    csv("monthly.csv", monthly)
    csv("crossovers.csv", every)
    csv("crossover_months.csv", months)
    label = getattr(background, "label", "")
    for band in scenario.bands:
        if band in dense:
            name = f"calendar_{band}.png"
            plot_calendar(out / name, dense, overpass_df, monthly, start, band, cal.threshold,
                          label=label)
            files[name] = out / name
    summary = {
        "start_local": str(start), "threshold": cal.threshold,
        "satellites": list(cal.satellites), "tle": cal.tle, "listed_times": list(cal.times),
        "background": label,
        "overpasses": int(overpass_df["time_utc"].nunique()) if len(overpass_df) else 0,
        "monthly": monthly.to_dict(orient="records"),
        "crossover_months": months.to_dict(orient="records"),
        "dense_step_s": cal.dense_step,
        "columns": {
            "overpasses.csv": "time_utc; date_local/time_local in the scenario's zone; "
                              "hours_after_start_h [h]; satellite; view_zenith_deg, "
                              "view_azimuth_deg (the satellite seen from the site) [deg]; band "
                              "[µm]; scr [-] (eq. 22); contrast_W_m-2_sr-1 (ship minus local "
                              "background, at-aperture); ship_apparent_K, "
                              "background_apparent_K, apparent_contrast_K (brightness "
                              "temperatures of the at-aperture radiance) [K]; "
                              "std_background_W_m-2_sr-1; sun_zenith_deg; daytime; "
                              "under_clutter (scr < threshold)",
            "monthly.csv": "per month and band: overpasses, under_clutter, fraction_under (all, "
                           "day, night), scr_median, apparent_contrast_median_K",
            "crossover_months.csv": "per month, band and direction: crossovers, days, "
                                    "median/p05/p95 of the local clock time [h]"}}
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, default=str) + "\n")
    files["summary.json"] = out / "summary.json"
    return files
