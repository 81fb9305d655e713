"""The thermal core against exact solutions (slabs, waves, plates, radiative equilibrium).

Every tolerance is derived from the discretisation (second order in space and time) or
from the size of a neglected physical effect; the numbers measured when the tests were
written are quoted next to them.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

from shipthermal.conditions import Adiabatic, Convection, FixedTemperature, SurfaceBalance
from shipthermal.materials import MATERIALS
from shipthermal.model import ThermalModel
from shipthermal.simulation import Simulation, steady_state
from shipthermal.units import DAY, SIGMA
from solver_meshes import box_tets, plate_graph

STEEL = MATERIALS["mild_steel"]
ALPHA = STEEL.diffusivity


# ---------------------------------------------------------------- 1. convective slab -----
def slab_series(x_over_l, fourier, biot, n_terms=60):
    """Carslaw & Jaeger (1959) §3.11 eq. (4); Incropera 6th ed. eq. 5.42: plane wall of
    half-thickness l, initially uniform, both faces convecting to T∞:
    θ/θ_i = Σ C_n exp(−ζ_n² Fo) cos(ζ_n x/l), ζ_n tan ζ_n = Bi,
    C_n = 4 sin ζ_n / (2 ζ_n + sin 2 ζ_n)."""
    zetas = np.array([brentq(lambda z: z * np.tan(z) - biot, n * np.pi + 1e-12,
                             n * np.pi + np.pi / 2 - 1e-12) for n in range(n_terms)])
    c = 4 * np.sin(zetas) / (2 * zetas + np.sin(2 * zetas))
    return np.sum(c[:, None] * np.exp(-zetas[:, None] ** 2 * fourier)
                  * np.cos(zetas[:, None] * np.asarray(x_over_l)[None, :]), axis=0)


HALF = 0.025          # half-thickness l [m]
H_CONV = 1000.0       # [W m-2 K-1] → Bi = h l / k = 0.47
T_INIT, T_INF = 350.0, 300.0
BIOT = H_CONV * HALF / STEEL.conductivity
FO_END = 0.4
T_END = FO_END * HALF**2 / ALPHA    # 16.2 s


def _slab_shell_error(cells, steps):
    g = plate_graph(2 * HALF, cells)
    bc = Convection(H_CONV, T_INF)
    m = ThermalModel(g, {"plate:outer": bc, "plate:inner": bc}, initial_temperature=T_INIT)
    res = Simulation(m, T_END / steps, T_END, scheme="bdf2", output_times=[T_END]).run()
    x = (HALF - g.metadata["cell_depth"]) / HALF
    exact = T_INF + (T_INIT - T_INF) * slab_series(x, FO_END, BIOT)
    return np.max(np.abs(res.final_temperature - exact)) / (T_INIT - T_INF)


def test_slab_shell_matches_carslaw_jaeger_series_at_second_order():
    # 20 → 40 → 80 cells with 100 → 400 → 1600 steps: with BDF2 both error terms fall 4× per
    # level (the 10-cell level is still pre-asymptotic: order 1.79 there).
    errs = [_slab_shell_error(c, s) for c, s in ((20, 100), (40, 400), (80, 1600))]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    print(f"slab (shell) max errors {errs}, observed orders {orders}")
    assert errs[-1] < 2e-4
    assert np.all(orders > 1.8), orders


def test_slab_tets_match_carslaw_jaeger_series():
    # The same slab as a pytetwild box 0.1 × 0.1 × 0.05 m, convecting on z faces only.
    # Measured RMS errors 5.8e-4 (edge 0.01 m, 4 k tets) and 2.6e-4 (0.007 m): order ≈ 2.2
    # in the edge length. The bound is 3× the coarse figure, room for pytetwild's run-to-run
    # variation (tet counts vary ~2 %); without the non-orthogonal correction the error is
    # 10–20× larger, so the bound still separates a consistent scheme from an inconsistent
    # one. The refinement must reduce the error. The linear solver is an exact factor: the
    # test is about the discretisation, and 'auto' picks a backend by timing it, so its solve
    # differs from run to run: in one CI run its Newton stalled at 1.07e-7 K against the
    # 1e-7 K asked, in step 35 of 40 (not reproduced in 16 repeats with auto, 2 with AMG).
    errs = []
    for edge in (0.01, 0.007):
        g = box_tets((0.1, 0.1, 2 * HALF), edge)
        bc = Convection(H_CONV, T_INF)
        m = ThermalModel(g, {"zmin": bc, "zmax": bc}, initial_temperature=T_INIT)
        res = Simulation(m, T_END / 40, T_END, scheme="bdf2", output_times=[T_END],
                         tolerance=1e-7, linear_solver="direct").run()
        x = (g.cell_centroid[:, 2] - HALF) / HALF
        exact = T_INF + (T_INIT - T_INF) * slab_series(x, FO_END, BIOT)
        w = g.cell_volume
        errs.append(np.sqrt(np.sum(w * (res.final_temperature - exact) ** 2) / w.sum())
                    / (T_INIT - T_INF))
    print(f"slab (tets) RMS errors {errs}")
    assert errs[0] < 2e-3
    assert errs[1] < errs[0]


# ------------------------------------------------------- 2. periodic semi-infinite solid --
def test_periodic_surface_temperature_damped_wave():
    """T(x, t) = T_m + A e^{−x/d} cos(ωt − x/d), d = √(2α/ω) (Carslaw & Jaeger §2.6)."""
    omega = 2 * np.pi / DAY
    d = np.sqrt(2 * ALPHA / omega)              # 0.65 m for steel
    depth_total = 6 * d                          # the exact wave has e^{-6} = 0.25 % left there
    cells = 96                                   # dz = d/16
    g = plate_graph(depth_total, cells)
    tm, amp = 290.0, 10.0
    x = g.metadata["cell_depth"]

    def exact(xx, t):
        return tm + amp * np.exp(-xx / d) * np.cos(omega * t - xx / d)

    m = ThermalModel(g, {"plate:outer": FixedTemperature(lambda t: tm + amp * np.cos(omega * t))},
                     initial_temperature=exact(x, 0.0))
    dt = 300.0
    res = Simulation(m, dt, 2 * DAY, scheme="bdf2", output_interval=dt).run()
    last = res.times >= DAY
    t = res.times[last][:-1]                     # one full period
    for depth in (0.5 * d, d, 2 * d):
        k = np.argmin(np.abs(x[: cells] - depth))
        xx = x[k]
        series = res.cell_temperature[last][:-1, k] - tm
        c = 2 * np.mean(series * np.exp(-1j * omega * t))   # complex amplitude A e^{-iφ}
        amp_num, lag_num = abs(c), -np.angle(c)
        amp_ex, lag_ex = amp * np.exp(-xx / d), xx / d
        # dz/d = 1/16 and ω dt = 0.022: both second-order errors ~1e-3 relative; the reflected
        # wave from the adiabatic bottom is e^{-(12d - 2x)/d} < 1e-4. Measured: 3e-4, 2e-4 rad.
        assert amp_num == pytest.approx(amp_ex, rel=3e-3), (depth, amp_num, amp_ex)
        assert lag_num == pytest.approx(lag_ex, abs=3e-3), (depth, lag_num, lag_ex)


# --------------------------------------------------- 3. thin plate, sinusoidal solar flux --
def test_thin_plate_sinusoidal_flux_lumped_solution():
    """C dT/dt = q0 sin ωt − 2h (T − T_a): T − T_a = q0/√((2h)² + (Cω)²) sin(ωt − φ),
    tan φ = Cω/(2h)."""
    thick, h, q0, ta = 0.02, 5.0, 300.0, 290.0
    omega = 2 * np.pi / DAY
    cap = STEEL.volumetric_heat_capacity * thick
    amp_ex = q0 / np.hypot(2 * h, cap * omega)
    phi = np.arctan2(cap * omega, 2 * h)
    g = plate_graph(thick, 4)
    outer = SurfaceBalance(absorbed_shortwave=lambda t: q0 * np.sin(omega * t), h=h, temp_air=ta)
    m = ThermalModel(g, {"plate:outer": outer, "plate:inner": Convection(h, ta)},
                     initial_temperature=ta + amp_ex * np.sin(-phi))
    dt = 300.0
    res = Simulation(m, dt, 3 * DAY, scheme="bdf2", output_interval=dt).run()
    last = res.times >= 2 * DAY
    t = res.times[last][:-1]
    series = res.part_mean("outer")["plate"].to_numpy()[last][:-1] - ta
    c = 2 * np.mean(series * np.exp(-1j * omega * t))
    amp_num, phase = abs(c), np.angle(c * 1j)    # sin(ωt − φ) → phase −φ
    # Lumping neglects the through-thickness gradient: Bi = h d / k = 0.002 → ~0.2 % of the
    # amplitude; the start-up transient decays as exp(−2h t/C) = e^{-25} by day 2.
    # Measured: amplitude 0.03 %, phase 2e-4 rad.
    assert amp_num == pytest.approx(amp_ex, rel=5e-3)
    assert phase == pytest.approx(-phi, abs=5e-3)


# ---------------------------------------------- 4. steady radiative-convective plate ------
@pytest.mark.parametrize("absorbed,emissivity,h", [(560.0, 0.9, 10.0), (0.0, 0.9, 2.0),
                                                   (900.0, 0.3, 0.0)])
def test_steady_radiative_convective_equilibrium(absorbed, emissivity, h):
    t_sky, t_air = 265.0, 300.0

    def balance(t):
        return absorbed - emissivity * SIGMA * (t**4 - t_sky**4) - h * (t - t_air)

    exact = brentq(balance, 150.0, 500.0, xtol=1e-12)
    g = plate_graph(0.01, 3)
    outer = SurfaceBalance(absorbed_shortwave=absorbed, emissivity=emissivity, temp_env=t_sky,
                           h=h, temp_air=t_air)
    m = ThermalModel(g, {"plate:outer": outer, "plate:inner": Adiabatic()}, initial_temperature=280.0)
    res = steady_state(m)
    # Newton converged to 1e-9 K; the insulated plate is isothermal at the surface value.
    np.testing.assert_allclose(res.final_temperature, exact, atol=1e-7)
    np.testing.assert_allclose(res.patch_mean("plate:outer"), exact, atol=1e-7)
