"""Checking scenario files before a run (``shipthermal check``): load each file, then open
its inputs and run every check the commands will run, listing every problem at once:

* the weather over the simulated span (columns, units, coverage, gaps, physical sense,
  the site of a typical-year file);
* the ship: a user mesh read with every mesh check (header, topology, outside by ray
  casting, parts, slivers, size at ``ship.edge_length``), a built-in ship's size;
* the berth: the ship's footprint at ``ship.mooring_position`` on the built-in port's
  water (:mod:`shipthermal.app.mooring`);
* the background files (headers, georeferencing, bands, QA, ROIs, DEM, met grid), and
  what `shipthermal background` needs for a Level-1 scene.
"""

from __future__ import annotations

import sys

from ...errors import InputError
from ..mooring import builtin_class_map, check_mooring, scenario_ship_outline
from .reading import load_scenario
from .spec import ScenarioError


def _background_problems(bgs) -> tuple[list, list]:
    """Problems and notes of ``[background] source = 'files'``."""
    # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (2 s, measured);
    # loading a scenario imports no imaging module but its parameters (test_load_is_lazy)
    from imaging.background.checks import check_dem_file, check_met_file
    from imaging.background.inputs import check_background_inputs

    # each file on its own first (readable, units, hours), then against the scene (bands,
    # QA, ROIs, DEM overlap, the overpass day and extent of the met grid) for the files
    # that passed
    met_problems = check_met_file(bgs.met, bgs.met_variable, bgs.met_units) if bgs.met else []
    dem_problems = check_dem_file(bgs.dem) if bgs.dem else []
    problems, notes = check_background_inputs(
        bgs.mtl, bgs.roi, None if dem_problems else bgs.dem,
        None if met_problems else bgs.met, bgs.band_files,
        met_variable=bgs.met_variable, met_units=bgs.met_units,
        met_margin_cells=bgs.met_margin_cells)
    problems = [str(p) for p in problems + met_problems + dem_problems]
    notes = list(notes)
    if bgs.met is None and not any(p.startswith("background.mtl") for p in problems):
        # deferred as above
        from imaging.background.landsat import read_mtl

        try:
            level = read_mtl(bgs.mtl, bgs.band_files).level
        except InputError:                 # reported above
            level = None
        if level == "L1" and bgs.water_vapour is None:
            problems.append(str(InputError(
                "background.water_vapour", None, "is required for the single-channel LST of "
                "a Level-1 scene without a met grid (shipthermal background)",
                "Set background.water_vapour [g cm-2] (e.g. 2.0 for a mid-latitude summer), "
                "give background.met, or use the Level-2 product (ST_B10)")))
    if bgs.dem is None or bgs.met is None:
        notes.append("background.dem and background.met are needed by `shipthermal run "
                     "--image` (the hourly background); `shipthermal background` writes the "
                     "overpass products without them")
    return problems, notes


def _ship_and_berth(sc) -> tuple[list, list]:
    """Problems and notes of the ship and of its footprint at the mooring."""
    problems, notes = [], []
    ship = None
    try:
        if sc.ship.files is not None:              # every mesh check
            ship, report = sc.ship.read_files()
            notes += list(report.get("repairs", []))
        else:
            ship = scenario_ship_outline(sc)
    except InputError as exc:
        problems.append(str(exc))
    classes = builtin_class_map(sc) if ship is not None else None
    if classes is not None:
        try:
            notes += check_mooring(sc, ship, *classes)
        except InputError as exc:
            problems.append(str(exc))
    return problems, notes


def check_files(files) -> int:
    """Check scenario files: one ``FILE: ok (...)`` line per good file on stdout, every
    problem of a bad one on stderr. Returns the exit code (0 all good, 2 a user error)."""
    status = 0
    for f in files:
        try:
            sc = load_scenario(f)
            problems, notes = [], []           # lines to print
            try:
                notes = list(sc.check_weather())
            except ScenarioError as exc:        # its own head line and one line per problem
                problems.append(str(exc))
            except InputError as exc:
                problems.append(f"{f}: {exc}")
            p, n = _ship_and_berth(sc)
            problems += [f"{f}: {x}" for x in p]
            notes += n
            if sc.background.source == "files":
                p, n = _background_problems(sc.background)
                problems += [f"{f}: {x}" for x in p]
                for line in n:
                    print(f"{f}: note: {line}", file=sys.stderr)
            if problems:
                for p in problems:
                    print(p, file=sys.stderr)
                status = 2
                continue
            print(f"{f}: ok ({sc.name}: {sc.time.season} {sc.time.date}, "
                  f"{sc.ship.builtin or 'user ship'}, bands {', '.join(sc.bands)})")
            for line in notes:
                print(f"  {line}")
        except InputError as exc:
            print(f"{f}: {exc}" if not isinstance(exc, ScenarioError) else str(exc),
                  file=sys.stderr)
            status = 2
    return status
