"""Weather-record runs: spin-up on the record's first day, then the record as it is.

A coarse patrol boat (30-min steps) on two real days of NDBC buoy 44009 (tests/data).
"""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.thermal import run_scenario_thermal
from shipthermal.app.scenario import load_scenario

NDBC = Path(__file__).resolve().parents[1] / "data" / "weather" / "44009h2013_mar03-09.txt"


def _scenario(**weather):
    return load_scenario({
        "name": "buoy",
        "location": {"latitude": 38.46, "longitude": -74.70, "time_zone": "Etc/GMT+5"},
        "time": {"season": "winter", "date": "2013-03-04", "output_interval": 1800},
        "weather": {"source": str(NDBC), "day": "record", "days": 2, "wind_height": 5.0,
                    "cloud_cover": 0.5, **weather},
        "ship": {"builtin": "patrol_boat", "edge_length": 5.6},
        "solver": {"time_step": 1800, "spinup_max_days": 8, "spinup_tolerance": 0.02,
                   "rays_per_face": 16, "samples_per_face": 4}})


@pytest.fixture(scope="module")
def record_run():
    sc = _scenario()
    return sc, run_scenario_thermal(sc, progress=False)


def test_record_covers_every_day_and_follows_the_file(record_run):
    sc, res = record_run
    pm = res.part_means
    # every output time of both recorded days, closing midnight included
    np.testing.assert_allclose(pm.index.to_numpy(), np.arange(0, 48.01, 0.5))
    assert res.meta["record_days"] == 2 and res.days == res.meta["spinup_days"] + 2
    assert res.converged
    # air and sea in the outputs are the file's :50 values interpolated onto the clock
    lines = NDBC.read_text().splitlines()[2:]
    t = np.array([pd.Timestamp(f"{r[0]}-{r[1]}-{r[2]}T{r[3]}:{r[4]}Z").timestamp()
                  for r in (x.split() for x in lines)])
    atmp = np.array([float(x.split()[13]) for x in lines])
    wtmp = np.array([float(x.split()[14]) for x in lines])
    # on the hours; the half hours lie halfway between them (the weather is hourly)
    hours = pm.index.to_numpy()[::2]
    g = sc.start.timestamp() + hours * 3600.0
    for col, raw in (("temp_air", atmp), ("temp_sea", wtmp)):
        on = pm[col].to_numpy()
        np.testing.assert_allclose(on[::2], np.interp(g, t, raw) + 273.15, atol=1e-9)
        np.testing.assert_allclose(on[1::2], 0.5 * (on[:-1:2] + on[2::2]), atol=1e-9)
    # energy bookkeeping over spin-up and record: within Newton's stopping rule every step
    assert res.energy.max_step_imbalance <= res.settings.energy_tolerance


def test_record_starts_from_the_spun_up_day(record_run):
    """Day 1 of the record has the spin-up day's weather except in its last hour (the
    record goes on into day 2, the periodic day wraps to its own midnight): until 22:00
    the two must agree to the spin-up tolerance plus the solver's round-off."""
    sc, res = record_run
    from shipthermal.app.thermal import settings_from_scenario
    from shipthermal.diurnal import run_diurnal

    spin = run_diurnal(res.ship, sc.environment().first_day(), settings_from_scenario(sc),
                       absorptivity={p: sc.solar_absorptivity(p) for p in res.ship.part_names},
                       emissivity={p: sc.longwave_emissivity(p) for p in res.ship.part_names},
                       graph=res.graph, traced=res.forcing.traced, progress=False)
    a = spin.part_means.loc[:22.0, ["hull", "deck", "superstructure"]].to_numpy()
    b = res.part_means.loc[:22.0, ["hull", "deck", "superstructure"]].to_numpy()
    assert np.max(np.abs(a - b)) < 2 * sc.solver.spinup_tolerance + 1e-6
    # the record then departs from the repeated day (day 2 is other weather)
    c = res.part_means.loc[24.0:46.0, ["deck"]].to_numpy()
    assert np.max(np.abs(c - a[: len(c)])) > 0.5


# ---- windows, chained runs, interruptions: the same answer -------------------------------
@pytest.fixture(scope="module")
def three_days():
    """A 3-day record run in one window (the reference), face temperatures in float64."""
    from shipthermal.app.thermal import thermal_inputs
    from shipthermal.diurnal import run_record

    inputs = thermal_inputs(_scenario(days=3))
    inputs.pop("checkpoint_interval")
    ref = run_record(**inputs, progress=False, window_days=3, face_dtype=np.float64)
    inputs.update(graph=ref.graph, traced=ref.forcing.traced)
    return inputs, ref


def _max_change(a, b):
    """Largest |ΔT| between two record runs over every face and output time [K]."""
    assert np.array_equal(a.record.times, b.record.times)
    return float(np.max(np.abs(a.record.face_temperature[:] - b.record.face_temperature[:])))


def test_daily_windows_equal_one_window(three_days):
    """Forcing tables per day and the simulation continued under each (its whole state:
    BDF2 history, step lengths, surface temperatures) = one window over the three days, to
    round-off (each window's table rows are the whole record's; nothing is restarted)."""
    from shipthermal.diurnal import run_record

    inputs, ref = three_days
    daily = run_record(**inputs, progress=False, window_days=1, face_dtype=np.float64)
    assert ref.record.face_temperature.shape == (3 * 48 + 1, ref.ship.n_faces)
    assert _max_change(ref, daily) < 1e-9
    np.testing.assert_allclose(daily.part_means.to_numpy(), ref.part_means.to_numpy(),
                               rtol=0, atol=1e-9)
    np.testing.assert_array_equal(daily.energy.time, ref.energy.time)
    assert daily.energy.max_step_imbalance <= daily.settings.energy_tolerance


def test_chained_one_day_runs_equal_one_run(three_days, tmp_path):
    """Three calls of one day each, every one a fresh start from the checkpoint the one
    before left (its final state): the 3-day run to round-off."""
    from shipthermal.diurnal import run_record

    inputs, ref = three_days
    ckpt = tmp_path / "buoy.npz"
    for day in (1, 2, 3):
        res = run_record(**inputs, progress=False, face_dtype=np.float64, checkpoint=ckpt,
                         resume=True, end_day=day)
        assert res.record.times[-1] == day * 86400.0
        assert res.days == res.meta["spinup_days"] + day
    assert _max_change(ref, res) < 1e-9
    assert res.day_changes == ref.day_changes


def _interrupt_when_logged(inputs, ckpt, message):
    """A record run with checkpoints, stopped by Ctrl-C (raised by its progress log) when
    it logs a line starting with ``message``."""
    from shipthermal.diurnal import run_record

    def stop(msg):
        if msg.startswith(message):
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_record(**inputs, progress=False, face_dtype=np.float64, checkpoint=ckpt, log=stop)


def test_interrupted_record_resumes_to_the_uninterrupted_answer(three_days, tmp_path):
    """Ctrl-C after day 2 (raised by the progress log): the checkpoint of day 2 is on disk;
    the resumed run skips the spin-up and day 1-2 and ends where the uninterrupted one does,
    bit for bit."""
    from shipthermal.diurnal import run_record

    inputs, ref = three_days
    ckpt = tmp_path / "buoy.npz"
    _interrupt_when_logged(inputs, ckpt, "record day 2 of 3")
    with np.load(ckpt) as c:
        assert float(c["time"]) == 2 * 86400.0 and int(c["extra_record_day"]) == 2
    said = []
    res = run_record(**inputs, progress=False, face_dtype=np.float64, checkpoint=ckpt,
                     resume=True, log=said.append)
    assert said[0].startswith("record: resumed") and not any("spin-up" in m for m in said)
    np.testing.assert_array_equal(res.record.face_temperature[:], ref.record.face_temperature[:])
    pd.testing.assert_frame_equal(res.part_means, ref.part_means)
    np.testing.assert_array_equal(res.energy.imbalance, ref.energy.imbalance)
    assert res.days == ref.days and res.converged == ref.converged


def test_record_outputs_file_and_lazy_history(three_days):
    """The streamed file: units and times as attributes, float32 face temperatures by
    default, chunked by time; the imaging history reads the two rows around a time."""
    import h5py

    from shipthermal.app.thermal import ship_thermal_history
    from shipthermal.diurnal import run_record

    inputs, ref = three_days
    res = run_record(**inputs, progress=False, end_day=2)
    with h5py.File(res.record.path, "r") as f:
        ft = f["face_temperature"]
        assert ft.dtype == np.float32 and ft.attrs["units"] == "K"
        assert ft.chunks[1] == res.ship.n_faces and ft.shape == (2 * 48 + 1, res.ship.n_faces)
        assert f["times"].attrs["units"] == "s" and f.attrs["start"].startswith("2013-03-04")
        assert f.attrs["days_done"] == 2 and f.attrs["record_days"] == 3
        # float32 of the same run: 3e-5 K at 300 K
        np.testing.assert_allclose(ft[:], ref.record.face_temperature[:2 * 48 + 1], atol=4e-5,
                                   rtol=0)
    # the history outlives the result; the temporary folder of its file goes with the last
    # of them
    import gc

    hist = ship_thermal_history(res)
    folder = res.record.path.parent
    del res
    gc.collect()
    reads = []

    class Counted:
        shape, dtype = hist.face_temperature.shape, hist.face_temperature.dtype

        def __getitem__(self, key):
            reads.append(key)
            return hist.face_temperature[key]

    from imaging.thermal_history import ShipThermalHistory

    lazy = ShipThermalHistory(hist.vertices, hist.faces, hist.face_part, hist.part_names,
                              hist.times_s, Counted(), temp_air=hist.temp_air,
                              temp_sea=hist.temp_sea, period_s=None)
    t = 30.25 * 3600.0
    got = lazy.at(t)
    assert reads == [slice(60, 62)]
    want = 0.5 * (ref.record.face_temperature[60] + ref.record.face_temperature[61])
    np.testing.assert_allclose(got, want, atol=4e-5, rtol=0)
    assert lazy.temp_sea_at(t) == pytest.approx(0.5 * (ref.part_means["temp_sea_skin"].iloc[60]
                                                       + ref.part_means["temp_sea_skin"].iloc[61]))
    assert folder.is_dir()
    del hist, lazy, Counted
    gc.collect()
    assert not folder.exists()


# ------------------------------------------------------- a record split over processes ------
@pytest.fixture(scope="module")
def five_days(tmp_path_factory):
    """Five days of the buoy in one piece (the reference) and split over three processes
    (``solver.jobs = 3``: days 1–2, 3, 4–5; the last segment spun up on day 2 and run
    unrecorded through days 2–3), face temperatures in float64."""
    import dataclasses

    from shipthermal.app.thermal import thermal_inputs
    from shipthermal.diurnal import run_record

    inputs = thermal_inputs(_scenario(days=5))
    inputs.pop("checkpoint_interval")
    ref = run_record(**inputs, progress=False, face_dtype=np.float64)
    split_inputs = dict(inputs, settings=dataclasses.replace(inputs["settings"], jobs=3))
    folder = tmp_path_factory.mktemp("split")
    split = run_record(**split_inputs, progress=False, face_dtype=np.float64,
                       checkpoint=folder / "buoy.npz")
    return split_inputs, ref, split, folder


def test_a_record_split_over_processes_equals_one_piece(five_days):
    """Each segment after the first starts two days early from a spin-up on that day: the
    plates forget their start within hours (steel, 20–30 W m-2 K-1 at the surface: ~20 min
    time constants), so two days take the start-up difference to round-off."""
    _, ref, split, folder = five_days
    assert split.meta["record_segments"] == [[0, 2], [2, 3], [3, 5]]
    assert np.array_equal(split.record.times, ref.record.times)
    np.testing.assert_array_equal(split.energy.time, ref.energy.time)
    d = _max_change(ref, split)
    print(f"split over 3 processes against one piece: faces within {d:.1e} K")
    assert d < 1e-9
    np.testing.assert_allclose(split.part_means.to_numpy(), ref.part_means.to_numpy(),
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(split.results.cell_temperature, ref.results.cell_temperature,
                               rtol=0, atol=1e-9)
    assert split.energy.max_step_imbalance <= split.settings.energy_tolerance
    assert sorted(p.name for p in folder.glob("buoy*.npz")) == [
        "buoy.npz", "buoy.segment1.npz", "buoy.segment2.npz"]


def test_a_split_record_resumes_only_with_its_own_segments(five_days):
    """Four processes cut the record elsewhere (days 1, 2, 3–4, 5): the first segment's
    checkpoint holds days 1–2 of another cut, and resuming with it is refused, naming the
    file and the fix."""
    import dataclasses

    from shipthermal.diurnal import run_record
    from shipthermal.errors import InputError

    inputs, _, _, folder = five_days
    four = dict(inputs, settings=dataclasses.replace(inputs["settings"], jobs=4))
    with pytest.raises(InputError, match=r"buoy.npz.*days 1–2 .*another split.*solver.jobs"):
        run_record(**four, progress=False, checkpoint=folder / "buoy.npz", resume=True)


def test_an_interrupted_split_record_resumes_to_the_uninterrupted_answer(five_days, tmp_path):
    """Ctrl-C in the first segment after its first day: the other processes are stopped
    wherever they are; the resumed run ends where the uninterrupted split run does, bit for
    bit."""
    from shipthermal.diurnal import run_record

    inputs, _, split, _ = five_days
    ckpt = tmp_path / "buoy.npz"
    _interrupt_when_logged(inputs, ckpt, "record day 1 of 5")
    res = run_record(**inputs, progress=False, face_dtype=np.float64, checkpoint=ckpt,
                     resume=True)
    np.testing.assert_array_equal(res.record.face_temperature[:],
                                  split.record.face_temperature[:])
    np.testing.assert_array_equal(res.energy.imbalance, split.energy.imbalance)
    np.testing.assert_array_equal(res.results.cell_temperature, split.results.cell_temperature)


def test_a_worker_process_runs_a_split_record_in_one_piece(three_days, monkeypatch):
    """A daemonic process (a dask worker running a sweep's case) may not start processes:
    the record runs in one piece, as the reference, and says so."""
    import dataclasses
    import multiprocessing

    from shipthermal.diurnal import run_record

    inputs, ref = three_days
    worker = type("Worker", (), {"daemon": True})()
    monkeypatch.setattr(multiprocessing, "current_process", lambda: worker)
    said = []
    res = run_record(**dict(inputs, settings=dataclasses.replace(inputs["settings"], jobs=2)),
                     progress=False, face_dtype=np.float64, log=said.append)
    assert "record_segments" not in res.meta
    assert any("solver.jobs ignored" in m for m in said)
    assert _max_change(ref, res) < 1e-9


def test_a_record_that_does_not_fit_on_the_disk_is_refused_before_hdf5_writes(
        three_days, tmp_path, monkeypatch):
    """On a full disk HDF5 fails part-way and its file closes with an error of its own; the
    objects left behind crashed the interpreter when collected. The assembly checks the
    room first; the parts stay, and a resume with room assembles them."""
    import shutil

    from shipthermal.diurnal import run_record
    from shipthermal.errors import InputError

    inputs, ref = three_days
    ckpt = tmp_path / "buoy.npz"
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=2 ** 20))
    with pytest.raises(InputError) as info:
        run_record(**inputs, progress=False, face_dtype=np.float64, checkpoint=ckpt)
    msg = str(info.value)
    assert "record.h5" in msg and "1 MiB free" in msg and "--out" in msg, msg
    assert not list(tmp_path.rglob("*.h5"))
    monkeypatch.setattr(shutil, "disk_usage", real)
    said = []
    res = run_record(**inputs, progress=False, face_dtype=np.float64, checkpoint=ckpt,
                     resume=True, log=said.append)
    assert said[0].startswith("record: resumed")
    np.testing.assert_array_equal(res.record.face_temperature[:], ref.record.face_temperature[:])
