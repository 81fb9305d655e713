"""Checking scenario files before a run (``shipthermal check``): load each file, then open
its inputs (weather over the simulated span, ship meshes, background rasters) and list
every problem at once."""

from __future__ import annotations

import sys

from ...errors import InputError
from .reading import load_scenario
from .spec import ScenarioError


def check_files(files) -> int:
    """Check scenario files: one ``FILE: ok (...)`` line per good file on stdout, every
    problem of a bad one on stderr. Returns the exit code (0 all good, 2 a user error)."""
    status = 0
    for f in files:
        try:
            sc = load_scenario(f)
            # open the input files too, and list every problem at once: the weather over
            # the simulated span (columns, units, coverage of the date, gaps), the ship's
            # meshes (every mesh check) and the background rasters (headers,
            # georeferencing, bands, QA, ROIs, DEM, met grid)
            problems, notes = [], []           # lines to print, and notes
            try:
                notes = list(sc.check_weather())
            except ScenarioError as exc:        # its own head line and one line per problem
                problems.append(str(exc))
            except InputError as exc:
                problems.append(f"{f}: {exc}")
            if sc.ship.files is not None:       # open the meshes: every mesh check
                try:
                    sc.ship.read_files()
                except InputError as exc:
                    problems.append(f"{f}: {exc}")
            bgs = sc.background
            if bgs.source == "files":
                from imaging.background.checks import check_dem_file, check_met_file
                from imaging.background.inputs import check_background_inputs

                # each file on its own first (readable, units, hours), then against the
                # scene (bands, QA, ROIs, DEM overlap, the overpass day and extent of the
                # met grid) for the files that passed
                met_problems = check_met_file(bgs.met, bgs.met_variable, bgs.met_units) \
                    if bgs.met else []
                dem_problems = check_dem_file(bgs.dem) if bgs.dem else []
                bg_problems, bg_notes = check_background_inputs(
                    bgs.mtl, bgs.roi, None if dem_problems else bgs.dem,
                    None if met_problems else bgs.met, bgs.band_files,
                    met_variable=bgs.met_variable, met_units=bgs.met_units,
                    met_margin_cells=bgs.met_margin_cells)
                problems += [f"{f}: {p}" for p in bg_problems + met_problems + dem_problems]
                for n in bg_notes:
                    print(f"{f}: note: {n}", file=sys.stderr)
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
