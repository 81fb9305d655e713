"""The paper's case calibrated (slow: ~50 coarse model runs, several minutes): noon values
fitted, 07:00 summer / 08:00 winter held out. Pins today's held-out errors (a change that
moves them states why in its commit message, never to match the reference) and checks the
verdicts the closing note relies on."""

import pytest

#: variant → held-out RMS error [K] of the 07:00 summer / 08:00 winter reference values
EXPECTED_HELDOUT_RMS_K = {"cloud": 5.32, "absorptivity": 4.64}
UNTUNED_HELDOUT_RMS_K = 9.58
TOLERANCE_K = 0.5


@pytest.mark.slow
def test_paper_case_heldout_errors():
    from shipthermal.app.calibration import paper_calibration

    paper = paper_calibration()
    for name, expected in EXPECTED_HELDOUT_RMS_K.items():
        s = paper[name].summary
        assert abs(s["rms_holdout_K"] - expected) <= TOLERANCE_K, (name, s["rms_holdout_K"])
        assert abs(s["rms_untuned_holdout_K"] - UNTUNED_HELDOUT_RMS_K) <= TOLERANCE_K
        assert s["rms_holdout_K"] < s["rms_untuned_holdout_K"]
    # neither explanation fits inside its physical bounds: both sit on a bound
    assert any("bound" in f for f in paper["cloud"].flags)
    assert paper["absorptivity"].parameters["on_bound"].iloc[0] == "lower"
