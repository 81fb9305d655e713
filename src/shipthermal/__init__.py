"""shipthermal: how a ship in a port looks to a space-based infrared sensor over a day or a
weather record, and when it fades into its background (thermal crossover).

The front door is one object from a scenario to the answer::

    import shipthermal as st
    sim = st.Simulation("my_port.toml")          # or st.Simulation.default("summer")
    res = sim.run()                              # thermal + background + imaging
    res.image("2023-07-15 13:00", "8-14")        # xarray.DataArray: x, y [m], CRS, units
    res.crossovers                               # tz-aware timestamps, band, direction
    res.report("out/report.html")

Exported here (imported on first use, so ``import shipthermal`` stays fast):
:class:`Simulation`, :class:`SimulationResult`, :class:`Scenario`, :func:`load_scenario`,
:func:`default_scenario`, :class:`InputError` and ``__version__``. The stages themselves
live in :mod:`shipthermal.app` (application layer) and in the physics packages
(:mod:`shipthermal.geometry`, :mod:`shipthermal.environment`, :mod:`shipthermal.diurnal`,
... and :mod:`imaging`).
"""

import os as _os

__all__ = ["Simulation", "SimulationResult", "Scenario", "load_scenario", "default_scenario",
           "InputError", "__version__"]

OMP_WAIT_POLICY = "PASSIVE"
"""How the idle threads of numba's OpenMP layer (libgomp) wait between parallel kernels,
unless the environment already says: asleep, not spinning. Spinning threads hold their cores;
when another process needs one, a kernel's barrier waits for a descheduled spinner. Measured
on 2 cores beside one busy process, 5000 launches of a 16,000-element kernel on 2 threads:
79 s spinning (libgomp's default) against 0.15 s passive; a 2 m frigate's record day went from
3 s to 60-120 s. Set here, in the package every module of both stages imports first, because
libgomp reads it once, when numba first starts its threads."""
_os.environ.setdefault("OMP_WAIT_POLICY", OMP_WAIT_POLICY)


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("shipthermal")
    except PackageNotFoundError:     # a source tree that was never installed
        return "0+unknown"


def __getattr__(name: str):
    # PEP 562: the exports are imported on first use, so that `import shipthermal` (run
    # before every `import shipthermal.<module>`) loads no numpy, pandas, scipy or
    # shipthermal.app (test_front_door); the chain alone takes about 2.5 s (measured)
    if name in ("Simulation", "SimulationResult"):
        from .app import chain

        value = getattr(chain, name)
    elif name in ("Scenario", "load_scenario", "default_scenario"):
        from .app import scenario

        value = getattr(scenario, name)
    elif name == "InputError":
        from .errors import InputError as value
    elif name == "__version__":
        value = _version()
    else:
        raise AttributeError(f"module 'shipthermal' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
