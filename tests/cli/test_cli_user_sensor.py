"""A user sensor end to end: ``[imaging.sensor] preset = "user"`` with a response file,
imaged by ``run --image`` under the band name ``user``."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from cli_helpers import write_tiny

from imaging.spectral_bands import read_response_file, user_band_names
from shipthermal.app.cli import main

SENSORS = Path(__file__).resolve().parents[1] / "data" / "sensors"


def _image(folder, name, extra, formats=("csv", "json")):
    sc = write_tiny(folder, name=name, extra=extra, formats=formats)
    out = folder / f"out_{name}"
    assert main(["-q", "run", str(sc), "--image", "--out", str(out)]) == 0
    return out / "imaging"


def test_a_user_band_equal_to_the_papers_images_the_same(tmp_path):
    """The 8-14 µm rectangle as a user's response file gives the paper's 8-14 µm band's
    frames: same atmosphere (the tables' own band there), emissivities, sea optics and
    products, so the metrics agree to the CSV's 7 digits."""
    (tmp_path / "rect.csv").write_text("wavelength_um,response\n8.0,1\n14.0,1\n")
    user = _image(tmp_path, "user", '[imaging.sensor]\npreset = "user"\n'
                                     'response_file = "rect.csv"\n')
    paper = _image(tmp_path, "paper", '[imaging]\nbands = ["8-14"]\n')
    a = pd.read_csv(user / "metrics_summer_user.csv")
    b = pd.read_csv(paper / "metrics_summer_8-14.csv")
    assert len(a) == len(b) > 100
    for col in ("contrast [W m-2 sr-1]", "mean_target [W m-2 sr-1]",
                "mean_background [W m-2 sr-1]", "path_radiance [W m-2 sr-1]", "tau_300k [-]"):
        np.testing.assert_allclose(a[col], b[col], rtol=2e-6, atol=1e-5, err_msg=col)
    assert "user" not in user_band_names()          # the name lives for the run only


@pytest.mark.parametrize("sensor", ["L7_Spectral_Response.txt"])
def test_a_real_sensors_response_file_is_imaged(sensor, tmp_path):
    """Landsat-7 ETM+ band 6 (USGS's response file, as downloaded): frames, crossovers and
    products of a band no preset has, and the run's report; the at-aperture brightness
    temperature is the band's Planck inverse of the at-aperture radiance."""
    from imaging.radiometry import brightness_temperature

    f = SENSORS / sensor
    img = _image(tmp_path, "l7", f'[imaging.sensor]\npreset = "user"\n'
                                 f'response_file = "{f.as_posix()}"\n',
                 formats=("csv", "json", "png", "html"))
    m = pd.read_csv(img / "metrics_summer_user.csv")
    assert len(m) > 100 and np.isfinite(m["contrast [W m-2 sr-1]"]).all()
    resp = read_response_file(f, "user")
    with xr.open_dataset(img / "images_summer_user.nc") as ds:
        rad = ds["radiance"].isel(time=0).values
        bt = ds["brightness_temperature"].isel(time=0).values
    ok = np.isfinite(rad) & np.isfinite(bt)
    np.testing.assert_allclose(bt[ok][:50], brightness_temperature(rad[ok][:50], resp),
                               atol=0.02)
    assert 250.0 < float(np.nanmean(bt)) < 320.0
    report = img.parent / "report.html"
    assert report.is_file() and "user" in report.read_text(encoding="utf-8")
