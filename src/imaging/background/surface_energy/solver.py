"""The time loop of the surface energy balance: spin-up over periodic days, a design day or a
record, the energy accounting, and its result."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from shipthermal.errors import check_finite, check_range, require
from shipthermal.parameters import DEFAULT_CONVECTION_MODEL
from shipthermal.units import DAY

from .columns import Columns
from .convection import convection_correlation
from .forcing import SurfaceForcing
from .kernels import (_KERNELS, _blocks, _factorise, _span_numba, _step_numba,
                      _step_numba_serial)


SCHEMES = {"backward_euler": 1.0, "crank_nicolson": 0.5}
"""Time schemes by name → θ."""

_PARALLEL_MIN_BLOCKS = 32
"""Fewer blocks than this run on one thread (see :class:`_Stepper`)."""

@dataclass(frozen=True)
class SurfaceEnergyResult:
    """Surface temperature and energy-balance terms on the forcing grid.

    Fluxes are instantaneous at the grid times, signs as in micrometeorology: radiation
    positive toward the surface, ``sensible``, ``latent`` positive away from it (upward),
    ``ground`` positive into the column; ``shortwave_net + longwave_net − sensible − latent −
    ground = 0`` at every instant (to the Newton tolerance).

    Attributes
    ----------
    temp_surface : numpy.ndarray
        (n_t, N) [K].
    shortwave_net, longwave_net, sensible, latent, ground : numpy.ndarray
        (n_t, N) [W m-2].
    h_convection : numpy.ndarray
        (n_t, N) convective coefficient used in the step ending at each instant [W m-2 K-1].
    temp_cells : numpy.ndarray
        (N, M) cell temperatures at the end of the run (padded with NaN) [K].
    energy_residual : numpy.ndarray
        (N,) stored-energy change of the run minus the time integral of the boundary fluxes
        (surface terms and the bottom flux) [J m-2].
    energy_scale : numpy.ndarray
        (N,) time integral of the absolute boundary fluxes [J m-2] (to judge the residual).
    surface_imbalance : numpy.ndarray
        (N,) largest |S_abs + ε L↓ − εσT⁴ − H − λE − G| over the run [W m-2].
    spinup_days : int
        Days of the periodic spin-up (the whole run in periodic mode).
    spinup_change : numpy.ndarray
        (N,) largest change of the surface temperature between the last two spin-up days [K].
    scheme : str
    substeps : int
        Solver steps per forcing interval.
    """

    temp_surface: np.ndarray
    shortwave_net: np.ndarray
    longwave_net: np.ndarray
    sensible: np.ndarray
    latent: np.ndarray
    ground: np.ndarray
    h_convection: np.ndarray
    temp_cells: np.ndarray
    energy_residual: np.ndarray
    energy_scale: np.ndarray
    surface_imbalance: np.ndarray
    spinup_days: int
    spinup_change: np.ndarray
    scheme: str
    substeps: int


# ---------------------------------------------------------------------------------------------
# Time loop
# ---------------------------------------------------------------------------------------------
@dataclass
class _State:
    temp: np.ndarray          # (M+1, N) surface node + cells, columns in the sorted order
    sb_old: np.ndarray        # (N,) surface net − bottom flux at the last level [W m-2]
    acc: np.ndarray           # (N,) ∫ boundary fluxes [J m-2]
    acc_abs: np.ndarray
    imbalance: np.ndarray


class _Stepper:
    """Advances all columns step by step with one kernel and one convection model."""

    def __init__(self, columns: Columns, convection: Callable, theta: float, dt: float,
                 kernel: Callable):
        self.columns = columns
        self.convection = convection
        self.theta = theta
        self.dt = dt
        self.kernel = kernel
        self.n_cells, self.capacity, self.cond = columns.padded()
        self.cap_dt, self.q, self.inv_den = _factorise(self.n_cells, self.capacity, self.cond,
                                                       dt, theta)
        n = columns.n_columns
        self.out = np.zeros((6, n))
        self.work = np.zeros((11, n))
        self.order, self.blocks = _blocks(np.asarray(columns.class_index))
        if kernel is _step_numba and len(self.blocks) < _PARALLEL_MIN_BLOCKS:
            self.kernel = _step_numba_serial
        self.emis = np.ascontiguousarray(columns.emissivity)
        self.rs = np.ascontiguousarray(columns.surface_resistance)
        self.tbot = np.ascontiguousarray(columns.bottom_temperature)
        # the aerodynamic convection's parameters when the whole span can run compiled
        aero = getattr(convection, "aerodynamic", None)
        self.span_convection = None
        if aero is not None and kernel in (_step_numba, _step_numba_serial):
            log_product, height_temp, stability, pressure = aero
            self.span_convection = (
                np.ascontiguousarray(np.broadcast_to(log_product, (n,)), dtype=np.float64),
                float(height_temp), bool(stability),
                np.ascontiguousarray(np.broadcast_to(pressure, (n,)), dtype=np.float64))

    def surface(self, state: _State) -> np.ndarray:
        """Surface temperature in the columns' order."""
        ts = np.empty(self.columns.n_columns)
        ts[self.order] = state.temp[0]
        return ts

    def step(self, state: _State, sw, lw, ta, rh, pres, wind) -> np.ndarray:
        h = np.ascontiguousarray(np.broadcast_to(
            self.convection(self.surface(state), ta, wind), ta.shape), dtype=float)
        self.kernel(state.temp, self.order, self.blocks, self.n_cells, self.cap_dt, self.cond,
                    self.q, self.inv_den, self.theta, self.emis, self.rs, self.tbot, sw, lw, ta,
                    rh, pres, h, self.dt, self.out, state.sb_old, state.acc, state.acc_abs,
                    state.imbalance, self.work)
        return h

    def stored_energy(self, temp: np.ndarray) -> np.ndarray:
        """Σ ρ c Δz T per column [J m-2], in the columns' order."""
        cap = self.capacity[self.columns.class_index[self.order]]      # (N, M) sorted
        e_sorted = np.einsum("nm,mn->n", cap, np.nan_to_num(temp[1:]))
        e = np.empty_like(e_sorted)
        e[self.order] = e_sorted
        return e

    def cells(self, state: _State) -> np.ndarray:
        """(N, M) cell temperatures in the columns' order (NaN below a column's bottom)."""
        out = np.empty((self.columns.n_columns, state.temp.shape[0] - 1))
        out[self.order] = state.temp[1:].T
        return out


def _forcing_rows(forcing: SurfaceForcing):
    names = ("shortwave_absorbed", "longwave_down", "temp_air", "relative_humidity", "pressure",
             "wind_speed")
    return [forcing.field(name) for name in names]


def _initial_state(columns: Columns, stepper_steady: _Stepper, rows, day_index) -> _State:
    """Steady column under the day-mean forcing (backward Euler with Δt → ∞, i.e. no
    storage): four steady solves, the convective coefficient refreshed between them."""
    n = columns.n_columns
    m_max = columns.n_cells_max
    means = [np.ascontiguousarray(np.asarray(r[day_index], dtype=float).mean(axis=0))
             for r in rows]
    temp = np.full((m_max + 1, n), np.nan)
    cls_sorted = columns.class_index[stepper_steady.order]
    t_mean = means[2][stepper_steady.order]
    for c, mesh in enumerate(columns.meshes):
        sel = cls_sorted == c
        temp[:mesh.n_cells + 1, sel] = t_mean[sel]
    state = _State(temp, np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
    for _ in range(4):
        stepper_steady.step(state, *means)
    return state


_OUTPUTS = ("temp_surface", "shortwave_net", "longwave_net", "sensible", "latent", "ground",
            "h_convection")


class _Run:
    """The time loop's pieces over one forcing: an interval of substeps, a periodic day,
    the energy accounting; the outputs on the forcing grid."""

    def __init__(self, stepper: _Stepper, forcing: SurfaceForcing, substeps: int,
                 outputs=_OUTPUTS, dtype=np.float64):
        self.stepper = stepper
        self.rows = _forcing_rows(forcing)
        self.substeps = substeps
        self.n_day = int(round(DAY / forcing.time_step))
        self.outputs = {name: np.empty((forcing.n_times, forcing.n_columns), dtype)
                        for name in outputs}

    def interval(self, state: _State, k_from: int, k_to: int) -> None:
        """Substeps from forcing index ``k_from`` to ``k_to`` (forcing linear in between);
        the end values are stored at ``k_to``."""
        # (float32 forcing of a long record: rows in float64, as the kernel computes)
        r0 = [np.asarray(r[k_from], dtype=float) for r in self.rows]
        r1 = [np.asarray(r[k_to], dtype=float) for r in self.rows]
        for s in range(1, self.substeps + 1):
            w = s / self.substeps
            now = [np.ascontiguousarray(b if w == 1.0 else a + w * (b - a))
                   for a, b in zip(r0, r1)]
            h = self.stepper.step(state, *now)
        out, o = self.stepper.out, self.outputs
        for name, value in (("temp_surface", out[5]), ("shortwave_net", now[0]),
                            ("longwave_net", out[0]), ("sensible", out[1]),
                            ("latent", out[2]), ("ground", out[3]), ("h_convection", h)):
            if name in o:
                o[name][k_to] = value

    def span(self, state: _State, k_from: np.ndarray, k_to: np.ndarray) -> None:
        """The intervals ``k_from[n] → k_to[n]`` in turn (:meth:`interval`); with the
        aerodynamic convection and the numba kernel in one compiled call
        (:func:`.kernels._span_numba`: the same arithmetic, each block of columns through the
        whole span on one thread: the year of the default port's 2 200 columns at 600 s
        with two substeps, 37.6 → 21.1 s)."""
        conv = self.stepper.span_convection
        if conv is None:
            for a, b in zip(k_from, k_to):
                self.interval(state, int(a), int(b))
            return
        st = self.stepper
        dummy = np.zeros((1, 1), self.outputs["temp_surface"].dtype)   # outputs not kept
        outputs = tuple(self.outputs.get(name, dummy) for name in _OUTPUTS)
        keep = np.array([name in self.outputs for name in _OUTPUTS])
        now = np.zeros((7, st.columns.n_columns))
        _span_numba(np.asarray(k_from, np.int64), np.asarray(k_to, np.int64), self.substeps,
                    tuple(self.rows), conv, state.temp, st.order, st.blocks, st.n_cells,
                    st.cap_dt, st.cond, st.q, st.inv_den, st.theta, st.emis, st.rs, st.tbot,
                    st.dt, st.out, state.sb_old, state.acc, state.acc_abs, state.imbalance,
                    st.work, now, keep, outputs)

    def periodic_day(self, state: _State) -> np.ndarray:
        """The first day of the forcing once, wrapping onto index 0; its surface temperature
        (n_day, N)."""
        k = np.arange(1, self.n_day + 1)
        self.span(state, k - 1, k % self.n_day)
        return self.outputs["temp_surface"][:self.n_day].copy()

    def record(self, state: _State) -> None:
        """The whole forcing from index 0 (the state at index 0 given)."""
        k = np.arange(1, len(self.rows[0]))
        self.span(state, k - 1, k)

    def start_accounting(self, state: _State) -> np.ndarray:
        """Zero the flux integrals; the stored energy now [J m-2]."""
        state.acc[:] = 0.0
        state.acc_abs[:] = 0.0
        state.imbalance[:] = 0.0
        return self.stepper.stored_energy(state.temp)


def _spin_up(run: _Run, state: _State, tolerance: float, min_days: int, max_days: int):
    """Periodic days until the largest day-to-day change of any column's surface temperature
    is below ``tolerance`` (and at least ``min_days``); returns (days, change (N,), stored
    energy at the start of the last day)."""
    previous = None
    change = np.full(state.temp.shape[1], np.inf)
    days = 0
    while days < max_days:
        energy_start = run.start_accounting(state)     # the last day's books: periodic mode
        day = run.periodic_day(state)
        days += 1
        if previous is not None:
            change = np.max(np.abs(day - previous), axis=0)
            if np.max(change) < tolerance and days >= min_days:
                break
        previous = day
    return days, change, energy_start


def _check_run(forcing: SurfaceForcing, columns: Columns, scheme: str, mode: str, backend: str,
               substeps, tolerance: float, min_days: int, max_days: int) -> None:
    forcing.validate()
    require(scheme in SCHEMES, "surface_energy.scheme", scheme,
            f"must be one of {', '.join(SCHEMES)}")
    require(mode in ("record", "periodic"), "surface_energy.mode", mode,
            "must be 'record' or 'periodic'")
    require(backend in _KERNELS, "surface_energy.backend", backend,
            f"must be one of {', '.join(_KERNELS)}")
    require(isinstance(substeps, (int, np.integer)) and substeps >= 1, "surface_energy.substeps",
            substeps, "must be an integer >= 1")
    check_range("surface_energy.tolerance", tolerance, 0.0, 10.0, "K", low_open=True)
    require(2 <= min_days <= max_days, "surface_energy.min_days", min_days,
            f"must lie in [2, max_days = {max_days}]")
    require(forcing.n_columns == columns.n_columns, "forcing.shortwave_absorbed",
            forcing.shortwave_absorbed.shape,
            f"must have one column per column ({columns.n_columns})")
    per_day = DAY / forcing.time_step
    require(abs(per_day - round(per_day)) < 1e-9, "forcing.time_step", forcing.time_step,
            "must divide a day (86400 s) into a whole number of steps")
    n_day = int(round(per_day))
    if mode == "periodic":
        require(forcing.n_times == n_day, "forcing.shortwave_absorbed",
                forcing.shortwave_absorbed.shape,
                f"must hold one day ({n_day} instants of {forcing.time_step:g} s) in "
                "periodic mode")
    else:
        require(forcing.n_times >= n_day, "forcing.shortwave_absorbed",
                forcing.shortwave_absorbed.shape,
                f"must hold at least one day ({n_day} instants) for the spin-up")
    for name in ("shortwave_absorbed", "longwave_down"):
        value = getattr(forcing, name)
        if not value.size or not (np.isfinite(np.min(value)) and np.isfinite(np.max(value))):
            check_finite(f"forcing.{name}", value)


def solve_surface_energy(forcing: SurfaceForcing, columns: Columns,
                         convection: Callable | str | None = None,
                         scheme: str = "backward_euler", substeps: int = 1,
                         mode: str = "record", tolerance: float = 0.01, max_days: int = 60,
                         min_days: int = 2, backend: str = "numba", outputs=None,
                         output_dtype=np.float64) -> SurfaceEnergyResult:
    """Surface temperature and energy balance of N columns.

    Parameters
    ----------
    forcing : SurfaceForcing
        On a uniform grid; a day must be a whole number of ``forcing.time_step``.
    columns : Columns
        From :func:`build_columns`.
    convection : callable, str or None
        ``h(temp_surface, temp_air, wind_speed) -> [W m-2 K-1]`` (vectorised over the
        columns), a model name of ``CONVECTION_MODELS`` (through
        :func:`convection_correlation`), or None for the project's default correlation on a
        horizontal ground pixel. :func:`convection_aerodynamic` is the log-law alternative.
        Evaluated once per step with the surface temperature at the start of the step.
    scheme : {'backward_euler', 'crank_nicolson'}
        Time scheme (:data:`SCHEMES`); backward Euler by default (L-stable: see the module
        notes).
    substeps : int
        Solver steps per forcing interval (forcing linearly interpolated in between).
    mode : {'record', 'periodic'}
        ``'periodic'``: the forcing is one design day, repeated until the largest change of
        any column's surface temperature from one day to the next is below ``tolerance``;
        the result is the last day. ``'record'``: the first day of the forcing is run
        periodically the same way (spin-up), then the whole record from its first instant.
    tolerance : float
        Day-to-day change that ends the spin-up [K].
    max_days : int
        Most spin-up days (the result reports the change reached).
    min_days : int
        Fewest spin-up days (≥ 2: a change needs two days). The surface temperature settles
        before the deep cells where the surface is pinned (a very large h): then set this
        from the column's slowest decay, exp(−α π² t / L²).
    backend : {'numba', 'reference'}
        The compiled kernel or the numpy reference (same arithmetic).
    outputs : sequence of str, optional
        The (n_t, N) results kept (default all; ``temp_surface`` always): the others are
        None. A year of 2 200 columns at 600 s holds 0.9 GB per float64 output.
    output_dtype : numpy dtype
        Storage of the kept outputs (float32 for a long record).

    Returns
    -------
    SurfaceEnergyResult

    Notes
    -----
    The spin-up starts from the steady column under the day-mean forcing, so only the
    diurnal wave and the nonlinearity's offset have to settle. In record mode index 0 of the
    result is the end of the spin-up (its periodic day wraps onto the record's first instant).
    """
    _check_run(forcing, columns, scheme, mode, backend, substeps, tolerance, min_days,
               max_days)
    if convection is None or isinstance(convection, str):
        convection = convection_correlation(convection or DEFAULT_CONVECTION_MODEL)
    require(callable(convection), "surface_energy.convection", type(convection).__name__,
            "must be a callable h(temp_surface, temp_air, wind_speed), a model name or None")
    kernel = _KERNELS[backend]
    stepper = _Stepper(columns, convection, SCHEMES[scheme], forcing.time_step / substeps,
                       kernel)
    keep = tuple(_OUTPUTS) if outputs is None else tuple(dict.fromkeys(("temp_surface",
                                                                         *outputs)))
    require(set(keep) <= set(_OUTPUTS), "surface_energy.outputs", list(keep),
            f"must name outputs of {', '.join(_OUTPUTS)}")
    run = _Run(stepper, forcing, int(substeps), keep, output_dtype)
    steady = _Stepper(columns, convection, 1.0, 1.0e30, kernel)
    state = _initial_state(columns, steady, run.rows, np.arange(run.n_day))
    days, change, energy_start = _spin_up(run, state, tolerance, min_days, max_days)
    if mode == "record":
        energy_start = run.start_accounting(state)
        run.record(state)
    energy_end = stepper.stored_energy(state.temp)
    return SurfaceEnergyResult(
        **{name: run.outputs.get(name) for name in _OUTPUTS}, temp_cells=stepper.cells(state),
        energy_residual=energy_end - energy_start - state.acc, energy_scale=state.acc_abs,
        surface_imbalance=state.imbalance.copy(), spinup_days=days, spinup_change=change,
        scheme=scheme, substeps=int(substeps))
