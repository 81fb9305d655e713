"""Steady state of a :class:`~shipthermal.model.ThermalModel` under the boundary conditions
of one time: damped Newton with the solver's preconditioners (:mod:`.linear`)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import InputError, SimulationError
from .linear import Anderson, choose_backend, make_preconditioner, pcg, single_threaded_blas
from .model import ThermalModel, boundary_state, conduction_flows
from .results import EnergyLog, Results

__all__ = ["steady_state"]


def steady_state(model: ThermalModel, time: float = 0.0, tolerance: float = 1e-9,
                 max_iterations: int = 100, linear_solver: str = "auto",
                 max_change: float = 100.0) -> Results:
    """Steady temperatures under the boundary conditions at ``time`` (Newton, damped so that
    no cell moves by more than ``max_change`` K per iteration).

    Needs a heat sink (a fixed, convective or radiative boundary): with adiabatic or
    flux-only boundaries no steady state exists.
    """
    g = model.graph
    if not model.has_sink:
        raise InputError("conditions", "no fixed, convective or radiative boundary",
                         "a steady state needs at least one boundary that exchanges heat with "
                         "a reference temperature", "Add a FixedTemperature, Convection, "
                         "Radiation or SurfaceBalance condition")
    forcing = model.forcing(time)
    source = model.source(time)
    temp = model.initial_temperature.copy()
    face = temp[g.bface_cell]
    backend = choose_backend(linear_solver, g.n_cells, g.kind)
    if backend == "column":
        # Without C/Δt lateral conduction is not small against the diagonal: factorise.
        backend = "direct"
    prec = None
    accel = Anderson(5) if (g.correction is not None or model.exchange is not None) else None
    with single_threaded_blas():
        return _steady_loop(model, g, forcing, source, temp, face, backend, prec, accel,
                            time, tolerance, max_iterations, max_change)


def _steady_loop(model, g, forcing, source, temp, face, backend, prec, accel, time,
                 tolerance, max_iterations, max_change):
    for it in range(max_iterations):
        corr_cell, bs = boundary_state(model, forcing, temp, face)
        face = bs.temp_face
        flow = (conduction_flows(g, temp) + np.bincount(g.bface_cell, bs.flow, g.n_cells)
                + corr_cell + source)
        jac = (g.conduction_matrix + sp.diags(np.bincount(g.bface_cell, bs.conductance, g.n_cells))).tocsr()
        est = np.max(np.abs(flow) / jac.diagonal())
        if est <= tolerance:
            break
        if prec is None:
            prec = make_preconditioner(jac, backend)
        delta, _, rel = pcg(jac, flow, prec.apply, rtol=1e-13, max_iterations=100)
        if rel > 1e-10:
            prec = make_preconditioner(jac, backend)
            delta, _, rel = pcg(jac, flow, prec.apply, rtol=1e-13, max_iterations=300)
        big = np.max(np.abs(delta))
        if big > max_change:
            delta *= max_change / big
        temp = temp + delta if accel is None else accel.update(temp, delta)
    else:
        raise SimulationError(f"steady state did not converge in {max_iterations} iterations "
                              f"(correction estimate {est:.3g} K)")
    log = EnergyLog.from_lists({"time": [time], "stored": [0.0], "stored_plain": [0.0],
                                "boundary": [float(np.sum(bs.flow))],
                                "source": [float(np.sum(source))],
                                "gross": [float(np.sum(np.abs(bs.flow)))],
                                "imbalance": [-float(np.sum(bs.flow)) - float(np.sum(source))]})
    return Results(graph=g, times=np.array([time]), cell_temperature=temp[None, :],
                   face_temperature=face[None, :], face_flow=bs.flow[None, :], energy=log,
                   scheme="steady", time_step=0.0, timing={"newton_iterations": it + 1},
                   backend=prec.backend if prec is not None else backend)
