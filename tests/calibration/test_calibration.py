"""Calibration: recovery of known parameters from synthetic measurements made by the model
itself (with seeded noise), the interval covering the truth, and the measurement reader."""

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.calibration import (Unknown, _Case, calibrate, parse_unknown,
                                     read_measurements)
from shipthermal.errors import InputError
from shipthermal.app.scenario import default_scenario

#: very coarse runs for the test: 8 m mesh, few rays, hourly steps (the recovery is of the
#: model by itself, so the resolution does not matter, only that truth and fit share it)
TINY = {"ship.edge_length": 8.0, "solver.rays_per_face": 16, "solver.samples_per_face": 2,
        "solver.time_step": 3600.0, "time.output_interval": 3600.0,
        "solver.spinup_tolerance": 0.02}
TRUTH = {"ship.solar_absorptivity.deck": 0.55, "weather.wind_speed_offset": 1.2}
NOISE_K = 0.5


def test_synthetic_truth_is_recovered_within_its_interval():
    sc = default_scenario("summer").updated(TINY)
    where = [(6, "deck"), (9, "deck"), (12, "deck"), (15, "deck"), (12, "superstructure"),
             (12, "hull"), (22, "deck"), (14, "deck")]
    rows = pd.DataFrame([{"case": "summer", "hour": float(h), "target": t, "temperature_K": 0.0,
                          "sigma_K": NOISE_K, "split": "holdout" if i == 7 else "fit",
                          "line": i + 2} for i, (h, t) in enumerate(where)])
    truth = _Case("summer", sc, rows).predict(TRUTH)
    rng = np.random.default_rng(1)
    rows["temperature_K"] = truth + rng.normal(0.0, NOISE_K, len(truth))
    rows.attrs["sigma_given"] = True
    res = calibrate(rows, ["ship.solar_absorptivity.deck=0.3:0.95",
                           "weather.wind_speed_offset=-2:3"], {"summer": sc}, settings={})
    p = res.parameters.set_index("unknown")
    for key, value in TRUTH.items():
        assert p.loc[key, "ci95_low"] <= value <= p.loc[key, "ci95_high"], (key, p.loc[key])
        assert p.loc[key, "on_bound"] == ""
    # the interval is informative: much narrower than the bounds
    assert p.loc["ship.solar_absorptivity.deck", "std"] < 0.05
    assert p.loc["weather.wind_speed_offset", "std"] < 0.6
    # residuals at the noise level; the untuned start (α 0.85, no wind offset) is far off
    assert res.summary["rms_fit_K"] < 2 * NOISE_K
    assert res.summary["rms_untuned_fit_K"] > 4.0
    # the held-out 14:00 deck value is predicted within a few noise levels
    assert res.summary["rms_holdout_K"] < 4 * NOISE_K
    assert res.flags == []
    assert "Residuals" in res.text()


def test_parse_unknown_and_its_errors():
    u = parse_unknown("summer:ship.solar_absorptivity.deck=0.2:0.95:0.7")
    assert u == Unknown("ship.solar_absorptivity.deck", 0.2, 0.95, 0.7, "summer")
    assert parse_unknown("weather.cloud_cover_offset=-0.5:0.5").case is None
    for bad, frag in (("weather.cloud_cover_offset", "KEY=LOWER:UPPER"),
                      ("weather.cloud_cover_offset=a:b", "numbers"),
                      ("weather.cloud_cover_offset=1:0", "LOWER < UPPER"),
                      ("weather.cloud_cover_offset=0:1:2", "within the bounds")):
        with pytest.raises(InputError, match=frag):
            parse_unknown(bad)


def test_measurement_csv(tmp_path):
    f = tmp_path / "m.csv"
    f.write_text("# deck thermocouples\ncase,time,target,temperature_C,sigma_K,split\n"
                 "summer,12:00,deck,31.5,0.8,fit\nsummer,7.5,point:0 0 8,19.0,,holdout\n")
    m = read_measurements(f)
    assert m["hour"].tolist() == [12.0, 7.5]
    assert np.allclose(m["temperature_K"], [304.65, 292.15])
    assert m["sigma_K"].tolist() == [0.8, 1.0]
    assert m["split"].tolist() == ["fit", "holdout"]
    assert m.attrs["sigma_given"]
    for text, frag in (("case,time,target\nsummer,12:00,deck\n", "temperature_K"),
                       ("case,time,target,temperature_K\nsummer,noon,deck,300\n", "HH:MM"),
                       ("case,time,target,temperature_K\nsummer,12:00,deck,30\n", "150 and 500"),
                       ("case,time,target,temperature_K,split\nsummer,12,deck,300,test\n",
                        "'fit' or 'holdout'"),
                       ("case,time,target,temperature_K\nsummer,12,point:1 2,300\n", "point")):
        f.write_text(text)
        with pytest.raises(InputError, match=frag):
            read_measurements(f)
