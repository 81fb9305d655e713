"""The parameter module: bands and their parser, ranges, per-part defaults."""

import numpy as np
import pytest

from shipthermal import parameters as P
from shipthermal.errors import InputError


@pytest.mark.parametrize("band, expected", [
    ("3-5", ("3-5", (3.0, 5.0))), ("LWIR", ("8-14", (8.0, 14.0))), ("mwir", ("3-5", (3.0, 5.0))),
    ("8-14 µm", ("8-14", (8.0, 14.0))), ("3.7-4.8um", ("3.7-4.8", (3.7, 4.8))),
    ([3, 5], ("3-5", (3.0, 5.0))), ((8.0, 14.0), ("8-14", (8.0, 14.0))),
    (np.array([10.0, 12.0]), ("10-12", (10.0, 12.0))), ((2.9, 14.5), ("2.9-14.5", (2.9, 14.5))),
])
def test_parse_band_accepts_names_aliases_strings_and_pairs(band, expected):
    assert P.parse_band(band) == expected


@pytest.mark.parametrize("band", ["9-11-13", "far", (2.8, 5.0), (8.0, 14.6), (5.0, 3.0),
                                  [True, 5], ("3", "5"), 7.0, (3.0,)])
def test_parse_band_rejects_with_the_allowed_range(band):
    with pytest.raises(InputError) as err:
        P.parse_band(band)
    assert err.value.field == "band"
    lo, hi = P.ATMOSPHERE_WAVELENGTH_UM
    assert f"{lo:g} <= lo < hi <= {hi:g}" in err.value.allowed


def test_imaging_uses_the_same_bands_and_parser():
    from imaging import atmosphere, radiometry

    assert atmosphere.parse_band is P.parse_band and atmosphere.BANDS is P.BANDS
    for name, (lo, hi) in P.BANDS.items():
        resp = radiometry.standard_band(name)
        assert (resp.wavelength_um[0], resp.wavelength_um[-1]) == (lo, hi)


def test_wind_speed_range():
    P.check_wind_speed("wind_speed", [0.0, P.WIND_SPEED_MAX])
    for bad in (-0.1, P.WIND_SPEED_MAX + 0.1):
        with pytest.raises(InputError) as err:
            P.check_wind_speed("scene.wind_speed", bad)
        assert err.value.field == "scene.wind_speed"


def test_part_defaults_cover_every_main_part():
    from shipthermal.geometry.parts import MAIN_PARTS, part_value

    for table in (P.LONGWAVE_EMISSIVITY, P.SOLAR_ABSORPTIVITY):
        for part in MAIN_PARTS + ("hull", "superstructure_funnel", "hull_dry_bow"):
            assert 0.0 < part_value(table, part) <= 1.0
    # the thermal stage's broadband emissivity is the imaging stage's 8-14 µm one
    assert all(P.LONGWAVE_EMISSIVITY[p] == P.BAND_EMISSIVITY[p]["8-14"] for p in P.BAND_EMISSIVITY)


def test_band_limits_are_the_atmosphere_tables_range():
    # the limits the parser accepts are those the embedded tables reach, to within one 5 cm-1
    # grid step (at 14.5 µm that is 14.5**2 * 5e-4 = 0.105 µm; at 2.9 µm 0.004 µm)
    from imaging.atmosphere import load_table

    lo, hi = P.ATMOSPHERE_WAVELENGTH_UM
    wl = load_table().wavelength_um
    assert abs(wl.min() - lo) <= lo ** 2 * 5e-4 and abs(wl.max() - hi) <= hi ** 2 * 5e-4


def test_table_view_zenith_limit_is_the_tables_last_node():
    # beyond the last view-zenith node the table backend would extrapolate
    from imaging.atmosphere import load_table
    from imaging.parameters import MAX_VIEW_ZENITH

    assert MAX_VIEW_ZENITH["table"] == load_table().nodes("view").max()
