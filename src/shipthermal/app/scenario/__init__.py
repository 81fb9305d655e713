"""One scenario file that drives the thermal and the imaging stage.

A scenario is a TOML file (or a dict of the same shape) read **once** by
:func:`load_scenario` into frozen dataclasses. Every key is checked at load: unknown keys
(with the closest valid key suggested), wrong types, values out of range, missing files,
bands outside the atmosphere tables and disagreements between sections (e.g. an output
interval that is not a multiple of the time step). All problems of a file are collected and
raised together as one :class:`ScenarioError` (a :class:`~shipthermal.errors.InputError`
whose ``.errors`` lists one ``InputError`` per problem, each naming the key's dotted path,
the value and what is allowed), so a user fixes a file in one pass.

The same object then feeds both stages, so location, time, weather and emissivities cannot
disagree between them::

    from shipthermal.app.scenario import load_scenario, default_scenario
    sc = load_scenario("summer.toml")      # or default_scenario("summer")
    env = sc.environment()                 # shipthermal.environment.Environment
    ship = sc.ship()                       # ShipGeometry (built-in or read); sc.ship.heading etc.
    eps = sc.emissivity("deck", "8-14")    # 0.95 (paper §5)
    sc.write(run_dir / "scenario.toml")    # the copy that goes with a run

Loading is cheap (no weather file, mesh or atmosphere table is read; heavy libraries are
imported only by the builders), so it is safe to validate a scenario before a long run.

Modules
-------
* :mod:`.values` — allowed values and defaults of the keys;
* :mod:`.spec` — the schema framework: field specifications, converters, error collection;
* the sections, one frozen dataclass per TOML table with its cross-field checks:
  :mod:`.site_sections` ([location], [time], [weather]), :mod:`.sections` (the [ship]
  tables), :mod:`.thermal_sections` ([solver], [convection], [outputs]),
  :mod:`.imaging_sections` ([background], [imaging], [calendar]);
* :mod:`.wiring` — :class:`Scenario`: the sections and the builders that hand each stage
  its inputs;
* :mod:`.reading` / :mod:`.writing` — TOML in and out;
* :mod:`.schema_doc` — the schema table of ``docs/SCENARIO.md``;
* :mod:`.check` — ``shipthermal check``: open a scenario's input files and list every problem.

Conventions
-----------
* Relative input paths are relative to the scenario file's folder (the working directory
  for a dict); they are stored absolute, so a copy written into a run directory still
  points at the same files. ``outputs.directory`` stays relative to the working directory.
* Clock times (``"HH:MM"``) and dates are local, in ``location.time_zone``.
* The solver clock is seconds after local midnight of ``time.date``
  (:attr:`Scenario.start`); :meth:`Scenario.environment` is built so that
  ``Environment.start == Scenario.start`` for every weather source.
* Some defaults depend on ``time.season`` (date, output times, compartment air); they are
  resolved at load and stored, so a written copy is explicit.

Allowed values and defaults the physics also uses are imported, never copied: from
:mod:`shipthermal.parameters` and :mod:`imaging.parameters` (which import nothing heavy), so
loading stays free of pandas, pvlib and scipy.

The user-facing schema table is generated from the dataclasses by :func:`schema_markdown`
(``docs/SCENARIO.md`` holds a copy that the tests keep in sync; ``shipthermal schema``
prints it).
"""

from .check import check_files
from .reading import default_scenario, example_path, load_scenario, loads_scenario
from .schema_doc import schema_keys, schema_markdown
from .imaging_sections import (AtmosphereSettings, BackgroundSettings, ImagingSettings,
                               SensorSettings)
from .sections import LayerSpec, ShipFiles, ShipParticulars, ShipSettings
from .site_sections import Location, Time, WeatherSettings
from .spec import ScenarioError, clock_seconds, parse_band
from .thermal_sections import ConvectionSettings, OutputSettings, SolverSettings
from .values import SEASONS
from .wiring import Scenario

__all__ = [
    "Scenario", "ScenarioError", "Location", "Time", "WeatherSettings", "ShipSettings",
    "ShipParticulars", "ShipFiles", "LayerSpec", "SolverSettings", "ConvectionSettings",
    "BackgroundSettings",
    "ImagingSettings", "SensorSettings", "AtmosphereSettings", "OutputSettings",
    "load_scenario", "loads_scenario", "default_scenario", "example_path", "schema_markdown",
    "schema_keys", "parse_band", "clock_seconds", "check_files", "SEASONS",
]
