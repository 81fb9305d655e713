"""The entry of a diurnal run: a periodic design day (:func:`~shipthermal.diurnal.periodic.
run_periodic`) or a weather record (:func:`~shipthermal.diurnal.record.run_record`), as
the environment's weather is.
"""

from __future__ import annotations

from ..units import HOUR
from .periodic import run_periodic
from .record import run_record
from .result import DiurnalResult
from .settings import DiurnalSettings


def run_diurnal(ship, environment, settings: DiurnalSettings | None = None, *,
                absorptivity=None, emissivity=None, graph=None, traced=None,
                progress: bool = True, checkpoint=None, checkpoint_interval: float = HOUR,
                resume: bool = False, log=None, initial_state=None) -> DiurnalResult:
    """Spin a ship up under a periodic design day and record the converged day (a weather
    record goes to :func:`~shipthermal.diurnal.record.run_record`, without
    ``checkpoint_interval`` and ``initial_state``).

    Parameters
    ----------
    ship : ShipGeometry
    environment : shipthermal.environment.Environment
        Periodic (design-day) weather, or a weather record; heading and speed of the
        ship.
    settings : DiurnalSettings
    absorptivity, emissivity : float or mapping part → value, optional
        Solar absorptivity and broadband long-wave emissivity per part [-].
    graph : CellGraph, optional
        A prebuilt shell graph of ``ship`` (default: built here from the ship's layups).
    traced : TracedShip, optional
        Reuse the ray tracing of an earlier run of the same ship (sensitivity studies).
    progress : bool
        Progress bars.
    checkpoint : path, optional
        Checkpoint file (.npz) written every ``checkpoint_interval`` of simulated time (on
        recording times: at most one per ``settings.output_interval``).
    resume : bool
        Continue from ``checkpoint`` if it exists (same result as an uninterrupted run).
    log : callable, optional
        ``log(str)`` for progress messages (default: silent).
    initial_state : (n_cells,) array, optional
        Start from these cell temperatures [K] (e.g. a converged run of the same mesh:
        sensitivity runs then need fewer spin-up days).

    Returns
    -------
    DiurnalResult
    """
    settings = settings or DiurnalSettings()
    if not environment.weather.periodic:
        return run_record(ship, environment, settings, absorptivity=absorptivity,
                          emissivity=emissivity, graph=graph, traced=traced,
                          progress=progress, log=log, checkpoint=checkpoint, resume=resume)
    return run_periodic(ship, environment, settings, absorptivity=absorptivity,
                        emissivity=emissivity, graph=graph, traced=traced, progress=progress,
                        checkpoint=checkpoint, checkpoint_interval=checkpoint_interval,
                        resume=resume, log=log, initial_state=initial_state)
