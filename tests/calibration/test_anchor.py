"""The ASHRAE sol-air anchor: the formula in SI against the handbook's own units, and the
full model's sunlit dark deck against it (slow: one full diurnal run)."""

import numpy as np
import pytest

from shipthermal.app.anchor import sol_air


def _f_to_k(f):
    return (f - 32.0) * 5.0 / 9.0 + 273.15


def test_sol_air_in_si_equals_the_handbook_formula_in_ip_units():
    # ASHRAE in IP units: t_e = t_o + (α/h_o) I − 7 °F with α/h_o = 0.30 for a dark
    # horizontal surface; 90 °F air and 300 Btu/(h ft²) give 90 + 90 − 7 = 173 °F
    irradiance_si = 300.0 * 3.154591            # Btu/(h ft²) → W m-2
    te = sol_air(_f_to_k(90.0), irradiance_si)
    assert abs(te - _f_to_k(173.0)) < 0.01
    # vertical: no long-wave term
    assert abs(sol_air(_f_to_k(90.0), irradiance_si, horizontal=False) - _f_to_k(180.0)) < 0.01


@pytest.mark.slow
def test_sunlit_dark_deck_against_sol_air():
    from shipthermal.app.anchor import sol_air_anchor

    df = sol_air_anchor().set_index("surface")
    deck = df.loc["horizontal deck"]
    assert deck["faces"] > 50
    # below t_e by the heat the plate loses to the compartment under it: inside film
    # 2.5–8 W m-2 K-1 against h_o = 17 gives the expected band (anchor.INSIDE_FILM_RANGE)
    assert deck["expected_low_K"] <= deck["model_minus_sol_air_K"] <= deck["expected_high_K"]
    assert np.isfinite(df["model_minus_sol_air_K"]).all()
