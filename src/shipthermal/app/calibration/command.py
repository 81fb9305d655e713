"""``shipthermal calibrate``: inputs checked first, products written when the fit has
finished."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ...errors import InputError, require
from ...results import atomic_path
from ..rundir.folder import RunDir
from ..rundir.inputs import scenario_inputs
from ..scenario import load_scenario
from .fit import CalibrationResult, calibrate
from .measurements import parse_unknown, read_measurements
from .paper_case import paper_calibration, paper_text


# --------------------------------------------------------------------------- command ----
def _measurement_inputs(path, meas: pd.DataFrame) -> list:
    """The files a calibration reads: the measurement CSV, the scenario files its cases
    name (relative to the CSV) and the files those scenarios name."""
    out = [str(path)]
    base = Path(path).parent
    for name in dict.fromkeys(meas["case"]):
        if name in ("summer", "winter"):
            continue
        p = Path(name) if Path(name).is_absolute() else base / name
        if p.is_file():
            out.append(str(p))
            try:
                out += scenario_inputs(load_scenario(p))
            except InputError:        # reported with its own message by the fit
                pass
    return out


def run_calibrate_command(args, con) -> int:
    """``shipthermal calibrate``: inputs checked first; products written only when the fit
    has finished (a user error leaves no folder behind)."""
    settings = {} if args.full else None
    if args.paper:
        require(not args.measurements and not args.unknown, "--paper", True,
                "takes no measurement file or --unknown (it fits the paper's reference values)")
        meas = unknowns = None
    else:
        require(bool(args.measurements), "measurements", None, "give a measurement CSV "
                "(docs/CALIBRATION.md) or --paper")
        meas = read_measurements(args.measurements)
        unknowns = [parse_unknown(u) for u in args.unknown]
        require(len(unknowns) > 0, "--unknown", None, "give at least one unknown "
                "[CASE:]KEY=LOWER:UPPER", "e.g. --unknown weather.cloud_cover_offset=-0.5:0.5")
    inputs = [] if args.paper else _measurement_inputs(args.measurements, meas)
    RunDir.check_target(Path(args.out), force=args.force, kind="calibrate", inputs=inputs)
    with RunDir(Path(args.out), force=args.force, command=args.argv, kind="calibrate",
                inputs=inputs) as run:
        with run.stage("calibration") as tmp:
            if args.paper:
                paper = paper_calibration(settings=settings, log=con.info,
                                          crossovers=args.crossovers)
                for name, res in paper.items():
                    if isinstance(res, CalibrationResult):
                        res.write(tmp / name)
                if paper.get("crossovers") is not None:
                    with atomic_path(tmp / "paper_crossovers.csv") as t:
                        paper["crossovers"].to_csv(t, index=False)
                with atomic_path(tmp / "paper_case.csv") as t:
                    paper["table"].to_csv(t, index=False, float_format="%.4f")
                text = paper_text(paper)
                with atomic_path(tmp / "paper_case.txt") as t:
                    t.write_text(text + "\n")
            else:
                res = calibrate(meas, unknowns, holdout=args.holdout, settings=settings,
                                log=con.info)
                res.write(tmp)
                text = res.text()
    con.out(text)
    return 0
