"""Calibration of unknown scenario quantities against measured surface temperatures.

Given measured temperatures of a ship (part area means or point values, at local times,
optionally with uncertainties; CSV format in ``docs/CALIBRATION.md``) and a list of unknown
scenario quantities with bounds (dotted scenario keys such as ``weather.cloud_cover_offset``
or ``ship.solar_absorptivity.deck``, optionally scoped to one case as
``summer:weather.cloud_cover_offset``), :func:`calibrate` estimates the unknowns by bounded
least squares (:func:`scipy.optimize.least_squares`, trust-region reflective) on the full
thermal model, and reports

* the values with 95 % intervals and the correlation matrix from the Jacobian at the
  solution (linearised covariance ``(JᵀWJ)⁻¹``, scaled by the residual variance when the
  measurements carry no uncertainty of their own);
* the residuals of the fitted rows and the errors on **held-out** rows (a named split, or
  leave-one-out refits warm-started from the full fit);
* flags: a value on a bound (the data want a value outside the bounds), a parameter the
  data do not determine (tiny singular value of the scaled Jacobian, or an interval wider
  than the bounds), strongly correlated pairs.

Cost: each model evaluation is a full diurnal run. The ship, its shell graph and its ray
tracing (sun-lit fractions and view factors, which depend on the geometry only) are built
once per case and reused by every evaluation; each run starts from the last converged state
of the same case (warm start), and a case is re-run only when one of *its* unknowns changed
(a season-scoped unknown does not re-run the other season). The calibration runs use a
coarse setting, :data:`CALIBRATION_SETTINGS` (4 m mesh, 64 rays, 900 s steps), whose deck
means differ from the 2 m / 300 s default by a few tenths of a kelvin; say ``settings={}``
to calibrate at the scenario's own resolution.

Nothing in the built-in scenarios changes: the fitted values are reported, not stored.

The package's modules: :mod:`.measurements` (the measurement CSV and the unknowns),
:mod:`.model` (the cases run by the fit), :mod:`.fit` (:func:`calibrate` and its statistics,
:func:`fit_unknowns`, on any model), :mod:`.paper_case` (the paper's reference values
explained), :mod:`.command` (``shipthermal calibrate``).
"""

from .fit import CalibrationResult, Problem, calibrate, fit_unknowns
from .measurements import DEFAULT_SIGMA_K, Unknown, parse_unknown, read_measurements
from .model import CALIBRATION_SETTINGS, _Case
from .paper_case import paper_calibration

__all__ = ["CALIBRATION_SETTINGS", "DEFAULT_SIGMA_K", "Unknown", "CalibrationResult",
           "read_measurements", "parse_unknown", "calibrate", "paper_calibration",
           "fit_unknowns", "Problem", "_Case"]
