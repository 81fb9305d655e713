"""How the thermal stage runs and what a run writes: the [solver], [convection] and
[outputs] sections of a scenario.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from ...parameters import (DAY_STEP, NIGHT_SETTLE, NIGHT_STEP, RECORD_SEGMENT_WARM_DAYS,
                           SPINUP_MAX_DAYS, SPINUP_TOLERANCE, SUN_SAMPLES_PER_FACE,
                           VIEW_RAYS_PER_FACE)
from .site_sections import _divides
from .spec import _opt
from .values import (CONVECTION_MODEL_SOURCES, CONVECTION_ROUGHNESS, DAY,
                     DEFAULT_CONVECTION_MODEL, OUTPUT_FORMATS, ROUGHNESS_CLASSES)


@dataclass(frozen=True)
class SolverSettings:
    """[solver]: time stepping, spin-up and ray tracing of the thermal stage."""

    time_step: float = _opt(DAY_STEP, "float", "Time step (must divide 24 h)", unit="s", lo=0.0,
                            hi=3600.0, lo_open=True)
    night_step: float = _opt(NIGHT_STEP, "float", "Longest time step of the night, from "
                             f"{NIGHT_SETTLE / 3600:g} h after the last sunlight to dawn: the "
                             "longest multiple of time_step up to it that divides "
                             "time.output_interval (time_step or less: uniform steps)",
                             unit="s", lo=0.0, hi=3600.0, lo_open=True)
    scheme: str = _opt("bdf2", "choice", "Time integration scheme",
                       choices=("backward_euler", "crank_nicolson", "bdf2"))
    spinup_tolerance: float = _opt(SPINUP_TOLERANCE, "float", "Spin-up stops when no cell "
                                   "temperature changes more than this over a day (end vs "
                                   "start)", unit="K", lo=0.0, hi=10.0, lo_open=True)
    spinup_max_days: int = _opt(SPINUP_MAX_DAYS, "int",
                                "Most days of spin-up before giving up (reported)",
                                lo=1, hi=100)
    rays_per_face: int = _opt(VIEW_RAYS_PER_FACE, "int",
                              "Hemisphere rays per face for view factors", lo=1, hi=65536)
    samples_per_face: int = _opt(SUN_SAMPLES_PER_FACE, "int",
                                 "Sample points per face for the sun-lit fraction",
                                 lo=1, hi=4096)
    seed: int = _opt(0, "int", "Seed of all Monte-Carlo sampling (runs are reproducible)",
                     lo=0, hi=2 ** 32 - 1)
    jobs: int = _opt(1, "int", "Processes a weather record (weather.day = 'record') is split "
                     "over: contiguous segments of days, each spun up "
                     f"{RECORD_SEGMENT_WARM_DAYS} days before its first and run unrecorded "
                     "to it (docs/WEATHER.md); 1 = one piece", lo=1, hi=64)
    backend: str = _opt("auto", "choice", "Ray tracer: Embree (float32) or the numba BVH "
                        "fallback; 'auto' = Embree when installed",
                        choices=("auto", "embree", "numba"))

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "time_step" not in bad and not _divides(obj.time_step, DAY):
            ctx.err(f"{path}.time_step", obj.time_step, "must divide 24 h (86400 s) into whole "
                    "steps (spin-up compares whole days)", "e.g. 60, 120, 300, 600, 900")
        return obj


@dataclass(frozen=True)
class ConvectionSettings:
    """[convection]: the exterior convection correlation of the ship's air faces."""

    model: str = _opt(DEFAULT_CONVECTION_MODEL, "choice", "Convection correlation of the "
                      "faces in the wind: flat plate (laminar then turbulent, or tripped at the "
                      "leading edge) with natural convection (Churchill 1977), the building "
                      "correlations DOE-2 (EnergyPlus's default), TARP, MoWiTT, McAdams, or "
                      "ISO 6946's 4 + 4v; each evaluated at the solved surface temperature "
                      "(sources and validity: shipthermal.parameters.CONVECTION_MODEL_SOURCES, "
                      "docs/CONVECTION.md)",
                      choices=tuple(CONVECTION_MODEL_SOURCES))
    parts: Mapping = _opt({}, "part_choices", "Correlation per part (a part, a main part or "
                          "'hull'), over model", choices=tuple(CONVECTION_MODEL_SOURCES))
    roughness: Mapping = _opt(CONVECTION_ROUGHNESS, "part_choices", "Roughness class per part "
                              "of the DOE-2 and TARP forced convection (Walton 1981: stucco "
                              "very_rough, brick rough, concrete medium_rough, clear pine "
                              "medium_smooth, smooth plaster smooth, glass very_smooth; "
                              "ASSUMPTION: painted plate smooth, non-skid deck medium_rough)",
                              choices=ROUGHNESS_CLASSES)

    def per_part(self) -> dict:
        """``{part: model}``: ``model`` for every main part, then ``parts``."""
        return {**{p: self.model for p in ("hull", "deck", "superstructure")}, **self.parts}


@dataclass(frozen=True)
class OutputSettings:
    """[outputs]: where and what to write."""

    directory: str = _opt(None, "str", "Run directory (relative to the working directory)",
                          dynamic=lambda ctx: None, default_text="runs/<name>",
                          allowed_text="non-empty path")
    formats: tuple = _opt(["vtkhdf", "csv", "png", "geotiff", "json", "html"], "choice_list",
                          "Products to write ('svg', 'pdf': every figure also as vector "
                          "graphics, for publication)", choices=OUTPUT_FORMATS)
    figure_dpi: int = _opt(110, "int", "Resolution of the PNG figures (300 for print)",
                           unit="dpi", lo=50, hi=600)
    checkpoint_interval: float = _opt(3600.0, "float", "Thermal checkpoint interval of "
                                      "simulated time (0 = none; a multiple of "
                                      "solver.time_step; checkpoints fall on recording "
                                      "times, so at most one per `time.output_interval`)",
                                      unit="s", lo=0.0, hi=DAY)

    @staticmethod
    def _check(obj, raw, path, ctx, bad):
        if "directory" in raw and "directory" not in bad and not obj.directory.strip():
            ctx.err(f"{path}.directory", obj.directory, "must be a non-empty path")
        return obj
