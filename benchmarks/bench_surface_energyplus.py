"""Land surface-energy solver against EnergyPlus: differences per case and term, and wall times.

A paving slab (asphalt / concrete / soil over a fixed bottom temperature) and a flat roof
(membrane / concrete deck / insulation over a room) on the TMY3 files shipped with the
EnergyPlus wheel (San Francisco, Phoenix, Miami), a July and a January week each; the model
and the forcing are those of ``tests/background/energyplus_land.py``.

Printed:

1. **matched** (h = 4 + 4 v in both codes, the EPW's infrared sky, the same irradiance,
   materials and boundaries): RMS and max |ΔT| of the hourly outer surface temperature (days
   2–7), and each term at local noon of the last day, ours / EnergyPlus;
2. **defaults** (our flat-plate correlation, EnergyPlus's DOE-2): the same, the noon terms
   side by side, and the RMS once EnergyPlus's h is replayed in our solver (what remains
   when the convection term is made equal);
3. wall times: one EnergyPlus run per climate (all four surfaces, both weeks, warm-up
   included) against our solver on the same cases, and the ratio.

Run: ``python benchmarks/bench_surface_energyplus.py [--climates phoenix,miami]``. Not a test;
wall times on the shared 2-core machine vary by ±30 %.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "background"))

import energyplus_peer as peer  # noqa: E402
import energyplus_land as ep  # noqa: E402

TERMS = peer.NOON_TERMS


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--climates", default=",".join(ep.CLIMATES))
    args = ap.parse_args()
    if not ep.energyplus_available():
        sys.exit("pyenergyplus (EnergyPlus) is not installed")
    climates = args.climates.split(",")
    print(f"EnergyPlus {ep.engine_version()}, {ep.TIMESTEPS_PER_HOUR} steps per hour; "
          f"slab conduction {ep.SLAB_ALGORITHM}, roof CTF\n")
    walls = []
    header = "  ".join(f"{label:>15s}" for _, label in TERMS)
    for climate in climates:
        c0 = time.process_time()
        df, wall_ep, _ = ep.run_energyplus(climate, workdir=tempfile.mkdtemp(prefix="eplus_"))
        cpu_ep = time.process_time() - c0
        c0 = time.process_time()
        plain = ep.compare(climate, df)
        cpu_ours = time.process_time() - c0
        replay = {(c.week, c.surface): c for c in ep.compare(climate, df, h_from_eplus=True)}
        wall_ours = sum(c.wall_ours for c in plain)
        walls.append((climate, wall_ep, wall_ours, cpu_ep, cpu_ours))
        print(f"== {climate} ==")
        print(f"{'week':8s} {'surface':13s} {'rms K':>7s} {'max K':>7s} {'rms, EnergyPlus h':>18s}"
              f"   noon (ours / EnergyPlus): {header}")
        for case in plain:
            st = ep.statistics(case)
            closed = ep.statistics(replay[(case.week, case.surface)])
            noon = "  ".join(f"{a:7.1f}/{b:<7.1f}" for a, b in
                             (st["noon"][term] for term, _ in TERMS))
            print(f"{case.week:8s} {case.surface:13s} {st['rms']:7.3f} {st['max']:7.3f} "
                  f"{closed['rms']:18.3f}   {noon}")
        print()
    print("wall times (EnergyPlus: one run, 4 surfaces x 2 weeks with warm-up; ours: the "
          "same 8 cases, spin-up included)")
    for climate, wall_ep, wall_ours, cpu_ep, cpu_ours in walls:
        print(f"  {climate:14s} EnergyPlus {wall_ep:6.2f} s (CPU {cpu_ep:5.2f} s)   ours "
              f"{wall_ours:6.2f} s (CPU, with the forcing: {cpu_ours:5.2f} s)   "
              f"EnergyPlus / ours {wall_ep / wall_ours:5.1f} (CPU {cpu_ep / cpu_ours:4.1f})")


if __name__ == "__main__":
    main()
