"""Classification: JM separability, kappa, Gaussian ML classifier, ROIs."""

import json

import numpy as np
import pytest
from scipy.integrate import quad, trapezoid
from scipy.stats import multivariate_normal, norm
from sklearn.metrics import cohen_kappa_score

from imaging.background.classify import (CLASS_CODES, bhattacharyya_distance, classify_scene, format_jm_table,
                                         jm_distance, jm_distance_univariate, jm_table, kappa_weighted, read_roi)
from imaging.background.landsat import SceneGrid, north_up_transform
from rasterio.crs import CRS
from shipthermal.errors import InputError


@pytest.mark.parametrize("m1,s1,m2,s2", [(0.0, 1.0, 1.0, 1.0), (0.1, 0.02, 0.13, 0.05), (5.0, 2.0, -1.0, 0.5)])
def test_jm_univariate_matches_bhattacharyya_integral(m1, s1, m2, s2):
    # Closed form of eq. 4 vs its definition B = -ln integral sqrt(p1 p2) dx (quadrature, ~1e-10).
    bc = quad(lambda x: np.sqrt(norm.pdf(x, m1, s1) * norm.pdf(x, m2, s2)), -np.inf, np.inf,
              epsabs=1e-13, epsrel=1e-12)[0]
    jm_ref = 2.0 * (1.0 - bc)
    assert jm_distance_univariate(m1, s1, m2, s2) == pytest.approx(jm_ref, abs=1e-9)
    assert jm_distance([m1], [[s1 ** 2]], [m2], [[s2 ** 2]]) == pytest.approx(jm_ref, abs=1e-9)


def test_jm_multivariate_independent_features_add():
    # For diagonal covariances the Bhattacharyya distance is the sum over features (exact).
    m1, m2 = np.array([0.1, 0.3, 0.2]), np.array([0.12, 0.25, 0.2])
    s1, s2 = np.array([0.01, 0.05, 0.02]), np.array([0.02, 0.04, 0.03])
    b_sum = sum(-np.log(1 - jm_distance_univariate(a, b, c, d) / 2) for a, b, c, d in zip(m1, s1, m2, s2))
    assert bhattacharyya_distance(m1, np.diag(s1 ** 2), m2, np.diag(s2 ** 2)) == pytest.approx(b_sum, rel=1e-12)


def test_jm_correlated_2d_vs_numerical_integral():
    # Correlated 2-D Gaussians: closed form vs the Bhattacharyya coefficient integrated on a fine
    # grid (trapezoid, h = 0.02 sigma: error < 1e-6).
    m1, c1 = np.array([0.0, 0.0]), np.array([[1.0, 0.6], [0.6, 1.0]])
    m2, c2 = np.array([1.0, -0.5]), np.array([[2.0, -0.3], [-0.3, 0.5]])
    x = np.arange(-9, 9, 0.02)
    xx, yy = np.meshgrid(x, x)
    pts = np.dstack([xx, yy])
    f = np.sqrt(multivariate_normal(m1, c1).pdf(pts) * multivariate_normal(m2, c2).pdf(pts))
    bc = trapezoid(trapezoid(f, x, axis=1), x)
    assert jm_distance(m1, c1, m2, c2) == pytest.approx(2 * (1 - bc), abs=1e-6)


def test_jm_table_from_samples_of_known_gaussians():
    # Sample estimates of JM converge to the closed form. With n = 100 000 samples per class the
    # mean difference is known to sqrt(2*0.3/n) = 2.4e-3 per feature, which moves B by ~1.2e-3
    # and JM (slope 2 exp(-B) ~ 1.7) by ~2.5e-3 (1 sigma): 1e-2 is a 4-sigma bound.
    rng = np.random.default_rng(0)
    means = {c: np.array([c * 0.5, -c * 0.2]) for c in CLASS_CODES}
    cov = np.array([[0.3, 0.05], [0.05, 0.2]])
    x = np.vstack([rng.multivariate_normal(means[c], cov, 100_000) for c in CLASS_CODES])
    y = np.repeat(CLASS_CODES, 100_000)
    table = jm_table(x, y)
    assert table.iloc[0, 1] == pytest.approx(jm_distance(means[1], cov, means[2], cov), abs=1e-2)
    assert table.iloc[0, 3] == pytest.approx(jm_distance(means[1], cov, means[4], cov), abs=1e-2)
    assert np.allclose(table.values, table.values.T, equal_nan=True)
    text = format_jm_table(table)
    assert text.splitlines()[0].split() == ["ROI", "Water", "Vegetation", "Land", "Building"]


def _labels_from_confusion(cm):
    ref, pred = [], []
    for i in range(cm.shape[0]):
        for j in range(cm.shape[1]):
            ref += [i] * cm[i, j]
            pred += [j] * cm[i, j]
    return np.array(ref), np.array(pred)


def test_kappa_of_known_confusion_matrix_by_hand():
    cm = np.array([[10, 2, 0], [1, 8, 1], [0, 3, 5]])
    # By hand, N = 30, row sums (12, 10, 8), column sums (11, 13, 6), w = (i-j)^2/4:
    #   sum w O = 0.25 (2 + 1 + 1 + 3) = 1.75
    #   sum w E = [0.25 (156 + 110 + 60 + 104) + 1 (72 + 88)] / 30 = 267.5 / 30
    #   kappa_q = 1 - 1.75 * 30 / 267.5 = 215 / 267.5
    # unweighted: p_o = 23/30, p_e = 310/900 -> kappa = 380/590
    assert kappa_weighted(cm) == pytest.approx(215 / 267.5, rel=1e-12)
    ref, pred = _labels_from_confusion(cm)
    assert cohen_kappa_score(ref, pred, weights="quadratic") == pytest.approx(215 / 267.5, rel=1e-12)
    assert cohen_kappa_score(ref, pred) == pytest.approx(380 / 590, rel=1e-12)


def _toy_scene(rng, n_per_side=60, sep=1.0):
    # 4 quadrants with Gaussian "reflectances"; ROIs = central squares of each quadrant.
    means = {1: [0.05, 0.03, 0.02], 2: [0.04, 0.35, 0.2], 3: [0.17, 0.23, 0.3], 4: [0.14, 0.16, 0.19]}
    n = n_per_side
    classes = np.zeros((2 * n, 2 * n), dtype=np.uint8)
    classes[:n, :n], classes[:n, n:], classes[n:, :n], classes[n:, n:] = 1, 2, 3, 4
    feats = np.empty((2 * n, 2 * n, 3))
    for c, m in means.items():
        k = classes == c
        feats[k] = np.asarray(m) * sep + 0.01 * rng.standard_normal((k.sum(), 3))
    roi = np.zeros_like(classes)
    for r0 in (0, n):
        for c0 in (0, n):
            roi[r0 + 10:r0 + 40, c0 + 10:c0 + 40] = classes[r0 + 10, c0 + 10]
    return feats, classes, roi


def test_qda_is_gaussian_maximum_likelihood():
    # Independent check: explicit Gaussian log-likelihood argmax with the training means and
    # (unbiased) covariances gives the same labels as sklearn's QDA with equal priors.
    rng = np.random.default_rng(1)
    feats, classes, roi = _toy_scene(rng)
    feats[..., 0] += 0.03 * rng.standard_normal(feats.shape[:2])   # some overlap
    res = classify_scene(feats, roi, seed=2)
    from imaging.background.classify import split_training
    train, _ = split_training(np.where(np.all(np.isfinite(feats), -1), roi, 0), 0.5, 2)
    flat = feats.reshape(-1, 3)
    ll = np.stack([multivariate_normal(feats[train & (roi == c)].mean(0),
                                       np.cov(feats[train & (roi == c)], rowvar=False)).logpdf(flat)
                   for c in CLASS_CODES], axis=-1)
    ml = np.asarray(CLASS_CODES)[ll.argmax(-1)].reshape(classes.shape)
    assert np.mean(ml == res.class_map) > 0.9999
    assert 0 < res.overall_accuracy <= 1 and res.kappa_quadratic == pytest.approx(res.kappa_quadratic_eq5, abs=1e-12)
    assert res.fractions["fraction"].sum() == pytest.approx(1.0)


def test_too_few_training_samples_is_an_error():
    rng = np.random.default_rng(2)
    feats, classes, roi = _toy_scene(rng)
    roi[roi == 2] = 0
    roi[10:14, 70:74] = 2          # 16 pixels, 8 left for training after the 50 % split
    with pytest.raises(InputError, match=r"roi\[vegetation\]\.training_samples = 8.*at least 20"):
        classify_scene(feats, roi)


def test_nan_features_are_left_unclassified():
    rng = np.random.default_rng(3)
    feats, classes, roi = _toy_scene(rng)
    feats[0, 0, 1] = np.nan
    res = classify_scene(feats, roi)
    assert res.class_map[0, 0] == 0 and res.class_map[0, 1] == 1


def test_geojson_roi_is_rasterised(tmp_path):
    grid = SceneGrid(north_up_transform(1000.0, 2000.0, 30.0, 30.0), CRS.from_epsg(32651), (20, 20))
    poly = {"type": "Polygon", "coordinates": [[[1030, 1970], [1150, 1970], [1150, 1880], [1030, 1880], [1030, 1970]]]}
    doc = {"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": poly,
                                                       "properties": {"class": "building"}}]}
    (tmp_path / "roi.geojson").write_text(json.dumps(doc))
    lab = read_roi(tmp_path / "roi.geojson", grid)
    # 120 m x 90 m = 4 x 3 pixels, starting at col 1, row 1
    assert (lab == 4).sum() == 12 and lab[1, 1] == 4 and lab[3, 4] == 4 and lab[4, 4] == 0
    doc["features"][0]["properties"]["class"] = "forest"
    (tmp_path / "bad.geojson").write_text(json.dumps(doc))
    with pytest.raises(InputError, match="properties.class"):
        read_roi(tmp_path / "bad.geojson", grid)


def test_region_split_keeps_roi_regions_whole():
    # Held-out pixels from the same polygon as training pixels are spatially autocorrelated
    # (optimistic accuracy): the default split holds out whole regions.
    from scipy.ndimage import label

    from imaging.background.classify import split_training

    roi = np.zeros((60, 60), np.uint8)
    for k, (r, c) in enumerate([(2, 2), (2, 20), (2, 40), (25, 2), (25, 20), (45, 40)]):
        roi[r:r + 8, c:c + 8 + k] = 1 + k % 2                   # 3 regions each of classes 1, 2
    roi[40:50, 2:12] = 3                                         # one region only: pixel fallback
    train, test = split_training(roi, 0.5, seed=1, by="regions")
    assert not (train & test).any() and ((train | test) == (roi > 0)).all()
    for c in (1, 2):
        regions, n = label(roi == c, structure=np.ones((3, 3), bool))
        assert n == 3
        for r in range(1, n + 1):
            m = regions == r
            assert train[m].all() or test[m].all()               # never split
        assert train[roi == c].any() and test[roi == c].any()    # both sides get a region
    m3 = roi == 3
    assert train[m3].sum() == test[m3].sum() == 50               # fallback: 50 / 50 pixels
    with pytest.raises(InputError, match="split.*'pixels' or 'regions'"):
        split_training(roi, 0.5, by="blocks")


def test_classify_scene_reports_its_split():
    rng = np.random.default_rng(4)
    feats, classes, roi = _toy_scene(rng)
    roi2 = roi.copy()
    roi2[roi == 1] = 0
    roi2[5:9, 5:9] = 1                                           # class 1 in two regions
    roi2[45:55, 45:55] = 1
    res = classify_scene(feats, roi2, min_samples=10)
    # n_test: mean held-out pixels over the splits (one region of 16 or 100 each time);
    # the final model is trained on all 116 ROI pixels of the class
    assert res.split == "regions" and 16 <= res.n_test["water"] <= 100
    assert res.n_train["water"] == 116
    assert len(res.splits) == 10 and set(res.splits["seed"]) == set(range(10))
