"""Land surface energy balance over layered columns: exact solutions, orders, conservation.

Each test states where its tolerance comes from.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pvlib
import pytest
from scipy.optimize import brentq

from imaging.background import surface_energy as se
from imaging.background.surface_energy import kernels, solver
from imaging.background.classify import CLASS_NAMES
from imaging.background.surface_classes import (LABELS, SURFACE_CLASSES, Layer, SurfaceClass,
                                                apply_overrides)
from shipthermal.environment import Environment, climate_day
from shipthermal.environment.convection import CONVECTION_MODELS, ExteriorFlow
from shipthermal.errors import InputError
from shipthermal.parameters import DEFAULT_CONVECTION_MODEL
from shipthermal.units import SIGMA

DAY = 86400.0
OMEGA = 2.0 * np.pi / DAY

# a homogeneous soil for the exact solutions (Oke 1987 Table 2.1 saturated sandy soil)
SOIL = Layer("soil", 1.0, 2.2, 2000.0, 1480.0)
ALPHA = SOIL.diffusivity
DAMPING = np.sqrt(2.0 * ALPHA / OMEGA)            # damping depth d = √(2α/ω) [m]


def one_class(layers, bottom="deep", film=None, name="test", emissivity=0.95, latent="none",
              rs=None):
    return SurfaceClass(code=9, name=name, albedo=0.1, albedo_range=(0.0, 1.0),
                        emissivity=emissivity, layers=tuple(layers), bottom=bottom,
                        room_film_coefficient=film, latent=latent, surface_resistance=rs,
                        surface_resistance_range=None, roughness_length=0.01,
                        roughness_length_heat=0.001, displacement_height=0.0)


def columns_from_meshes(meshes, class_index, bottom_temperature, emissivity, rs=None):
    """Columns with meshes built by the test (uniform cells for the order tests)."""
    n = len(class_index)
    classes = tuple(one_class([SOIL], name=f"m{i}") for i in range(len(meshes)))
    return se.Columns(classes, tuple(meshes), np.asarray(class_index, dtype=np.int64),
                      np.broadcast_to(np.asarray(bottom_temperature, float), (n,)).copy(),
                      np.broadcast_to(np.asarray(emissivity, float), (n,)).copy(),
                      np.full(n, -1.0) if rs is None else np.asarray(rs, float))


def uniform_mesh(depth, n_cells, k=SOIL.conductivity, rc=SOIL.heat_capacity):
    dz = np.full(n_cells, depth / n_cells)
    cond = np.full(n_cells + 1, k / dz[0])
    cond[0] = cond[-1] = 2.0 * k / dz[0]
    return se.ColumnMesh(dz, np.cumsum(dz) - dz / 2, rc * dz, cond, np.zeros(n_cells, int),
                         "deep")


def constant_forcing(n_cols, n_t=288, sw=400.0, lw=320.0, ta=290.0, rh=60.0, wind=2.0):
    f = lambda v: np.full((n_t, n_cols), float(v))  # noqa: E731
    return se.SurfaceForcing(DAY / n_t, f(sw), f(lw), f(ta), f(rh), f(wind))


# ------------------------------------------------------------------------------------------
# Classes
# ------------------------------------------------------------------------------------------
def test_classes_match_the_class_map_and_every_number_is_sourced():
    for name, cls in SURFACE_CLASSES.items():
        assert CLASS_NAMES[cls.code] == name
        assert cls.albedo_range[0] <= cls.albedo <= cls.albedo_range[1]
        for key in ("albedo", "albedo_range", "emissivity", "bottom", "latent",
                    "roughness_length", "roughness_length_heat", "displacement_height"):
            assert cls.sources[key].split(":")[0].split()[0] in LABELS, (name, key)
        for layer in cls.layers:
            assert layer.source.split(":")[0] in LABELS, (name, layer.name)
    assert 1 not in {c.code for c in SURFACE_CLASSES.values()}      # water is the sea's
    assert SURFACE_CLASSES["vegetation"].surface_resistance == 70.0  # FAO-56 reference grass


def test_overrides_validate_and_name_the_key():
    classes = apply_overrides({"land": {"albedo": 0.2,
                                        "layers": [{"thickness": 0.1, "conductivity": 1.0,
                                                    "density": 2000, "specific_heat": 900}]}})
    assert classes["land"].albedo == 0.2
    assert classes["land"].sources["albedo"] == "user input"
    assert len(classes["land"].layers) == 1
    assert SURFACE_CLASSES["land"].albedo == 0.12                     # the named set is intact
    with pytest.raises(InputError, match=r"background\.classes\.land\.albedo"):
        apply_overrides({"land": {"albedo": 0.6}})                    # outside albedo_range
    with pytest.raises(InputError, match=r"background\.classes\.land\.albedo"):
        apply_overrides({"land": {"albedo": -0.1}})
    with pytest.raises(InputError, match=r"land\.layers\[0\]\.conductivity"):
        apply_overrides({"land": {"layers": [{"thickness": 0.1, "conductivity": 1e4,
                                              "density": 2000, "specific_heat": 900}]}})
    with pytest.raises(InputError, match=r"land\.colour"):
        apply_overrides({"land": {"colour": "grey"}})
    with pytest.raises(InputError, match="water"):
        apply_overrides({"water": {"albedo": 0.06}})
    with pytest.raises(InputError, match=r"gravel\.code"):
        apply_overrides({"gravel": {"albedo": 0.2}})
    new = apply_overrides({"gravel": {
        "code": 5, "albedo": 0.25, "albedo_range": [0.15, 0.35], "emissivity": 0.92,
        "layers": [{"thickness": 0.3, "conductivity": 0.7, "density": 1700,
                    "specific_heat": 850}],
        "bottom": "deep", "latent": "none", "roughness_length": 0.003}})["gravel"]
    assert new.code == 5 and new.roughness_length_heat == pytest.approx(0.0003)
    with pytest.raises(InputError, match=r"gravel\.code"):
        apply_overrides({"gravel": {
            "code": 3, "albedo": 0.25, "albedo_range": [0.15, 0.35], "emissivity": 0.92,
            "layers": [{"thickness": 0.3, "conductivity": 0.7, "density": 1700,
                        "specific_heat": 850}],
            "bottom": "deep", "latent": "none", "roughness_length": 0.003}})


# ------------------------------------------------------------------------------------------
# Mesh
# ------------------------------------------------------------------------------------------
def test_mesh_interfaces_on_faces_and_series_conductances():
    cls = SURFACE_CLASSES["land"]
    mesh = se.column_mesh(cls.layers, "deep", first_cell=0.002, growth=1.3)
    faces = np.concatenate([[0.0], np.cumsum(mesh.thickness)])
    for z in np.cumsum([layer.thickness for layer in cls.layers]):
        assert np.min(np.abs(faces - z)) < 1e-12
    assert mesh.thickness[0] < 0.0025 and 15 <= mesh.n_cells <= 25
    # steady conduction: the series of all face resistances is Σ d/k exactly
    assert np.sum(1.0 / mesh.conductance) == pytest.approx(cls.thermal_resistance, rel=1e-12)
    roof = SURFACE_CLASSES["building"]
    mesh = se.column_mesh(roof.layers, "room", roof.room_film_coefficient)
    assert np.sum(1.0 / mesh.conductance) == pytest.approx(
        roof.thermal_resistance + 1.0 / roof.room_film_coefficient, rel=1e-12)


# ------------------------------------------------------------------------------------------
# Exact solutions
# ------------------------------------------------------------------------------------------
def periodic_wave(meshes, days, scheme="crank_nicolson", substeps=2, amplitude=10.0):
    """Each mesh under T_surface = T0 + A sin(ωt) and T0 + A cos(ωt) (imposed through
    h = 1e7 W m-2 K-1, no radiation), bottom held at T0, run for ``days`` days (the surface is
    pinned, so the day-to-day change of its temperature cannot tell when the interior has
    settled: the slowest mode of a slab of depth L decays as exp(−α π² t / L²), and ``days``
    is chosen from that); returns the final (t = 0 mod day) profiles of the sine and cosine
    runs, one pair per mesh."""
    t0 = 290.0
    n_t = 288
    t = np.arange(n_t) * DAY / n_t
    n = 2 * len(meshes)
    ta = np.empty((n_t, n))
    ta[:, 0::2] = t0 + amplitude * np.sin(OMEGA * t)[:, None]
    ta[:, 1::2] = t0 + amplitude * np.cos(OMEGA * t)[:, None]
    cols = columns_from_meshes(meshes, np.repeat(np.arange(len(meshes)), 2), t0, 0.0)
    forcing = se.SurfaceForcing(DAY / n_t, np.zeros((n_t, n)), np.zeros((n_t, n)), ta,
                                np.full(n_t, 50.0), np.zeros(n_t))
    res = se.solve_surface_energy(forcing, cols, convection=se.convection_linear(1e7, 0.0),
                                  scheme=scheme, substeps=substeps, mode="periodic",
                                  tolerance=1e-12, max_days=days, min_days=days,
                                  backend="numba")
    assert res.spinup_days == days
    return [(res.temp_cells[2 * i, :mesh.n_cells] - t0, res.temp_cells[2 * i + 1, :mesh.n_cells] - t0)
            for i, mesh in enumerate(meshes)], res


def exact_slab(z, depth, amplitude=10.0):
    """Periodic state of a slab 0 < z < L, T(0) = A e^{iωt}, T(L) = 0: A sinh(κ(L−z))/sinh(κL),
    κ = (1 + i)/d; returns the sine and cosine responses at t = 0."""
    kappa = (1.0 + 1.0j) / DAMPING
    g = amplitude * np.sinh(kappa * (depth - z)) / np.sinh(kappa * depth)
    # sin(ωt) = Im e^{iωt} → Im g at t = 0; cos(ωt) = Re e^{iωt} → Re g
    return g.imag, g.real


def test_damped_wave_amplitude_and_phase_semi_infinite():
    # L = 5 d: the bottom's reflection is e^{-2L/d} = 4.5e-5 of the wave: a semi-infinite
    # solid to that accuracy. The slowest mode decays by e^{-α π² day/L²} = 0.29 a day: 20 days
    # leave 1e-11 of the start.
    depth = 5.0 * DAMPING
    mesh = uniform_mesh(depth, 160)                  # h = d/32
    ((sine, cosine),), _ = periodic_wave([mesh], days=20)
    amp = np.hypot(sine, cosine) / 10.0
    lag = np.unwrap(np.arctan2(-sine, cosine))      # T = A e^{-z/d} sin(ωt − z/d)
    # error budget, in units of the surface amplitude A: the O((h/d)²) discretisation error
    # measured by the order test (2.4e-4 at h = d/32), the reflection 4.5e-5, Crank–Nicolson
    # (ωΔt)²/12 = 1e-5 at Δt = 150 s → 5e-4; a phase error is that divided by e^{-z/d}
    budget = 5e-4
    for zd in (0.5, 1.0, 2.0):
        i = np.argmin(np.abs(mesh.depth - zd * DAMPING))
        z = mesh.depth[i] / DAMPING
        assert amp[i] == pytest.approx(np.exp(-z), abs=budget), (zd, amp[i], np.exp(-z))
        assert lag[i] == pytest.approx(z, abs=budget / np.exp(-z)), (zd, lag[i], z)


def test_damped_wave_converges_at_second_order_in_space():
    depth = 3.0 * DAMPING
    sizes = [12, 24, 48, 96]
    # L = 3 d: the slowest mode decays by 0.033 a day, 8 days leave 1e-12
    runs, _ = periodic_wave([uniform_mesh(depth, n) for n in sizes], days=8, substeps=10)
    errs = []
    for n, (sine, cosine) in zip(sizes, runs):
        z = uniform_mesh(depth, n).depth
        ex_s, ex_c = exact_slab(z, depth)
        errs.append(max(np.max(np.abs(sine - ex_s)), np.max(np.abs(cosine - ex_c))))
    h = depth / np.array(sizes)
    rate = np.polyfit(np.log(h), np.log(errs), 1)[0]
    assert 1.85 < rate < 2.15, f"observed order {rate:.3f} (errors {errs})"


@pytest.mark.parametrize("scheme,order", [("backward_euler", 1.0), ("crank_nicolson", 2.0)])
def test_time_order(scheme, order):
    # fixed mesh, Δt = 1200, 600, 300, 150 s; reference Δt = 37.5 s (same scheme and mesh)
    depth = 3.0 * DAMPING
    mesh = uniform_mesh(depth, 24)
    prof = []
    for substeps in (1, 2, 4, 8, 32):
        n_t = 72
        t = np.arange(n_t) * DAY / n_t
        cols = columns_from_meshes([mesh], [0], 290.0, 0.0)
        ta = 290.0 + 10.0 * np.sin(OMEGA * t)
        forcing = se.SurfaceForcing(DAY / n_t, np.zeros((n_t, 1)), np.zeros((n_t, 1)), ta,
                                    np.full(n_t, 50.0), np.zeros(n_t))
        res = se.solve_surface_energy(forcing, cols, convection=se.convection_linear(1e7, 0.0),
                                      scheme=scheme, substeps=substeps, mode="periodic",
                                      tolerance=1e-12, max_days=8, min_days=8)
        prof.append(res.temp_cells[0])
    errs = [np.max(np.abs(p - prof[-1])) for p in prof[:-1]]
    dt = DAY / 72 / np.array([1, 2, 4, 8])
    rate = np.polyfit(np.log(dt), np.log(errs), 1)[0]
    assert abs(rate - order) < 0.15, f"{scheme}: observed order {rate:.3f} (errors {errs})"


@pytest.mark.parametrize("name", ["land", "building"])
def test_steady_layered_column_is_series_resistance(name):
    cls = SURFACE_CLASSES[name]
    cols = se.build_columns([name], 283.15)
    cols = dataclasses.replace(cols, emissivity=np.zeros(1))    # linear top boundary
    h, sw, ta, tb = 12.0, 350.0, 298.0, 283.15
    res = se.solve_surface_energy(constant_forcing(1, sw=sw, ta=ta), cols,
                                  convection=se.convection_linear(h, 0.0), mode="periodic")
    r = cls.thermal_resistance + (1.0 / cls.room_film_coefficient if cls.bottom == "room"
                                  else 0.0)
    ts = (sw + h * ta + tb / r) / (h + 1.0 / r)
    q = (ts - tb) / r
    # round-off of a 20-cell elimination of O(300 K) values: 1e-9 K
    assert res.temp_surface[0, 0] == pytest.approx(ts, abs=1e-9)
    assert res.ground[0, 0] == pytest.approx(q, abs=1e-8)
    # temperature at each layer interface: T_s − q Σ d/k above it (linear within layers)
    mesh = cols.meshes[0]
    faces_r = np.cumsum(1.0 / mesh.conductance)[:-1]       # resistance surface → cell centre
    np.testing.assert_allclose(res.temp_cells[0, :mesh.n_cells], ts - q * faces_r, atol=1e-9)


@pytest.mark.parametrize("name", ["insulated", "land", "building", "vegetation"])
def test_steady_surface_balance_equals_scalar_root(name):
    if name == "insulated":
        # the balance αS + εL↓ = εσT⁴ + h(T − T_air) alone: a roof over a room through a film
        # of 1e-9 W m-2 K-1 (G ≈ 1e-7 W m-2, kept in the root below all the same)
        cls = dataclasses.replace(SURFACE_CLASSES["building"], name=name,
                                  room_film_coefficient=1e-9)
    else:
        cls = SURFACE_CLASSES[name]
    tb = 288.0
    cols = se.build_columns([name], tb, classes={name: cls})
    sw, lw, ta, rh, wind, p = 600.0, 340.0, 300.0, 55.0, 3.0, 101325.0
    conv = se.convection_linear(5.0, 3.0)
    h = 5.0 + 3.0 * wind
    r = cls.thermal_resistance + (1.0 / cls.room_film_coefficient if cls.bottom == "room"
                                  else 0.0)
    rs = cls.surface_resistance if cls.latent == "penman_monteith" else None

    def balance(t):
        lat = 0.0 if rs is None else se.latent_heat_flux(t, ta, rh, h, rs, p)
        return (sw + cls.emissivity * lw - cls.emissivity * SIGMA * t ** 4 - h * (t - ta)
                - lat - (t - tb) / r)

    root = brentq(balance, 200.0, 400.0, xtol=1e-12, rtol=1e-15)
    res = se.solve_surface_energy(constant_forcing(1, sw=sw, lw=lw, ta=ta, rh=rh, wind=wind), cols,
                                  convection=conv, mode="periodic")
    assert res.temp_surface[0, 0] == pytest.approx(root, abs=1e-6)


# ------------------------------------------------------------------------------------------
# Conservation, backends
# ------------------------------------------------------------------------------------------
def diurnal_forcing(names, days=3, n_per_day=96, seed=1):
    rng = np.random.default_rng(seed)
    n = len(names)
    n_t = days * n_per_day
    t = np.arange(n_t) * DAY / n_per_day
    sun = np.clip(np.sin(2 * np.pi * (t / DAY - 0.25)), 0, None)
    sw = 850.0 * sun[:, None] * rng.uniform(0.6, 0.95, n) * (1 + 0.1 * np.sin(t / 7000.0))[:, None]
    lw = 300.0 + 40.0 * rng.random((n_t, n))
    ta = 290.0 + 6.0 * np.sin(2 * np.pi * (t / DAY - 0.375)) + 0.5 * np.sin(t / 3000.0)
    rh = 60.0 - 20.0 * sun
    wind = 2.5 + 1.5 * np.abs(np.sin(t / 20000.0))
    return se.SurfaceForcing(DAY / n_per_day, sw, lw, ta, rh, wind)


NAMES = ["land", "building", "vegetation"] * 3


@pytest.mark.parametrize("scheme", ["backward_euler", "crank_nicolson"])
def test_energy_conserved_to_round_off_over_days(scheme):
    cols = se.build_columns(NAMES, np.linspace(283, 296, len(NAMES)))
    res = se.solve_surface_energy(diurnal_forcing(NAMES), cols, scheme=scheme, substeps=3,
                                  convection=se.convection_aerodynamic(0.005))
    # stored energy Σ ρcΔz T ~ 1e9 J m-2: float64 keeps it to ~1e-7 J m-2 per sum; the
    # bound 1e-12 of the integrated |fluxes| (~1e8 J m-2) is 1e-4 J m-2
    rel = np.abs(res.energy_residual) / res.energy_scale
    assert rel.max() < 1e-12, rel
    assert res.surface_imbalance.max() < 1e-6     # Newton converged: |S − G| [W m-2]
    bal = (res.shortwave_net + res.longwave_net - res.sensible - res.latent - res.ground)
    assert np.abs(bal).max() < 1e-6
    assert (res.latent[:, 2::3] != 0).any() and (res.latent[:, 0::3] == 0).all()


@pytest.mark.parametrize("parallel", [False, True])
@pytest.mark.parametrize("scheme", ["backward_euler", "crank_nicolson"])
def test_numba_kernel_equals_reference(scheme, parallel, monkeypatch):
    names = NAMES * 22                           # two blocks per class
    # small batches run the serial build; lower the threshold to run the parallel one too
    monkeypatch.setattr(solver, "_PARALLEL_MIN_BLOCKS", 1 if parallel else 10 ** 9)
    cols = se.build_columns(names, 290.0)
    stepper = solver._Stepper(cols, se.convection_linear(1.0, 1.0), 1.0, 1.0, kernels._step_numba)
    assert stepper.kernel is (kernels._step_numba if parallel else kernels._step_numba_serial)
    forcing = diurnal_forcing(names, days=2, n_per_day=48)
    kw = dict(scheme=scheme, substeps=2, convection=se.convection_correlation(), max_days=3)
    a = se.solve_surface_energy(forcing, cols, backend="numba", **kw)
    b = se.solve_surface_energy(forcing, cols, backend="reference", **kw)
    # same operations in the same order; exp() of numba (LLVM) and numpy may differ in the
    # last bit: differences at round-off of 300 K values through a few hundred steps
    np.testing.assert_allclose(a.temp_surface, b.temp_surface, rtol=0, atol=1e-10)
    np.testing.assert_allclose(a.temp_cells, b.temp_cells, rtol=0, atol=1e-10)
    for name in ("longwave_net", "sensible", "latent", "ground"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=0, atol=1e-8)
    assert a.spinup_days == b.spinup_days



@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_compiled_span_equals_the_step_loop(dtype):
    """With the aerodynamic convection the numba backend runs whole spans in one compiled
    call (each block of columns through every step on one thread); the per-step loop (the
    same convection hidden behind a plain function) must give the same record (and that
    loop equals the numpy reference: test_numba_kernel_equals_reference). Stable nights and
    unstable days both occur (stability factors of both signs), the forcing is float32 as a
    long record's is, two substeps interpolate it."""
    names = NAMES * 22
    cols = se.build_columns(names, np.linspace(283, 296, len(names)))
    f64 = diurnal_forcing(names, days=3, n_per_day=48)
    forcing = dataclasses.replace(f64, **{name: getattr(f64, name).astype(np.float32) for name
                                          in ("shortwave_absorbed", "longwave_down",
                                              "temp_air", "relative_humidity", "wind_speed")})
    aero = se.convection_aerodynamic(np.linspace(0.001, 0.5, len(names)), stability=True,
                                     height_wind=10.0, height_temp=2.0, pressure=100500.0)
    hidden = lambda ts, ta, u: aero(ts, ta, u)          # noqa: E731  no .aerodynamic
    kw = dict(substeps=2, max_days=4, outputs=("sensible", "h_convection"),
              output_dtype=dtype)
    fast = se.solve_surface_energy(forcing, cols, convection=aero, **kw)
    loop = se.solve_surface_energy(forcing, cols, convection=hidden, **kw)
    ri_sign = np.sign(f64.temp_air[:, None] - fast.temp_surface)
    assert (ri_sign > 0).any() and (ri_sign < 0).any()
    assert fast.latent is None and fast.h_convection.dtype == dtype
    # the same operations in the same order: pow() of numba (LLVM) and numpy may differ in
    # the last bit (5.7e-14 K seen after three days), as in
    # test_numba_kernel_equals_reference; stored outputs to a few units of their precision
    eps = float(np.finfo(dtype).eps)
    np.testing.assert_allclose(fast.temp_surface, loop.temp_surface, rtol=0, atol=1e-10)
    np.testing.assert_allclose(fast.temp_cells, loop.temp_cells, rtol=0, atol=1e-10)
    # stored energy ~1e9 J m-2 to 1e-7 J m-2 per sum: 1e-4 J m-2 is still round-off
    np.testing.assert_allclose(fast.energy_residual, loop.energy_residual, rtol=0, atol=1e-4)
    # h follows the surface temperature through the Richardson number
    np.testing.assert_allclose(fast.h_convection, loop.h_convection, rtol=max(1e-12, 4 * eps))
    np.testing.assert_allclose(fast.sensible, loop.sensible, rtol=0, atol=1e-8)
    assert fast.spinup_days == loop.spinup_days


def test_periodic_spinup_reports_days_and_change():
    cols = se.build_columns(["land", "vegetation"], 290.0)
    one_day = diurnal_forcing(["land", "vegetation"], days=1)
    res = se.solve_surface_energy(one_day, cols, mode="periodic", tolerance=0.01)
    assert res.spinup_change.max() < 0.01 and 2 <= res.spinup_days < 60
    tight = se.solve_surface_energy(one_day, cols, mode="periodic", tolerance=1e-9, max_days=3)
    assert tight.spinup_days == 3 and tight.spinup_change.max() > 1e-9


# ------------------------------------------------------------------------------------------
# Latent heat: FAO-56
# ------------------------------------------------------------------------------------------
def test_penman_monteith_equals_fao56_within_the_linearisation():
    grass = SURFACE_CLASSES["vegetation"]
    cols = se.build_columns(["vegetation"] * 3, 290.0)
    # FAO-56 eq. 4 at z_m = z_h = 2 m for the reference grass: r_a = 208/u2 (their rounding)
    conv = se.convection_aerodynamic(grass.roughness_length, grass.roughness_length_heat,
                                     grass.displacement_height, height_wind=2.0)
    n_t = 288
    sw = np.tile([300.0, 550.0, 750.0], (n_t, 1))
    forcing = se.SurfaceForcing(DAY / n_t, sw, np.full((n_t, 3), 330.0),
                                np.full((n_t, 3), 298.0), np.tile([40.0, 60.0, 80.0], (n_t, 1)),
                                np.tile([1.0, 2.0, 4.0], (n_t, 1)))
    res = se.solve_surface_energy(forcing, cols, convection=conv, mode="periodic")
    ts = res.temp_surface[0]
    rn_g = res.shortwave_net[0] + res.longwave_net[0] - res.ground[0]    # R_n − G [W m-2]
    ta, rh, u2, p = 298.0, np.array([40.0, 60.0, 80.0]), np.array([1.0, 2.0, 4.0]), 101325.0
    h = conv(ts, ta, u2)
    rho_cp = se.air_heat_capacity(ta, p)
    r_a = rho_cp / h
    r_s = grass.surface_resistance
    gamma = se.psychrometric_constant(p)
    es = se.saturation_vapour_pressure(ta)
    ea = rh / 100 * es
    delta = se.saturation_vapour_pressure_slope(ta)
    # FAO-56 eq. 3 (the general Penman–Monteith form)
    eq3 = (delta * rn_g + rho_cp * (es - ea) / r_a) / (delta + gamma * (1 + r_s / r_a))
    # derived difference: with H = ρc_p(T_s − T_a)/r_a and R = e°(T_s) − e°(T_a) − Δ(T_s − T_a)
    # (the Taylor remainder eq. 3 drops), the exact balance gives
    # λE − λE_eq3 = (ρc_p/r_a) R / (Δ + γ(1 + r_s/r_a))   exactly
    remainder = se.saturation_vapour_pressure(ts) - es - delta * (ts - ta)
    expected = rho_cp / r_a * remainder / (delta + gamma * (1 + r_s / r_a))
    np.testing.assert_allclose(res.latent[0] - eq3, expected, rtol=1e-8, atol=1e-9)
    assert (np.abs(expected) > 0.05).all()          # the linearisation is visible (W m-2)
    # FAO-56 hourly numeric form (eq. 53; eq. 6 with 37 for 900/24), kPa, MJ m-2 h-1, °C
    tc = ta - 273.15
    d_k, g_k, es_k, ea_k = delta / 1e3, 0.665e-3 * p / 1e3, es / 1e3, ea / 1e3
    et0 = ((0.408 * d_k * rn_g * 3600e-6 + g_k * 37.0 / (tc + 273) * u2 * (es_k - ea_k))
           / (d_k + g_k * (1 + 0.34 * u2)))                                  # [mm h-1]
    eq53 = et0 * se.LATENT_HEAT_VAPORISATION / 3600.0                          # [W m-2]
    # its constants round λ⁻¹ (0.408 vs 0.40816), ρc_p/r_a (37 vs 37.1), r_s/r_a (0.34 vs
    # 70/208) and γ (0.665e-3 vs 0.6647e-3): their effect is eq. 53 − eq. 3 itself (≈ 1 %),
    # the remainder adds the linearisation
    rounding = np.abs(eq53 - eq3)
    assert (rounding < 0.02 * eq3).all()
    assert (np.abs(res.latent[0] - eq53) <= rounding + np.abs(expected) + 1e-9).all()


# ------------------------------------------------------------------------------------------
# Convection and forcing helpers
# ------------------------------------------------------------------------------------------
def test_convection_helpers():
    ts, ta, v = np.array([300.0, 320.0]), np.array([295.0, 295.0]), np.array([1.0, 6.0])
    h = se.convection_correlation()(ts, ta, v)
    ref = CONVECTION_MODELS[DEFAULT_CONVECTION_MODEL].h(ts, ta,
                                                        ExteriorFlow(1.0, v, 30.0, 30.0, 7.5))
    np.testing.assert_array_equal(h, ref)
    np.testing.assert_array_equal(se.convection_linear(4.0, 4.0)(ts, ta, v), 4 + 4 * v)
    grass = SURFACE_CLASSES["vegetation"]
    conv = se.convection_aerodynamic(grass.roughness_length, grass.roughness_length_heat,
                                     grass.displacement_height, height_wind=2.0)
    r_a = se.air_heat_capacity(ta) / conv(ts, ta, v)
    # FAO-56 eq. 4 rounds its value to 208/u2: 207.7/u2 with k = 0.41
    np.testing.assert_allclose(r_a * v, 208.0, rtol=3e-3)
    stab = se.convection_aerodynamic(0.005, stability=True)
    assert stab(320.0, 295.0, 2.0) > conv(320.0, 295.0, 2.0) * 0 + \
        se.convection_aerodynamic(0.005)(320.0, 295.0, 2.0)        # unstable: more exchange
    assert stab(280.0, 295.0, 2.0) < se.convection_aerodynamic(0.005)(280.0, 295.0, 2.0)


def test_tilted_beam_by_hand_at_50N_in_winter():
    times = pd.date_range("2023-12-21 10:00", "2023-12-21 14:00", freq="1min", tz="UTC")
    sp = pvlib.solarposition.get_solarposition(times, 50.0, 0.0)
    noon = sp["apparent_elevation"].to_numpy().argmax()
    zen = sp["apparent_zenith"].to_numpy()[[noon]]
    azi = sp["azimuth"].to_numpy()[[noon]]
    dni, dhi = np.array([700.0]), np.array([80.0])
    ghi = dni * np.cos(np.radians(zen)) + dhi
    tilt = np.array([0.0, 30.0, 30.0])
    aspect = np.array([180.0, 180.0, 0.0])           # flat, south-facing, north-facing
    out = se.shortwave_on_tilted(tilt, aspect, zen, azi, dni, ghi, dhi, albedo_ground=0.2)
    z, a = np.radians(zen[0]), np.radians(azi[0])
    s, g = np.radians(tilt), np.radians(aspect)
    cos_i = np.cos(z) * np.cos(s) + np.sin(z) * np.sin(s) * np.cos(a - g)
    np.testing.assert_allclose(out["poa_direct"][0], dni[0] * np.maximum(cos_i, 0), rtol=1e-12)
    assert out["poa_direct"][0, 1] > 1.5 * out["poa_direct"][0, 0] > out["poa_direct"][0, 2]
    svf = se.sky_view_factor(tilt)
    np.testing.assert_allclose(out["poa_sky_diffuse"][0], dhi[0] * svf, rtol=1e-12)
    np.testing.assert_allclose(out["poa_ground_diffuse"][0], ghi[0] * 0.2 * (1 - svf),
                               rtol=1e-12, atol=1e-12)
    lw = se.longwave_incoming(np.array([[300.0]]), svf, 290.0, 1.0)
    np.testing.assert_allclose(lw[0], svf * 300 + (1 - svf) * SIGMA * 290.0 ** 4)


def test_diffuse_models_broadcast_like_one_pixel_at_a_time():
    zen, azi = np.array([30.0, 60.0, 95.0]), np.array([150.0, 200.0, 250.0])
    dni, dhi = np.array([800.0, 500.0, 0.0]), np.array([100.0, 120.0, 0.0])
    ghi = dni * np.clip(np.cos(np.radians(zen)), 0, None) + dhi
    tilt, aspect = np.array([0.0, 10.0, 30.0, 45.0]), np.array([180.0, 90.0, 0.0, 270.0])
    extra, am = np.full(3, 1360.0), pvlib.atmosphere.get_relative_airmass(zen)
    for model in ("isotropic", "haydavies", "perez"):
        out = se.shortwave_on_tilted(tilt, aspect, zen, azi, dni, ghi, dhi, model=model,
                                     dni_extra=extra, airmass=am)["poa_global"]
        for j in range(4):
            one = pvlib.irradiance.get_total_irradiance(
                tilt[j], aspect[j], zen, azi, dni, ghi, dhi, dni_extra=extra, airmass=am,
                albedo=0.2, model=model)["poa_global"]
            np.testing.assert_allclose(out[:, j], np.nan_to_num(one), rtol=1e-12, err_msg=model)


def test_forcing_from_the_ship_environment_runs_a_design_day():
    env = Environment.from_climate_day(climate_day("summer"))
    state = env.at(np.arange(0.0, DAY, 300.0))
    names = ["land", "building", "vegetation", "land"]
    albedo = [SURFACE_CLASSES[n].albedo for n in names]
    forcing = se.forcing_from_environment(state, 300.0, albedo, surface_tilt=[0, 0, 0, 20],
                                          surface_azimuth=[180, 180, 180, 180])
    # flat pixels: absorbed = (1 − albedo) GHI; sky view 1: L↓ of the environment
    np.testing.assert_allclose(forcing.shortwave_absorbed[:, 0], (1 - albedo[0]) * state.ghi,
                               rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(forcing.longwave_down[:, 1], state.longwave_down, rtol=1e-12)
    cols = se.build_columns(names, float(np.mean(state.temp_air)))
    res = se.solve_surface_energy(forcing, cols, mode="periodic")
    assert res.spinup_change.max() < 0.01
    assert (np.abs(res.energy_residual) < 1e-12 * res.energy_scale).all()
    noon = np.argmax(state.ghi)
    # sunlit dry paving runs hotter than the air and than the transpiring grass at noon
    assert res.temp_surface[noon, 0] > state.temp_air[noon] + 5.0
    assert res.temp_surface[noon, 2] < res.temp_surface[noon, 0]


def test_forcing_errors_name_the_field():
    cols = se.build_columns(["land"], 290.0)
    bad = constant_forcing(1, ta=500.0)
    with pytest.raises(InputError, match="forcing.temp_air"):
        se.solve_surface_energy(bad, cols)
    with pytest.raises(InputError, match="forcing.time_step"):
        se.solve_surface_energy(dataclasses.replace(constant_forcing(1), time_step=700.0), cols)
    with pytest.raises(InputError, match="columns.class"):
        se.build_columns([1], 290.0)
    with pytest.raises(InputError, match="surface_energy.scheme"):
        se.solve_surface_energy(constant_forcing(1), cols, scheme="rk4")
