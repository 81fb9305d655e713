"""The thermal model: a cell graph, its boundary conditions and the flux operators.

Physics (per cell ``P`` of heat capacity ``C_P = ρ c V`` [J K-1])::

    C_P dT_P/dt = Σ_faces G_f (T_N − T_P)            two-point conduction (operator K)
                + Σ_faces k_f ∇T_f·(S_f − A_f cos θ e_f)  non-orthogonal correction (tets)
                + Σ_bfaces Q_b                        boundary heat flows into the body

Each boundary face ``b`` (area ``A``, cell-to-face conductance ``g``) carries a surface
temperature ``T_s`` that satisfies its own energy balance (no heat is stored in a
surface)::

    g (T_P − T_s) − c_b + A q(T_s) = 0,
    q(T_s) = q0 + h (T_fl − T_s) + ε L_in − e σ T_s⁴ + s_x                    [W m-2]

with ``q0`` absorbed short-wave / prescribed flux, ``h``/``T_fl`` convection, ``ε L_in``
absorbed long-wave, ``e = ε + Σ_j R_bj / A`` the emitting weight (own emission to the
surroundings plus to other faces of a :class:`RadiativeExchange`), ``s_x = σ/A Σ_j R_bj
T_j⁴`` the long-wave received from those faces and ``c_b`` the non-orthogonal part of the
conduction flux at the face. The heat flow into the cell is then ``Q_b = A q(T_s)``. The
balance is solved per face by Newton's method (the function is concave and decreasing in
``T_s``, so Newton converges monotonically from any positive start), which makes T⁴ fully
implicit: nothing is lagged across a time step. Its derivative gives the boundary part of
the global Jacobian, ``∂Q_b/∂T_P = −A γ κ/(γ + κ)`` with ``γ = g/A``, ``κ = h + 4 e σ T_s³``.

A coefficient that depends on the surface temperature (natural convection:
:class:`~shipthermal.conditions.ConvectionLaw`) is evaluated at the surface temperature of
the iterate (:func:`law_coefficients` at the surface temperatures the pass starts from: the
previous pass's solution), a fixed point carried by the outer Newton iteration: when it has
converged, ``h`` is the coefficient at the solved ``T_s`` (the change of ``T_s`` between the
last two passes is below the tolerance). The flux's full slope ``h + ΔT ∂h/∂ΔT`` enters
``κ``, so the Jacobian is that of the coefficient at the solved temperature. One evaluation
of the law per face and pass: solving each face balance with ``h(T)`` inside
(:func:`solve_law_face`, a bracketed Newton) took 5–6 times the boundary time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np
import scipy.sparse as sp
from numba import njit, prange

from .conditions import (BoundaryCondition, FaceForcing, evaluate, fill, law_h_and_slope,
                         plausible)
from .errors import InputError, check_finite, require
from .mesh.graph import CellGraph
from .units import SIGMA

__all__ = ["RadiativeExchange", "ThermalModel", "BoundaryState", "surface_balance",
           "solve_law_face", "law_coefficients",
           "nonorthogonal_flows", "conduction_flows", "boundary_state", "add_exchange_flow"]


@dataclass(frozen=True, eq=False)
class RadiativeExchange:
    """Grey long-wave exchange between boundary faces (e.g. ship faces that see each other).

    Parameters
    ----------
    bfaces : (k,) int array
        Boundary-face indices of the exchanging faces.
    area_exchange : (k, k) sparse matrix [m2]
        ``R_ij = A_i ε_i ε_j F_ij`` (symmetric by reciprocity ``A_i F_ij = A_j F_ji``). The net
        long-wave flow into face i is ``σ Σ_j R_ij (T_j⁴ − T_i⁴)`` [W]; with R symmetric the
        exchange conserves energy exactly.
    """

    bfaces: np.ndarray
    area_exchange: sp.csr_matrix

    def __post_init__(self):
        bf = np.asarray(self.bfaces, dtype=np.int64)
        r = sp.csr_matrix(self.area_exchange, dtype=float)
        require(bf.ndim == 1 and len(np.unique(bf)) == len(bf), "exchange.bfaces", bf.shape,
                "must be a 1-D array of distinct boundary-face indices")
        require(r.shape == (len(bf), len(bf)), "exchange.area_exchange", r.shape,
                f"must be square with one row per exchanging face ({len(bf)})")
        check_finite("exchange.area_exchange", r.data)
        require(bool(np.all(r.data >= 0)), "exchange.area_exchange", float(r.data.min(initial=0)),
                "entries A_i ε_i ε_j F_ij must be ≥ 0")
        asym = abs(r - r.T).max() if r.nnz else 0.0
        scale = abs(r).max() if r.nnz else 1.0
        require(asym <= 1e-9 * scale, "exchange.area_exchange", f"asymmetry {asym:.3g} m2",
                "must be symmetric (reciprocity A_i F_ij = A_j F_ji)",
                "Impose reciprocity first (shipthermal.raytrace.symmetrize)")
        r.setdiag(0.0)     # a flat face does not see itself; self-exchange is zero net anyway
        r.eliminate_zeros()
        object.__setattr__(self, "bfaces", bf)
        object.__setattr__(self, "area_exchange", r)

    def loss_per_face(self, n_bfaces: int) -> np.ndarray:
        """``Σ_j R_ij`` on all ``n_bfaces`` boundary faces, zero where a face exchanges
        nothing [m2] (built once)."""
        full = self.__dict__.get("_loss_full")
        if full is None or len(full) != n_bfaces:
            full = np.zeros(n_bfaces)
            full[self.bfaces] = self.row_sum
            object.__setattr__(self, "_loss_full", full)
        return full

    @property
    def row_sum(self) -> np.ndarray:
        """``Σ_j R_ij`` per exchanging face [m2] (computed once: the matrix is fixed)."""
        rs = self.__dict__.get("_row_sum")
        if rs is None:
            rs = np.asarray(self.area_exchange.sum(axis=1)).ravel()
            object.__setattr__(self, "_row_sum", rs)
        return rs


class ThermalModel:
    """A cell graph with boundary conditions per patch and an initial temperature.

    Parameters
    ----------
    graph : CellGraph
    conditions : mapping patch name → boundary condition
        Patches left out are adiabatic.
    initial_temperature : float or (n_cells,) array [K]
    exchange : RadiativeExchange, optional
        Face-to-face long-wave exchange, solved implicitly with the rest.
    heat_source : float, (n_cells,) array or f(t), optional
        Volumetric heat source [W m-3] (e.g. machinery, or a manufactured solution).
    """

    def __init__(self, graph: CellGraph, conditions: Mapping[str, BoundaryCondition] | None = None,
                 initial_temperature=293.15, exchange: RadiativeExchange | None = None,
                 heat_source=None):
        require(isinstance(graph, CellGraph), "graph", type(graph).__name__, "must be a CellGraph")
        conditions = dict(conditions or {})
        for name in conditions:
            if name not in graph.patch_names:
                import difflib

                close = difflib.get_close_matches(name, graph.patch_names, n=1)
                raise InputError(f"conditions[{name!r}]", name,
                                 f"unknown patch; the graph has: {', '.join(graph.patch_names)}",
                                 f"Did you mean {close[0]!r}?" if close else "")
        t0 = np.asarray(initial_temperature, dtype=float)
        if t0.ndim == 0:
            t0 = np.full(graph.n_cells, float(t0))
        require(t0.shape == (graph.n_cells,), "initial_temperature", t0.shape,
                f"must be a number or one value per cell ({graph.n_cells})")
        check_finite("initial_temperature", t0)
        require(bool(np.all(t0 > 0)), "initial_temperature", float(t0.min()), "must be > 0 K")
        if exchange is not None:
            require(isinstance(exchange, RadiativeExchange), "exchange", type(exchange).__name__,
                    "must be a RadiativeExchange")
            require(exchange.bfaces.max(initial=-1) < graph.n_bfaces and exchange.bfaces.min(initial=0) >= 0,
                    "exchange.bfaces", (int(exchange.bfaces.min(initial=0)),
                                        int(exchange.bfaces.max(initial=-1))),
                    f"must index boundary faces 0..{graph.n_bfaces - 1}")
        self.graph = graph
        self.heat_source = heat_source
        self.conditions = conditions
        self.initial_temperature = t0
        self.exchange = exchange
        self._patch_idx = {name: graph.patch_faces(name) for name in conditions}
        # Check the conditions once at t = 0 so that a bad value fails before any solve
        # (every check, including those plausible() cannot tell: a Radiation's ε = 0).
        self._fill(0.0, check=True)
        self.source(0.0)

    def forcing(self, t: float) -> FaceForcing:
        """Per-boundary-face forcing at time ``t`` [s].

        The patches are filled without their per-value checks and the joined forcing is
        checked in one pass (:func:`~shipthermal.conditions.plausible`); when that fails
        they are filled again with the checks, whose error names the patch, the field and
        the value (with the natural law's table rows computed alone, see
        :meth:`~shipthermal.environment.convection.ConvectionModel.natural_law`: 1.87 →
        1.08 ms a step of the frigate at 2 m)."""
        f = self._fill(t, check=False)
        if plausible(f):
            return f
        return self._fill(t, check=True)   # raises, naming the bad value

    def _fill(self, t: float, check: bool) -> FaceForcing:
        f = FaceForcing.zeros(self.graph.n_bfaces)
        for name, bc in self.conditions.items():
            fill(f, self._patch_idx[name], bc, t, f"conditions[{name!r}]", check)
        return f.finish()

    def source(self, t: float) -> np.ndarray:
        """Heat generated in each cell at time ``t`` [W]."""
        g = self.graph
        if self.heat_source is None:
            return np.zeros(g.n_cells)
        q = evaluate(self.heat_source, t, g.n_cells, "heat_source")
        return q * g.cell_volume

    @property
    def has_sink(self) -> bool:
        """True when some boundary can exchange heat with a fixed reference (needed for a
        steady state)."""
        f = self.forcing(0.0)
        return bool(np.any(f.fixed) or np.any(f.h > 0) or np.any(f.emissivity > 0)
                    or f.has_law)


@dataclass
class BoundaryState:
    """Boundary faces at one Newton iterate."""

    temp_face: np.ndarray   # (b,) surface temperature [K]
    flow: np.ndarray        # (b,) heat flow into the body [W]
    conductance: np.ndarray  # (b,) −∂flow/∂T_cell [W K-1]
    converged: bool = True   # the face-to-face fixed point reached its tolerance


def surface_balance(graph: CellGraph, forcing: FaceForcing, temp_cell: np.ndarray,
                    temp_guess: np.ndarray, correction_flow: np.ndarray | None = None,
                    exchange: RadiativeExchange | None = None,
                    exchange_temp: np.ndarray | None = None, tol: float = 1e-12,
                    max_iterations: int = 60, exchange_flow: bool = True,
                    received: np.ndarray | None = None,
                    law_values: tuple | None = None) -> BoundaryState:
    """Solve every boundary face's energy balance for its surface temperature (see module
    docstring) and return the flows into the cells and their derivatives.

    Parameters
    ----------
    temp_cell : (n,) cell temperatures [K]
    temp_guess : (b,) starting surface temperatures [K] (e.g. the previous iterate)
    correction_flow : (b,) non-orthogonal conduction flow from the face into the cell ``c_b``
        [W], lagged (None: zero)
    exchange_temp : (b,) surface temperatures used for the radiation received from other
        faces (lagged within the nonlinear iteration) [K]
    exchange_flow : bool
        Include the face-to-face part in ``flow`` (a fixed-point loop over the faces needs
        it only once, at the end: :func:`add_exchange_flow`).
    received : (k,) array, optional
        ``Σ_j R_ij T_j⁴`` of the exchanging faces at ``exchange_temp`` [m2 K4], when the
        caller has it (computed here otherwise).
    law_values : (h, slope), optional
        The coefficients of :func:`law_coefficients` when the caller has them (computed
        here at ``temp_guess`` otherwise).
    """
    area = graph.bface_area
    g = graph.bface_conductance
    none = np.zeros(0)             # (the kernel reads an empty array as zeros)
    cb = none if correction_flow is None else correction_flow
    gain = loss = none
    if exchange is not None:
        gain = np.zeros_like(area)      # σ Σ_j R_ij T_j⁴ (lagged) [W]
        if received is None:
            received = _received(exchange, exchange_temp)
        gain[exchange.bfaces] = SIGMA * received
        loss = exchange.loss_per_face(len(area))
    ts = np.empty_like(area)
    flow = np.empty_like(area)
    cond = np.empty_like(area)
    h, slope, temp_ref = forcing.h, none, none
    if forcing.has_law:
        h, slope, temp_ref = (law_coefficients(forcing, temp_guess) if law_values is None
                              else law_values)
    step = _balance_kernel(area, g, np.ascontiguousarray(temp_cell, dtype=np.float64),
                           graph.bface_cell, cb, forcing.q0, h, forcing.temp_fluid,
                           forcing.emissivity, forcing.longwave_in, forcing.fixed,
                           forcing.temp_fixed, gain, loss, np.asarray(temp_guess, float),
                           float(tol), int(max_iterations), ts, flow, cond, slope, temp_ref)
    if step > 0.0:
        raise RuntimeError(f"surface energy balance did not converge (max step {step:.3g} K)")
    state = BoundaryState(ts, flow, cond)
    if exchange is not None and exchange_flow:
        add_exchange_flow(state, exchange)
    return state


def add_exchange_flow(state: BoundaryState, exchange: RadiativeExchange,
                      temp_face: np.ndarray | None = None,
                      received: np.ndarray | None = None) -> None:
    """Add the face-to-face part to ``state.flow``, with the *same* temperatures on both
    sides, σ Σ_j R_ij (T_j⁴ − T_i⁴): it cancels exactly in the energy sum whatever the lag
    of the temperatures the balance was solved with. The temperatures are ``temp_face``
    (default: the state's own) and ``received`` their ``Σ_j R_ij T_j⁴`` (computed when not
    given)."""
    idx = exchange.bfaces
    temp = state.temp_face if temp_face is None else temp_face
    if received is None:
        received = _received(exchange, temp)
    t2 = temp[idx] ** 2
    t4 = t2 * t2                     # as in _received_kernel
    state.flow[idx] += SIGMA * (received - exchange.row_sum * t4)


def _received(exchange: RadiativeExchange, temp_face: np.ndarray) -> np.ndarray:
    """``Σ_j R_ij T_j⁴`` of every exchanging face [m2 K4]: ``R @ T⁴`` on the process's
    threads (rows summed in scipy's order)."""
    r = exchange.area_exchange
    out = np.empty(r.shape[0])
    _received_kernel(r.indptr, r.indices, r.data, exchange.bfaces,
                     np.ascontiguousarray(temp_face, dtype=np.float64), out)
    return out


@njit(parallel=True, cache=True)
def _received_kernel(indptr, indices, data, bfaces, temp_face, out):
    t4 = np.empty(bfaces.shape[0])
    for i in prange(bfaces.shape[0]):
        t = temp_face[np.uint64(bfaces[i])]
        t4[i] = (t * t) * (t * t)
    for i in prange(out.shape[0]):
        s = 0.0
        for k in range(np.uint64(indptr[i]), np.uint64(indptr[i + 1])):
            s += data[k] * t4[np.uint64(indices[k])]
        out[i] = s


def law_coefficients(forcing: FaceForcing, temp_face: np.ndarray):
    """``(h, slope, temp_face)`` of every boundary face: the coefficient [W m-2 K-1] at the
    surface temperatures ``temp_face`` [K] (its :class:`~shipthermal.conditions.ConvectionLaw`
    where it has one, else ``forcing.h``), ``ΔT ∂h/∂ΔT`` [W m-2 K-1] (zero without a law) and
    the temperatures themselves (where the balance linearises the flux)."""
    h = forcing.h.copy()
    slope = np.zeros_like(h)
    temp = np.ascontiguousarray(temp_face, dtype=np.float64)
    _law_kernel(forcing.law_faces, forcing.h, forcing.temp_fluid, forcing.law_natural,
                forcing.law_blend, forcing.law_multiplier, forcing.law_normal_z, temp, h, slope)
    return h, slope, temp


@njit(parallel=True, cache=True)
def _law_kernel(law_faces, h_forced, tfl, natural, blend, mult, nz, temp_face, h, slope):
    """Each law row ``j`` at its face ``law_faces[j]``: the threads share the law faces,
    not all faces (frigate at 0.5 m, 40 288 law faces of 119 388: 5.1 → 2.6 ms a call on
    two threads, the same on one)."""
    for j in prange(law_faces.shape[0]):
        i = law_faces[j]
        h[i], slope[i] = law_h_and_slope(h_forced[i], blend[j], mult[j], nz[j], natural[j],
                                         temp_face[i] - tfl[i])


@njit(parallel=True, cache=True)
def _balance_kernel(area, g, temp_cell, bface_cell, cb_in, q0, h, tfl, eps, lw, fixed, tfix,
                    gain_in, loss_in, guess,
                    tol, max_iterations, ts, flow, cond, slope_in, temp_ref):
    """Per face: Newton on ``f(T) = rhs − (γ + h) T − e σ T⁴`` (concave, decreasing: monotone
    convergence from any positive start), then the flow into the cell (without the
    face-to-face part, added by the caller) and ``−∂flow/∂T_cell``. One pass over the faces
    (on the process's threads) instead of ~30 array operations per Newton sweep; each face
    stops on its own step ``|ΔT| ≤ tol·T``. Empty ``cb_in`` / ``gain_in`` / ``loss_in`` /
    ``slope_in`` read as zeros. ``slope_in`` is ``ΔT ∂h/∂ΔT`` of a coefficient that depends
    on the surface temperature, ``h`` its value at ``temp_ref`` (:func:`law_coefficients`):
    the convective flux is then taken to first order about ``temp_ref``,
    ``h (T_ref − T_fl) + (h + slope)(T − T_ref)``, exact where ``T = T_ref`` (the outer
    iteration's fixed point). Returns 0.0, or the largest last step of faces that did not
    converge."""
    unconverged = np.zeros(area.shape[0])
    with_cb = cb_in.shape[0] > 0
    with_exchange = gain_in.shape[0] > 0
    with_slope = slope_in.shape[0] > 0
    for i in prange(area.shape[0]):
        tci = temp_cell[np.uint64(bface_cell[i])]
        cbi = cb_in[i] if with_cb else 0.0
        gain = gain_in[i] if with_exchange else 0.0
        loss = loss_in[i] if with_exchange else 0.0
        gamma = g[i] / area[i]
        e = eps[i] + loss / area[i]
        es = e * SIGMA
        hi_ = h[i]
        sl = slope_in[i] if with_slope else 0.0
        # convective flux out of the face: (h + sl) T − h T_fl − sl T_ref
        lin = gamma + hi_ + sl
        conv0 = hi_ * tfl[i] + (sl * temp_ref[i] if sl != 0.0 else 0.0)
        rhs = gamma * tci - cbi / area[i] + q0[i] + conv0 + eps[i] * lw[i] \
            + gain / area[i]
        if es > 0.0:
            t = max(guess[i], 1.0)
            ok = False
            step = 0.0
            for _ in range(max_iterations):
                t3 = t * t * t
                f = rhs - lin * t - es * t3 * t
                df = -lin - 4.0 * es * t3
                step = f / df
                t = t - step
                if abs(step) <= tol * t:
                    ok = True
                    break
            if not ok:
                unconverged[i] = abs(step)
        else:
            t = rhs / lin
        kappa = hi_ + sl + 4.0 * es * t * t * t
        if fixed[i]:
            ts[i] = tfix[i]
            flow[i] = g[i] * (tfix[i] - tci) + cbi
            cond[i] = g[i]
        else:
            ts[i] = t
            t2 = t * t
            flow[i] = area[i] * (q0[i] + conv0 - (hi_ + sl) * t + eps[i] * lw[i]
                                 - eps[i] * SIGMA * t2 * t2)
            cond[i] = area[i] * gamma * kappa / (gamma + kappa)
    return unconverged.max() if area.shape[0] else 0.0


@njit(cache=True)
def solve_law_face(rhs0, gamma, es, h_forced, tfl, blend, mult, nz, law, guess, tol,
              max_iterations):
    """One face's balance ``rhs0 − γ T − h(T)(T − T_fl) − e σ T⁴ = 0`` with ``h`` of its
    convection law at ``T``: Newton with the flux slope ``h + ΔT ∂h/∂ΔT``, kept inside a
    bracket of the root (``f`` is strictly decreasing) by bisection. Returns ``(T, h(T),
    flux slope, 0.0)`` or, when it did not converge, the last step as the fourth value."""
    t = max(guess, 1.0)
    lo = 0.0
    hi = np.inf
    step = 0.0
    for _ in range(max_iterations):
        d = t - tfl
        hh, gg = law_h_and_slope(h_forced, blend, mult, nz, law, d)
        t3 = t * t * t
        f = rhs0 - gamma * t - hh * d - es * t3 * t
        if f > 0.0:
            lo = t
        else:
            hi = t
        df = -gamma - (hh + gg) - 4.0 * es * t3
        step = f / df
        t_new = t - step
        if abs(step) <= tol * t_new:
            t = t_new
            hh, gg = law_h_and_slope(h_forced, blend, mult, nz, law, t - tfl)
            return t, hh, hh + gg, 0.0
        if t_new <= lo or t_new >= hi:
            # a step out of the bracket (the flux's curvature changes sign at T_fl)
            t_new = 0.5 * (lo + hi) if np.isfinite(hi) else 2.0 * t
            step = t - t_new
        t = t_new
    hh, gg = law_h_and_slope(h_forced, blend, mult, nz, law, t - tfl)
    return t, hh, hh + gg, step


@njit(cache=True)
def _change_and_max(new, old):
    """``(max |new − old|, max new)`` of two face-temperature arrays (0 when empty)."""
    change = 0.0
    top = -np.inf if new.shape[0] else 0.0
    for i in range(new.shape[0]):
        d = abs(new[i] - old[i])
        if d != d:              # a NaN is the answer, as numpy's max gives
            return d, d
        if d > change:
            change = d
        if new[i] > top:
            top = new[i]
    return change, top


def conduction_flows(graph: CellGraph, temp_cell: np.ndarray) -> np.ndarray:
    """Net two-point conductive heat flow into each cell, ``−K T`` [W].

    Evaluated face by face from temperature *differences*, not as ``K @ T``: the products
    ``G T`` of the matrix form carry a round-off of ~1e-16·G·T per cell (W-sized for stiff
    plates at 300 K), which would show up as an energy imbalance; the flux form is
    antisymmetric face by face (each side computes ``G (T_other − T_self)``, the exact
    negative of the other side's), so interior flows cancel to round-off of the fluxes
    themselves. Gathered per cell, so the cells are shared among the process's threads.
    """
    out = np.empty(graph.n_cells)
    ptr, nb, g = graph.cell_faces
    _conduction_kernel(ptr, nb, g, np.ascontiguousarray(temp_cell, dtype=np.float64), out)
    return out


@njit(parallel=True, cache=True)
def _conduction_kernel(ptr, nb, g, temp, out):
    for c in prange(out.shape[0]):
        tc = temp[c]
        s = 0.0
        for k in range(np.uint64(ptr[c]), np.uint64(ptr[c + 1])):
            s += g[k] * (temp[np.uint64(nb[k])] - tc)
        out[c] = s


def nonorthogonal_flows(graph: CellGraph, temp_cell: np.ndarray, temp_face: np.ndarray):
    """Explicit non-orthogonal correction (deferred correction).

    Returns
    -------
    cell_flow : (n,) net correction heat flow into each cell from interior faces [W]
    bface_flow : (b,) correction flow from each boundary face into its cell ``c_b`` [W]
    """
    corr = graph.correction
    n = graph.n_cells
    grad = (corr.gradient @ np.concatenate([temp_cell, temp_face])).reshape(3, n).T
    own, nei = graph.face_cells[:, 0], graph.face_cells[:, 1]
    w = corr.face_weight[:, None]
    grad_f = w * grad[own] + (1.0 - w) * grad[nei]
    flux = np.einsum("ij,ij->i", corr.face_kt, grad_f)   # into the owner
    cell_flow = np.bincount(own, flux, n) - np.bincount(nei, flux, n)
    bface_flow = np.einsum("ij,ij->i", corr.bface_kt, grad[graph.bface_cell])
    return cell_flow, bface_flow


#: The surface temperatures' fixed point is converged when its last sweep changed no face
#: by more than this fraction of the largest surface temperature [-] (:func:`boundary_state`;
#: round-off of a surface temperature's ~300 K, the solver's own default).
SURFACE_TOLERANCE = 1e-11


def boundary_state(model: "ThermalModel", forcing: FaceForcing, temp_cell: np.ndarray,
                   temp_guess: np.ndarray, tol: float = SURFACE_TOLERANCE, max_iterations: int = 200,
                   sweeps: int | None = None):
    """Surface temperatures and flows consistent with the cell field ``temp_cell``.

    The surface balance of a face depends on other faces through the non-orthogonal
    correction (the cell gradient uses the face temperatures) and the face-to-face
    radiation; both are iterated here, at fixed cell temperatures, to a fixed point
    (cheap: local work and one sparse product per pass). The result is then a function
    of ``temp_cell`` alone, which the outer Newton/Anderson iteration needs.

    ``sweeps`` caps the passes of the fixed point instead (no error when it stops short;
    ``state.converged`` tells): an outer iteration that moves ``temp_cell`` anyway can
    carry the fixed point along and accept only a converged one.

    Returns
    -------
    corr_cell : (n,) non-orthogonal interior correction flow into each cell [W] (0.0 if none)
    state : BoundaryState
    """
    g = model.graph
    exch = model.exchange
    tf = temp_guess
    if g.correction is None and exch is None:
        return 0.0, surface_balance(g, forcing, temp_cell, tf)
    if g.correction is not None:
        bgrad, local = g.boundary_gradient
        bkt = g.correction.bface_kt
        m = bgrad.shape[0] // 3
    cb = None
    limit = max_iterations if sweeps is None else max(1, int(sweeps))
    converged = False
    # a temperature-dependent coefficient at the temperatures the sweeps start from (the
    # outer iteration carries it to the solved ones); an uncapped fixed point (a steady
    # state) carries it along itself, sweep by sweep
    law = law_coefficients(forcing, tf) if forcing.has_law else None
    for _ in range(limit):
        if g.correction is not None:
            grad = (bgrad @ np.concatenate([temp_cell, tf])).reshape(3, m).T
            cb = np.einsum("ij,ij->i", bkt, grad[local])
        received = _received(exch, tf) if exch is not None else None
        bs = surface_balance(g, forcing, temp_cell, tf, cb, exch, tf, exchange_flow=False,
                             received=received, law_values=law)
        if law is not None and sweeps is None:
            law = law_coefficients(forcing, bs.temp_face)
        change, top = _change_and_max(bs.temp_face, tf)
        tf_in, tf = tf, bs.temp_face
        if change <= tol * max(1.0, top):
            converged = True
            break
    if not converged and sweeps is None:
        raise RuntimeError(f"boundary fixed point did not converge (last change {change:.3g} K)")
    bs.converged = converged
    if exch is not None:
        # The face-to-face flows at the temperatures the last pass received from (their
        # R T⁴ is at hand): on a converged fixed point they differ from its result by the
        # tolerance, and the flows cancel in the energy sum either way.
        add_exchange_flow(bs, exch, tf_in, received)
    corr_cell = 0.0
    if g.correction is not None:
        # Interior correction once, with the converged face temperatures; c_b of the last
        # pass is consistent with them to the tolerance.
        corr_cell, _ = nonorthogonal_flows(g, temp_cell, tf)
    return corr_cell, bs
