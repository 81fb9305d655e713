"""The subcommands of ``shipthermal``: one ``cmd_<name>(args, con)`` per subcommand, each
returning its exit code, and the run-folder steps they share (which folders a command may
read, the imaging stage, the report, the crossover table)."""

from __future__ import annotations

import json
import os
import re
import sys
import time
from pathlib import Path

import pandas as pd

from ..atomic import atomic_path, atomic_write_text
from ..errors import InputError
from ..geometry import build_ship_mesh, render_parts_png, write_ship
from ..geometry.cad import CHECK_COLOURS
from ..units import strip_units
from .background_cmd import run_background
from .console import EXIT_FAILURE, EXIT_OK, Console
from .mooring import check_mooring_on
from .pipeline import (QUICK_EDGE_LENGTH, QUICK_SCR_INTERVAL, build_background,
                       check_imaging_bands, demo_scenarios, frame_times, history_file,
                       image_cases, load_history, output_inputs, prepare, thermal_case)
from .report import is_report_file, write_report
from .rundir.folder import RunDir
from .rundir.inputs import changes_from_copy, scenario_inputs
from .rundir.ownership import MANIFEST, MARKER, is_complete, read_signature
from .scenario import (SEASONS, check_files, default_scenario, load_scenario,
                       schema_markdown)


# ---------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------
def _load_scenario(path):
    if path in ("summer", "winter"):
        return default_scenario(path)
    return load_scenario(path)


def _require_run(path, kinds: tuple = ()) -> Path:
    """A run folder this tool wrote (signed manifest, or one of an earlier version), of one
    of ``kinds`` when given: the only folders ``image``, ``report``, ``crossover`` and
    ``validate --into`` read and amend."""
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
    ens = run_path / "ensemble" / "crossovers.csv"
    if ens.is_file():                           # a weather ensemble: the distribution
        # deferred: the ensemble module, 7 ms of every command's start-up (measured)
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
                auto = read_report.pop("auto_parts")
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
    # deferred: the calendar loads the renderer (85 ms of every command's start-up, measured)
    from .calendar import run_calendar, year_overpasses, year_scenarios

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
        # deferred: an installation without the validation still runs every other command
        # (and it is 19 ms of every command's start-up, measured)
        from .validation import validate
    except ImportError as exc:
        con.error(f"validation is not available in this installation "
                  f"(shipthermal.app.validation: {exc})")
        return EXIT_FAILURE
    if args.into:      # the folders are checked here, before the (slow) validation
        path = _require_run(args.into)
        ctx = RunDir(path, command=args.argv, kind="validate", amend=True)
    else:
        ctx = RunDir(Path(args.out), force=args.force, command=args.argv, kind="validate")
    with ctx as run:
        with run.stage("validation") as tmp:
            rep = validate(out_dir=tmp, progress=con.progress, quick=args.quick,
                           **({"calibrate": True} if getattr(args, "calibrate", False) else {}))
            with atomic_path(tmp / "validation_table.csv") as t:
                rep.table.to_csv(t, index=False, float_format="%.4f")
        _report(run, con, finishing=not args.into)
    con.out(rep.text())
    return EXIT_OK


def cmd_calibrate(args, con: Console) -> int:
    # deferred: the calibration, 16 ms of every command's start-up (measured)
    from .calibration.command import run_calibrate_command

    return run_calibrate_command(args, con)


def cmd_background(args, con: Console) -> int:
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
    # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (0.8 s of every
    # command's start-up, measured)
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
    # deferred: the sweep modules, 9 ms of every command's start-up (measured)
    from .sweep import run_sweep
    from .sweep_file import load_sweep, sweep_inputs

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
    # deferred: the sweep and ensemble modules, 12 ms of every command's start-up (measured)
    from .ensemble import (DISTRIBUTIONS, draw_members, ensemble_sweep_text, format_distribution,
                           load_ensemble_sweep, parse_distribution, write_ensemble)
    from .sweep import run_sweep
    from .sweep_file import sweep_inputs

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
    return check_files(args.files)


def cmd_schema(args, con: Console) -> int:
    sys.stdout.write(schema_markdown(compact=args.compact))
    return EXIT_OK


def cmd_report(args, con: Console) -> int:
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
