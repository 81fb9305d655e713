"""Safe run directories: nothing half-written ever looks complete.

Layout of ``runs/<name>/`` (every stage writes into a hidden staging folder that is
renamed into place only when the stage has finished)::

    runs/<name>/
      manifest.json          signature (tool, kind, entries written), versions, git commit,
                             seeds, command line, start/end, timings
      scenario.toml          the scenario of a single-case run (explicit copy), or
      scenario_<case>.toml   one per case (the demo: summer and winter)
      mesh/                  `shipthermal mesh`: ship files, part picture, mesh report
      thermal/<case>/        part_means.csv/.png, surface_HHMM.png, thermal.vtkhdf,
                             thermal_summary.json, energy.csv, history.npz (a weather
                             record: history.h5)
      imaging/               images_*.nc, typical_*.tif, panels_*.png, scr_*.png,
                             metrics_*.csv, crossovers.csv, band_comparison.csv, summary.json
      validation/            validation table (when run)
      report.html            self-contained report (images embedded)
      checkpoints/<case>.npz thermal checkpoints while a run is unfinished (a weather
                             record: also <case>.record/, its outputs day by day)
      COMPLETE               written last; its absence means "not finished"

Rules (what makes it safe):

* a stage's files are written in ``.stage-<stage>.<pid>/`` and the folder is renamed to its
  final name when the stage is done, so a stage folder that exists is complete;
* single files (manifest, report, scenario copies) go through a temporary name and
  ``os.replace`` (:mod:`shipthermal.atomic`);
* ``COMPLETE`` is written after everything else and removed first when a run is reopened;
* a ``.lock`` file holds the pid of the process working in the folder; a second process
  is refused, a stale lock (dead pid) of this tool is taken over;
* reopening a run (fresh or ``--resume``) deletes stale temporaries of crashed writers;
* ``--resume`` keeps finished stages and thermal checkpoints, and refuses a scenario that
  differs from the copy in the folder;
* a user error (:class:`~shipthermal.errors.InputError`) in a fresh run removes what it
  wrote (the folder too when the run created it); a crash or Ctrl-C keeps the unfinished
  folder (manifest status ``failed`` / ``interrupted``, no marker) for ``--resume``.

What makes it unable to destroy a user's files:

* a folder is a run folder only when its ``manifest.json`` is signed: ``"tool":
  "shipthermal"``, the ``kind`` of command that wrote it, and ``"entries"``, the top-level
  names this tool created there (each is listed, and the manifest saved, before it is
  written). A manifest of an earlier version (no signature, but ``kind``, ``versions`` with
  a ``shipthermal`` key and a command starting with ``shipthermal``) is accepted; its
  entries are the names of this tool's products that are present (:data:`PRODUCTS`);
* a command replaces (``--force``), continues (``--resume``) or amends only a run folder
  of its own kind (amendments: ``image`` a ``run`` or ``demo`` folder, ``report`` and
  ``validate --into`` any signed folder);
* everything a command deletes is an entry of the manifest or a temporary of this tool
  (``.stage-*``, ``.<stem>.<random>.tmp<suffix>``, ...); nothing else is ever deleted or
  written over. A fresh start (or ``--force``) in a run folder that holds anything else is
  refused (exit 2, naming it): the user moves it away or chooses another folder;
  ``--resume`` and amendments leave such files alone;
* any other non-empty folder (a user folder, a ``manifest.json`` of someone else's, a
  ``.lock`` that this tool did not write) is never written into, with or without
  ``--force``; a file is never turned into a folder;
* the output folder may not be, or contain, an input of the command (scenario, weather,
  mesh, raster or measurement files): refused before anything is written.

Modules: :mod:`.folder` (:class:`RunDir`), :mod:`.ownership` (the names this tool writes,
its temporaries, a folder's signature), :mod:`.locks` (the ``.lock`` file),
:mod:`.manifest` (the manifest's signed head),
:mod:`.inputs` (the files a scenario reads, changes against a run's scenario copy).
"""

from ...atomic import atomic_write_text
from .folder import RunDir
from .inputs import (changes_from_copy, check_inputs, named_files, scenario_changes,
                     scenario_inputs)
from .locks import stale_lock
from .manifest import git_commit, new_manifest, package_versions
from .ownership import (KINDS, MANIFEST, MARKER, PRODUCTS, TOOL, Signature, is_complete,
                        read_signature)

__all__ = ["RunDir", "MARKER", "MANIFEST", "package_versions", "git_commit",
           "atomic_write_text", "is_complete", "scenario_changes", "changes_from_copy",
           "stale_lock", "Signature", "read_signature", "check_inputs", "scenario_inputs",
           "named_files", "new_manifest", "TOOL", "KINDS", "PRODUCTS"]
