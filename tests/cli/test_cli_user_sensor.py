"""A user sensor end to end: ``[imaging.sensor] preset = "user"`` with a response file,
imaged by ``run --image`` under the band name ``user`` (that it renders the frames a named
band would: ``tests/imaging/test_img_user_bands.py``)."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from cli_helpers import write_tiny

from shipthermal.optics.responses import read_response_file, user_band_names
from shipthermal.app.cli import main

SENSORS = Path(__file__).resolve().parents[1] / "data" / "sensors"


def _image(folder, name, extra, formats=("csv", "json")):
    sc = write_tiny(folder, name=name, extra=extra, formats=formats)
    out = folder / f"out_{name}"
    assert main(["-q", "run", str(sc), "--image", "--out", str(out)]) == 0
    return out / "imaging"


# slow (~2 min: a whole run with images and the HTML report); the default run keeps the
# user sensor's path from the scenario key to the images (test_scenario_reach) and its frames
# against the named band's (tests/imaging/test_img_user_bands.py)
@pytest.mark.slow
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
    assert "user" not in user_band_names()          # the name lives for the run only
    report = img.parent / "report.html"
    assert report.is_file() and "user" in report.read_text(encoding="utf-8")
