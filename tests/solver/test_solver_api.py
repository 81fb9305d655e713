"""The solver API: bad input, checkpoints, outputs, part means."""

import math

import numpy as np
import pytest

from shipthermal.conditions import (Convection, ConvectionLaw, FixedTemperature, HeatFlux,
                                   SurfaceBalance)
from shipthermal.errors import InputError
from shipthermal.materials import Layer, Layup, Material
from shipthermal.mesh import check_closed_surface
from shipthermal.model import ThermalModel
from shipthermal.simulation import Simulation, steady_state
from solver_meshes import SQUARE_F, SQUARE_V, plate_graph


def _model(**kw):
    g = plate_graph(0.01, 3)
    omega = 2 * math.pi / 86400
    outer = SurfaceBalance(absorbed_shortwave=lambda t: 400 * max(math.sin(omega * t), 0.0),
                           emissivity=0.9, temp_env=270.0, h=10.0, temp_air=293.0)
    return ThermalModel(g, {"plate:outer": outer, "plate:inner": Convection(3.0, 295.0)},
                        initial_temperature=290.0, **kw)


# ------------------------------------------------------------------ bad input ---------------
@pytest.mark.parametrize("make,field,allowed", [
    (lambda: Layup((Layer("mild_steel", -0.01),)), "thickness", "> 0"),
    (lambda: Layup((Layer("mild_steel", 0.0),)), "thickness", "> 0"),
    (lambda: Layup((Layer("unobtainium", 0.01),)), "material", "unknown material"),
    (lambda: Material("x", 7800.0, 0.0, 50.0), "specific_heat", "> 0"),
    (lambda: Simulation(_model(), 0.0, 100.0), "time_step", "> 0"),
    (lambda: Simulation(_model(), -5.0, 100.0), "time_step", "> 0"),
    (lambda: Simulation(_model(), 10.0, 100.0, scheme="rk4"), "scheme", "must be one of"),
    (lambda: Simulation(_model(), 10.0, 100.0, output_interval=15.0), "output_interval", "multiple"),
    (lambda: ThermalModel(plate_graph(0.01, 2), initial_temperature=float("nan")),
     "initial_temperature", "finite"),
    (lambda: ThermalModel(plate_graph(0.01, 2), {"plate:outr": Convection(5.0, 290.0)}),
     "conditions['plate:outr']", "unknown patch"),
    (lambda: ThermalModel(plate_graph(0.01, 2), {"plate:outer": Convection(5.0, float("nan"))}),
     "temp_fluid", "finite"),
    (lambda: ThermalModel(plate_graph(0.01, 2), {"plate:outer": Convection(-1.0, 290.0)}),
     ".h", "≥ 0"),
    (lambda: ThermalModel(plate_graph(0.01, 2), {"plate:outer": SurfaceBalance(emissivity=1.2, temp_env=260.0)}),
     "emissivity", "[0, 1]"),
    (lambda: ThermalModel(plate_graph(0.01, 2), {"plate:outer": HeatFlux(np.ones(5))}),
     "flux", "one value per face"),
    (lambda: check_closed_surface(SQUARE_V, SQUARE_F), "surface", "closed (watertight)"),
    (lambda: steady_state(ThermalModel(plate_graph(0.01, 2), {"plate:outer": HeatFlux(10.0)})),
     "conditions", "steady state needs"),
])
def test_bad_input_names_field_and_allowed(make, field, allowed):
    with pytest.raises(InputError) as info:
        make()
    msg = str(info.value)
    assert field in msg and allowed in msg, msg


def _later(bad, good):
    """A value that turns bad after the first steps (the model's check at t = 0 passes)."""
    return lambda t: bad if t > 25.0 else good


_LAW = dict(natural=np.zeros((2, 6)), multiplier=1.0, normal_z=0.0)


@pytest.mark.parametrize("condition,field,allowed", [
    (HeatFlux(_later(float("nan"), 10.0)), "conditions['plate:outer'].flux", "finite"),
    (Convection(_later(-1.0, 5.0), 290.0), "conditions['plate:outer'].h", "≥ 0"),
    (Convection(5.0, _later(float("inf"), 290.0)), "temp_fluid", "finite"),
    (SurfaceBalance(emissivity=_later(1.2, 0.9), temp_env=260.0), "emissivity", "[0, 1]"),
    (SurfaceBalance(absorbed_shortwave=_later(np.array([0.0, np.nan]), 0.0)), "absorbed_shortwave",
     "finite"),
    (FixedTemperature(_later(-5.0, 290.0)), "temperature", "> 0 K"),
    (Convection(5.0, 290.0, law=ConvectionLaw(blend=_later(0.5, 3.0), **_LAW)), "law.blend",
     "≥ 1"),
])
def test_a_value_that_turns_bad_during_a_run_is_named(condition, field, allowed):
    # the steps fill the forcing without the per-value checks and check the joined arrays
    # in one pass; a bad value is then named as the checks at t = 0 would name it
    model = ThermalModel(plate_graph(0.01, 2), {"plate:outer": condition,
                                                "plate:inner": Convection(3.0, 295.0)},
                         initial_temperature=290.0)
    sim = Simulation(model, 10.0, 100.0)
    with pytest.raises(InputError) as info:
        sim.run_until(100.0)
    msg = str(info.value)
    assert field in msg and allowed in msg, msg


def test_the_steps_forcing_equals_the_checked_one():
    model = _model()
    for t in (0.0, 3600.0, 43200.0 + 17.0):
        fast, checked = model.forcing(t), model._fill(t, check=True)
        for name in ("fixed", "temp_fixed", "q0", "h", "temp_fluid", "emissivity",
                     "longwave_in", "law_index", "law_natural"):
            assert np.array_equal(getattr(fast, name), getattr(checked, name)), name


def test_self_intersecting_surface_rejected():
    import trimesh

    a = trimesh.creation.box(extents=(1, 1, 1))
    b = trimesh.creation.box(extents=(1, 1, 1))
    b.apply_translation((0.5, 0.5, 0.5))
    both = trimesh.util.concatenate([a, b])
    with pytest.raises(InputError, match="must not intersect itself"):
        check_closed_surface(both.vertices, both.faces)


# ------------------------------------------------------------- checkpoints ------------------
@pytest.mark.parametrize("scheme", ["crank_nicolson", "bdf2"])
def test_checkpoint_resume_reproduces_uninterrupted_run(tmp_path, scheme):
    full = Simulation(_model(), 300.0, 86400.0, scheme=scheme, output_interval=3600.0).run()
    first = Simulation(_model(), 300.0, 86400.0, scheme=scheme, output_interval=3600.0)
    first.run_until(43200.0)
    path = first.save_checkpoint(tmp_path / "ck.npz")
    del first
    again = Simulation(_model(), 300.0, 86400.0, scheme=scheme, output_interval=3600.0)
    again.load_checkpoint(path)
    res = again.run()
    np.testing.assert_array_equal(res.times, full.times)
    # Same state, same equations; only the preconditioner is rebuilt from a later Jacobian
    # after the resume, so the converged solves may differ in the last bit (measured 2e-16).
    np.testing.assert_allclose(res.cell_temperature, full.cell_temperature, rtol=1e-13, atol=0)
    assert len(res.energy.imbalance) == len(full.energy.imbalance) == 288
    other = Simulation(_model(), 600.0, 86400.0, scheme=scheme)
    with pytest.raises(InputError, match="different setup"):
        other.load_checkpoint(path)


def test_checkpoints_write_each_record_once_and_resume_from_any(tmp_path, monkeypatch):
    """Each checkpoint writes only the records taken since the one before (a day's hourly
    checkpoints rewrote the whole day so far: 5.9 GB for the frigate at 0.5 m); a resume
    reads them all back in order; after the records are cleared a fresh list starts and
    the old files go once the new checkpoint is in place; a checkpoint whose write failed
    leaves the one before readable with its files; removal takes the files along."""
    from shipthermal import checkpoint as ck

    kw = dict(scheme="bdf2", output_interval=3600.0)
    path = tmp_path / "ck.npz"
    folder = tmp_path / "ck.npz.records"
    sim = Simulation(_model(), 300.0, 2 * 86400.0, **kw)
    for hour in (5, 6, 12):
        sim.run_until(hour * 3600.0)
        sim.save_checkpoint(path)
    with np.load(path) as d:
        counts = [int(c) for c in d["records_counts"]]
    # records at 0, 1, …, 12 h: 6 + 1 + 6, each written once
    assert counts == [6, 1, 6]
    assert sorted(f.name.split("-")[1] for f in folder.iterdir()) == \
        ["00000.npz", "00001.npz", "00002.npz"]

    def resumed(at=path):
        again = Simulation(_model(), 300.0, 2 * 86400.0, **kw)
        again.load_checkpoint(at)
        return again

    back = resumed()
    np.testing.assert_array_equal(back.results().times, sim.results().times)
    np.testing.assert_array_equal(back.results().cell_temperature,
                                  sim.results().cell_temperature)
    np.testing.assert_array_equal(back.results().face_flow, sim.results().face_flow)
    # the resumed run goes on appending to the same list
    back.run_until(14 * 3600.0)
    back.save_checkpoint(path)
    with np.load(path) as d:
        assert [int(c) for c in d["records_counts"]] == [6, 1, 6, 2]
    old = sorted(folder.iterdir())
    # cleared: a fresh list (one file); the old list's four files are gone
    back.clear_records()
    back.run_until(16 * 3600.0)
    back.save_checkpoint(path)
    now = sorted(folder.iterdir())
    assert len(now) == 1 and not set(now) & set(old)
    np.testing.assert_array_equal(resumed().results().times, [15 * 3600.0, 16 * 3600.0])

    # the next checkpoint's own write fails after its record file: the last one stands
    real = np.savez

    def fail_main(file, **arrays):
        if "records_token" in arrays:
            raise OSError(28, "No space left on device", str(file))
        return real(file, **arrays)

    back.run_until(18 * 3600.0)
    monkeypatch.setattr(ck.np, "savez", fail_main)
    with pytest.raises(OSError, match="ck.npz"):
        back.save_checkpoint(path)
    monkeypatch.setattr(ck.np, "savez", real)
    last = resumed()
    assert last.time == 16 * 3600.0
    np.testing.assert_array_equal(last.results().times, [15 * 3600.0, 16 * 3600.0])
    assert sorted(folder.iterdir()) == now          # the failed write took its file back
    # a listed record file missing: named, with the way out
    now[0].unlink()
    with pytest.raises(InputError, match=f"lists the record file {now[0].name}.*missing"):
        resumed()
    ck.remove_checkpoint(path)
    assert list(tmp_path.iterdir()) == []


def test_a_checkpoint_holding_its_records_itself_still_resumes(tmp_path):
    """Checkpoints written before the records had files of their own held them inline
    (``rec_times``, ``rec_cell``, ``rec_face``, ``rec_flow``): they resume as before."""
    kw = dict(scheme="bdf2", output_interval=3600.0)
    sim = Simulation(_model(), 300.0, 86400.0, **kw)
    sim.run_until(5 * 3600.0)
    path = sim.save_checkpoint(tmp_path / "ck.npz")
    res = sim.results()
    with np.load(path) as d:
        arrays = {k: d[k] for k in d.files if not k.startswith("records_")}
    arrays.update(rec_times=res.times, rec_cell=res.cell_temperature,
                  rec_face=res.face_temperature, rec_flow=res.face_flow)
    old = tmp_path / "old.npz"
    np.savez(old, **arrays)
    again = Simulation(_model(), 300.0, 86400.0, **kw)
    again.load_checkpoint(old)
    np.testing.assert_array_equal(again.results().cell_temperature, res.cell_temperature)
    np.testing.assert_array_equal(again.results().times, res.times)
    # its next checkpoint starts a list of record files with all of them
    again.run_until(6 * 3600.0)
    again.save_checkpoint(old)
    with np.load(old) as d:
        assert [int(c) for c in d["records_counts"]] == [7]


# --------------------------------------------------------------- outputs --------------------
def test_vtu_and_vtkhdf_read_back(tmp_path):
    import pyvista as pv
    import vtk

    res = Simulation(_model(), 600.0, 7200.0, scheme="bdf2", output_interval=3600.0).run()
    files = res.to_vtu(tmp_path / "vtu")
    grid = pv.read(files[0])
    np.testing.assert_allclose(grid.cell_data["temperature_K"], res.cell_temperature[0], atol=1e-4)
    np.testing.assert_array_equal(grid.cell_data["part_id"], res.graph.cell_part)
    assert (tmp_path / "vtu" / "thermal.pvd").exists()
    series = pv.get_reader(tmp_path / "vtu" / "thermal.pvd")         # pyvista sees the times
    assert series.time_values == pytest.approx(list(res.times))
    surf = pv.read(tmp_path / "vtu" / "thermal_surface_0002.vtp")
    np.testing.assert_allclose(surf.cell_data["temperature_K"], res.face_temperature[2], atol=1e-4)

    path = res.to_vtkhdf(tmp_path / "run.vtkhdf", time_units="s since 2023-07-15 00:00:00+08:00")
    reader = vtk.vtkHDFReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    assert reader.GetNumberOfSteps() == len(res.times)
    for k in range(len(res.times)):
        reader.SetStep(k)
        reader.Update()
        out = pv.wrap(reader.GetOutput())
        assert out.n_cells == res.graph.n_cells
        np.testing.assert_allclose(out.cell_data["temperature_K"], res.cell_temperature[k], atol=1e-4)
        np.testing.assert_array_equal(out.cell_data["part_id"], res.graph.cell_part)
        assert list(out.field_data["part_names"]) == list(res.graph.part_names)
        assert out.field_data["Time"][0] == pytest.approx(res.times[k])
    # pyvista's own reader: a step by its index, with its time
    r = pv.get_reader(path)
    r.reader.SetStep(len(res.times) - 1)
    last = r.read()
    np.testing.assert_allclose(last["temperature_K"], res.cell_temperature[-1], atol=1e-4)
    assert last.field_data["Time"][0] == pytest.approx(res.times[-1])
    import h5py

    with h5py.File(path) as f:          # units for HDF5 readers
        assert f["VTKHDF/CellData/temperature_K"].attrs["units"] == "K"
        assert f["VTKHDF/Steps"].attrs["time_units"].startswith("s since 2023-07-15")
    assert not list(tmp_path.rglob("*.tmp*"))


def test_a_vtkhdf_file_that_does_not_fit_is_refused_before_hdf5_writes(tmp_path, monkeypatch):
    # HDF5 failing part-way on a full disk hid the error and crashed the interpreter later
    import shutil

    res = Simulation(_model(), 600.0, 7200.0, scheme="bdf2", output_interval=3600.0).run()
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=2 ** 20))
    with pytest.raises(InputError) as info:
        res.to_vtkhdf(tmp_path / "out" / "run.vtkhdf")
    msg = str(info.value)
    assert "run.vtkhdf" in msg and "1 MiB free" in msg and "--out" in msg, msg
    assert not list(tmp_path.rglob("*.vtkhdf")) and not list(tmp_path.rglob("*.hdf"))


def test_part_means_area_weighted():
    res = Simulation(_model(), 600.0, 3600.0, output_interval=3600.0).run()
    df = res.part_mean("outer")
    g = res.graph
    idx = g.patch_faces("plate:outer")
    w = g.bface_area[idx]
    np.testing.assert_allclose(df["plate"].to_numpy(), res.face_temperature[:, idx] @ w / w.sum())
    assert list(res.part_mean("outer", groups={"plate": "hull"}).columns) == ["hull"]


def test_fixed_temperature_plate_steady_is_linear():
    # Fourier's law through a two-layer wall: the flux is (T1 − T2) / Σ(d/k).
    lay = Layup((Layer("mild_steel", 0.01, 4), Layer("mineral_wool", 0.05, 10)))
    from shipthermal.mesh import build_shell_graph

    g = build_shell_graph(SQUARE_V, SQUARE_F, np.zeros(2, int), ["w"], {"w": lay})
    m = ThermalModel(g, {"w:outer": FixedTemperature(320.0), "w:inner": FixedTemperature(295.0)})
    res = steady_state(m)
    flux = (320.0 - 295.0) / lay.thermal_resistance
    np.testing.assert_allclose(res.face_heat_flux()[0, g.patch_faces("w:outer")], flux, rtol=1e-9)


def test_the_answer_does_not_depend_on_the_kernels_thread_count(monkeypatch):
    """Small models step on one thread (``shipthermal._threads.SERIAL_BELOW_CELLS``), large
    ones on numba's budget: the kernels' sums are ordered, so the same day either way is
    the same bit for bit."""
    import numba

    from shipthermal import _threads

    if numba.get_num_threads() < 2:
        pytest.skip("one numba thread: nothing to compare")
    runs = []
    for limit in (0, 10**9):       # every model on the budget / every model on one thread
        monkeypatch.setattr(_threads, "SERIAL_BELOW_CELLS", limit)
        runs.append(Simulation(_model(), 600.0, 86400.0, output_interval=3600.0).run())
    np.testing.assert_array_equal(runs[0].cell_temperature, runs[1].cell_temperature)
    np.testing.assert_array_equal(runs[0].energy.imbalance, runs[1].energy.imbalance)
