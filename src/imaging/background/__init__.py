"""Port background from remote sensing (paper §2.1–2.4).

Landsat-8/9 readers, Level-1 and Level-2, with QA masks (:mod:`.landsat`), single-channel
LST (:mod:`.lst`), input checks that open every file (:mod:`.inputs`),
Gaussian maximum-likelihood classification with JM/confusion/kappa (:mod:`.classify`),
hourly met grids (:mod:`.met`) and Ordinary Kriging (:mod:`.kriging`), DEM slope/aspect and
the eq. 15 regression (:mod:`.terrain`), the pipeline (:mod:`.background`; its options
:class:`.settings.BackgroundSettings`, the overpass part :mod:`.overpass_products`), products
(:mod:`.outputs`) and the built-in synthetic port (:mod:`.synthetic`).

Entry point::

    from imaging.background import build_port_background
    bg = build_port_background("summer", out_dir="out/summer")
    bg.temperature_at(14.5)        # float32 K on bg.grid
"""

from .background import PortBackground, build_background_from_files, build_port_background
from .classify import CLASS_NAMES
from .landsat.grid import SceneGrid
from .settings import BackgroundSettings

__all__ = ["PortBackground", "BackgroundSettings", "build_background_from_files", "build_port_background",
           "CLASS_NAMES", "SceneGrid"]
