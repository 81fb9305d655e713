"""Observed orders and conservation."""

import numpy as np
import pytest
import scipy.sparse as sp

from shipthermal.conditions import Convection, FixedTemperature, SurfaceBalance
from shipthermal.errors import InputError
from shipthermal.materials import Material
from shipthermal.mesh import build_shell_graph, build_tet_graph
from shipthermal.materials import Layer, Layup
from shipthermal.model import RadiativeExchange, ThermalModel
from shipthermal.raytrace.analytic import parallel_rectangles
from shipthermal.simulation import Simulation, steady_state
from shipthermal.units import DAY, HOUR
from solver_meshes import box_tets, kuhn_cube_tets, plate_graph


# ------------------------------------------------ 5. manufactured solution on tets --------
K_MMS = 2.0
MMS_MAT = Material("mms", 1000.0, 1000.0, K_MMS, "manufactured-solution test material")


def _exact(p):
    return 300.0 + 10.0 * np.sin(np.pi * p[:, 0]) * np.cos(0.5 * np.pi * p[:, 1]) * np.exp(p[:, 2])


def _source(p):
    # −k ∇²T for the field above: ∇² = (−π² − π²/4 + 1) × (T − 300)
    return -K_MMS * (_exact(p) - 300.0) * (-np.pi**2 - 0.25 * np.pi**2 + 1.0)


def _mms_error(pts, tets, correct=True):
    g = build_tet_graph(pts, tets, material=MMS_MAT, correct_nonorthogonality=correct)
    m = ThermalModel(g, {"boundary": FixedTemperature(_exact(g.bface_centroid))},
                     initial_temperature=300.0, heat_source=_source(g.cell_centroid))
    res = steady_state(m)
    w = g.cell_volume
    err = np.sqrt(np.sum(w * (res.final_temperature - _exact(g.cell_centroid)) ** 2) / w.sum())
    return (w.mean()) ** (1 / 3), err


@pytest.fixture(scope="module")
def mms(unit_cube_tets):
    """(h, error with correction, error without) per refinement."""
    out = []
    for p, t in unit_cube_tets:
        h, e = _mms_error(p, t, True)
        out.append((h, e, _mms_error(p, t, False)[1]))
    return np.array(out)


def test_manufactured_solution_on_tets_is_second_order():
    # Kuhn-subdivided cubes: the same mesh every run, so the measured order is the scheme's
    # (pytetwild's cubes differ between runs, even on one thread: their fitted order
    # ranged 1.79–2.27 over five runs)
    out = np.array([_mms_error(*kuhn_cube_tets(n)) for n in (5, 10, 14)])
    hs, errs = out[:, 0], out[:, 1]
    order = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    pairs = np.log(errs[:-1] / errs[1:]) / np.log(hs[:-1] / hs[1:])
    print(f"MMS on Kuhn cubes: h {hs}, L2 errors {errs}, order {order:.3f}, pairwise {pairs}")
    # measured 1.847 (pairwise 1.823, 1.909): second order approached from below as the
    # non-orthogonal correction's gradient error shrinks
    assert order >= 1.8, f"observed spatial order {order:.2f} < 1.8 (errors {errs})"
    assert pairs[-1] > pairs[0] and pairs[-1] >= 1.85, pairs


def test_manufactured_solution_on_pytetwild_tets_converges(mms):
    # the meshes the product makes: random between runs, so only a band (a first-order
    # scheme fits ~1; this one 1.79–2.27 over five runs)
    hs, errs = mms[:, 0], mms[:, 1]
    order = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    print(f"MMS on pytetwild cubes: h {hs}, L2 errors {errs}, observed order {order:.2f}")
    assert order >= 1.6, f"observed spatial order {order:.2f} < 1.6 (errors {errs})"


def test_two_point_flux_alone_is_inconsistent_on_tets(mms):
    # The reason for the correction: without it the error on the finest mesh is an order of
    # magnitude larger (measured 0.11 K vs 0.005 K).
    print(f"MMS errors without correction {mms[:, 2]}, with {mms[:, 1]}")
    assert np.all(mms[:, 2] > 10 * mms[:, 1])


# ------------------------------------------------------------- 6. temporal order ---------
def _plate_day_model():
    """Steel plate with a radiating, convecting outer face under a day of sun."""
    g = plate_graph(0.012, 3)
    omega = 2 * np.pi / DAY
    outer = SurfaceBalance(
        absorbed_shortwave=lambda t: 600.0 * np.maximum(np.sin(omega * t), 0.0) ** 2,
        emissivity=0.9, temp_env=lambda t: 270.0 + 5 * np.sin(omega * t),
        h=8.0, temp_air=lambda t: 295.0 + 4 * np.sin(omega * t - 0.5))
    return ThermalModel(g, {"plate:outer": outer, "plate:inner": Convection(3.0, 293.0)},
                        initial_temperature=290.0)


END_ORDER = 6 * HOUR + 0.25 * DAY   # mid-morning: forcing smooth and changing fast


@pytest.fixture(scope="module")
def order_reference():
    model = _plate_day_model()
    return model, Simulation(model, 7.5, END_ORDER, scheme="bdf2",
                             output_times=[END_ORDER]).run().final_temperature


@pytest.mark.parametrize("scheme,expected", [("backward_euler", 1.0), ("crank_nicolson", 2.0),
                                             ("bdf2", 2.0)])
def test_temporal_order(scheme, expected, order_reference):
    model, ref = order_reference
    end = END_ORDER
    steps = np.array([900.0, 450.0, 225.0, 112.5])
    errs = [np.max(np.abs(Simulation(model, dt, end, scheme=scheme, output_times=[end]).run()
                          .final_temperature - ref)) for dt in steps]
    order = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    print(f"{scheme}: errors {errs}, observed order {order:.2f}")
    # The reference (Δt = 7.5 s) is 15⁻² ≈ 4e-3 of the finest error for the 2nd-order schemes.
    assert abs(order - expected) < 0.2, f"{scheme}: observed order {order:.2f}, expected {expected}"


def _varying_steps(model, h, end):
    """BDF2 from 0 to ``end`` in hour-long segments of steps h, 2h, h, 2h, … (ratios 2, ½)."""
    sim = Simulation(model, h, end, scheme="bdf2", output_times=[end])
    for k in range(int(round(end / HOUR))):
        sim.set_time_step(h if k % 2 == 0 else 2 * h)
        sim.run_until((k + 1) * HOUR)
    return sim


def test_bdf2_with_varying_steps_stays_second_order(order_reference):
    # The variable-step BDF2 coefficients (ratio ω): halving every step halves every
    # segment's step, and the error falls as h².
    model, ref = order_reference
    steps = np.array([450.0, 225.0, 112.5])
    errs = [np.max(np.abs(_varying_steps(model, h, END_ORDER).results().final_temperature
                          - ref)) for h in steps]
    order = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    print(f"bdf2, steps h/2h alternating hourly: errors {errs}, observed order {order:.2f}")
    assert abs(order - 2.0) < 0.2
    # and the error lies between those of uniform steps h and 2h (measured 0.0063 < 0.019
    # < 0.026 K at h = 450 s)
    uniform = [np.max(np.abs(Simulation(model, dt, END_ORDER, scheme="bdf2",
                                        output_times=[END_ORDER]).run().final_temperature - ref))
               for dt in (450.0, 900.0)]
    assert uniform[0] < errs[0] < uniform[1]


def test_set_time_step_keeps_bdf2_stable_and_the_recording_grid():
    model = _plate_day_model()
    sim = Simulation(model, 300.0, DAY, scheme="bdf2", output_interval=1800.0)
    sim.run_until(1800.0)
    with pytest.raises(InputError, match="at most double"):
        sim.set_time_step(900.0)
    with pytest.raises(InputError, match="recording times"):
        sim.set_time_step(400.0)
    sim.set_time_step(600.0)
    sim.run_until(3600.0)
    sim.set_time_step(900.0)
    sim.run_until(5400.0)
    assert sim.time_step == 900.0
    assert np.allclose(sim.results().times, [0.0, 1800.0, 3600.0, 5400.0])


# --------------------------------------------------------------- 7. energy -----------------
def test_energy_closes_over_1000_steps_with_radiation():
    """Two parallel plates facing each other (face-to-face exchange), both radiating to the
    sky and convecting, one heated by the sun: stored energy vs boundary heat, every step."""
    gap, side = 1.0, 1.0
    v_low = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.0]])
    v_up = v_low + [0, 0, gap]
    f_low = np.array([[0, 1, 2], [0, 2, 3]])           # normal +z (towards the upper plate)
    f_up = np.array([[4, 6, 5], [4, 7, 6]])            # normal −z
    verts = np.vstack([v_low, v_up])
    faces = np.vstack([f_low, f_up])
    lay = Layup((Layer("marine_paint", 0.0003, 1), Layer("mild_steel", 0.008, 2)))
    g = build_shell_graph(verts, faces, np.array([0, 0, 1, 1]), ["low", "up"],
                          {"low": lay, "up": lay})
    eps = 0.9
    f12 = parallel_rectangles(side, side, gap)
    # Each outer triangle (area 0.5) sees the opposite plate's two triangles equally.
    area = 0.5
    r = np.zeros((4, 4))
    r[:2, 2:] = area * eps * eps * f12 / 2
    r[2:, :2] = r[:2, 2:].T
    outer = np.concatenate([g.patch_faces("low:outer"), g.patch_faces("up:outer")])
    exch = RadiativeExchange(outer, sp.csr_matrix(r))
    omega = 2 * np.pi / DAY
    sun = SurfaceBalance(absorbed_shortwave=lambda t: 500 * max(np.sin(omega * t), 0.0),
                         emissivity=eps * (1 - f12), temp_env=265.0, h=6.0, temp_air=293.0)
    cool = SurfaceBalance(emissivity=eps * (1 - f12), temp_env=265.0, h=6.0, temp_air=293.0)
    m = ThermalModel(g, {"low:outer": sun, "up:outer": cool, "low:inner": Convection(2.0, 295.0),
                         "up:inner": Convection(2.0, 295.0)}, initial_temperature=285.0,
                     exchange=exch)
    for scheme in ("backward_euler", "crank_nicolson", "bdf2"):
        res = Simulation(m, 86.4, 1000 * 86.4, scheme=scheme, output_interval=8640.0).run()
        e = res.energy
        assert len(e.time) == 1000
        print(f"{scheme}: {e.summary()}")
        assert e.relative_imbalance <= 1e-10, (scheme, e.summary())
        assert e.max_step_imbalance <= 1e-10, (scheme, e.summary())
        # the exchange moved heat: the shaded upper plate ends warmer than without it
        assert res.patch_mean("up:outer")[-1] > 265.0


# --------------------------------------------- 8. shell vs tets of the same plate ---------
def test_shell_and_tets_of_one_plate_agree():
    """A 0.05 × 0.05 × 0.02 m steel plate under a day-like solar flux on top and convection
    on both faces: the shell (one column, 8 cells) and pytetwild tets agree within the
    tets' own discretisation error (estimated from two refinements)."""
    thick = 0.02
    omega = 2 * np.pi / (6 * HOUR)
    top = dict(absorbed_shortwave=lambda t: 800 * max(np.sin(omega * t), 0.0), h=12.0,
               temp_air=295.0, emissivity=0.9, temp_env=270.0)
    bottom = Convection(4.0, 293.0)
    end = 3 * HOUR
    dt = 60.0

    shell = plate_graph(thick, 8)
    ms = ThermalModel(shell, {"plate:outer": SurfaceBalance(**top), "plate:inner": bottom},
                      initial_temperature=293.0)
    rs = Simulation(ms, dt, end, scheme="bdf2", output_interval=1800.0).run()
    top_shell = rs.patch_mean("plate:outer")

    tops = []
    for edge in (0.006, 0.004):
        tg = box_tets((0.05, 0.05, thick), edge)
        mt = ThermalModel(tg, {"zmax": SurfaceBalance(**top), "zmin": bottom},
                          initial_temperature=293.0)
        rt = Simulation(mt, dt, end, scheme="bdf2", output_interval=1800.0, tolerance=1e-7).run()
        tops.append(rt.patch_mean("zmax"))
    tet_error = np.max(np.abs(tops[1] - tops[0]))
    diff = np.max(np.abs(top_shell - tops[1]))
    print(f"shell vs tets: max top-surface difference {diff:.4f} K; tet refinement change "
          f"{tet_error:.4f} K; plate warmed by {top_shell.max() - 293:.1f} K")
    # Both are second order; the plate is nearly isothermal through its thickness (Bi ≈
    # 0.005), so the shell column is close to exact and the difference is the tets' error,
    # bounded by the change between the two tet levels (plus 1 mK of solver tolerance).
    assert diff <= 2 * tet_error + 1e-3
    assert top_shell.max() - 293 > 5.0   # the forcing did something
