"""Folding a time into a periodic axis has one rule (``shipthermal.units.fold_time``) and
every periodic axis uses it: the weather's cycle, the forcing's time tables, the ship's
thermal history and the background's day."""

import numpy as np

from shipthermal.units import DAY, fold_time


def test_fold_time_is_the_floor_mod_from_the_axis_origin():
    t = np.array([-DAY - 5.0, -5.0, 0.0, 5.0, DAY, DAY + 5.0, 3 * DAY + 7.5])
    np.testing.assert_array_equal(fold_time(t, DAY), [DAY - 5.0, DAY - 5.0, 0.0, 5.0, 0.0,
                                                      5.0, 7.5])
    # an axis that starts at 600 s: times fold into [600, 600 + period)
    np.testing.assert_array_equal(fold_time(t, DAY, 600.0),
                                  [DAY - 5.0, DAY - 5.0, DAY, DAY + 5.0, DAY, DAY + 5.0,
                                   DAY + 7.5])
    # whole periods away give the same time, bit for bit (the float mod is exact; the times
    # are quarter seconds so that s + k period is itself exact)
    rng = np.random.default_rng(7)
    s = rng.integers(0, 4 * int(DAY), 1000) / 4.0
    for k in (1, 2, 17, -3):
        np.testing.assert_array_equal(fold_time(s + k * DAY, DAY), fold_time(s, DAY))
    # python floats and numpy agree
    assert fold_time(-5.0, DAY) == float(np.mod(-5.0, DAY))


def test_every_periodic_axis_folds_with_the_one_rule():
    from shipthermal.environment import climate_day
    from shipthermal.forcing.tables import PeriodicTable
    from imaging.thermal_history import _interp_periodic

    w = climate_day("summer").weather()
    t = np.array([-3600.0, 5.0, 30 * 3600.0])
    np.testing.assert_array_equal(w.fold(t), fold_time(t, w.period))
    table = PeriodicTable(np.arange(0.0, DAY, 1800.0))
    assert table.weights(DAY + 900.0) == table.weights(900.0)
    times = np.arange(0.0, DAY, 3600.0)
    values = np.sin(times / DAY * 2 * np.pi)
    assert _interp_periodic(times, values, DAY + 1800.0, DAY) == _interp_periodic(
        times, values, 1800.0, DAY)
