"""Implicit time stepping and steady state of a :class:`~shipthermal.model.ThermalModel`.

Schemes (constant step Δt; ``T*`` the history, ``F(T, t) = −K T + Σ Q_b + S_corr`` the net
heat flow into each cell)::

    backward_euler   C (T¹ − T⁰)/Δt              = F(T¹, t¹)                  order 1
    crank_nicolson   C (T¹ − T⁰)/Δt              = ½ F(T¹, t¹) + ½ F(T⁰, t⁰)   order 2
    bdf2             C (3T² − 4T¹ + T⁰)/(2Δt)    = F(T², t²)                  order 2
                     (first step backward Euler)

Each step is a nonlinear system (T⁴ radiation, non-orthogonal and face-to-face exchange
terms) solved by Newton's method with the exact boundary Jacobian (:mod:`.model`). The
parts left out of the (symmetric) Jacobian — non-orthogonal correction, radiation received
from other faces — are iterated to convergence inside the same loop (deferred correction,
Anderson-accelerated), so the step is fully implicit. Convergence: the Jacobi-scaled
residual ``max |R_i| / J_ii`` (an estimate of the next correction [K]) is below
``tolerance`` [K].

Energy bookkeeping (every step)::

    stored    = Σ C (a T^{n+1} − T*)        the scheme's own stored-energy change [J]
    boundary  = Δt Σ_b [θ Q_b^{n+1} + (1 − θ) Q_b^n]    heat in through the boundary [J]

Interior fluxes cancel pairwise, so ``stored − boundary = Δt Σ_i R_i``, the sum of the
nonlinear residuals: at convergence it is at round-off level. For BDF2 the conserved
stored quantity is ``Σ C (3T^{n+1} − T^n)/2``, which differs from ``Σ C T`` by half the
last step's change (reported separately as ``stored_plain``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._aggregates import column_aggregates
from ._step_kernels import cell_residual, exchange_values, max_ratio, moved_faces_kernel
from ._tridiagonal import ColumnSolve, column_bounds, column_factor
from ._threads import kernel_threads
from .errors import SimulationError, check_finite, check_positive, require
from .linear import (Anderson, JacobianPattern, Preconditioner, choose_backend,
                     make_preconditioner, pcg, single_threaded_blas)
from .steady import steady_state
from .model import (SURFACE_TOLERANCE, ThermalModel, boundary_state, conduction_flows,
                    surface_balance)
from .checkpoint import SolverState, read_checkpoint, write_checkpoint
from .results import EnergyLog, Results
from .units import SIGMA

__all__ = ["SCHEMES", "Simulation", "steady_state", "SimulationError"]

SCHEMES = ("backward_euler", "crank_nicolson", "bdf2")

#: Relative residual to which a Newton correction is solved at most (inexact Newton):
#: below it the correction is more accurate than the Newton step it belongs to.
NEWTON_LINEAR_RTOL = 1e-4
#: Passes of the face-to-face fixed point (:func:`.model.boundary_state`) per Newton pass at
#: most: the Newton passes move the cells anyway, so the faces converge along with them and
#: a step is accepted only with a converged fixed point. Built-in frigate day at 0.5 m: the
#: boundary balances take 7.0 → 5.0 s with the same 4.13 Newton passes a step (one pass:
#: 4.1 s but 5.0 Newton passes a step, whose solves cost more than the saving).
BOUNDARY_SWEEPS = 2


class _ExtrapolatedCorrection:
    """The non-orthogonal correction of a step held fixed from the predicted field
    (:mod:`.mesh.graph`, treatment ``"extrapolated"``): ``(interior flow into each cell,
    flow from each boundary face into its cell)`` [W].

    The cells are predicted by the caller (``2Tⁿ − Tⁿ⁻¹``); the surface temperatures are
    made consistent with them by the boundary fixed point (each face's balance with the
    correction flow of its cell's gradient, as :func:`.model.boundary_state`), started from
    the surface temperatures extrapolated like the cells (the current ones on a first step
    or after a checkpoint was loaded; the answer does not depend on the start beyond the
    tolerance). Extrapolated surface temperatures used as they are made the steps unstable
    on convecting boxes (measured: growth ×100 per halving of Δt).

    ``active`` is False when the graph has no correction, asks for it iterated, or exchanges
    radiation face to face (whose fixed point the iterated path solves with the correction).
    """

    #: Fixed-point tolerance on the surface temperatures, relative to the largest (≈ 3e-7 K
    #: at 300 K): the predicted correction itself carries the O(Δt²) extrapolation error.
    TOLERANCE = 1e-9

    def __init__(self, model):
        g = model.graph
        self.model = model
        self.active = (g.correction is not None and g.correction.treatment == "extrapolated"
                       and model.exchange is None)
        if self.active:
            bface = g.correction_operators[1]
            self._b_cell = bface[:, :g.n_cells].tocsr()
            self._b_face = bface[:, g.n_cells:].tocsr()
        self._last = None       # (state, its step, its surface temperatures)
        self.iterations = 0

    def __call__(self, forcing, state, temp_pred, max_iterations=200):
        g = self.model.graph
        last, self._last = self._last, (state, state.step, state.temp_face)
        tf = state.temp_face
        if last is not None and last[0] is state and last[1] == state.step - 1:
            tf = 2.0 * tf - last[2]
        from_cells = self._b_cell @ temp_pred
        for _ in range(max_iterations):
            self.iterations += 1
            bs = surface_balance(g, forcing, temp_pred, tf, from_cells + self._b_face @ tf)
            change = np.max(np.abs(bs.temp_face - tf)) if len(tf) else 0.0
            tf = bs.temp_face
            if change <= self.TOLERANCE * max(1.0, float(np.max(tf))):
                break
        else:
            raise SimulationError("boundary fixed point of the extrapolated non-orthogonal "
                                  f"correction did not converge (last change {change:.3g} K)")
        return g.correction_flows(temp_pred, tf)


@dataclass
class _Timing:
    forcing: float = 0.0
    boundary: float = 0.0
    assembly: float = 0.0
    solve: float = 0.0
    setup: float = 0.0
    newton_iterations: int = 0
    linear_iterations: int = 0
    preconditioner_builds: int = 0

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class _Step:
    """What stays fixed over the Newton passes of one step."""

    t_new: float                   # the step's end [s]
    dt: float
    a: float                       # the scheme's coefficient of T at the new time
    theta: float                   # its weight of F at the new time
    hist: np.ndarray               # T* (the scheme's history term) [K]
    explicit: np.ndarray | None    # (1 − θ) F at the old time (Crank–Nicolson) [W]
    forcing: object
    source: np.ndarray
    temp: np.ndarray               # predicted cells [K]
    face_lag: np.ndarray           # surface temperatures to start the balances from [K]
    diag_c: np.ndarray             # a C/Δt [W K-1]
    pattern: JacobianPattern
    key: tuple                     # (Δt, a, θ) of this step's Jacobian
    prec_a: float                  # a of the Jacobian the preconditioner is built from
    prec_key: tuple
    fixed_corr: tuple | None       # the non-orthogonal correction held over the step
    accel: Anderson | None


class Simulation:
    """Time integration of a thermal model.

    Parameters
    ----------
    model : ThermalModel
    time_step : float
        Δt [s], > 0.
    stop_time : float
        End of :meth:`run` [s] (clock of the boundary conditions).
    start_time : float
        Start [s].
    scheme : {'backward_euler', 'crank_nicolson', 'bdf2'}
    output_interval : float, optional
        Record every this many seconds of the clock (a multiple of ``time_step``); default:
        every step.
    output_times : array_like, optional
        Explicit record times [s] on the step grid (instead of ``output_interval``).
    tolerance : float
        Nonlinear convergence tolerance on the estimated temperature correction [K].
    energy_tolerance : float
        The step's energy residual ``Δt |Σ_i R_i|`` must also fall below this fraction of
        the gross boundary heat of the step [-].
    surface_tolerance : float
        ... and the surface temperatures' fixed point (face-to-face exchange) must have
        changed no face by more than this fraction of the largest surface temperature in
        its last sweep [-].
    max_iterations : int
        Newton iterations per step before :class:`SimulationError`.
    linear_solver : {'auto', 'direct', 'amg', 'column', 'cholmod'}
        Preconditioner backend (:mod:`.linear`; ``auto`` measures).
    progress : bool
        Show a tqdm progress bar.
    """

    def __init__(self, model: ThermalModel, time_step: float, stop_time: float,
                 start_time: float = 0.0, scheme: str = "bdf2", output_interval: float | None = None,
                 output_times=None, tolerance: float = 1e-9, max_iterations: int = 50,
                 linear_solver: str = "auto", progress: bool = False,
                 energy_tolerance: float = 1e-12,
                 surface_tolerance: float = SURFACE_TOLERANCE):
        require(isinstance(model, ThermalModel), "model", type(model).__name__,
                "must be a ThermalModel")
        check_positive("time_step", time_step, "s")
        check_finite("start_time", start_time)
        check_finite("stop_time", stop_time)
        require(stop_time > start_time, "stop_time", stop_time, f"must be > start_time ({start_time} s)")
        require(scheme in SCHEMES, "scheme", scheme, f"must be one of {SCHEMES}")
        check_positive("tolerance", tolerance, "K")
        self.model = model
        self.graph = model.graph
        self.dt = float(time_step)          # the run's base step (``set_time_step`` varies it)
        self._dt_now = self.dt
        self.start_time = float(start_time)
        self.stop_time = float(stop_time)
        self.scheme = scheme
        self.tolerance = float(tolerance)
        check_positive("energy_tolerance", energy_tolerance)
        self.energy_tolerance = float(energy_tolerance)
        check_positive("surface_tolerance", surface_tolerance)
        self.surface_tolerance = float(surface_tolerance)
        self.max_iterations = int(max_iterations)
        self.backend = choose_backend(linear_solver, self.graph.n_cells, self.graph.kind)
        self.progress = progress
        self._output_interval = None
        self._output_times = None
        if output_times is not None:
            ot = np.atleast_1d(np.asarray(output_times, dtype=float))
            check_finite("output_times", ot)
            k = (ot - self.start_time) / self.dt
            require(bool(np.all(np.abs(k - np.round(k)) < 1e-6)), "output_times", ot,
                    f"must lie on the step grid start_time + k·time_step (time_step {self.dt} s)")
            self._output_times = self.start_time + np.round(k) * self.dt
        elif output_interval is not None:
            check_positive("output_interval", output_interval, "s")
            k = output_interval / self.dt
            require(abs(k - round(k)) < 1e-9 and round(k) >= 1, "output_interval", output_interval,
                    f"must be a whole multiple of time_step ({self.dt} s)")
            self._output_interval = round(k) * self.dt
        self.timing = _Timing()
        self._column_break = None
        self._column_bounds = None
        self._aggregates = None    # column groups of the preconditioner (see _aggregates)
        # (checkpoint path, its record files, whether the records still continue them)
        self._record_files = (None, None, False)
        if self.backend == "column":
            cf = self.graph.metadata["cell_face"]
            self._column_break = cf[1:] != cf[:-1]
        self._precond = None
        self._precond_key = None
        self._state = self._initial_state()

    # ------------------------------------------------------------------ state --------------
    def _initial_state(self) -> SolverState:
        m = self.model
        t0 = self.start_time
        temp = m.initial_temperature.copy()
        forcing = m.forcing(t0)
        guess = temp[self.graph.bface_cell]
        source = m.source(t0)
        cell_flow, bstate = self._flows(temp, forcing, guess)
        st = SolverState(t0, 0, temp, None, bstate.temp_face, bstate.flow, source, cell_flow + source,
                    self._face_slope(bstate), origin=(t0, 0))
        self._maybe_record(st, force=True)
        return st

    @property
    def time(self) -> float:
        """Current clock [s]."""
        return self._state.time

    @property
    def temperature(self) -> np.ndarray:
        """Current cell temperatures [K] (a copy)."""
        return self._state.temp.copy()

    @property
    def face_temperature(self) -> np.ndarray:
        """Current boundary-face surface temperatures [K] (a copy)."""
        return self._state.temp_face.copy()

    @property
    def face_flow(self) -> np.ndarray:
        """Current heat flow into the body through each boundary face [W] (a copy)."""
        return self._state.flow_face.copy()

    def _is_output_time(self, t: float) -> bool:
        tol = 1e-6 * self.dt
        if self._output_times is not None:
            return bool(np.any(np.abs(self._output_times - t) <= tol))
        if self._output_interval is not None:
            k = (t - self.start_time) / self._output_interval
            return abs(k - round(k)) * self._output_interval <= tol
        return True

    def _maybe_record(self, st: SolverState, force: bool = False) -> None:
        if not (force and self._output_times is None) and not self._is_output_time(st.time):
            return
        self._record(st)

    @property
    def time_step(self) -> float:
        """Length of the next step [s]."""
        return self._dt_now

    def set_time_step(self, time_step: float) -> None:
        """Take steps of ``time_step`` [s] from the current time on.

        BDF2 continues with its variable-step form (coefficients from the ratio ω of the new
        step to the last one): second order, and zero-stable for ω < 1 + √2 (Grigorieff;
        Hairer, Nørsett & Wanner, *Solving ODEs I*, §III.5), so a step may at most double
        (a longer step is reached through intermediate ones). Recording times must stay on
        the new grid.
        """
        check_positive("time_step", time_step, "s")
        dt = float(time_step)
        st = self._state
        if dt == self._dt_now:
            return
        if self.scheme == "bdf2" and st.dt_prev > 0.0:
            require(dt <= 2.0 * st.dt_prev * (1 + 1e-12), "time_step", dt,
                    f"may at most double the last step ({st.dt_prev:g} s) under BDF2",
                    "lengthen the step through intermediate steps")
        tol = 1e-6 * dt
        if self._output_times is not None:
            ahead = self._output_times[self._output_times > st.time + tol] - st.time
        elif self._output_interval is not None:
            iv = self._output_interval
            k = np.ceil((st.time - self.start_time) / iv - 1e-9)
            ahead = np.array([self.start_time + k * iv - st.time, iv])
        else:
            ahead = np.zeros(0)
        k = ahead / dt
        require(bool(np.all(np.abs(k - np.round(k)) * dt <= tol)), "time_step", dt,
                "must keep the recording times on the step grid", "a divisor of the "
                "recording interval, started on a recording time")
        self._dt_now = dt
        st.origin = (st.time, st.step)

    def continue_with(self, model: ThermalModel) -> None:
        """Go on from the current state under ``model``: the same graph and face-to-face
        exchange, other boundary conditions (a weather record's next window of forcing
        tables, :func:`shipthermal.diurnal.run_record`).

        The whole state carries over — temperatures and the step before (BDF2's history),
        the last step's length, surface temperatures and their slopes, the recording grid,
        the preconditioner and its column groups — so a run continued this way equals one
        run under a single model whose conditions agree at every time it is asked for.
        """
        require(isinstance(model, ThermalModel), "model", type(model).__name__,
                "must be a ThermalModel")
        require(model.graph is self.graph, "model.graph", "another graph",
                "must be the simulation's own graph (a new model continues the same cells)")
        require(model.exchange is self.model.exchange, "model.exchange", "another exchange",
                "must be the simulation's own RadiativeExchange object (or None for both)")
        self.model = model
        corr = self.__dict__.get("_extrapolated_corr")
        if corr is not None:
            corr.model = model

    # ----------------------------------------------------------- operators -----------------
    def _flows(self, temp, forcing, face_guess):
        """Net heat flow into each cell F(T) (without sources) and the boundary state."""
        g = self.graph
        corr_cell, bs = boundary_state(self.model, forcing, temp, face_guess)
        flow = conduction_flows(g, temp) + np.bincount(g.bface_cell, bs.flow, g.n_cells) + corr_cell
        return flow, bs

    def _exchange_jacobian(self, bs) -> np.ndarray:
        """Cell-to-cell part of the face-to-face radiation in the Jacobian [W K-1].

        The flow into face i gains ``σ R_ij T_j⁴`` from face j; through the surface balances,
        ``∂T_s/∂T_cell = s = 1 − G_eff/g`` on each side, so cells i and j couple by
        ``s_i 4σ R_ij T̄³ s_j`` (T̄³ the mean of the two faces' cubes keeps it symmetric). The
        losses ``4σ Σ_j R_ij T_i³`` are already in the diagonal. With this term Newton
        converges quadratically instead of linearly in the exchange. All of it pays: on the
        frigate's day at 0.5 m (1.2 M exchange entries of the Jacobian), keeping only the
        larger half of the entries (77 % of their sum) or a fifth (59 %) or none made the
        time loop 21.6 → 23.3, 26.6 and 23.5 s (Newton passes a step 2.18 → 2.47, 2.78 and
        2.96): the smaller matrix saves less than the extra passes cost.
        """
        ex = self.model.exchange
        g = self.graph
        row, col, data, _, _ = self._exchange_coo()
        bf = ex.bfaces
        s = 1.0 - bs.conductance[bf] / g.bface_conductance[bf]
        t3 = bs.temp_face[bf] ** 3
        # values at the pattern's extra entries (cell of face i, cell of face j)
        out = np.empty_like(data)
        exchange_values(data, row, col, t3, s, 4.0 * SIGMA, out)
        return out

    def _exchange_coo(self):
        """The exchange entries ``(face i, face j, R_ij, cell of i, cell of j)``, ordered by
        their cell pair, i.e. by their place in the Jacobian's value array (the fill then
        reads them in sequence, not scattered: 2.4 → 1.7 ms a fill on the frigate, two
        threads)."""
        if not hasattr(self, "_ex_coo"):
            ex = self.model.exchange
            r = ex.area_exchange.tocoo()
            cells = self.graph.bface_cell[ex.bfaces]
            crow, ccol = cells[r.row], cells[r.col]
            order = np.lexsort((ccol, crow))
            self._ex_coo = tuple(np.ascontiguousarray(a[order])
                                 for a in (r.row, r.col, r.data, crow, ccol))
        return self._ex_coo

    def _exchange_cells(self):
        return self._exchange_coo()[3:]

    def _jacobian_pattern(self, theta: float) -> "JacobianPattern":
        """θ K with room for the diagonal, built once per θ (the sparsity never changes)."""
        pats = self.__dict__.setdefault("_patterns", {})
        if theta not in pats:
            extra = self._exchange_cells() if self.model.exchange is not None else (None, None)
            pats[theta] = JacobianPattern(theta * self.graph.conduction_matrix, *extra)
        return pats[theta]

    def _coefficients(self, first_step: bool, omega: float = 1.0):
        """(a, θ) of the scheme for this step (BDF2 starts with a backward Euler step; ω is
        this step over the last: a = (1 + 2ω)/(1 + ω), 3/2 on a uniform grid)."""
        if self.scheme == "backward_euler" or (self.scheme == "bdf2" and first_step):
            return 1.0, 1.0
        if self.scheme == "crank_nicolson":
            return 1.0, 0.5
        return (1.0 + 2.0 * omega) / (1.0 + omega), 1.0

    def _preconditioner(self, base_key, matrix):
        if self.backend == "column":
            # O(n): rebuilt from the current Jacobian at every step (its bands read from the
            # known positions in the value array).
            t0 = time.perf_counter()
            pat = self._pattern
            if self._column_bounds is None:
                self._column_bounds = column_bounds(self._column_break)
            factor = column_factor(matrix.data, pat.diag_pos, pat.sup_pos, self._column_break,
                                   self._column_bounds)
            # Columns held by strong sideways couplings are solved with their neighbours,
            # found once from the first Jacobian (the worst columns are the same slivers
            # whatever the step: only how many pass the ratio changes with it).
            if self._aggregates is None:
                self._aggregates = column_aggregates(matrix, self._column_break)
            groups = self._aggregates
            groups.factor(matrix.data)
            self._precond = Preconditioner("column", ColumnSolve(factor, groups),
                                           time.perf_counter() - t0)
            self.timing.setup += time.perf_counter() - t0
            self.timing.preconditioner_builds += 1
            return self._precond
        if self._precond is None or self._precond_key != base_key:
            t0 = time.perf_counter()
            self._precond = make_preconditioner(matrix, self.backend)
            self._precond_key = base_key
            self.timing.setup += time.perf_counter() - t0
            self.timing.preconditioner_builds += 1
        return self._precond

    def _face_slope(self, bs) -> np.ndarray:
        """``s = ∂T_s/∂T_cell = 1 − G_eff/g`` of every boundary face in the balance ``bs``."""
        return 1.0 - bs.conductance / self.graph.bface_conductance

    def _moved_faces(self, temp_face, cell_change, slope):
        """``T_s + s ΔT_cell`` (``slope`` None: ``T_s`` as it is)."""
        if slope is None:
            return temp_face.copy()
        out = np.empty_like(temp_face)
        moved_faces_kernel(temp_face, np.ascontiguousarray(cell_change), slope,
                      self.graph.bface_cell, out)
        return out

    # ------------------------------------------------------------------ step ---------------
    def step(self) -> None:
        """Advance one time step: the step's fixed terms and predicted state, Newton passes
        until the residual and the energy balance converge, the energy booked."""
        st = self._state
        s = self._begin_step(st)
        temp, bs, flow = self._newton(st, s)
        self._finish_step(st, s, temp, bs, flow)

    def _begin_step(self, st: SolverState) -> _Step:
        """The terms fixed over a step's Newton passes, and its predicted cells and faces."""
        g = self.graph
        dt = self._dt_now
        t_origin, step_origin = st.origin
        t_new = t_origin + (st.step + 1 - step_origin) * dt
        first = st.temp_prev is None
        # ω: this step over the last (BDF2's variable-step form; 1 on a uniform grid)
        omega = 1.0 if first else dt / st.dt_prev
        a, theta = self._coefficients(first, omega)
        cap = g.heat_capacity
        if self.scheme != "bdf2" or first:
            hist = st.temp
        else:   # (ω = 1: 2 Tₙ − ½ Tₙ₋₁, the same floating-point operations)
            hist = (1.0 + omega) * st.temp - (omega * omega / (1.0 + omega)) * st.temp_prev
        explicit = (1.0 - theta) * st.cell_flow if theta != 1.0 else None   # CN: old half

        t0 = time.perf_counter()
        forcing = self.model.forcing(t_new)
        source = self.model.source(t_new)
        self.timing.forcing += time.perf_counter() - t0

        # Initial guess: linear extrapolation (exact for linear-in-time solutions).
        temp = st.temp.copy() if first else (1.0 + omega) * st.temp - omega * st.temp_prev
        # Surface temperatures to start the balances from: moved with their cells by
        # ∂T_s/∂T_cell (the last balance's), so the face-to-face fixed point of the
        # boundary starts a first-order error closer (3.6 → 2.9 sweeps a pass, frigate day).
        face_lag = self._moved_faces(st.temp_face, temp - st.temp, st.face_slope)
        pattern = self._jacobian_pattern(theta)
        self._pattern = pattern
        # BDF2 starts with one backward Euler step. Its Jacobian differs from all later ones
        # only by C/(2Δt) on the diagonal, so the later steps' preconditioner serves it too
        # (spectrum of the preconditioned system within [2/3, 1]: ~13 PCG iterations to
        # 1e-13 with an exact factor) and the factorisation is done once, not twice.
        prec_a = 1.5 if (self.scheme == "bdf2" and first and self.backend != "column") else a
        # The non-orthogonal correction is left out of the Jacobian: held fixed from the
        # extrapolated field (default), or iterated with Anderson acceleration. The
        # face-to-face exchange is in the Jacobian (see _exchange_jacobian).
        fixed_corr = None
        if g.correction is not None:
            if not hasattr(self, "_extrapolated_corr"):
                self._extrapolated_corr = _ExtrapolatedCorrection(self.model)
            if self._extrapolated_corr.active:
                t1 = time.perf_counter()
                fixed_corr = self._extrapolated_corr(forcing, st, temp)
                self.timing.boundary += time.perf_counter() - t1
        accel = Anderson(5) if g.correction is not None and fixed_corr is None else None
        return _Step(t_new=t_new, dt=dt, a=a, theta=theta, hist=hist, explicit=explicit,
                     forcing=forcing, source=source, temp=temp, face_lag=face_lag,
                     diag_c=a * cap / dt, pattern=pattern, key=(dt, a, theta), prec_a=prec_a,
                     prec_key=(dt, prec_a, theta), fixed_corr=fixed_corr, accel=accel)

    def _newton(self, st: SolverState, s: _Step):
        """Newton passes from the predicted state until converged: ``(T, boundary state,
        net flow into each cell)``."""
        g = self.graph
        temp, face_lag = s.temp, s.face_lag
        converged = False
        jac_step = exch_step = prec = None
        for it in range(self.max_iterations):
            t1 = time.perf_counter()
            if s.fixed_corr is None:
                corr_cell, bs = boundary_state(self.model, s.forcing, temp, face_lag,
                                               tol=self.surface_tolerance,
                                               sweeps=BOUNDARY_SWEEPS)
            else:
                corr_cell = s.fixed_corr[0]
                bs = surface_balance(g, s.forcing, temp, face_lag, s.fixed_corr[1])
            self.timing.boundary += time.perf_counter() - t1
            t2 = time.perf_counter()
            flow, resid, jdiag_b = cell_residual(g, temp, s.hist, s.a, s.dt, s.theta, bs,
                                                 corr_cell, s.source, s.explicit)
            # The matrix itself is built only when a correction is solved for (the last pass
            # of a step only checks convergence and needs the diagonal alone), and only on
            # the first pass: the later passes of the step solve with it again (chord
            # Newton; the residual is always the exact one). The Jacobian moves little within
            # a step, so this costs few iterations (frigate day: 4.10 → 4.13 Newton passes a
            # step, 5.4 PCG iterations a pass either way) and saves computing and refilling
            # its 1.2 M exchange entries (time loop 32.7 → 29.3 s). The diagonal of the
            # convergence estimate takes the fresh boundary part.
            jac = jac_step
            exch = exch_step
            if exch is None and self.model.exchange is not None:
                exch = -s.theta * self._exchange_jacobian(bs)
            jdiag = s.pattern.diagonal(s.diag_c + jdiag_b, exch)
            face_lag = bs.temp_face
            self.timing.assembly += time.perf_counter() - t2
            est = max_ratio(resid, jdiag)
            if not np.isfinite(est):
                raise SimulationError(f"non-finite temperature at t = {s.t_new:.6g} s "
                                      f"(step {st.step + 1}); reduce time_step or check the "
                                      "boundary conditions")
            if self._converged(est, it, bs, resid, s.source):
                converged = True
                break
            delta, jac, prec = self._correction(s, resid, jdiag_b, exch, jac, prec, est)
            jac_step, exch_step = jac, exch
            if s.accel is None:
                temp = temp + delta
                face_lag = self._moved_faces(face_lag, delta, self._face_slope(bs))
            else:
                temp = s.accel.update(temp, delta)
        self.timing.newton_iterations += it + 1
        if not converged:
            raise SimulationError(f"Newton did not converge in {self.max_iterations} iterations "
                                  f"at t = {s.t_new:.6g} s (correction estimate {est:.3g} K); "
                                  "reduce time_step")
        return temp, bs, flow

    def _converged(self, est: float, it: int, bs, resid, source) -> bool:
        """Is the step converged after pass ``it`` (correction estimate ``est`` [K])?"""
        # At least one Newton solve per step: from the extrapolated guess the residual may
        # already be below the tolerance, but only a solve takes it to round-off, which
        # is what makes the energy balance close to ~1e-12 rather than to tolerance·C/Δt.
        if not (est <= self.tolerance and it > 0 and bs.converged):
            return False
        # ... and the step's energy residual Δt |Σ R_i| is at round-off relative to
        # the heat moved (interior fluxes cancel, so Σ R_i is exactly the imbalance).
        # Only lagged couplings (face-to-face radiation, non-orthogonal correction)
        # converge linearly and may need an extra iteration for it. Once the
        # correction estimate is 1e-4 × tolerance there is nothing left but
        # round-off (stiff columns with tiny Δt sit near 1e-12).
        gross = np.sum(np.abs(bs.flow)) + np.sum(np.abs(source)) + 1e-300
        return bool(abs(np.sum(resid)) <= self.energy_tolerance * gross
                    or est <= 1e-4 * self.tolerance)

    def _correction(self, s: _Step, resid, jdiag_b, exch, jac, prec, est: float):
        """The Newton correction by PCG: ``(ΔT, the Jacobian solved with, its
        preconditioner)`` (``jac``/``prec`` None: not built yet in this step)."""
        pattern = s.pattern
        column = self.backend == "column"
        t3 = time.perf_counter()
        if prec is None:
            # The preconditioner is built from the first Jacobian of a (dt, scheme) pair
            # and reused while the Jacobian only drifts (boundary diagonal); the O(n)
            # column preconditioner from the first Jacobian of every step, for the step's
            # later passes too (frigate day, 48 steps: the same 967 PCG iterations as
            # with one per pass, 151 → 48 factorisations, 6.14 → 5.83 s).
            if self.backend != "column" and self._precond_key == s.prec_key:
                prec = self._precond
            elif s.prec_a != s.a:
                # (``pattern.jacobian`` refills one shared matrix: ``jac`` is built after.)
                base = pattern.jacobian(s.prec_a * self.graph.heat_capacity / s.dt + jdiag_b,
                                        exch).copy()
                prec = self._preconditioner(s.prec_key, base)
                jac = None    # the shared matrix now holds the preconditioner's values
            else:
                if jac is None:
                    jac = pattern.jacobian(s.diag_c + jdiag_b, exch, fresh=not column)
                prec = self._preconditioner(s.prec_key, jac)
        if jac is None:
            jac = pattern.jacobian(s.diag_c + jdiag_b, exch, fresh=not column)
        # Inexact Newton: the correction is needed only to ~1e-3 of the tolerance (the next
        # pass re-evaluates the true residual), so with a preconditioner from an earlier
        # Jacobian (radiation, drifting boundary diagonal) PCG stops after fewer
        # iterations; an exact factor of the current Jacobian reaches 1e-13 in one anyway.
        # Far from convergence the Newton step itself is only accurate to its own
        # quadratic (and lagged-coupling) error, ~1e-4 of the step on a ship day
        # (measured: successive corrections 0.25 K, 1e-4 K, 3e-8 K): solving it to
        # 1e-9 relative bought nothing. ``NEWTON_LINEAR_RTOL`` is that floor. (Not for
        # BDF2's backward-Euler start preconditioned by the BDF2 factor: there the tight
        # solve is what keeps a linear problem at one correction.)
        floor = NEWTON_LINEAR_RTOL if s.prec_a == s.a else 0.0
        lin_rtol = min(1e-3, max(1e-13, 0.1 * self.tolerance / est, floor))
        delta, nit, rel = pcg(jac.tocsr(), -resid, prec.apply, rtol=lin_rtol, max_iterations=60)
        if rel > max(1e-10, lin_rtol):
            # The Jacobian has drifted too far from the preconditioner: rebuild once.
            self._precond_key = None
            prec = self._preconditioner(s.key, jac)
            delta, nit2, rel = pcg(jac.tocsr(), -resid, prec.apply, rtol=1e-13,
                                   max_iterations=200)
            nit += nit2
        elif nit > 20:
            self._precond_key = None   # converged, but slowly: rebuild for the next step
        self.timing.linear_iterations += nit
        self.timing.solve += time.perf_counter() - t3
        return delta, jac, prec

    def _finish_step(self, st: SolverState, s: _Step, temp, bs, flow) -> None:
        """Book the step's energy and make its end the current state."""
        cap = self.graph.heat_capacity
        a, theta, dt, hist, source = s.a, s.theta, s.dt, s.hist, s.source
        stored = float(np.sum(cap * (a * temp - hist)))
        b_new = float(np.sum(bs.flow))
        b_old = float(np.sum(st.flow_face))
        boundary = dt * (theta * b_new + (1.0 - theta) * b_old)
        src = dt * (theta * float(np.sum(source)) + (1.0 - theta) * float(np.sum(st.source)))
        gross = dt * (theta * float(np.sum(np.abs(bs.flow))) + (1.0 - theta) * float(np.sum(np.abs(st.flow_face))))
        e = st.energy
        e["time"].append(s.t_new)
        e["stored"].append(stored)
        e["stored_plain"].append(float(np.sum(cap * (temp - st.temp))))
        e["boundary"].append(boundary)
        e["source"].append(src)
        e["gross"].append(gross)
        e["imbalance"].append(stored - boundary - src)
        st.temp_prev = st.temp
        st.dt_prev = dt
        st.temp = temp
        st.temp_face = bs.temp_face
        st.face_slope = self._face_slope(bs)
        st.flow_face = bs.flow
        st.source = source
        st.cell_flow = flow
        st.time = s.t_new
        st.step += 1
        self._maybe_record(st)

    def run_until(self, end_time: float, progress: bool | None = None, desc: str = "thermal") -> None:
        """Step until the clock reaches ``end_time`` (on the step grid) [s]."""
        n = int(round((end_time - self._state.time) / self._dt_now))
        require(n >= 0, "end_time", end_time, f"must be ≥ the current time {self._state.time} s")
        show = self.progress if progress is None else progress
        from tqdm.auto import tqdm

        with tqdm(total=n, desc=desc, unit="step", disable=not show, leave=False) as bar, \
                single_threaded_blas(), kernel_threads(self.graph.n_cells):
            for _ in range(n):
                self.step()
                bar.update(1)

    def run(self, progress: bool | None = None) -> Results:
        """Integrate to ``stop_time`` and return the results."""
        self.run_until(self.stop_time, progress)
        return self.results()

    def results(self) -> Results:
        """Everything recorded so far."""
        st = self._state
        return Results(
            graph=self.graph, times=np.array(st.recorded_times),
            cell_temperature=np.array(st.recorded_cell), face_temperature=np.array(st.recorded_face),
            face_flow=np.array(st.recorded_flow),
            energy=EnergyLog.from_lists(st.energy), scheme=self.scheme, time_step=self.dt,
            timing=self.timing.as_dict(),
            backend=self._precond.backend if self._precond is not None else self.backend)

    def clear_records(self) -> None:
        """Forget recorded outputs and the energy log (e.g. after a spin-up)."""
        st = self._state
        st.recorded_times, st.recorded_cell, st.recorded_face, st.recorded_flow = [], [], [], []
        # the next checkpoint starts a fresh list of record files
        self._record_files = self._record_files[:2] + (False,)
        st.energy = {k: [] for k in EnergyLog.FIELDS}

    def record_now(self) -> None:
        """Record the current state (whatever the output grid)."""
        self._record(self._state)

    @staticmethod
    def _record(st: SolverState) -> None:
        if st.recorded_times and abs(st.recorded_times[-1] - st.time) < 1e-9:
            return
        st.recorded_times.append(st.time)
        st.recorded_cell.append(st.temp.copy())
        st.recorded_face.append(st.temp_face.copy())
        st.recorded_flow.append(st.flow_face.copy())

    # ------------------------------------------------------------ checkpoints ---------------
    def _signature(self) -> np.ndarray:
        return np.array([self.dt, self.start_time, SCHEMES.index(self.scheme),
                         self.graph.n_cells, self.graph.n_bfaces], dtype=float)

    def save_checkpoint(self, path, extra: dict | None = None) -> Path:
        """Write the full state (and what was recorded) to ``path`` (.npz), atomically.

        What was recorded goes into ``<path>.records/`` beside it, each record once: a
        checkpoint adds the records taken since the last one written to the same path
        (:mod:`shipthermal.checkpoint`; remove both with
        :func:`~shipthermal.checkpoint.remove_checkpoint`).

        ``extra``: arrays of a caller's own bookkeeping (e.g. a spin-up's day counter),
        stored under ``extra_<name>`` and returned by :meth:`load_checkpoint`.
        """
        # the preconditioner's column groups go along, so that a resumed run solves with the
        # very same ones (found from the first Jacobian of the run)
        path = Path(path)
        last = self._record_files if self._record_files[0] == path else (None, None, False)
        files = write_checkpoint(path, self._state, self._dt_now, self._signature(),
                                 self._aggregates, extra, records=last[1], continued=last[2])
        self._record_files = (path, files, True)
        return path

    def load_checkpoint(self, path) -> dict:
        """Continue from a checkpoint written by :meth:`save_checkpoint` of the same setup;
        returns its ``extra`` arrays."""
        st, dt_now, groups, extra, files = read_checkpoint(path, self._signature(), self.dt,
                                                           self.start_time)
        self._record_files = (Path(path), files, True)
        if groups is not None:
            self._aggregates = groups
        self._state = st
        self._dt_now = dt_now
        return extra
