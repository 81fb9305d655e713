"""The physical background's pieces that need no column solve: the ground of the synthetic
port at any site, the scene albedo, orientation groups, the anchoring inversion and the
scene-date rule."""

import numpy as np
import pandas as pd
import pytest

from imaging.background.physical import (ALBEDO_SAMPLES, MAX_SCENE_DAYS, Observation,
                                         broadband_albedo, ground_from_synthetic,
                                         orientation_bins)
from imaging.background.physical.anchoring import _fit_position, _scene_seconds
from imaging.background.synthetic import synthetic_surface, write_synthetic_port
from shipthermal.errors import InputError


def test_synthetic_ground_is_the_summer_port_at_any_site(tmp_path):
    # The physical builtin port has exactly the classes of the paper-path synthetic summer
    # port of the same seed (so the default mooring is the same harbour water), and its grid
    # follows the site: UTM zone and hemisphere from the location.
    port = write_synthetic_port(tmp_path, "summer", seed=7, size_px=90)
    s = synthetic_surface(seed=7, size_px=90)
    np.testing.assert_array_equal(s["class_map"], port.truth["class_map"])
    np.testing.assert_allclose(s["elevation"], port.truth["elevation"], atol=1e-4)
    south = ground_from_synthetic(-33.9, 18.4, size_px=90, seed=7)      # Cape Town
    assert south.grid.crs.to_epsg() == 32734
    np.testing.assert_array_equal(south.class_map, s["class_map"])
    assert "synthetic port" in south.label and "33.90 S" in south.label
    assert np.isnan(south.albedo[south.class_map == 1]).all()
    land = south.albedo[south.class_map != 1]
    assert 0.03 < np.percentile(land, 1) and np.percentile(land, 99) < 0.3


def test_liang_albedo_coefficients():
    # Liang (2001) Table 5 for TM/ETM+: a grey surface of reflectance r gives
    # (0.356 + 0.130 + 0.373 + 0.085 + 0.072) r - 0.0018 = 1.016 r - 0.0018
    r = np.array([0.0, 0.1, 0.5])
    a = broadband_albedo({b: r for b in (2, 4, 5, 6, 7)})
    np.testing.assert_allclose(a, 1.016 * r - 0.0018, atol=1e-15)
    with pytest.raises(InputError, match="needs OLI bands"):
        broadband_albedo({2: r, 4: r})


def test_orientation_bins_means():
    # level ground below 2 deg; 15-deg aspect sectors centred on north; circular means
    slope = np.array([[0.0, 1.9, 5.0, 6.0], [20.0, 20.0, 40.0, 10.0]])
    aspect = np.array([[0.0, 90.0, 355.0, 5.0], [180.0, 185.0, 270.0, 135.0]])
    idx, s, a = orientation_bins(slope, aspect)
    assert idx[0, 0] == idx[0, 1] == 0 and s[0] == 0.0          # level ground
    k = idx[0, 2]
    assert idx[0, 3] == k and s[k] == pytest.approx(5.5)        # one north-facing bin
    assert min(abs(a[k] - 0.0), abs(a[k] - 360.0)) < 1e-9         # circular mean of 355, 5
    j = idx[1, 0]
    assert idx[1, 1] == j and a[j] == pytest.approx(182.5)
    assert len(s) == 5


def test_albedo_fit_inverts_a_linear_response_exactly():
    # T(a) linear in albedo: the piecewise-linear inverse is exact inside the range, and the
    # residual is exactly what lies beyond the bounds
    k = ALBEDO_SAMPLES
    grid = np.tile(np.linspace(0.05, 0.35, k), (4, 1))
    t_ov = 320.0 - 60.0 * grid                                      # 317 K … 299 K
    lst = np.array([310.0, 317.0, 325.0, 290.0])
    pos, res = _fit_position(t_ov, lst)
    albedo = 0.05 + pos / (k - 1) * 0.30
    np.testing.assert_allclose(albedo[:2], (320.0 - lst[:2]) / 60.0, atol=1e-12)
    np.testing.assert_allclose(res, [0.0, 0.0, 325.0 - 317.0, 290.0 - 299.0], atol=1e-12)
    assert albedo[2] == pytest.approx(0.05) and albedo[3] == pytest.approx(0.35)


def _obs(when):
    return Observation(np.zeros((2, 2), np.float32), pd.Timestamp(when, tz="UTC"), "test", 1.5)


def test_scene_date_rule():
    start = pd.Timestamp("2023-07-15", tz="Europe/London")
    # periodic day: the scene's local clock time, whatever its date within the window
    s, note = _scene_seconds(_obs("2023-07-20 10:30"), start, 86100.0, periodic=True)
    assert s == pytest.approx(11.5 * 3600) and note is None          # BST = UTC+1
    # a record: the instant itself
    s, note = _scene_seconds(_obs("2023-07-17 10:30"), start, 5 * 86400.0, periodic=False)
    assert s == pytest.approx(2 * 86400 + 11.5 * 3600) and note is None
    # beyond the window: refused with the key, the distance and the fix
    far = start + pd.Timedelta(days=MAX_SCENE_DAYS + 2)
    with pytest.raises(InputError, match="background.mtl.*days away"):
        _scene_seconds(_obs(far.tz_convert("UTC").tz_localize(None)), start, 86100.0, True)
