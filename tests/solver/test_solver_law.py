"""A convection coefficient that depends on the surface temperature
(:class:`~shipthermal.conditions.ConvectionLaw`) is evaluated by the solver at the surface
temperature it solves for: the steady state against an independent root of the face balance,
the coefficient of every step against the law at that step's solved temperature, and the
energy balance of a day with the coefficient moving."""

import numpy as np
import pytest
from scipy.optimize import brentq
from solver_meshes import plate_graph

from shipthermal.conditions import ConvectionLaw, FixedTemperature, SurfaceBalance, law_h
from shipthermal.environment import convection as cv
from shipthermal.model import ThermalModel
from shipthermal.simulation import Simulation, steady_state
from shipthermal.units import SIGMA

EPS = 0.9
T_IN = 295.0


def _doe2(wind, roughness=1.52, nz=1.0):
    """DOE-2 on a horizontal face: forced part and law (EnergyPlus's default model)."""
    flow = cv.ExteriorFlow(normal_z=np.full(2, nz), wind_speed=np.full(2, wind),
                           roughness=roughness)
    return cv.CONVECTION_MODELS["doe2"].terms(np.full(2, 300.0), flow)


@pytest.mark.parametrize("absorbed, t_air, wind", [(700.0, 300.0, 0.5), (0.0, 290.0, 0.0),
                                                   (0.0, 285.0, 3.0), (300.0, 305.0, 8.0)])
def test_steady_surface_temperature_is_the_root_with_h_at_that_temperature(absorbed, t_air, wind):
    # a 10 mm steel plate, the inside held at 295 K: the outer face balances sun, sky,
    # convection with h(T_s) and conduction; brentq on the scalar balance is the peer
    g = plate_graph(0.010, 2)
    hf, law = _doe2(wind)
    lw = 330.0
    bc = SurfaceBalance(absorbed_shortwave=absorbed, emissivity=EPS, longwave_in=lw, h=hf,
                        temp_air=t_air, law=law)
    m = ThermalModel(g, {"plate:outer": bc, "plate:inner": FixedTemperature(T_IN)},
                     initial_temperature=300.0)
    res = steady_state(m, tolerance=1e-12)
    ts = float(res.face_temperature[0, g.patch_faces("plate:outer")][0])
    u = 53.3 / 0.010                                      # steel k / thickness [W m-2 K-1]

    def balance(t):
        h = float(law_h(hf[0], ConvectionLaw(law.natural[0], 2.0, 1.52, 1.0), t - t_air))
        return absorbed + h * (t_air - t) + EPS * (lw - SIGMA * t ** 4) - u * (t - T_IN)

    root = brentq(balance, 200.0, 400.0, xtol=1e-13)
    assert ts == pytest.approx(root, abs=1e-8)


def test_every_step_uses_the_law_at_its_solved_temperature_and_conserves_energy():
    # a day of sun, air and wind on a painted plate over a 295 K compartment, 300 s BDF2
    g = plate_graph(0.008, 1)
    day = 86400.0

    def air(t):
        return 290.0 + 6.0 * np.sin(2 * np.pi * (t - 9 * 3600) / day)

    def sun(t):
        return max(0.0, 800.0 * np.sin(np.pi * (t - 6 * 3600) / (12 * 3600)))

    def wind(t):
        return 2.0 + 1.5 * np.sin(2 * np.pi * t / day)

    flow = lambda t: cv.ExteriorFlow(np.ones(2), np.full(2, wind(t)), 20.0, 1.0, 5.0)  # noqa
    model = cv.CONVECTION_MODELS["flat_plate_turbulent"]
    nat = lambda t: model.terms(np.full(2, air(t)), flow(t))[1].natural           # noqa
    law = ConvectionLaw(natural=nat, blend=3.0, multiplier=1.0, normal_z=1.0)
    bc = SurfaceBalance(absorbed_shortwave=sun, emissivity=EPS, longwave_in=320.0,
                        h=lambda t: model.terms(np.full(2, air(t)), flow(t), law=False)[0],
                        temp_air=air, law=law)
    inner = SurfaceBalance(h=2.5, temp_air=T_IN)
    m = ThermalModel(g, {"plate:outer": bc, "plate:inner": inner}, initial_temperature=293.0)
    sim = Simulation(m, 300.0, day, output_interval=300.0)
    res = sim.run(progress=False)
    idx = g.patch_faces("plate:outer")
    a = g.bface_area[idx]
    worst = 0.0
    for k, t in enumerate(res.times[1:], start=1):
        ts = res.face_temperature[k, idx]
        hf = model.terms(np.full(2, air(t)), flow(t), law=False)[0]
        h = law_h(hf, ConvectionLaw(nat(t), 3.0, 1.0, 1.0), ts - air(t))
        want = a * (sun(t) + h * (air(t) - ts) + EPS * (320.0 - SIGMA * ts ** 4))
        worst = max(worst, float(np.max(np.abs(res.face_flow[k, idx] - want) / a)))
    # the step's flow is the law's at the solved temperature, to the Newton tolerance
    # (1e-9 K × a flux slope of ~1e4 W m-2 K-1 through the steel): well below 1e-4 W m-2
    assert worst < 1e-4, worst
    # energy: what the plate stored is what came through its faces, step by step
    assert res.energy.max_step_imbalance <= 1e-10, res.energy.summary()
    print(f"\nlaw at the solved temperature: largest flow mismatch {worst:.1e} W m-2, "
          f"step imbalance {res.energy.max_step_imbalance:.1e}")


def test_law_coefficients_of_scattered_law_patches_equal_the_law_face_by_face():
    # two patches with laws among faces without one (the solver's loop takes the law rows
    # and their faces, FaceForcing.law_faces): every face's h and slope against law_h
    # evaluated face by face, and the faces without a law keep their h
    from shipthermal.conditions import FaceForcing
    from shipthermal.model import law_coefficients

    rng = np.random.default_rng(3)
    b = 40
    f = FaceForcing.zeros(b)
    f.h[:] = rng.uniform(1.0, 12.0, b)
    f.temp_fluid[:] = rng.uniform(280.0, 300.0, b)
    patches = (np.array([31, 5, 17, 2]), np.arange(20, 29))
    laws = {}
    for k, idx in enumerate(patches):
        hf, law = _doe2(1.0 + k, nz=(1.0, -1.0)[k])
        nat = np.repeat(law.natural[:1], len(idx), axis=0)
        blend, mult, nz = np.full(len(idx), 2.0), np.full(len(idx), 1.0 + 0.5 * k), \
            np.full(len(idx), (1.0, -1.0)[k])
        f.set_law(idx, nat, blend, mult, nz)
        laws.update({int(i): (nat[j], blend[j], mult[j], nz[j]) for j, i in enumerate(idx)})
    f.finish()
    assert np.array_equal(f.law_index[f.law_faces], np.arange(len(laws)))
    temp = rng.uniform(270.0, 330.0, b)
    h, slope, _ = law_coefficients(f, temp)
    for i in range(b):
        if i in laws:
            nat, blend, mult, nz = laws[i]
            want = law_h(f.h[i], ConvectionLaw(nat, blend, mult, nz), temp[i] - f.temp_fluid[i],
                         return_slope=True)
            assert (h[i], slope[i]) == pytest.approx((float(want[0]), float(want[1])),
                                                     rel=1e-14), i
        else:
            assert (h[i], slope[i]) == (f.h[i], 0.0)
    # a forcing whose law rows were not given through set_law finds the same faces
    g = FaceForcing.zeros(b)
    g.law_index, g.law_blend = f.law_index.copy(), f.law_blend.copy()
    assert np.array_equal(g.law_faces, f.law_faces)
