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

With ``calendar.years`` the same dates (month and day of ``time.date``, ``weather.days``)
run in every listed year (:func:`year_scenarios`: one scenario per year, its weather from
``calendar.year_sources`` or ``weather.source``); the tables carry a ``year`` column, the
pictures are ``calendar_<band>_<year>.png``, and ``crossover_dates.csv`` gives every
calendar date's crossover times across the years (median and 5-95 %,
:func:`imaging.calendar.crossover_dates_table`).
"""

from __future__ import annotations

import json
import time as _time
from pathlib import Path

import pandas as pd

from imaging.calendar import (crossover_dates_table, crossover_table, image_dense,
                              image_overpasses, monthly_table, plot_calendar)
from imaging.overpass import (listed_overpasses, satellite, satellite_overpasses,
                              tle_overpasses)

from ..atomic import atomic_path, atomic_write_text
from ..errors import InputError
from .pipeline import (build_background, check_imaging_bands, imaging_scenario, load_history,
                       record_span_s, thermal_case)

__all__ = ["calendar_inputs", "calendar_overpasses", "calendar_span_s", "run_calendar",
           "write_calendar", "year_overpasses", "year_scenarios"]


def calendar_overpasses(scenario, end_s: float, *, times_elsewhere: bool = False) -> list:
    """Every overpass of ``[calendar]`` inside ``[start, start + end_s]``; a listed instant
    outside it is refused unless ``times_elsewhere`` (it belongs to another year's
    record)."""
    cal, loc = calendar_inputs(scenario), scenario.location
    start = scenario.start
    t0, t1 = start.tz_convert("UTC"), (start + pd.Timedelta(seconds=end_s)).tz_convert("UTC")
    out = []
    for name in cal["satellites"]:
        out += satellite_overpasses(name, loc.latitude, loc.longitude, t0, t1)
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
        if outside and not times_elsewhere:
            raise InputError("calendar.times", outside[0], f"must lie within the record "
                             f"({t0:%Y-%m-%d %H:%M} … {t1:%Y-%m-%d %H:%M} UTC)",
                             "Drop it, or extend weather.days")
    return sorted(out, key=lambda o: o.time_utc)


def year_overpasses(years) -> dict:
    """``{year: overpasses}`` over the records of :func:`year_scenarios`; refused when the
    named satellites were all launched after the last record and no elements or instants
    are given (the calendar would have no overpass)."""
    several = len(years) > 1
    out = {y: calendar_overpasses(sc, calendar_span_s(sc), times_elsewhere=several)
           for y, sc in years}
    sc = years[-1][1]
    cal = calendar_inputs(sc)
    if several:
        seen = {o.time_utc for found in out.values() for o in found
                if o.source == "listed"}
        for i, t in enumerate(cal["times"]):
            if pd.Timestamp(t).tz_convert("UTC") not in seen:
                raise InputError(f"calendar.times[{i}]", t, "must lie within the record of "
                                 "one of calendar.years (the dates of time.date and "
                                 "weather.days in that year)",
                                 "Drop it, or add its year to calendar.years")
    end = sc.start + pd.Timedelta(seconds=calendar_span_s(sc))
    flying = [n for n in cal["satellites"]
              if pd.Timestamp(satellite(n).launched, tz="UTC") <= end]
    if cal["satellites"] and not flying and cal["tle"] is None and not cal["times"]:
        launched = ", ".join(f"{n} {satellite(n).launched}" for n in cal["satellites"])
        raise InputError("calendar.satellites", list(cal["satellites"]), "none of them flies "
                         f"during the record (which ends {end:%Y-%m-%d}); launched: "
                         f"{launched}",
                         "Give the elements of a satellite flying then (calendar.tle with "
                         "calendar.swath), or list the overpass times (calendar.times)")
    return out


def calendar_inputs(scenario) -> dict:
    """What the calendar receives from a scenario besides the stages it runs: the overpass
    sources and the thresholds of ``[calendar]``."""
    cal = scenario.calendar
    return {"satellites": tuple(cal.satellites), "tle": cal.tle, "swath_m": cal.swath,
            "times": tuple(cal.times), "threshold": cal.threshold,
            "dense_step_s": cal.dense_step, "years": tuple(cal.years),
            "year_sources": tuple(cal.year_sources)}


def year_scenarios(scenario) -> list:
    """``[(year, scenario), ...]``: the scenario itself without ``calendar.years``; with
    them, one scenario per year with the month and day of ``time.date`` in that year, the
    year's weather file (``calendar.year_sources``, else ``weather.source``) and the name
    ``<name>-<year>``. Every year's file is opened and checked over its dates here: a year
    the files do not cover is refused naming it."""
    cal = scenario.calendar
    if not cal.years:
        return [(int(scenario.time.date[:4]), scenario)]
    month_day = scenario.time.date[5:]
    out = []
    for i, year in enumerate(cal.years):
        source = cal.year_sources[i] if cal.year_sources else scenario.weather.source
        date = f"{year}-{month_day}"
        key = f"calendar.year_sources[{i}]" if cal.year_sources else "weather.source"
        try:
            sc = scenario.updated({"time.date": date, "weather.source": source,
                                   "calendar.years": [], "calendar.year_sources": [],
                                   "name": f"{scenario.name}-{year}"})
            sc.check_weather()
        except InputError as exc:
            first = getattr(exc, "errors", [exc])[0]
            raise InputError(f"calendar.years[{i}]", year, f"needs {Path(source).name} "
                             f"({key}) over {date} and weather.days after it: "
                             f"{first.field} = {first.value!r}: {first.allowed}",
                             "Drop the year, or give a file that covers its dates "
                             "(calendar.year_sources)") from None
        out.append((year, sc))
    return out


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
    """The calendar of a scenario into ``run`` (a RunDir): for each year of
    :func:`year_scenarios` the thermal stage, background, overpass and dense imaging; then
    the tables and pictures (``overpasses``: :func:`year_overpasses` found before, or found
    here).
    Returns the summary."""
    say = log or (lambda m: None)
    years = year_scenarios(scenario)
    if overpasses is None:
        overpasses = year_overpasses(years)
    results, times = [], {"overpass": 0.0, "dense": 0.0}
    thermal = {}
    for year, sc in years:
        end_s = calendar_span_s(sc)
        found = overpasses[year]
        say(f"calendar {year}: {len(found)} overpasses in {end_s / 86400:.0f} days "
            f"({', '.join(sorted({o.satellite for o in found})) or 'none'})")
        res = _calendar_year(sc, run, found, end_s, progress, say, ship)
        times["overpass"] += res.pop("seconds_overpass")
        times["dense"] += res.pop("seconds_dense")
        thermal[sc.name] = res.pop("thermal")
        results.append((year, sc, res))
    with run.stage("calendar") as tmp:
        files = write_calendar(tmp, scenario, results)
    n = sum(len(r["found"]) for _, _, r in results)
    out = {"overpasses": n, "years": [y for y, _ in years],
           "frames_overpass": int(sum(len(r["overpass_df"]) for _, _, r in results)),
           "seconds_overpass_imaging": round(times["overpass"], 2),
           "seconds_dense_imaging": round(times["dense"], 2), "files": sorted(files),
           "thermal": thermal}
    run.manifest["settings"]["calendar"] = out
    run.save_manifest()
    return out


def _calendar_year(scenario, run, overpasses, end_s, progress, say, ship) -> dict:
    """One record's thermal stage, background and imaging (module docstring, steps 2-3)."""
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
    t0 = _time.perf_counter()
    if scenario.calendar.dense_step > 0:
        say(f"calendar: every {scenario.calendar.dense_step / 60:g} min of every day")
        dense = image_dense(history, img, end_s, scenario.calendar.dense_step, bands,
                            progress=progress)
    return {"found": overpasses, "overpass_df": op, "dense": dense, "background": background,
            "seconds_overpass": t_op, "seconds_dense": _time.perf_counter() - t0,
            "thermal": {k: summary.get(k) for k in ("days", "converged", "surface_faces")}}


def write_calendar(out_dir, scenario, results) -> dict:
    """The calendar's products in ``out_dir`` (module docstring) from ``results``, a list
    of ``(year, year's scenario, {"overpass_df", "dense", "background", ...})``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cal = scenario.calendar
    several = len(results) > 1
    files = {}
    tables, everies, monthlies, months_ = [], [], [], []
    for year, sc, res in results:
        monthly = monthly_table(res["overpass_df"], cal.threshold)
        every, months = crossover_table(res["dense"], sc.start)
        tables.append(res["overpass_df"].assign(year=year))
        everies.append(every.assign(year=year))
        monthlies.append(monthly)
        months_.append(months)
        res["monthly"] = monthly
    overpass_df = pd.concat(tables, ignore_index=True)
    every = pd.concat(everies, ignore_index=True)
    monthly = pd.concat(monthlies, ignore_index=True)
    months = pd.concat(months_, ignore_index=True)
    background = results[0][2]["background"]
    start = scenario.start

    def csv(name, df):
        path = out / name
        with atomic_path(path) as tmp:
            df.to_csv(tmp, index=False, float_format="%.6g")
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
    if several:
        csv("crossover_dates.csv", crossover_dates_table(every))
    label = getattr(background, "label", "")
    for year, sc, res in results:
        for band in scenario.bands:
            if band in res["dense"]:
                name = f"calendar_{band}_{year}.png" if several else f"calendar_{band}.png"
                plot_calendar(out / name, res["dense"], res["overpass_df"], res["monthly"],
                              sc.start, band, cal.threshold, label=label)
                files[name] = out / name
    summary = {
        "start_local": str(start), "threshold": cal.threshold,
        "satellites": list(cal.satellites), "tle": cal.tle, "listed_times": list(cal.times),
        "background": label,
        "overpasses": int(overpass_df["time_utc"].nunique()) if len(overpass_df) else 0,
        "monthly": monthly.to_dict(orient="records"),
        "crossover_months": months.to_dict(orient="records"),
        "dense_step_s": cal.dense_step, "years": [y for y, _, _ in results],
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
                                    "median/p05/p95 of the local clock time [h]",
            "crossover_dates.csv": "calendar.years only: per calendar date (MM-DD), band and "
                                   "direction: years with a crossover that day, crossovers, "
                                   "median/p05/p95 of the local clock time over the years [h]"}}
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, default=str) + "\n")
    files["summary.json"] = out / "summary.json"
    return files
