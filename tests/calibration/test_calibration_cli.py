"""`shipthermal calibrate` end to end on a tiny scenario: exit 0, the products, the printed
summary; the fitted value agrees with the truth the measurements were made with."""

import json

import pandas as pd
import pytest

from shipthermal.app.calibration import _Case
from shipthermal.app.cli import main
from shipthermal.app.scenario import load_scenario

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "cli"))
from cli_helpers import write_tiny  # noqa: E402


@pytest.mark.slow                     # ~15 tiny model runs (about 20 s of CPU)
def test_calibrate_command_recovers_an_absorptivity(tmp_path, monkeypatch, capsys):
    sc_path = write_tiny(tmp_path, name="my")
    sc = load_scenario(sc_path)
    rows = pd.DataFrame([{"case": "my.toml", "hour": h, "target": "deck", "temperature_K": 0.0,
                          "sigma_K": 0.3, "split": s, "line": i + 2}
                         for i, (h, s) in enumerate([(10, "fit"), (13, "fit"), (16, "holdout")])])
    truth = _Case("my.toml", sc, rows).predict({"ship.solar_absorptivity.deck": 0.5})
    lines = ["case,time,target,temperature_K,sigma_K,split"]
    lines += [f"my.toml,{int(h):02d}:00,deck,{t:.3f},0.3,{s}"
              for (h, s), t in zip([(10, "fit"), (13, "fit"), (16, "holdout")], truth)]
    (tmp_path / "m.csv").write_text("\n".join(lines) + "\n")
    monkeypatch.chdir(tmp_path)
    code = main(["-q", "calibrate", "m.csv", "--unknown", "ship.solar_absorptivity.deck=0.2:0.95",
                 "--out", "runs/cal"])
    cap = capsys.readouterr()
    out = cap.out
    assert code == 0, cap.err
    assert "ship.solar_absorptivity.deck" in out and "held-out" in out
    d = tmp_path / "runs" / "cal"
    assert (d / "COMPLETE").exists()
    p = pd.read_csv(d / "calibration" / "calibration_parameters.csv")
    # the CLI runs at the scenario's own (tiny) resolution, as the truth was made
    assert abs(p["estimate"][0] - 0.5) < 0.01
    assert p["ci95_low"][0] <= 0.5 <= p["ci95_high"][0]
    js = json.loads((d / "calibration" / "calibration.json").read_text())
    assert js["summary"]["rms_holdout_K"] < 0.3
