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
import difflib
import os
import re
import signal
import sys
import threading
import traceback
from importlib.metadata import PackageNotFoundError, version

from ..errors import InputError, input_error_from_os
from .commands import (cmd_background, cmd_calendar, cmd_calibrate, cmd_check, cmd_crossover,
                       cmd_demo, cmd_ensemble, cmd_image, cmd_mesh, cmd_report, cmd_run,
                       cmd_schema, cmd_sweep, cmd_validate)
from .console import (EXIT_FAILURE, EXIT_INTERRUPTED, EXIT_OK, EXIT_TERMINATED, EXIT_USER,
                      Console, Terminated)
from .pipeline import QUICK_EDGE_LENGTH
from .scenario import ScenarioError

__all__ = ["main", "build_parser"]


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
