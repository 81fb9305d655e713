"""``shipthermal``: the command line over the Python API, driven by one scenario file.

Subcommands (``shipthermal <command> --help`` for each)::

    demo       the built-in default end to end: summer and winter thermal runs, images in
               3-5 and 8-14 µm, SCR curves, crossover times, report
    mesh       build the ship of a scenario: mesh files, part picture, mesh report
    run        thermal run of a scenario file (checkpointed; --resume continues)
    image      imaging stage on a finished thermal run directory
    calendar   the ship's detectability at every overpass of a weather record
    crossover  print the crossover times of a run directory
    validate   deck temperatures vs the paper's reference, sensitivity table
    calibrate  fit unknown conditions to measured temperatures; held-out errors
    background the port background from real files (Landsat, ROIs[, DEM, met grid])
    sweep      parameter sweep on dask.distributed
    ensemble   weather ensemble: crossover times with a median and a 5-95 % range
    report     (re)write the self-contained HTML report of a run directory
    check      load scenario files and open their inputs; list every problem
    schema     print the scenario schema (docs/SCENARIO.md) as a Markdown table

Exit codes: 0 success; 2 user error (bad scenario, sweep file, option or folder: the
message only, no traceback); 1 internal failure (traceback with ``-v``; a sweep with failed
cases); 130 interrupted (Ctrl-C), 143 terminated (SIGTERM): an interrupted run leaves no
``COMPLETE`` marker and resumes with ``--resume``.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
import time
import traceback
from pathlib import Path

from ..errors import InputError, input_error_from_os
from ..units import strip_units

__all__ = ["main", "build_parser"]

EXIT_OK, EXIT_FAILURE, EXIT_USER, EXIT_INTERRUPTED, EXIT_TERMINATED = 0, 1, 2, 130, 143


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like Ctrl-C (the run directory records 'interrupted')."""


class Console:
    """Where messages go: results to stdout; progress and notes to stderr.

    ``quiet``: no progress bars and no notes (results and errors only); ``verbose``: stage
    details and tracebacks of internal failures.
    """

    def __init__(self, quiet: bool = False, verbose: bool = False):
        self.quiet = quiet
        self.verbose = verbose and not quiet
        self.progress = not quiet

    def info(self, msg: str) -> None:
        if not self.quiet:
            print(msg, file=sys.stderr, flush=True)

    def debug(self, msg: str) -> None:
        if self.verbose:
            print(f"  {msg}", file=sys.stderr, flush=True)

    def out(self, msg: str) -> None:
        print(msg, flush=True)

    def error(self, msg: str) -> None:
        print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------
def _load_scenario(path):
    from .scenario import default_scenario, load_scenario

    if path in ("summer", "winter"):
        return default_scenario(path)
    return load_scenario(path)


def _require_run(path, kinds: tuple = ()) -> Path:
    """A run folder this tool wrote (signed manifest, or one of an earlier version), of one
    of ``kinds`` when given: the only folders ``image``, ``report``, ``crossover`` and
    ``validate --into`` read and amend."""
    from .rundir import MANIFEST, read_signature

    p = Path(path)
    sig = read_signature(p) if p.is_dir() else None
    if sig is None:
        foreign = p.is_dir() and (p / MANIFEST).exists()
        raise InputError("run directory", str(path), "must be a shipthermal run directory "
                         "(with manifest.json)" + ("; this manifest.json was not written by "
                                                   "shipthermal" if foreign else ""),
                         "Give a folder written by `shipthermal run` or `shipthermal demo`")
    if kinds and sig.kind not in kinds:
        raise InputError("run directory", str(path), f"is a shipthermal {sig.kind} folder; "
                         f"this command needs a thermal run ({' or '.join(kinds)})",
                         "Give a folder written by `shipthermal run` or `shipthermal demo`")
    return p


def _require_report_file(path) -> None:
    """``report --output``: a new file, or a report this tool wrote (never another file)."""
    from .report import is_report_file

    p = Path(path)
    if p.is_dir():
        raise InputError("--output", str(path), "must be a file name (a folder of that name "
                         "exists)", "Name the HTML file to write, e.g. report-copy.html")
    if os.path.lexists(p) and not is_report_file(p):
        raise InputError("--output", str(path), "is a file that shipthermal did not write (not "
                         "one of its reports)", "Choose a new file name: shipthermal writes "
                         "over a report it wrote, never over another file")


def _cases_of(run_path: Path) -> dict:
    """case → Scenario of a run directory (from its scenario copies)."""
    import json

    from .scenario import load_scenario

    manifest = json.loads((run_path / "manifest.json").read_text())
    out = {}
    for case, info in (manifest.get("cases") or {}).items():
        f = run_path / info.get("scenario", "")
        if f.is_file():
            out[case] = load_scenario(f)
    if not out:
        raise InputError("run directory", str(run_path), "holds no scenario copy "
                         "(scenario*.toml)", "Was it written by `shipthermal run`?")
    return out


def _report(run, con: Console, finishing: bool = False) -> Path:
    from .report import write_report

    t0 = time.perf_counter()
    run.claim("report.html")
    if finishing and not run.amend:
        run.mark_finished()
    path = write_report(run.path, finishing=finishing)
    run.record("report", time.perf_counter() - t0)
    con.debug(f"report {path} ({time.perf_counter() - t0:.1f} s)")
    return path


def _imaging(run, cases: dict, con: Console, step_s: float | None = None,
             backgrounds: dict | None = None) -> dict:
    """Imaging stage of a run: ``cases = {case: Scenario}`` with finished thermal stages."""
    from .pipeline import image_cases, load_history

    inputs = {c: (sc, load_history(run.path / "thermal" / c))
              for c, sc in cases.items()}
    con.info(f"imaging: {', '.join(cases)} x {', '.join(next(iter(cases.values())).bands)} µm")
    with run.stage("imaging") as tmp:
        res = image_cases(inputs, tmp, progress=con.progress, log=con.info, step_s=step_s,
                          backgrounds=backgrounds)
    if step_s:
        run.manifest["settings"]["imaging_step_s"] = step_s
        run.save_manifest()
    return res


def _print_crossovers(run_path: Path, con: Console, as_csv: bool = False) -> int:
    import pandas as pd

    ens = run_path / "ensemble" / "crossovers.csv"
    if ens.is_file():                           # a weather ensemble: the distribution
        from .ensemble import format_distribution

        df = strip_units(pd.read_csv(ens, dtype={"median": str, "p05": str, "p95": str}))
        con.out(df.to_csv(index=False).rstrip() if as_csv else
                "crossover moments over the weather ensemble (median, 5-95 % range):\n"
                + format_distribution(df))
        return EXIT_OK
    files = sorted((run_path / "imaging").glob("**/crossovers.csv"))
    if not files:
        raise InputError("run directory", str(run_path), "has no imaging results "
                         "(imaging/crossovers.csv)", f"Run `shipthermal image {run_path}` first")
    for f in files:
        raw = pd.read_csv(f)
        df = strip_units(raw)
        rel = f.parent.relative_to(run_path)
        if as_csv:
            con.out(raw.to_csv(index=False).rstrip())
            continue
        con.out(f"thermal crossover moments ({rel}):")
        if len(df):
            cols = ("season", "band", "time_local", "direction")
            if "date_local" in df and (df.groupby("season")["date_local"].nunique() > 1).any():
                # a weather record: its crossovers fall on several dates
                cols = ("season", "band", "date_local", "time_local", "direction")
            units = df.attrs["units"]
            show = df[[c for c in cols if c in df]]
            con.out(show.rename(columns=lambda c: f"{c} [{units[c]}]" if c in units else c)
                    .to_string(index=False))
        else:
            con.out("  none found")
    return EXIT_OK


# ---------------------------------------------------------------------------------------
# subcommands
# ---------------------------------------------------------------------------------------
def cmd_demo(args, con: Console) -> int:
    from .pipeline import QUICK_EDGE_LENGTH, QUICK_SCR_INTERVAL, demo_scenarios, thermal_case
    from .rundir import RunDir, is_complete

    out = Path(args.out)
    RunDir.check_target(out, resume=args.resume, force=args.force, kind="demo")
    if args.resume and is_complete(out):
        con.info(f"{out} is already complete: nothing to resume")
        return EXIT_OK
    scen = demo_scenarios(quick=args.quick, seasons=tuple(args.seasons))
    t0 = time.perf_counter()
    with RunDir(out, resume=args.resume, force=args.force, command=args.argv, kind="demo",
                log=con.info) as run:
        mesh = f"edge {QUICK_EDGE_LENGTH:g} m" if args.quick else "default mesh"
        run.manifest["settings"].update({
            "quick": args.quick, "ship": "frigate (built-in)",
            "edge_length_m": QUICK_EDGE_LENGTH if args.quick else None,
            "imaging_step_s": QUICK_SCR_INTERVAL if args.quick else 600.0,
            "note": "the built-in default scenarios, default_scenario(season), unchanged; "
                    f"--quick changes the ship edge length to {QUICK_EDGE_LENGTH:g} m and "
                    "images every 30 min instead of the scenario's 10 min"})
        for season, sc in scen.items():
            run.add_scenario(sc, case=season)
        for season, sc in scen.items():
            con.info(f"{season}: thermal run ({sc.ship.builtin}, {mesh})")
            s = thermal_case(sc, run, season, resume=args.resume, progress=con.progress,
                             log=con.debug)
            edge = s.get("edge_length_m")
            con.info(f"{season}: {s['surface_faces']} faces"
                     + (f" (edge {edge:.2g} m)" if edge else "") + f", {s['days']} days "
                     f"(converged: {s['converged']}), energy imbalance "
                     f"{s['energy']['relative_imbalance']:.1e}")
        if not args.no_imaging:
            if not (args.resume and run.has("imaging")):
                _imaging(run, scen, con, QUICK_SCR_INTERVAL if args.quick else None)
        report = _report(run, con, finishing=True)
    con.info(f"demo finished in {time.perf_counter() - t0:.0f} s: {out}")
    if not args.no_imaging:
        _print_crossovers(out, con)
    con.out(f"report: {report}")
    return EXIT_OK


def cmd_mesh(args, con: Console) -> int:
    import json

    from ..geometry import build_ship_mesh, render_parts_png, write_ship
    from .rundir import RunDir, scenario_inputs

    sc = _load_scenario(args.scenario)
    changes = {}
    if args.builtin:
        changes["ship.builtin"] = args.builtin
    if args.edge_length is not None:
        changes["ship.edge_length"] = args.edge_length
    if changes:
        sc = sc.updated(changes)
    out = Path(args.out or f"runs/{sc.name}-mesh")
    inputs = scenario_inputs(sc)
    RunDir.check_target(out, force=args.force, kind="mesh", inputs=inputs)
    with RunDir(out, force=args.force, command=args.argv, kind="mesh", inputs=inputs) as run:
        run.add_scenario(sc)
        con.info(f"mesh: building the ship ({sc.ship.builtin or 'user files'})")
        with run.stage("mesh") as tmp:
            t0 = time.perf_counter()
            ship, read_report = sc.ship(return_report=True)
            for line in read_report.get("repairs", []):
                con.info(f"mesh: {line}")
            graph, report = build_ship_mesh(ship)
            files = write_ship(ship, tmp, stem="ship")
            backend = render_parts_png(ship, tmp / "parts.png")
            if "auto_parts" in read_report:
                from ..geometry.cad import CHECK_COLOURS

                auto = read_report.pop("auto_parts")
                import re

                text = json.dumps(auto, indent=1)       # one [start, stop] range per line
                text = re.sub(r"\[\s+(-?[\d.e+-]+),\s+(-?[\d.e+-]+)\s+\]", r"[\1, \2]", text)
                (tmp / "auto_parts.json").write_text(text)
                files["auto_parts"] = tmp / "auto_parts.json"
                for view in ("iso", "side"):
                    render_parts_png(ship, tmp / f"auto_parts_{view}.png", view=view,
                                     colours=CHECK_COLOURS)
                reuse = ("edit auto_parts.json and give it as ship.files.part_map"
                         if auto["faces_as_in_file"] else "the repaired surface with its "
                         "parts is ship.ply + ship_parts.json")
                con.info("mesh: parts assigned by rules: check auto_parts_iso.png and "
                         f"auto_parts_side.png; {reuse}")
            report = {"ship": ship.name, "length_m": ship.length, "beam_m": ship.beam,
                      "draught_m": ship.draught, "edge_length_m": ship.edge_length,
                      **report, "read_report": read_report, "picture_backend": backend,
                      "files": sorted(str(Path(p).relative_to(tmp)) for p in files.values()),
                      "seconds": time.perf_counter() - t0}
            (tmp / "mesh_report.json").write_text(json.dumps(report, indent=1, default=str))
        _report(run, con, finishing=True)
    con.out(f"{ship.name}: {ship.n_faces} surface faces (median edge "
            f"{report['edge_median']:.2f} m), {graph.n_cells} cells; "
            f"parts {', '.join(f'{k} {v}' for k, v in report['surface_faces_per_part'].items())}")
    con.out(f"mesh files: {out / 'mesh'}")
    return EXIT_OK


def cmd_run(args, con: Console) -> int:
    from .pipeline import output_inputs, prepare, thermal_case
    from .rundir import RunDir, changes_from_copy, is_complete, scenario_inputs

    sc = _load_scenario(args.scenario)
    out = Path(args.out or output_inputs(sc)["directory"])
    inputs = scenario_inputs(sc)
    RunDir.check_target(out, resume=args.resume, force=args.force, scenario=sc, kind="run",
                        inputs=inputs)
    if args.resume and is_complete(out):
        changed = changes_from_copy(out, sc)
        if changed:
            raise InputError("--resume", str(out), f"is a finished run of a different scenario "
                             f"(changed: {', '.join(changed)})", "Pass --force to rerun it with "
                             "this scenario, or choose another --out")
        con.info(f"{out} is already complete: nothing to resume")
        return EXIT_OK
    t0 = time.perf_counter()
    case = sc.name
    con.debug("reading the inputs (ship, weather" + (", background)" if args.image else ")"))
    ship, background = prepare(sc, imaging=args.image, progress=con.progress, log=con.info)
    if args.image:                      # the ship must float where the images put it
        from .mooring import check_mooring_on

        for line in check_mooring_on(sc, ship, background):
            con.error(f"warning: {line}")
    for line in sc.check_weather():     # gaps interpolated, constants used, wind height
        con.info(f"  {line}")
    with RunDir(out, resume=args.resume, force=args.force, command=args.argv, kind="run",
                log=con.info, scenario=sc, inputs=inputs) as run:
        run.add_scenario(sc)
        run.manifest["cases"][case]["scenario"] = "scenario.toml"
        con.info(f"{case}: thermal run ({sc.ship.builtin or 'user ship'}, "
                 f"{sc.time.season} {sc.time.date})")
        s = thermal_case(sc, run, case, resume=args.resume, progress=con.progress,
                         log=con.debug, ship=ship)
        if args.image and not (args.resume and run.has("imaging")):
            _imaging(run, {case: sc}, con, backgrounds={case: background})
        if "html" in sc.outputs.formats and not args.no_report:
            _report(run, con, finishing=True)
    con.info(f"finished in {time.perf_counter() - t0:.0f} s")
    deck_max = s["parts"].get("deck", {}).get("max_K", float("nan"))
    days = (f"{s['spinup_days']} spin-up + {s['record_days']} recorded days"
            if s.get("record_days") else f"{s['days']} days")
    con.out(f"{case}: {s['surface_faces']} faces, {days} (converged: "
            f"{s['converged']}), deck max {deck_max:.2f} K; run directory {out}")
    if args.image:
        _print_crossovers(out, con)
    return EXIT_OK


def cmd_calendar(args, con: Console) -> int:
    import pandas as pd

    from .calendar import run_calendar, year_overpasses, year_scenarios
    from .pipeline import output_inputs, prepare
    from .rundir import RunDir, scenario_inputs

    sc = _load_scenario(args.scenario)
    changes = {}
    if args.satellites is not None:
        changes["calendar.satellites"] = list(args.satellites)
    if args.threshold is not None:
        changes["calendar.threshold"] = args.threshold
    if args.dense_step_min is not None:
        changes["calendar.dense_step"] = 60.0 * args.dense_step_min
    if changes:
        sc = sc.updated(changes)
    out = Path(args.out or f"{output_inputs(sc)['directory']}-calendar")
    inputs = scenario_inputs(sc)
    RunDir.check_target(out, force=args.force, scenario=sc, kind="calendar", inputs=inputs)
    t0 = time.perf_counter()
    years = year_scenarios(sc)                                    # every refusal up front
    overpasses = year_overpasses(years)
    ship, _ = prepare(sc, progress=con.progress, log=con.info)
    for _, s in years:
        for line in s.check_weather():
            con.info(f"  {line}")
    with RunDir(out, force=args.force, command=args.argv, kind="calendar", log=con.info,
                scenario=sc, inputs=inputs) as run:
        run.add_scenario(sc)
        run.manifest["cases"][sc.name]["scenario"] = "scenario.toml"
        res = run_calendar(sc, run, progress=con.progress, log=con.info, ship=ship,
                           overpasses=overpasses)
        if "html" in sc.outputs.formats:
            _report(run, con, finishing=True)
    con.info(f"finished in {time.perf_counter() - t0:.0f} s")
    monthly = strip_units(pd.read_csv(out / "calendar" / "monthly.csv"))
    con.out(f"{res['overpasses']} overpasses; under the clutter (SCR < "
            f"{sc.calendar.threshold:g}) by month:")
    if len(monthly):
        con.out(monthly[["month", "band", "overpasses", "under_clutter", "fraction_under"]]
                .to_string(index=False, float_format=lambda x: f"{x:.2f}"))
    con.out(f"calendar: {out / 'calendar'}")
    return EXIT_OK


def cmd_image(args, con: Console) -> int:
    from .pipeline import build_background, check_imaging_bands, frame_times, history_file
    from .rundir import MARKER, RunDir

    step = None if args.step_min is None else 60.0 * args.step_min
    if step is not None and not 60.0 <= step <= 10800.0:
        raise InputError("--step-min", args.step_min, "must lie in [1, 180] min")
    path = _require_run(args.run_dir, kinds=("run", "demo"))
    if not (path / MARKER).is_file():
        raise InputError("run directory", str(path), "is not finished (no COMPLETE marker)",
                         f"Finish it first: shipthermal run --resume ... --out {path}")
    cases = _cases_of(path)
    missing = [c for c in cases if not history_file(path / "thermal" / c).is_file()]
    if missing:
        raise InputError("run directory", str(path), f"has no thermal result for "
                         f"{', '.join(missing)} (thermal/<case>/history.npz or .h5)")
    if args.bands:
        cases = {c: sc.updated({"imaging.bands": list(args.bands)}) for c, sc in cases.items()}
    for sc in cases.values():
        frame_times(sc, step)
        check_imaging_bands(sc)
    backgrounds = {c: build_background(sc, progress=con.progress) for c, sc in cases.items()}
    from .mooring import check_mooring_on
    from .pipeline import load_history

    for c, sc in cases.items():             # the ship must float where the images put it
        hist = load_history(path / "thermal" / c)
        for line in check_mooring_on(sc, hist, backgrounds[c]):
            con.error(f"warning: {c}: {line}")
    with RunDir(path, command=args.argv, kind="image", amend=True) as run:
        _imaging(run, cases, con, step, backgrounds)
        _report(run, con)
    return _print_crossovers(path, con)


def cmd_crossover(args, con: Console) -> int:
    return _print_crossovers(_require_run(args.run_dir), con, as_csv=args.csv)


def cmd_validate(args, con: Console) -> int:
    try:
        from .validation import validate
    except ImportError as exc:
        con.error(f"validation is not available in this installation "
                  f"(shipthermal.app.validation: {exc})")
        return EXIT_FAILURE
    from .rundir import RunDir

    if args.into:      # the folders are checked here, before the (slow) validation
        path = _require_run(args.into)
        ctx = RunDir(path, command=args.argv, kind="validate", amend=True)
    else:
        ctx = RunDir(Path(args.out), force=args.force, command=args.argv, kind="validate")
    with ctx as run:
        with run.stage("validation") as tmp:
            rep = validate(out_dir=tmp, progress=con.progress, quick=args.quick,
                           **({"calibrate": True} if getattr(args, "calibrate", False) else {}))
            from ..results import atomic_path

            with atomic_path(tmp / "validation_table.csv") as t:
                rep.table.to_csv(t, index=False, float_format="%.4f")
        _report(run, con, finishing=not args.into)
    con.out(rep.text())
    return EXIT_OK


def cmd_calibrate(args, con: Console) -> int:
    from .calibration import run_calibrate_command

    return run_calibrate_command(args, con)


def cmd_background(args, con: Console) -> int:
    from .background_cmd import run_background
    from .rundir import scenario_inputs

    opts = dict(mtl=args.mtl, roi=args.roi, dem=args.dem, met=args.met, band_files=args.band_files)
    offset = 0.0
    inputs = []
    if args.scenario:
        sc = _load_scenario(args.scenario)
        inputs = scenario_inputs(sc)
        bgs = sc.background
        if bgs.source != "files":
            raise InputError("background.source", bgs.source, "must be 'files' for `shipthermal background`")
        for k in ("mtl", "roi", "dem", "met", "band_files"):
            opts[k] = opts[k] or getattr(bgs, k, None)
        if args.water_vapour is None:
            args.water_vapour = bgs.water_vapour
        offset = sc.start.utcoffset().total_seconds() / 3600.0
    for k in ("mtl", "roi"):
        if not opts[k]:
            raise InputError(f"--{k}", None, "is required (or a scenario whose [background] names it)")
    _check_background_files(opts, args)
    res = run_background(args.out, **opts, bounds=args.bounds, use_qa=not args.no_qa,
                         n_splits=args.splits, seed=args.seed, utc_offset_hours=offset,
                         water_vapour=args.water_vapour, force=args.force, log=con.info,
                         progress=con.progress, command=args.argv, inputs=inputs)
    sp = res["summary"].get("accuracy_over_splits", {}).get("overall_accuracy")
    if sp:
        con.out(f"classification: overall accuracy {sp['mean']:.3f} +- {sp['std']:.3f} over "
                f"{res['summary']['accuracy_over_splits']['n_splits']} held-out ROI splits")
    con.out(f"background: {len(res['files'])} files in {args.out} ({res['seconds']:.1f} s)")
    return EXIT_OK


def _check_background_files(opts: dict, args) -> None:
    """Open the DEM and the met grid before anything is built (a file that is no raster
    or no met grid is the user's, named by the flag or key that gave it)."""
    from imaging.background.checks import check_dem_file, check_met_file

    problems = []
    if opts.get("dem"):
        problems += check_dem_file(opts["dem"])
    if opts.get("met"):
        problems += check_met_file(opts["met"])
    if problems:
        e = problems[0]
        key = e.field.split(".")[1] if e.field.startswith("background.") else e.field
        flag = f"--{key}" if getattr(args, key, None) else e.field
        raise InputError(flag, e.value, e.allowed, e.fix)


def cmd_sweep(args, con: Console) -> int:
    from .rundir import RunDir, atomic_write_text
    from .sweep import load_sweep, run_sweep, sweep_inputs

    spec = load_sweep(args.sweep)
    out = Path(args.out or f"runs/sweep-{spec.name}")
    con.info(f"sweep {spec.name}: {len(spec.cases)} cases over {', '.join(spec.axis_names)}")
    # re-running continues the sweep (finished cases are skipped); --force starts afresh
    with RunDir(out, resume=not args.force, force=args.force, command=args.argv, kind="sweep",
                inputs=sweep_inputs(spec)) as run:
        run.claim("sweep.toml")
        atomic_write_text(out / "sweep.toml", spec.text)
        run.manifest["settings"].update({"sweep": str(args.sweep), "stages": list(spec.stages),
                                         "axes": {k: len(v) for k, v in spec.axes.items()}})
        res = run_sweep(spec, out, scheduler=args.scheduler, n_workers=args.workers,
                        serial=args.serial, retry_failed=not args.keep_failed,
                        progress=con.progress, log=con.info, run=run)
        _report(run, con, finishing=True)
    show = [c for c in res.table.columns if c not in ("worker", "case", "error")
            and not c.startswith(("first_crossover", "energy", "surface"))]
    con.out(res.table[show].to_string(index=False, float_format=lambda x: f"{x:.2f}"))
    bad = res.table[res.table["status"] != "ok"]
    for _, r in bad.iterrows():
        con.out(f"case {r['case']} failed: {r['error']}")
    con.out(f"{len(res.table)} cases: {res.ran} ran, {res.skipped} skipped (finished before), "
            f"{res.failed} failed; {res.seconds:.1f} s; table {res.files['csv']}")
    return EXIT_OK if res.failed == 0 else EXIT_FAILURE


def cmd_ensemble(args, con: Console) -> int:
    from .ensemble import (DISTRIBUTIONS, draw_members, ensemble_sweep_text, format_distribution,
                           load_ensemble_sweep, parse_distribution, write_ensemble)
    from .pipeline import QUICK_EDGE_LENGTH
    from .rundir import RunDir, atomic_write_text
    from .scenario import SEASONS
    from .sweep import run_sweep, sweep_inputs

    dists = dict(DISTRIBUTIONS)
    for text in args.dist:
        d = parse_distribution(text)
        dists[d.name] = d
    draws = draw_members(dists.values(), args.members, args.seed)
    if args.scenario in SEASONS:
        base = args.scenario
    else:
        p = Path(args.scenario)
        if not p.is_file():
            raise InputError("scenario", args.scenario, "must be 'summer', 'winter' or an "
                             "existing scenario TOML file", "Check the path")
        base = str(p.resolve())
    fixed = {"ship.edge_length": QUICK_EDGE_LENGTH} if args.quick else None
    text = ensemble_sweep_text(base, draws, args.seasons, fixed)
    spec = load_ensemble_sweep(text)          # every member validated before any writing
    out = Path(args.out)
    con.info(f"ensemble: {args.members} members x {len(spec.cases) // args.members} "
             f"season(s), seed {args.seed}")
    with RunDir(out, resume=not args.force, force=args.force, command=args.argv,
                kind="ensemble", inputs=sweep_inputs(spec)) as run:
        run.claim("sweep.toml", "ensemble")
        atomic_write_text(out / "sweep.toml", text)
        run.manifest["settings"].update({"members": args.members, "seed": args.seed,
                                         "quick": args.quick,
                                         "distributions": [d.describe() for d in dists.values()]})
        res = run_sweep(spec, out, scheduler=args.scheduler, n_workers=args.workers,
                        serial=args.serial, progress=con.progress, log=con.info, run=run)
        ens = write_ensemble(spec, out, draws, list(dists.values()), args.seed, args.seasons,
                             args.quick)
        _report(run, con, finishing=True)
    con.out("crossover moments over the weather ensemble (median, 5-95 % range):")
    con.out(format_distribution(ens["crossovers"]))
    for _, r in res.table[res.table["status"] != "ok"].iterrows():
        con.out(f"member case {r['case']} failed: {r['error']}")
    con.out(f"{len(res.table)} cases: {res.ran} ran, {res.skipped} skipped, {res.failed} "
            f"failed; {res.seconds:.1f} s; {ens['files']['ensemble.png']}")
    return EXIT_OK if res.failed == 0 else EXIT_FAILURE


def cmd_check(args, con: Console) -> int:
    from .scenario import check_files

    return check_files(args.files)


def cmd_schema(args, con: Console) -> int:
    from .scenario import schema_markdown

    sys.stdout.write(schema_markdown(compact=args.compact))
    return EXIT_OK


def cmd_report(args, con: Console) -> int:
    from .report import write_report
    from .rundir import RunDir

    path = _require_run(args.run_dir)
    if args.output:
        _require_report_file(args.output)
        out = write_report(path, args.output)
    else:
        with RunDir(path, command=args.argv, kind="report", amend=True) as run:
            run.claim("report.html")
            out = write_report(run.path)
    con.out(f"report: {out}")
    return EXIT_OK


# ---------------------------------------------------------------------------------------
# parser
# ---------------------------------------------------------------------------------------
def _common(p: argparse.ArgumentParser, top: bool) -> None:
    d = {} if top else {"default": argparse.SUPPRESS}
    g = p.add_mutually_exclusive_group()
    g.add_argument("-q", "--quiet", action="store_true", help="no progress bars or notes "
                   "(results and errors only)", **d)
    g.add_argument("-v", "--verbose", action="store_true", help="stage details; traceback "
                   "of internal failures", **d)


class _Parser(argparse.ArgumentParser):
    """Command-line misuse on one line (the usage is one ``--help`` away), exit 2; a
    mistyped subcommand or option gets the nearest valid one (``did you mean``)."""

    #: the command line being parsed (set by :func:`main`): where to look for a subcommand
    argv: list = []

    def error(self, message):
        hint = _did_you_mean(self, message, self.argv)
        self.exit(EXIT_USER, f"error: {message}{hint} (see {self.prog} --help)\n")


def _did_you_mean(parser: argparse.ArgumentParser, message: str, argv: list) -> str:
    """``"; did you mean 'run'?"`` for an invalid subcommand choice or an unknown option
    (the nearest name by :func:`difflib.get_close_matches`), else ``""``."""
    import difflib
    import re

    m = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
    if m:
        words, choices = [m.group(1)], re.findall(r"'?([\w-]+)'?", m.group(2))
    else:
        m = re.search(r"unrecognized arguments: (.*)", message)
        if not m:
            return ""
        words = [w.split("=", 1)[0] for w in m.group(1).split() if w.startswith("-")]
        choices = list(parser._option_string_actions)
        sub = _subparser_of(parser, argv)
        if sub is not None:
            choices += list(sub._option_string_actions)
    for word in words:
        near = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
        if near:
            return f"; did you mean '{near[0]}'?"
    return ""


def _subparser_of(parser: argparse.ArgumentParser, argv: list):
    """The subcommand parser named in ``argv`` (None without one)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for word in argv:
                if word in action.choices:
                    return action.choices[word]
    return None


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("shipthermal")
    except PackageNotFoundError:            # running from a source tree, not installed
        return "unknown (not installed)"


#: Example command lines shown under each subcommand's ``--help`` (each parses: tested)
EXAMPLES = {
    "demo": ("shipthermal demo --quick", "shipthermal demo --seasons summer --out runs/summer",
             "shipthermal demo --resume"),
    "mesh": ("shipthermal mesh summer", "shipthermal mesh my.toml --edge-length 1.5"),
    "run": ("shipthermal run my.toml --image", "shipthermal run winter --out runs/winter",
            "shipthermal run my.toml --resume"),
    "image": ("shipthermal image runs/my", "shipthermal image runs/my --step-min 5 "
              "--bands 8-14"),
    "calendar": ("shipthermal calendar record.toml",
                 "shipthermal calendar record.toml --satellites landsat8 landsat9 "
                 "--threshold 1.5"),
    "crossover": ("shipthermal crossover runs/demo", "shipthermal crossover runs/demo --csv"),
    "validate": ("shipthermal validate --quick", "shipthermal validate --into runs/demo"),
    "calibrate": ("shipthermal calibrate --paper",
                  "shipthermal calibrate measured.csv --unknown "
                  "weather.temp_air_offset=-3:3"),
    "background": ("shipthermal background my.toml",
                   "shipthermal background --mtl LC08_MTL.txt --roi rois.gpkg "
                   "--out runs/bg"),
    "sweep": ("shipthermal sweep sweep.toml --workers 2", "shipthermal sweep sweep.toml "
              "--serial"),
    "ensemble": ("shipthermal ensemble summer --members 16 --quick",
                 "shipthermal ensemble my.toml --dist wind=uniform:-2:2"),
    "report": ("shipthermal report runs/demo", "shipthermal report runs/demo --output "
               "demo.html"),
    "check": ("shipthermal check my.toml", "shipthermal check a.toml b.toml"),
    "schema": ("shipthermal schema", "shipthermal schema --compact"),
}


def build_parser() -> argparse.ArgumentParser:
    from .pipeline import QUICK_EDGE_LENGTH

    p = _Parser(
        prog="shipthermal", description="Ship infrared signature in a port: thermal runs, "
        "imaging, SCR and crossover times from one scenario file.",
        epilog="Exit codes: 0 ok, 2 user error, 1 internal failure (or failed sweep cases), "
               "130 interrupted (143 on SIGTERM). "
               "Scenario keys: docs/SCENARIO.md (shipthermal schema).")
    _common(p, True)
    p.add_argument("--version", action="version", version=f"shipthermal {_version()}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)

    def add(name, help_, func):
        examples = "\n".join(f"  {e}" for e in EXAMPLES.get(name, ()))
        sp = sub.add_parser(name, help=help_, description=help_,
                            epilog=f"examples:\n{examples}" if examples else None,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
        _common(sp, False)
        sp.set_defaults(func=func)
        return sp

    d = add("demo", "the built-in default end to end: summer and winter thermal runs of the "
            "frigate, images in 3-5 and 8-14 µm, SCR curves, crossover times, HTML report",
            cmd_demo)
    d.add_argument("--quick", action="store_true", help=f"coarser ship mesh "
                   f"({QUICK_EDGE_LENGTH:g} m edges instead of the default ship's) and "
                   "images every 30 min instead of 10")
    d.add_argument("--out", default="runs/demo", help="run directory (default runs/demo)")
    d.add_argument("--force", action="store_true", help="replace a demo folder this tool "
                   "wrote (never other files)")
    d.add_argument("--resume", action="store_true", help="continue an interrupted demo")
    d.add_argument("--seasons", nargs="+", default=["summer", "winter"],
                   choices=["summer", "winter"], help="seasons (default both)")
    d.add_argument("--no-imaging", action="store_true", help="thermal runs only")

    m = add("mesh", "build a scenario's ship: mesh files (PLY + part map + STL per part), "
            "part picture, mesh report", cmd_mesh)
    m.add_argument("scenario", nargs="?", default="summer",
                   help="scenario TOML file, or 'summer' / 'winter' (built-in; default summer)")
    m.add_argument("--builtin", choices=["frigate", "patrol_boat", "cargo_ship"],
                   help="use this built-in ship")
    m.add_argument("--edge-length", type=float, help="target surface edge length [m]")
    m.add_argument("--out", help="run directory (default runs/<name>-mesh)")
    m.add_argument("--force", action="store_true", help="replace a finished run "
                   "folder of this command (only what it wrote there)")

    r = add("run", "thermal run of a scenario (spin-up until periodic, recorded day, "
            "checkpoints every outputs.checkpoint_interval)", cmd_run)
    r.add_argument("scenario", help="scenario TOML file, or 'summer' / 'winter' (built-in)")
    r.add_argument("--out", help="run directory (default: the scenario's outputs.directory)")
    r.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from its last checkpoint")
    r.add_argument("--force", action="store_true", help="replace a finished run "
                   "folder of this command (only what it wrote there)")
    r.add_argument("--image", action="store_true", help="also run the imaging stage")
    r.add_argument("--no-report", action="store_true", help="no HTML report")

    i = add("image", "imaging stage (images, SCR curves, crossover times) on a finished "
            "thermal run directory", cmd_image)
    i.add_argument("run_dir", help="run directory written by `shipthermal run`")
    i.add_argument("--step-min", type=float, help="frame step of the SCR curves and "
                   "crossover search [min] (default the scenario's imaging.scr_interval)")
    i.add_argument("--bands", nargs="+", help="bands instead of the scenario's (e.g. 3-5 8-14)")

    cl = add("calendar", "the ship's detectability at every overpass of a weather record "
             "(named satellites, two-line elements or listed times): SCR and apparent "
             "temperatures per overpass, the fraction under the clutter by month, crossover "
             "times, a day x local-time picture", cmd_calendar)
    cl.add_argument("scenario", help="scenario TOML file with weather.day = 'record'")
    cl.add_argument("--satellites", nargs="+", metavar="NAME",
                    help="named satellites instead of calendar.satellites (e.g. landsat8)")
    cl.add_argument("--threshold", type=float, help="SCR under which an overpass counts as "
                    "under the clutter (default calendar.threshold, 1)")
    cl.add_argument("--dense-step-min", type=float, help="every-day imaging step [min] "
                    "(0: overpasses only; default calendar.dense_step)")
    cl.add_argument("--out", help="run directory (default <outputs.directory>-calendar)")
    cl.add_argument("--force", action="store_true", help="replace a finished calendar folder")

    c = add("crossover", "print the thermal-crossover times of a run directory", cmd_crossover)
    c.add_argument("run_dir", help="run directory with imaging results")
    c.add_argument("--csv", action="store_true", help="print CSV")

    v = add("validate", "deck temperatures vs the paper's reference values, sensitivity "
            "table (shipthermal.app.validation)", cmd_validate)
    v.add_argument("--out", default="runs/validation", help="run directory (default "
                   "runs/validation)")
    v.add_argument("--into", help="add the validation to this existing run directory instead")
    v.add_argument("--quick", action="store_true", help="coarse mesh and fewer rays")
    v.add_argument("--calibrate", action="store_true", help="also fit the reference's "
                   "conditions to its noon values, predict 07:00 / 08:00 held out, and the "
                   "sol-air anchor (docs/CALIBRATION.md; a few minutes more)")
    v.add_argument("--force", action="store_true", help="replace a finished run "
                   "folder of this command (only what it wrote there)")

    cb = add("calibrate", "fit unknown scenario quantities (bounded least squares on the "
             "full model) to measured temperatures: values, intervals, held-out errors "
             "(docs/CALIBRATION.md)", cmd_calibrate)
    cb.add_argument("measurements", nargs="?", help="measurement CSV (docs/CALIBRATION.md)")
    cb.add_argument("--unknown", action="append", default=[], metavar="[CASE:]KEY=LO:HI[:START]",
                    help="an unknown scenario key with bounds (repeat)")
    cb.add_argument("--holdout", choices=["split", "loo", "none"], default="split",
                    help="held-out error: the CSV's split column (default), or also "
                    "leave-one-out refits")
    cb.add_argument("--paper", action="store_true", help="the paper's case: fit the noon "
                    "reference deck means, predict 07:00 summer and 08:00 winter")
    cb.add_argument("--crossovers", action="store_true", help="with --paper: crossover "
                    "moments with the fitted conditions (imaging every 10 min)")
    cb.add_argument("--full", action="store_true", help="the scenarios' own mesh and steps "
                    "instead of the coarse calibration setting (much slower)")
    cb.add_argument("--out", default="runs/calibration", help="run directory (default "
                    "runs/calibration)")
    cb.add_argument("--force", action="store_true", help="replace a finished run "
                   "folder of this command (only what it wrote there)")

    b = add("background", "build and write the port background from real files: Landsat "
            "L1/L2 scene + ROIs give LST, classes, QA mask, accuracy; with --dem and --met the "
            "hourly background", cmd_background)
    b.add_argument("scenario", nargs="?", help="scenario TOML whose [background] names the files "
                   "(options below override)")
    b.add_argument("--mtl", help="Landsat *_MTL.txt / .json (Level-1 or Level-2)")
    b.add_argument("--roi", help="training ROIs: GeoJSON / GeoPackage / Shapefile polygons "
                   "(any CRS) or a label GeoTIFF")
    b.add_argument("--dem", help="DEM GeoTIFF (with --met: hourly background)")
    b.add_argument("--met", help="hourly met NetCDF (with --dem)")
    b.add_argument("--band-files", help="band file name template when the names on disk differ "
                   "from the MTL, e.g. 'l8_{band}.tif'")
    b.add_argument("--bounds", nargs=4, type=float, metavar=("W", "S", "E", "N"),
                   help="crop box in the scene CRS [m]")
    b.add_argument("--water-vapour", type=float, help="column water vapour [g cm-2] for the "
                   "single-channel LST of a Level-1 scene without a met grid")
    b.add_argument("--splits", type=int, default=10, help="held-out ROI splits (default 10)")
    b.add_argument("--seed", type=int, default=0, help="seed of the first split")
    b.add_argument("--no-qa", action="store_true", help="do not mask clouds/shadows from QA")
    b.add_argument("--out", default="runs/background", help="output folder (default "
                   "runs/background)")
    b.add_argument("--force", action="store_true", help="replace an earlier output "
                   "folder of `shipthermal background` (never other files)")

    en = add("ensemble", "weather ensemble: crossover times and SCR curves with a median "
             "and a 5-95 percent range (shipthermal.app.ensemble; one sweep case per member and "
             "season)", cmd_ensemble)
    en.add_argument("scenario", help="scenario TOML file, or 'summer' / 'winter' (built-in)")
    en.add_argument("--members", type=int, default=8, help="members (>= 2; default 8)")
    en.add_argument("--seed", type=int, default=0, help="seed of the Latin hypercube "
                    "(default 0)")
    en.add_argument("--seasons", nargs="+", choices=["summer", "winter"],
                    help="run these seasons (default: the scenario's own)")
    en.add_argument("--dist", action="append", default=[], metavar="NAME=KIND:A:B",
                    help="replace a distribution: NAME cloud, wind or air; KIND "
                    "uniform:LOWER:UPPER or normal:MEAN:SD (repeat)")
    en.add_argument("--quick", action="store_true", help="coarse ship mesh (as demo "
                    "--quick)")
    en.add_argument("--out", default="runs/ensemble", help="ensemble directory (default "
                    "runs/ensemble)")
    en.add_argument("--scheduler", help="address of an existing dask scheduler")
    en.add_argument("--workers", type=int, help="LocalCluster workers (default: the cores)")
    en.add_argument("--serial", action="store_true", help="run the members one by one here")
    en.add_argument("--force", action="store_true", help="start afresh (deletes only "
                    "what an earlier ensemble wrote there)")

    s = add("sweep", "parameter sweep: the Cartesian product of scenario changes, one "
            "dask task per case; re-running skips finished cases", cmd_sweep)
    s.add_argument("sweep", help="sweep TOML file (see shipthermal.app.sweep)")
    s.add_argument("--out", help="sweep directory (default runs/sweep-<name>)")
    s.add_argument("--scheduler", help="address of an existing dask scheduler "
                   "(default: a LocalCluster on this machine)")
    s.add_argument("--workers", type=int, help="LocalCluster workers (default: the cores)")
    s.add_argument("--serial", action="store_true", help="run the cases one by one here")
    s.add_argument("--keep-failed", action="store_true", help="do not retry cases that "
                   "failed before")
    s.add_argument("--force", action="store_true", help="start the sweep afresh "
                   "(deletes only what an earlier sweep wrote there)")

    rp = add("report", "write the self-contained HTML report of a run directory", cmd_report)
    rp.add_argument("run_dir", help="run directory")
    rp.add_argument("--output", help="write here instead of <run_dir>/report.html")

    ck = add("check", "load scenario files and open their inputs (weather over the "
             "simulated span, ship meshes, background rasters): every problem listed at once, "
             "exit 2 if any", cmd_check)
    ck.add_argument("files", nargs="+", metavar="FILE", help="scenario TOML files")

    sm = add("schema", "print the scenario schema (every key with type, default, unit, "
             "allowed values) as a Markdown table", cmd_schema)
    sm.add_argument("--compact", action="store_true", help="one row per section")
    return p


def main(argv=None) -> int:
    """Entry point of ``shipthermal``; returns the exit code (also via SystemExit). Without
    arguments: the help (what the tool does, its commands and where to start)."""
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv:
        parser.print_help()
        print("\nStart with `shipthermal demo --quick` (a few minutes), or "
              "`shipthermal <COMMAND> --help`.")
        return EXIT_OK
    _Parser.argv = argv
    args = parser.parse_args(argv)
    args.argv = ["shipthermal"] + argv
    con = Console(quiet=getattr(args, "quiet", False), verbose=getattr(args, "verbose", False))
    if (args.command in ("sweep", "ensemble") and args.workers is not None
            and args.workers < 1):
        parser.error("--workers must be >= 1")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        code = args.func(args, con)
    except InputError as exc:
        con.error(f"error: {_in_user_words(exc, args)}")
        return EXIT_USER
    except KeyboardInterrupt as exc:
        con.error("interrupted (an unfinished run resumes with --resume)")
        return EXIT_TERMINATED if isinstance(exc, Terminated) else EXIT_INTERRUPTED
    except Exception as exc:
        user = input_error_from_os(exc)
        if user is not None:                   # permission, disk full, name too long, ...
            con.error(f"error: {user}")
            if con.verbose:
                traceback.print_exc()
            return EXIT_USER
        con.error(f"internal error: {type(exc).__name__}: {exc}")
        if con.verbose:
            traceback.print_exc()
        else:
            con.error("(run with -v for the traceback)")
        return EXIT_FAILURE
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    return code


#: Argument names of the library's functions that a user never typed, and the scenario key
#: (``[background]``) or command-line flag (``shipthermal background``) that carries them
_BACKGROUND_WORDS = {"mtl_path": "mtl", "mtl": "mtl", "roi_path": "roi", "roi": "roi",
                     "dem_path": "dem", "dem": "dem", "met_path": "met", "met": "met",
                     "water_vapour": "water_vapour", "band_files": "band_files",
                     "--dem/--met": "dem/met"}


def _in_user_words(exc: InputError, args) -> InputError:
    """The error with its field named as the user gave it: a ``[background]`` key for a
    scenario, the flag for ``shipthermal background`` options given on the command line."""
    import re

    from .scenario import ScenarioError

    if isinstance(exc, ScenarioError):
        return exc
    m = re.match(r"^(--dem/--met|[A-Za-z_]+)(.*)$", str(exc.field), re.S)
    if not m or m.group(1) not in _BACKGROUND_WORDS:
        return exc
    key, rest = _BACKGROUND_WORDS[m.group(1)], m.group(2)
    if args.command == "background":
        flags = {k: getattr(args, k.replace("/", "_"), None) for k in key.split("/")}
        from_flags = all(flags.values()) or not getattr(args, "scenario", None)
        if from_flags:
            name = "/".join(f"--{k.replace('_', '-')}" for k in key.split("/"))
        else:
            name = "/".join(f"background.{k}" for k in key.split("/"))
    elif args.command in ("run", "image", "check", "sweep", "ensemble", "calibrate", "demo",
                          "validate", "mesh"):
        name = "/".join(f"background.{k}" for k in key.split("/"))
    else:
        return exc
    return InputError(name + rest, exc.value, exc.allowed, exc.fix)


def _on_sigterm(signum, frame):
    raise Terminated


def _entry() -> None:
    sys.exit(main())


if __name__ == "__main__":
    _entry()
