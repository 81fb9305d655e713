"""The thermal stage of a scenario: the scenario's ship, environment, optical properties
and solver settings handed to :func:`shipthermal.diurnal.run_diurnal`, and the run's
surface temperatures handed on to the imaging stage."""

from __future__ import annotations

from imaging.thermal_history import ShipThermalHistory

from ..diurnal import DiurnalResult, DiurnalSettings, run_diurnal
from ..units import DAY, HOUR

__all__ = ["settings_from_scenario", "thermal_inputs", "run_scenario_thermal",
           "ship_thermal_history"]


def settings_from_scenario(scenario) -> DiurnalSettings:
    """The thermal settings of a :class:`~shipthermal.app.scenario.Scenario`."""
    s = scenario.solver
    return DiurnalSettings(time_step=s.time_step, night_step=s.night_step, scheme=s.scheme,
                           output_interval=scenario.time.output_interval,
                           spinup_tolerance=s.spinup_tolerance, spinup_max_days=s.spinup_max_days,
                           samples_per_face=s.samples_per_face, rays_per_face=s.rays_per_face,
                           seed=s.seed, backend=s.backend, jobs=s.jobs,
                           convection=(scenario.convection.per_part()
                                       if scenario.convection.parts
                                       else scenario.convection.model),
                           convection_roughness=dict(scenario.convection.roughness))


def thermal_inputs(scenario, ship=None) -> dict:
    """What the thermal stage receives from a scenario: the keyword arguments of
    :func:`~shipthermal.diurnal.run_diurnal` that carry the scenario — ``ship`` (default
    ``scenario.ship()``), ``environment`` (the run's one :meth:`Scenario.environment
    <shipthermal.app.scenario.Scenario.environment>`), ``settings``, per-part
    ``absorptivity`` and long-wave ``emissivity`` (every part name of the ship, sub-parts
    included) and ``checkpoint_interval`` [s]."""
    ship = ship if ship is not None else scenario.ship()
    return {"ship": ship, "environment": scenario.environment(),
            "settings": settings_from_scenario(scenario),
            "absorptivity": {p: scenario.solar_absorptivity(p) for p in ship.part_names},
            "emissivity": {p: scenario.longwave_emissivity(p) for p in ship.part_names},
            "checkpoint_interval": scenario.outputs.checkpoint_interval or HOUR}


def run_scenario_thermal(scenario, *, ship=None, progress: bool = True, checkpoint=None,
                         resume: bool = False, log=None, overrides: dict | None = None,
                         traced=None, graph=None, initial_state=None) -> DiurnalResult:
    """The thermal stage of a scenario: its ship, environment, optical properties and solver
    settings (one object, so nothing can disagree with the imaging stage).

    ``overrides`` may replace ``absorptivity`` / ``emissivity`` mappings (sensitivity runs).
    """
    inputs = thermal_inputs(scenario, ship)
    if overrides:
        inputs["absorptivity"] = overrides.get("absorptivity", inputs["absorptivity"])
        inputs["emissivity"] = overrides.get("emissivity", inputs["emissivity"])
    res = run_diurnal(**inputs, progress=progress, checkpoint=checkpoint, resume=resume,
                      log=log, traced=traced, graph=graph, initial_state=initial_state)
    res.meta["scenario"] = scenario.name
    res.meta["date"] = str(scenario.time.date)
    res.meta["season"] = scenario.time.season
    sensor = scenario.imaging.sensor
    res.meta["sensor_view_deg"] = [float(sensor.view_zenith_deg), float(sensor.view_azimuth_deg)]
    res.meta["weather_report"] = scenario.check_weather()
    return res


def ship_thermal_history(result: DiurnalResult):
    """The imaging stage's input (:class:`imaging.thermal_history.ShipThermalHistory`) from
    a diurnal run: outer-surface temperature of every ship triangle over the recorded day
    (or the whole weather record), with the air temperature and the sea's skin temperature
    (what the hull sees and reflects, and what the image's water radiates from). A record's
    face temperatures are read lazily from its outputs file."""
    s = result.ship
    times = result.record.times if result.record is not None else result.results.times
    return ShipThermalHistory(s.vertices, s.faces, s.face_part, s.part_names,
                              times, result.outer_face_temperature(),
                              temp_air=result.part_means["temp_air"].to_numpy(),
                              temp_sea=result.part_means["temp_sea_skin"].to_numpy(),
                              label=f"diurnal thermal run ({s.name})",
                              # a weather record is not periodic: no wrap past its end
                              period_s=None if result.is_record else DAY)
