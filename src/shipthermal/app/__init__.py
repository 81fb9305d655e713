"""The application layer: the only place that wires the stages together.

* :mod:`.chain` — :class:`~shipthermal.app.chain.Simulation`, the front door
  (``shipthermal.Simulation``): one object from a scenario to images, SCR, crossovers and
  the report, wiring the stages below;
* :mod:`.scenario` — one TOML scenario, validated once, that drives every stage;
* :mod:`.thermal` — a scenario's thermal stage (:func:`shipthermal.diurnal.run_diurnal`)
  and its hand-over to the imaging stage;
* :mod:`.pipeline` — the stages of a run (mesh, thermal, background, imaging);
* :mod:`.cli` — the ``shipthermal`` command line (parser, entry point), :mod:`.commands`
  — its subcommands, :mod:`.console` — where its messages go, its exit codes;
  :mod:`.sweep`, :mod:`.sweep_file`, :mod:`.ensemble` — parameter sweeps (the sweep file,
  the runs) and weather ensembles on dask.distributed;
* :mod:`.rundir` — run folders (lock, manifest, resume); :mod:`.report`,
  :mod:`.report_day` — the HTML report;
* :mod:`.validation`, :mod:`.calibration`, :mod:`.anchor`, :mod:`.paper` — the paper's
  reference values, validation and calibration; :mod:`.background_cmd` — the port
  background from real files.

The physics packages (:mod:`shipthermal` outside this folder, :mod:`imaging`) never import
from here (``tests/test_layers.py``).
"""
