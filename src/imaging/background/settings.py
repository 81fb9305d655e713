"""The options of the file-based background chain (:func:`.background.build_background_from_files`)."""

from __future__ import annotations

from dataclasses import dataclass

from shipthermal.errors import check_range, require

from ..parameters import DEM_NODATA, N_SPLITS
from .lst import EMISSIVITY_PARAMETERS


@dataclass(frozen=True)
class BackgroundSettings:
    """How the background chain reads, classifies, kriges and extends a scene; each option
    is checked on construction and named when the chain does not know it.

    Attributes
    ----------
    season : str, optional
        Label only.
    utc_offset_hours : float
        Local standard time minus UTC [h].
    water_vapour : float, optional
        Column water vapour [g cm-2]; default: the met file's at the overpass (or its
        fallback, :func:`.met.met_for_scene`).
    variogram_model : str
        pykrige model fitted per hour.
    krige_coarsen : int
        Krige every n-th pixel then bilinear (1 = every pixel).
    lst_method : {"planck", "taylor"}
    emissivity_model : str
        NDVI-thresholds coefficient set (:data:`.lst.EMISSIVITY_PARAMETERS`): ``"tirs_b10"``
        (band-10 specific, default) or ``"tm6_sobrino2004"``.
    dem_nodata : {"error", "mask", "fill"}
        DEM voids over land: raise, mask explicitly (terrain term left out there; counted), or
        fill them from the surrounding elevations (:func:`.terrain.load_dem`; counted).
    residual_scaling : {"constant", "solar"}
        Diurnal weight ``w(t)`` of the Landsat class residual (:mod:`.background`).
    border_unmixing : bool
        Unmix land–water border pixels into a land and a water end-member
        (:mod:`.background`); False treats them as pure land or pure water by their class.
    test_fraction : float
        Share of ROI pixels held out for the confusion matrix.
    roi_split : {"regions", "pixels"}
        Hold out whole ROI regions (spatially independent, default) or random pixels
        (:func:`.classify.split_training`).
    seed : int
        Seed of the train/test split.
    bounds : (west, south, east, north), optional
        Crop the scene to this box in its projected CRS [m] (the port out of a full 185 km
        Landsat scene; widened to whole pixels). The DEM, met grid and ROIs are then used on
        the cropped grid.
    band_files : str or dict, optional
        Band files named differently on disk than in the MTL (:func:`.landsat.read_mtl`).
    use_qa : bool
        Mask fill, cloud, cirrus and cloud shadow from the quality band (QA_PIXEL / BQA) and
        fill those pixels from same-class neighbours (:func:`.overpass_products.build_overpass`).
    n_splits : int
        Held-out ROI splits for the accuracy (mean and spread); the map uses all ROIs.
    progress : bool
        Show a tqdm progress bar over the hourly kriging.
    met_variable : str, optional
        Temperature variable of the met file (default: detected).
    met_units : {"auto", "K", "degC", "degF"}
        Temperature unit of the met file (``auto``: its ``units`` attribute, checked).
    met_margin_cells : int
        Met cells kept around the scene for the kriging.
    krige_statistics : bool
        pykrige's leave-one-out statistics per hour (slow for large grids).

    """

    season: str | None = None
    utc_offset_hours: float = 8.0
    water_vapour: float | None = None
    variogram_model: str = "spherical"
    krige_coarsen: int = 5
    lst_method: str = "planck"
    emissivity_model: str = "tirs_b10"
    dem_nodata: str = "error"
    residual_scaling: str = "constant"
    border_unmixing: bool = True
    test_fraction: float = 0.5
    roi_split: str = "regions"
    seed: int = 0
    bounds: tuple | None = None
    band_files: str | dict | None = None
    use_qa: bool = True
    n_splits: int = N_SPLITS
    progress: bool = False
    met_variable: str | None = None
    met_units: str = "auto"
    met_margin_cells: int = 4
    krige_statistics: bool = False

    def __post_init__(self):
        require(self.dem_nodata in DEM_NODATA, "dem_nodata", self.dem_nodata,
                "must be " + ", ".join(repr(d) for d in DEM_NODATA[:-1]) + f" or {DEM_NODATA[-1]!r}")
        require(self.residual_scaling in ("constant", "solar"), "residual_scaling", self.residual_scaling,
                "must be 'constant' or 'solar'")
        require(self.lst_method in ("planck", "taylor"), "lst_method", self.lst_method,
                "must be 'planck' or 'taylor'")
        require(self.emissivity_model in EMISSIVITY_PARAMETERS, "emissivity_model", self.emissivity_model,
                f"must be one of {sorted(EMISSIVITY_PARAMETERS)}")
        check_range("utc_offset_hours", self.utc_offset_hours, -12.0, 14.0, unit="h")
