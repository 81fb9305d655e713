"""imaging: port background, radiometry, atmosphere, sensor, rendering and metrics.

The imaging stage of :mod:`shipthermal` (see :class:`shipthermal.Simulation` for the whole
chain). Exported here, imported on first use: :class:`~imaging.experiment.ImagingScenario`,
:func:`~imaging.experiment.render_series`, :func:`~imaging.experiment.run_experiment`,
:class:`~imaging.render.SceneRenderer`, :class:`~imaging.thermal_history.ShipThermalHistory`,
:func:`~imaging.metrics.local_scr`, :func:`~imaging.metrics.crossover_times`,
:func:`~shipthermal.optics.planck.band_radiance`,
:func:`~shipthermal.optics.planck.brightness_temperature`
and ``__version__`` (the ``shipthermal`` distribution's).
"""

__all__ = ["ImagingScenario", "render_series", "run_experiment", "SceneRenderer",
           "ShipThermalHistory", "local_scr", "crossover_times", "band_radiance",
           "brightness_temperature", "__version__"]


def __getattr__(name: str):
    # PEP 562: the exports are imported on first use, so that `import imaging` (run before
    # every `import imaging.<module>`) loads no numpy, scipy or pandas (test_front_door);
    # the experiment alone takes about 2 s (measured)
    if name in ("ImagingScenario", "render_series", "run_experiment"):
        from . import experiment

        value = getattr(experiment, name)
    elif name == "SceneRenderer":
        from .render import SceneRenderer as value
    elif name == "ShipThermalHistory":
        from .thermal_history import ShipThermalHistory as value
    elif name in ("local_scr", "crossover_times"):
        from . import metrics

        value = getattr(metrics, name)
    elif name in ("band_radiance", "brightness_temperature"):
        from shipthermal.optics import planck

        value = getattr(planck, name)
    elif name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("shipthermal")
        except PackageNotFoundError:
            value = "0+unknown"
    else:
        raise AttributeError(f"module 'imaging' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
