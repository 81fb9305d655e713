"""The ship's boundary against EnergyPlus: differences per plate, term and modelling choice,
and wall times.

A 20 m deck, walls facing N, E, S and W, a plate tilted 45° to the south and an insulated
bulkhead with a compartment behind it, on the TMY3 files of San Francisco and Miami, a July
and a January week each (the models and the forcing: ``tests/boundary/energyplus_ship.py``).

Printed, per climate:

1. **matched** (DOE-2 in both codes, ours evaluating it at the solved surface temperature;
   the Perez sky; the ground at the air temperature; fixed inside films): RMS and max |ΔT| of
   the hourly outer surface temperature (days 2–7) and each term at local noon of the last
   day, ours / EnergyPlus;
2. **defaults, term by term**: the RMS as our side moves from its own choices to
   EnergyPlus's one at a time (``default`` → DOE-2 convection → Perez sky → the ground
   below = ``matched``), and the noon terms of the defaults;
3. wall times: one EnergyPlus run per climate (every plate, both weeks, warm-up included)
   and our solver (one run per week holding every plate and step).

Run: ``python benchmarks/bench_boundary_energyplus.py [--climates san_francisco,miami]``. Not a
test; wall times on the shared 2-core machine vary by ±30 %.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "tests" / "boundary"))

import energyplus_peer as ep  # noqa: E402
import energyplus_ship as es  # noqa: E402

TERMS = ep.NOON_TERMS


def main() -> None:
    import numba

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--climates", default=",".join(es.CLIMATES))
    args = ap.parse_args()
    if not ep.energyplus_available():
        sys.exit("pyenergyplus (EnergyPlus) is not installed")
    numba.set_num_threads(1)     # 32 faces: a parallel launch costs more than its work
    print(f"EnergyPlus {ep.engine_version()}, {ep.TIMESTEPS_PER_HOUR} steps per hour; ours "
          f"BDF2 at {es.TIME_STEP:g} s, default convection {es.DEFAULT_CONVECTION_MODEL}\n")
    header = "  ".join(f"{label:>15s}" for _, label in TERMS)
    walls = []
    for climate in args.climates.split(","):
        df, wall_ep, _ = es.run_energyplus(climate, workdir=tempfile.mkdtemp(prefix="eplus_"))
        t0 = time.perf_counter()
        res = es.compare(climate, df, steps=es.STEPS)
        walls.append((climate, wall_ep, time.perf_counter() - t0))
        print(f"== {climate}: matched ==")
        print(f"{'week':8s} {'plate':14s} {'rms K':>6s} {'max K':>6s}   noon (ours / "
              f"EnergyPlus): {header}")
        for week in ep.WEEKS:
            for p in es.PLATES:
                st = ep.statistics(res[("matched", week, p.name)])
                noon = "  ".join(f"{a:7.1f}/{b:<7.1f}" for a, b in
                                 (st["noon"][term] for term, _ in TERMS))
                print(f"{week:8s} {p.name:14s} {st['rms']:6.3f} {st['max']:6.3f}   {noon}")
        print(f"\n== {climate}: defaults, RMS / max [K] as our side takes EnergyPlus's "
              f"choices one at a time ==")
        print(f"{'week':8s} {'plate':14s} " + "  ".join(f"{s:>13s}" for s in es.STEPS)
              + f"   noon of the defaults (ours / EnergyPlus): {header}")
        for week in ep.WEEKS:
            for p in es.PLATES:
                st = [ep.statistics(res[(s, week, p.name)]) for s in es.STEPS]
                cells = "  ".join(f"{x['rms']:6.2f}/{x['max']:<6.2f}" for x in st)
                noon = "  ".join(f"{a:7.1f}/{b:<7.1f}" for a, b in
                                 (st[0]["noon"][term] for term, _ in TERMS))
                print(f"{week:8s} {p.name:14s} {cells}   {noon}")
        print()
    print("wall times (EnergyPlus: one run, every plate and both weeks with warm-up; ours: "
          "every plate and step, both weeks)")
    for climate, wall_ep, wall_ours in walls:
        print(f"  {climate:14s} EnergyPlus {wall_ep:6.2f} s   ours {wall_ours:6.2f} s")


if __name__ == "__main__":
    main()
