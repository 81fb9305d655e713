"""Supervised land-cover classification (paper §2.2): Gaussian maximum likelihood, JM
separability (eqs. 3–4), confusion matrix, overall accuracy and quadratic-weighted kappa
(eqs. 5–6).

The maximum-likelihood classifier is scikit-learn's ``QuadraticDiscriminantAnalysis``: one
full-covariance Gaussian per class, decision by the largest posterior. With equal priors (the
ENVI default the paper used) that is the maximum-likelihood rule.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass

import numpy as np
import pandas as pd
from sklearn.discriminant_analysis import QuadraticDiscriminantAnalysis
from sklearn.metrics import cohen_kappa_score, confusion_matrix

from shipthermal.errors import InputError, require
from shipthermal.figures import CLASS_COLOURS as PALETTE

from ..parameters import CLASS_NAMES, N_SPLITS

__all__ = [
    "CLASS_CODES",
    "CLASS_NAMES",
    "CLASS_COLOURS",
    "jm_distance_univariate",
    "bhattacharyya_distance",
    "jm_distance",
    "jm_table",
    "format_jm_table",
    "kappa_weighted",
    "read_roi",
    "split_training",
    "ClassificationResult",
    "classify_scene",
    "water_index_check",
    "N_SPLITS",
]

CLASS_CODES = tuple(CLASS_NAMES)
"""Class codes of the class map (0 = unclassified/fill): those of
:data:`imaging.parameters.CLASS_NAMES`."""
CLASS_COLOURS = {code: PALETTE[name] for code, name in CLASS_NAMES.items()}
"""Colour of each class code: :data:`shipthermal.figures.CLASS_COLOURS` (told apart under
colour-blindness)."""


# ---------------------------------------------------------------------------------------------
# Separability
# ---------------------------------------------------------------------------------------------

def jm_distance_univariate(m1, s1, m2, s2):
    """Jeffries–Matusita distance of two 1-D Gaussians (paper eqs. 3–4).

    Parameters
    ----------
    m1, m2 : float or array
        Feature means of the two classes [feature units].
    s1, s2 : float or array
        Feature standard deviations [feature units], > 0.

    Returns
    -------
    float or ndarray
        ``JM = 2 (1 - exp(-B))`` in [0, 2) [-].

    Notes
    -----
    Eq. 4: ``B = (m1-m2)^2 / (4 (s1^2+s2^2)) + 0.5 ln((s1^2+s2^2)/(2 s1 s2))``.
    """
    s1 = np.asarray(s1, dtype=float)
    s2 = np.asarray(s2, dtype=float)
    var = s1 ** 2 + s2 ** 2
    b = 0.125 * (np.asarray(m1) - np.asarray(m2)) ** 2 * 2.0 / var + 0.5 * np.log(var / (2 * s1 * s2))
    return 2.0 * (1.0 - np.exp(-b))


def bhattacharyya_distance(mean1, cov1, mean2, cov2) -> float:
    """Bhattacharyya distance of two multivariate Gaussians [-].

    ``B = 1/8 dm^T S^-1 dm + 1/2 ln(det S / sqrt(det S1 det S2))`` with ``S = (S1+S2)/2``;
    in one dimension this is the paper's eq. 4.
    """
    mean1, mean2 = np.atleast_1d(mean1).astype(float), np.atleast_1d(mean2).astype(float)
    cov1, cov2 = np.atleast_2d(cov1).astype(float), np.atleast_2d(cov2).astype(float)
    s = 0.5 * (cov1 + cov2)
    dm = mean1 - mean2
    term1 = 0.125 * dm @ np.linalg.solve(s, dm)
    _, logdet_s = np.linalg.slogdet(s)
    _, logdet_1 = np.linalg.slogdet(cov1)
    _, logdet_2 = np.linalg.slogdet(cov2)
    return float(term1 + 0.5 * (logdet_s - 0.5 * (logdet_1 + logdet_2)))


def jm_distance(mean1, cov1, mean2, cov2) -> float:
    """Jeffries–Matusita distance ``2 (1 - exp(-B))`` of two Gaussians [-] (eq. 3)."""
    return 2.0 * (1.0 - np.exp(-bhattacharyya_distance(mean1, cov1, mean2, cov2)))


def jm_table(features, labels, codes=CLASS_CODES, names=CLASS_NAMES) -> pd.DataFrame:
    """Pairwise multivariate JM separability of training samples (like the paper's Table 1).

    Parameters
    ----------
    features : ndarray (n_samples, n_features)
    labels : ndarray (n_samples,)
        Class codes.

    Returns
    -------
    DataFrame
        Symmetric, rows/columns named by class; the diagonal is NaN (a class against itself
        has JM = 0 by definition; the paper's table prints a placeholder there).
    """
    stats = {}
    for c in codes:
        x = features[labels == c]
        stats[c] = (x.mean(axis=0), np.cov(x, rowvar=False))
    k = len(codes)
    out = np.full((k, k), np.nan)
    for i, ci in enumerate(codes):
        for j, cj in enumerate(codes):
            if i != j:
                out[i, j] = jm_distance(*stats[ci], *stats[cj])
    cols = [names[c].capitalize() for c in codes]
    return pd.DataFrame(out, index=cols, columns=cols)


def format_jm_table(table: pd.DataFrame) -> str:
    """Text rendering of :func:`jm_table` in the layout of the paper's Table 1."""
    width = max(len(c) for c in table.columns) + 2
    lines = ["ROI".ljust(width) + "".join(c.rjust(width) for c in table.columns)]
    for name, row in table.iterrows():
        cells = ["-".rjust(width) if not np.isfinite(v) else f"{v:.3f}".rjust(width) for v in row]
        lines.append(name.ljust(width) + "".join(cells))
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Accuracy
# ---------------------------------------------------------------------------------------------

def kappa_weighted(confusion) -> float:
    """Quadratic-weighted kappa from a confusion matrix (paper eqs. 5–6).

    Parameters
    ----------
    confusion : array_like (N, N)
        Counts, rows = reference, columns = predicted.

    Returns
    -------
    float
        ``1 - sum(w O) / sum(w E)`` with ``w_ij = (i-j)^2/(N-1)^2`` and ``E`` the outer product
        of the marginals divided by the total [-].
    """
    o = np.asarray(confusion, dtype=float)
    n = o.shape[0]
    i, j = np.indices(o.shape)
    w = (i - j) ** 2 / (n - 1) ** 2
    e = np.outer(o.sum(axis=1), o.sum(axis=0)) / o.sum()
    return float(1.0 - (w * o).sum() / (w * e).sum())


# ---------------------------------------------------------------------------------------------
# Training samples
# ---------------------------------------------------------------------------------------------

ROI_VECTOR_SUFFIXES = (".json", ".geojson", ".gpkg", ".shp", ".zip")
"""Vector ROI files read with pyogrio (OGR): GeoJSON, GeoPackage, Shapefile (or zipped)."""

ROI_CLASS_FIELDS = ("class", "Class", "CLASS", "classname", "label", "code")
"""Attribute names looked up, in order, for the class of a ROI polygon."""


def _roi_code(value, where: str) -> int:
    by_name = {v: k for k, v in CLASS_NAMES.items()}
    if isinstance(value, str):
        code = by_name.get(value.strip().lower(), value.strip())
        try:
            code = int(code)
        except ValueError:
            pass
    elif isinstance(value, (int, np.integer, float, np.floating)) and float(value).is_integer():
        code = int(value)
    else:
        code = value
    require(code in CLASS_CODES, where, value,
            f"must be one of {list(CLASS_CODES)} or {list(CLASS_NAMES.values())}")
    return int(code)


def _read_roi_vector(path: str, grid) -> np.ndarray:
    """Polygons of any OGR vector format and CRS, reprojected and rasterised on the grid."""
    import warnings

    import pyogrio
    import shapely
    from rasterio.crs import CRS
    from rasterio.features import rasterize
    from rasterio.warp import transform_geom

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            meta, _, geoms, fields = pyogrio.raw.read(path)
    except Exception as exc:                     # pyogrio raises its own DataSourceError & co.
        raise InputError("roi_path", path, "must be a readable vector file (GeoJSON, GeoPackage, "
                         "Shapefile) of polygons", str(exc).splitlines()[0]) from None
    names = list(meta["fields"])
    col = next((f for f in ROI_CLASS_FIELDS if f in names), None)
    require(col is not None, "roi_path", path, f"must have a class attribute ({', '.join(ROI_CLASS_FIELDS[:3])}) "
            f"per polygon; found {names}", "Add a 'class' field: water/vegetation/land/building or 1-4")
    values = fields[names.index(col)]
    src_crs = meta.get("crs")
    if src_crs is None and path.lower().endswith((".json", ".geojson")):
        src_crs = "EPSG:4326"                    # RFC 7946: GeoJSON without a crs member is WGS 84 lon/lat
    require(src_crs is not None, "roi_path.crs", path, "the polygons must carry a CRS",
            "Save the file with its CRS (a .prj beside a Shapefile)")
    src_crs = CRS.from_user_input(src_crs)
    shapes = []
    t = grid.transform
    scene = shapely.box(t.c, t.f + grid.shape[0] * t.e, t.c + grid.shape[1] * t.a, t.f)
    outside = 0
    for n, (wkb, value) in enumerate(zip(geoms, values)):
        if wkb is None:
            continue
        geom = shapely.geometry.mapping(shapely.from_wkb(wkb))
        require(geom["type"] in ("Polygon", "MultiPolygon"), f"roi.features[{n}].geometry", geom["type"],
                "must be a Polygon or MultiPolygon")
        code = _roi_code(value, f"roi.features[{n}].{col}")
        if src_crs != grid.crs:
            geom = transform_geom(src_crs, grid.crs, geom)
        if not shapely.intersects(shapely.geometry.shape(geom), scene):
            outside += 1
        shapes.append((geom, code))
    require(bool(shapes), "roi_path", path, "must contain at least one polygon feature")
    require(outside < len(shapes), "roi_path", path,
            f"all {len(shapes)} polygons lie outside the scene (bounds {tuple(round(v) for v in scene.bounds)} "
            f"in {grid.crs}; the polygons' CRS is {src_crs})",
            "Draw the ROIs on this scene, or fix the file's CRS")
    return rasterize(shapes, out_shape=grid.shape, transform=grid.transform, fill=0, dtype="uint8")


def read_roi(path: str | os.PathLike, grid) -> np.ndarray:
    """Read regions of interest as a label raster on the scene grid.

    Parameters
    ----------
    path : path-like
        A vector file of polygons (GeoJSON, GeoPackage, Shapefile; any CRS, reprojected to
        the scene's; the class in a ``class`` attribute as code 1–4 or name; GeoJSON without
        a ``crs`` member is WGS 84 lon/lat per RFC 7946), rasterised with
        ``rasterio.features.rasterize``; or a GeoTIFF of class codes (0 = no sample) on the
        scene grid or a pixel-aligned raster covering it (e.g. of the uncropped scene).
    grid : SceneGrid

    Returns
    -------
    ndarray of uint8, shape ``grid.shape``

    Raises
    ------
    InputError
        Unreadable file, unknown class, no polygon in the scene, raster on another grid.
    """
    import json

    import rasterio

    path = os.fspath(path)
    require(os.path.isfile(path), "roi_path", path, "must be an existing GeoTIFF or vector file "
            "(GeoJSON, GeoPackage, Shapefile)")
    if path.lower().endswith((".json", ".geojson")):
        with open(path, encoding="utf-8") as fh:
            try:
                doc = json.load(fh)
            except json.JSONDecodeError as exc:
                raise InputError("roi_path", path, "must be valid GeoJSON", str(exc)) from None
        # Projected GeoJSON written by older tools names its CRS in a "crs" member; OGR reads
        # it. Without one, a GeoJSON whose coordinates are plainly not degrees is taken to be
        # in the scene CRS (the historical behaviour of this reader).
        if "crs" not in doc:
            coords = json.dumps([f.get("geometry") for f in doc.get("features", [])])
            nums = [abs(float(v)) for v in re.findall(r"-?\d+\.?\d*(?:[eE][-+]?\d+)?", coords)]
            if nums and max(nums) > 360:
                from rasterio.features import rasterize

                shapes = []
                for n, feat in enumerate(doc.get("features", [])):
                    props = feat.get("properties") or {}
                    value = next((props[f] for f in ROI_CLASS_FIELDS if f in props), None)
                    shapes.append((feat["geometry"], _roi_code(value, f"roi.features[{n}].properties.class")))
                require(bool(shapes), "roi_path", path, "must contain at least one polygon feature")
                out = rasterize(shapes, out_shape=grid.shape, transform=grid.transform, fill=0, dtype="uint8")
                require(bool(out.any()), "roi_path", path, "all polygons lie outside the scene",
                        "Draw the ROIs on this scene (coordinates in its CRS, or lon/lat)")
                return out
    if path.lower().endswith(ROI_VECTOR_SUFFIXES):
        return _read_roi_vector(path, grid)
    from rasterio.windows import Window

    try:
        src = rasterio.open(path)
    except rasterio.errors.RasterioIOError as exc:
        raise InputError("roi_path", path, "must be a readable label GeoTIFF or a vector file",
                         str(exc).splitlines()[0]) from None
    with src:
        if (src.height, src.width) == grid.shape and src.crs == grid.crs \
                and src.transform.almost_equals(grid.transform):
            return src.read(1).astype(np.uint8)
        # A ROI raster of the full Landsat scene used with a cropped scene: read the window
        # if the scene grid is a pixel-aligned part of it (same CRS and pixel size).
        t, g = src.transform, grid.transform
        col = (g.c - t.c) / t.a
        row = (g.f - t.f) / t.e
        aligned = (src.crs == grid.crs and abs(t.a - g.a) < 1e-9 * abs(t.a) and abs(t.e - g.e) < 1e-9 * abs(t.e)
                   and t.b == g.b == 0 and t.d == g.d == 0
                   and abs(col - round(col)) < 1e-6 and abs(row - round(row)) < 1e-6)
        col, row = int(round(col)), int(round(row))
        if not (aligned and 0 <= col and 0 <= row and col + grid.shape[1] <= src.width
                and row + grid.shape[0] <= src.height):
            raise InputError("roi_path", path, f"the ROI raster must be on the scene grid {grid.shape} {grid.crs} "
                             "or a pixel-aligned raster covering it",
                             "Rasterise the ROIs onto the Landsat grid, or give them as polygons")
        return src.read(1, window=Window(col, row, grid.shape[1], grid.shape[0])).astype(np.uint8)


def split_training(labels, test_fraction: float = 0.5, seed: int = 0, by: str = "pixels"):
    """Stratified random split of ROI pixels into training and held-out test masks.

    Parameters
    ----------
    labels : ndarray
        ROI class codes (0 = no sample).
    test_fraction : float
        Target share of each class's ROI pixels held out [-].
    seed : int
    by : {"pixels", "regions"}
        ``"pixels"`` draws pixels at random, so neighbouring pixels of one ROI polygon land in
        both sets and the held-out accuracy is optimistic (spatial autocorrelation).
        ``"regions"`` holds out whole ROI regions (8-connected components of a class), in
        random order, while that brings the held-out share nearer ``test_fraction``, keeping
        at least one region on each side; a class drawn as a single region falls back to
        pixels.

    Returns
    -------
    train, test : ndarray of bool
    """
    require(by in ("pixels", "regions"), "split", by, "must be 'pixels' or 'regions'")
    from scipy.ndimage import label as connected

    rng = np.random.default_rng(seed)
    train = np.zeros(labels.shape, dtype=bool)
    test = np.zeros(labels.shape, dtype=bool)
    flat = labels.ravel()
    for c in CLASS_CODES:
        if by == "regions":
            regions, n_regions = connected(labels == c, structure=np.ones((3, 3), bool))
            if n_regions >= 2:
                sizes = np.bincount(regions.ravel(), minlength=n_regions + 1)[1:]
                target = test_fraction * sizes.sum()
                held, count = [], 0
                for r in rng.permutation(n_regions):
                    # hold a region out when that brings the held-out count nearer the target
                    if abs(count + sizes[r] - target) < abs(count - target) and len(held) < n_regions - 1:
                        held.append(r + 1)
                        count += sizes[r]
                if not held:                       # every region larger than twice the target
                    held.append(int(np.argmin(sizes)) + 1)
                in_test = np.isin(regions, held)
                test |= in_test
                train |= (labels == c) & ~in_test
                continue
        idx = np.flatnonzero(flat == c)
        rng.shuffle(idx)
        n_test = int(round(test_fraction * idx.size))
        test.flat[idx[:n_test]] = True
        train.flat[idx[n_test:]] = True
    return train, test


# ---------------------------------------------------------------------------------------------
# Classification
# ---------------------------------------------------------------------------------------------

@dataclass
class ClassificationResult:
    """Class map and the accuracy figures of the paper's §2.2, over repeated held-out splits.

    Attributes
    ----------
    class_map : ndarray of uint8
        Class codes (0 = fill), from the model trained on **all** ROI pixels.
    jm : DataFrame
        JM separability of all ROI samples (eqs. 3–4, multivariate).
    confusion : DataFrame
        Held-out confusion matrix pooled over the splits (rows = reference, columns =
        predicted) [pixels].
    overall_accuracy : float
        Mean over the splits [-].
    kappa_quadratic : float
        sklearn ``cohen_kappa_score(weights="quadratic")``, mean over the splits [-].
    kappa_quadratic_eq5 : float
        Eqs. 5–6 (:func:`kappa_weighted`) per split, mean; cross-check of ``kappa_quadratic`` [-].
    kappa_unweighted : float
        Cohen's kappa without weights, mean over the splits [-].
    fractions : DataFrame
        Class fractions of the scene [-].
    n_train, n_test : dict[str, int]
        ROI pixels per class used by the final model, and held out per split (mean).
    model : QuadraticDiscriminantAnalysis
        The final model (all ROIs).
    split : str
        How the held-out samples were drawn (``"regions"`` or ``"pixels"``).
    splits : DataFrame
        One row per split: seed, overall accuracy, kappas, share of each class in the
        held-out map of that split's model, per-class recall.
    """

    class_map: np.ndarray
    jm: pd.DataFrame
    confusion: pd.DataFrame
    overall_accuracy: float
    kappa_quadratic: float
    kappa_quadratic_eq5: float
    kappa_unweighted: float
    fractions: pd.DataFrame
    n_train: dict
    n_test: dict
    model: QuadraticDiscriminantAnalysis
    split: str = "regions"
    splits: pd.DataFrame | None = None

    def spread(self) -> dict:
        """Mean, standard deviation, min and max over the splits of OA and kappas."""
        out = {}
        if self.splits is None:
            return out
        for col in ("overall_accuracy", "kappa_quadratic", "kappa_unweighted"):
            v = self.splits[col].to_numpy(float)
            out[col] = {"mean": float(v.mean()), "std": float(v.std(ddof=1)) if v.size > 1 else 0.0,
                        "min": float(v.min()), "max": float(v.max())}
        out["n_splits"] = int(len(self.splits))
        return out


def _check_training(labels_train, n_features: int, min_samples: int | None, what: str = "training"):
    need = max(2 * (n_features + 1), 20) if min_samples is None else min_samples
    for c in CLASS_CODES:
        n = int((labels_train == c).sum())
        if n < need:
            raise InputError(f"roi[{CLASS_NAMES[c]}].{what}_samples", n,
                             f"need at least {need} {what} pixels per class (a full covariance "
                             f"of {n_features} features needs > {n_features})",
                             f"Draw a larger region of interest for '{CLASS_NAMES[c]}'")


def predict_chunked(model, features, valid, chunk: int = 262_144) -> np.ndarray:
    """Predict class codes for the valid pixels in chunks (bounded memory); 0 elsewhere."""
    out = np.zeros(valid.shape, dtype=np.uint8)
    idx = np.flatnonzero(valid.ravel())
    flat = features.reshape(-1, features.shape[-1])
    for start in range(0, idx.size, chunk):
        sel = idx[start:start + chunk]
        out.flat[sel] = model.predict(flat[sel])
    return out


def _ml_model(x, y) -> QuadraticDiscriminantAnalysis:
    # sklearn's rank check is an absolute variance threshold (default 1e-4); reflectance
    # variances within a class are ~1e-6, so the default would reject a well-posed covariance.
    model = QuadraticDiscriminantAnalysis(priors=np.full(len(CLASS_CODES), 1.0 / len(CLASS_CODES)), tol=1e-12)
    return model.fit(x, y)


def classify_scene(features, roi_labels, test_fraction: float = 0.5, seed: int = 0,
                   min_samples: int | None = None, split: str = "regions",
                   n_splits: int = N_SPLITS) -> ClassificationResult:
    """Assess the Gaussian ML classifier on held-out ROIs over repeated splits, then train it
    on all ROI pixels and classify the scene.

    Parameters
    ----------
    features : ndarray (rows, cols, n_features)
        Per-pixel features (reflectances [-]); NaN marks fill / masked pixels.
    roi_labels : ndarray (rows, cols)
        ROI class codes, 0 = no sample.
    test_fraction : float
        Share of each class's ROI pixels held out per split.
    seed : int
        Seed of the first split; split ``k`` uses ``seed + k``.
    min_samples : int, optional
        Minimum training pixels per class (default ``max(2 (n_features+1), 20)``).
    split : {"regions", "pixels"}
        Hold out whole ROI regions (default: spatially independent test samples) or random
        pixels (:func:`split_training`).
    n_splits : int
        Number of held-out splits (>= 1); accuracy is reported as mean and spread.

    Raises
    ------
    InputError
        A class with too few training samples; features and ROI of different shapes.
    """
    if features.shape[:2] != roi_labels.shape:
        raise InputError("roi.shape", roi_labels.shape, f"must equal the scene shape {features.shape[:2]}")
    require(isinstance(n_splits, (int, np.integer)) and n_splits >= 1, "n_splits", n_splits,
            "must be an integer >= 1")
    valid = np.all(np.isfinite(features), axis=-1)
    labels = np.where(valid, roi_labels, 0)
    n_feat = features.shape[-1]
    names = [CLASS_NAMES[c] for c in CLASS_CODES]
    pooled = np.zeros((len(CLASS_CODES), len(CLASS_CODES)), dtype=np.int64)
    rows = []
    n_test_sum = {n: 0 for n in names}
    for k in range(int(n_splits)):
        train, test = split_training(labels, test_fraction, seed + k, split)
        _check_training(labels[train], n_feat, min_samples)
        model_k = _ml_model(features[train], labels[train])
        y_test = labels[test]
        y_pred = model_k.predict(features[test]).astype(np.uint8)
        cm = confusion_matrix(y_test, y_pred, labels=list(CLASS_CODES))
        pooled += cm
        recall = np.diag(cm) / np.maximum(cm.sum(axis=1), 1)
        rows.append({"seed": seed + k, "overall_accuracy": float(np.trace(cm) / cm.sum()),
                     "kappa_quadratic": float(cohen_kappa_score(y_test, y_pred, labels=list(CLASS_CODES),
                                                                weights="quadratic")),
                     "kappa_quadratic_eq5": kappa_weighted(cm),
                     "kappa_unweighted": float(cohen_kappa_score(y_test, y_pred, labels=list(CLASS_CODES))),
                     **{f"recall_{n}": float(r) for n, r in zip(names, recall)}})
        for n, c in zip(names, CLASS_CODES):
            n_test_sum[n] += int((y_test == c).sum())
    table = pd.DataFrame(rows)
    x_all, y_all = features[labels > 0], labels[labels > 0]
    model = _ml_model(x_all, y_all)
    class_map = predict_chunked(model, features, valid)
    counts = np.array([(class_map == c).sum() for c in CLASS_CODES], dtype=float)
    fractions = pd.DataFrame({"class": names, "pixels": counts.astype(int),
                              "fraction": counts / max(valid.sum(), 1)})
    return ClassificationResult(
        class_map=class_map,
        jm=jm_table(x_all, y_all),
        confusion=pd.DataFrame(pooled, index=[f"ref_{n}" for n in names], columns=[f"pred_{n}" for n in names]),
        overall_accuracy=float(table["overall_accuracy"].mean()),
        kappa_quadratic=float(table["kappa_quadratic"].mean()),
        kappa_quadratic_eq5=float(table["kappa_quadratic_eq5"].mean()),
        kappa_unweighted=float(table["kappa_unweighted"].mean()),
        fractions=fractions,
        n_train={CLASS_NAMES[c]: int((y_all == c).sum()) for c in CLASS_CODES},
        n_test={n: int(round(v / n_splits)) for n, v in n_test_sum.items()},
        model=model,
        split=split,
        splits=table,
    )


# ---------------------------------------------------------------------------------------------
# Spectral water index cross-check
# ---------------------------------------------------------------------------------------------

WATER_INDEX_THRESHOLD = 0.0
"""NDWI / MNDWI above which a pixel is open water (McFeeters 1996; Xu 2006)."""

WATER_DISAGREEMENT_FLAG = 0.05
"""Share of index-water not classed water (or of classed water not index-water) that flags
the classification [-]."""


def water_index_check(green, nir, swir1, class_map, water_code: int = 1,
                      flag_share: float = WATER_DISAGREEMENT_FLAG) -> dict:
    """Compare the water class with spectral water indices.

    Parameters
    ----------
    green, nir, swir1 : ndarray
        Reflectances of OLI bands 3, 5 and 6 [-] (NaN = masked).
    class_map : ndarray uint8
    water_code : int
    flag_share : float
        Disagreement share that raises the flag [-].

    Returns
    -------
    dict
        ``ndwi_water``/``mndwi_water`` pixel counts, ``missed_share`` (MNDWI water not
        classed water, over MNDWI water), ``extra_share`` (classed water with MNDWI < 0, over
        classed water), the same for NDWI, ``flag`` (bool) and ``message``; ``disagree``
        the per-pixel disagreement mask (MNDWI).

    Notes
    -----
    NDWI = (G - NIR)/(G + NIR) (McFeeters 1996, IJRS 17:1425); MNDWI = (G - SWIR1)/(G + SWIR1)
    (Xu 2006, IJRS 27:3025), which separates water from built-up land better. Water where
    the index > 0.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        ndwi = (green - nir) / (green + nir)
        mndwi = (green - swir1) / (green + swir1)
    classed = class_map == water_code
    ok = np.isfinite(ndwi) & np.isfinite(mndwi) & (class_map > 0)
    out: dict = {}
    for name, idx in (("mndwi", mndwi), ("ndwi", ndwi)):
        wet = ok & (idx > WATER_INDEX_THRESHOLD)
        out[f"{name}_water"] = int(wet.sum())
        out[f"{name}_missed_share"] = float((wet & ~classed).sum() / max(wet.sum(), 1))
        out[f"{name}_extra_share"] = float((ok & classed & ~wet).sum() / max((ok & classed).sum(), 1))
    out["classified_water"] = int((ok & classed).sum())
    miss, extra = out["mndwi_missed_share"], out["mndwi_extra_share"]
    out["flag"] = bool(miss > flag_share or extra > flag_share)
    out["message"] = (f"water class vs MNDWI > 0: {100 * miss:.1f} % of index water not classed water, "
                      f"{100 * extra:.1f} % of classed water not index water"
                      + (f" (above {100 * flag_share:.0f} %: check the water ROIs)" if out["flag"] else ""))
    out["disagree"] = ok & ((mndwi > WATER_INDEX_THRESHOLD) != classed)
    return out
