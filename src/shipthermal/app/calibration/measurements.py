"""What a calibration is given: measured temperatures (:func:`read_measurements`, the CSV
of ``docs/CALIBRATION.md``) and the unknown scenario quantities with their bounds
(:func:`parse_unknown`)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from ...errors import InputError, require
from ...units import ZERO_CELSIUS


#: Measurement uncertainty assumed when the CSV gives none [K]: a calibrated thermocouple or
#: IR radiometer on a painted plate, area-averaged (ASSUMPTION; give ``sigma_K`` per row).
DEFAULT_SIGMA_K = 1.0


SPLITS = ("fit", "holdout")


# --------------------------------------------------------------------------- inputs -----
@dataclass(frozen=True)
class Unknown:
    """An unknown scenario quantity: dotted ``key`` (optionally ``case:key``), bounds and a
    start value (default: the scenario's own value, clipped into the bounds)."""

    key: str
    lower: float
    upper: float
    start: float | None = None
    case: str | None = None

    @property
    def label(self) -> str:
        return f"{self.case}:{self.key}" if self.case else self.key


def parse_unknown(text: str) -> Unknown:
    """``[case:]key=lower:upper[:start]`` → :class:`Unknown`."""
    fix = "write e.g. weather.cloud_cover_offset=-0.5:0.5 or summer:ship.solar_absorptivity.deck=0.2:0.95:0.7"
    if "=" not in text:
        raise InputError("--unknown", text, "must be KEY=LOWER:UPPER[:START]", fix)
    name, rng = text.split("=", 1)
    case = None
    if ":" in name:
        case, name = name.split(":", 1)
    nums = rng.split(":")
    try:
        vals = [float(v) for v in nums]
    except ValueError:
        raise InputError("--unknown", text, "bounds must be numbers LOWER:UPPER[:START]", fix)
    require(len(vals) in (2, 3), "--unknown", text, "must give LOWER:UPPER or LOWER:UPPER:START", fix)
    require(all(math.isfinite(v) for v in vals) and vals[0] < vals[1], "--unknown", text,
            "needs finite bounds with LOWER < UPPER", fix)
    if len(vals) == 3:
        require(vals[0] <= vals[2] <= vals[1], "--unknown", text, "START must lie within the bounds", fix)
    return Unknown(name.strip(), vals[0], vals[1], vals[2] if len(vals) == 3 else None,
                   case.strip() if case else None)


_CLOCK = re.compile(r"^(\d{1,3}):([0-5]\d)(?::([0-5]\d))?$")


def _hour(value, row) -> float:
    text = str(value).strip()
    allowed = ("must be HH:MM[:SS] local time (minutes and seconds 00-59) or decimal hours "
               "after local midnight of the scenario's day")
    try:
        if ":" in text:
            m = _CLOCK.match(text)
            if m is None:
                raise ValueError(text)
            h = int(m.group(1)) + int(m.group(2)) / 60.0 + int(m.group(3) or 0) / 3600.0
        else:
            h = float(text)
    except ValueError:
        raise InputError(f"measurements row {row}: time", text, allowed) from None
    require(math.isfinite(h) and h >= 0.0, f"measurements row {row}: time", text,
            "must be ≥ 00:00 (hours after local midnight)")
    return h


def read_measurements(path) -> pd.DataFrame:
    """Read a measurement CSV (``docs/CALIBRATION.md``) into a normalised table with
    columns case, hour, target, temperature_K, sigma_K, split."""
    path = Path(path)
    require(path.is_file(), "measurements", str(path), "must be an existing CSV file")
    try:
        df = pd.read_csv(path, comment="#", skipinitialspace=True, dtype=str)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError("measurements", str(path), f"must be a CSV table ({exc})".strip())
    df.columns = [c.strip() for c in df.columns]
    need = {"case", "time", "target"}
    missing = sorted(need - set(df.columns))
    has_t = [c for c in ("temperature_K", "temperature_C") if c in df.columns]
    if missing or not has_t:
        raise InputError("measurements", str(path), "needs columns case, time, target and "
                         "temperature_K (or temperature_C); optional sigma_K, split",
                         f"missing: {', '.join(missing + ([] if has_t else ['temperature_K']))}")
    require(len(df) > 0, "measurements", str(path), "holds no rows")
    rows = []
    for i, r in df.iterrows():
        n = i + 2                               # line number in the file (header = 1)
        col = has_t[0]
        try:
            t = float(r[col])
        except (TypeError, ValueError):
            raise InputError(f"measurements row {n}: {col}", r[col], "must be a number")
        t = t + ZERO_CELSIUS if col == "temperature_C" else t
        require(math.isfinite(t) and 150.0 < t < 500.0, f"measurements row {n}: {col}", r[col],
                "must be a surface temperature between 150 and 500 K",
                "temperature_K is in kelvin, temperature_C in degrees Celsius")
        sigma = DEFAULT_SIGMA_K
        if "sigma_K" in df.columns and isinstance(r["sigma_K"], str) and r["sigma_K"].strip():
            try:
                sigma = float(r["sigma_K"])
            except ValueError:
                raise InputError(f"measurements row {n}: sigma_K", r["sigma_K"], "must be a number")
            require(math.isfinite(sigma) and sigma > 0, f"measurements row {n}: sigma_K",
                    r["sigma_K"], "must be > 0 K")
        split = "fit"
        if "split" in df.columns and isinstance(r["split"], str) and r["split"].strip():
            split = r["split"].strip().lower()
            require(split in SPLITS, f"measurements row {n}: split", r["split"],
                    "must be 'fit' or 'holdout'")
        target = str(r["target"]).strip()
        if target.startswith("point:"):
            try:
                xyz = [float(v) for v in target[6:].replace(";", " ").replace(",", " ").split()]
            except ValueError:
                xyz = []
            require(len(xyz) == 3, f"measurements row {n}: target", target,
                    "a point is 'point:x y z' in ship coordinates [m]")
        rows.append({"case": str(r["case"]).strip(), "hour": _hour(r["time"], n),
                     "target": target, "temperature_K": t, "sigma_K": sigma, "split": split,
                     "line": n})
    out = pd.DataFrame(rows)
    out.attrs["source"] = str(path)
    out.attrs["sigma_given"] = "sigma_K" in df.columns
    return out
