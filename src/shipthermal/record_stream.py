"""The outputs of a weather-record run, streamed to disk window by window.

A record of weeks to a year is run in windows of a few days (:func:`shipthermal.diurnal.
run_record`). What each window records is written at its end to a part file of its own
(written to a temporary name and renamed, so a killed run leaves only whole parts); the
memory of a run then holds one window, whatever the record's length. When the record is
done the parts are copied, one at a time, into one HDF5 file (:func:`assemble`), the
record's product::

    /times                 (n,) float64    output times [s after local midnight of the
                                           record's first day]
    /face_temperature      (n, M) float32  outer-surface temperature of each ship triangle
                                           (``ship.faces`` order) [K]; chunked by time
    /part_means            (n, P) float64  area-mean outer temperature per reporting part,
                                           then temp_air, temp_sea, temp_sea_skin [K]
                                           (attribute ``columns``)
    /energy/<field>        (s,) float64    every solver step of the record (EnergyLog)
    /sample/times          (k,) float64    the sampled days' output times [s] (VTKHDF, VTU)
    /sample/cell_temperature (k, n_cells) float32 [K]
    /sample/face_temperature (k, n_bfaces) float32 [K]
    /sample/face_flow      (k, n_bfaces) float32 [W]
    /ship/vertices, /ship/faces, /ship/face_part, /ship/part_names

Attributes of the root: ``format`` (:data:`RECORD_FORMAT`), ``version``, ``start`` (ISO
8601 local midnight of the first recorded day), ``record_days``, ``days_done``,
``output_interval_s``, ``label``; each dataset carries ``units``.

A reader (:class:`RecordFile`) reads rows lazily: two rows of ``face_temperature`` per time
asked for, never the whole array.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from .atomic import check_room
from .errors import InputError, require
from .results import EnergyLog, atomic_path

__all__ = ["RECORD_FORMAT", "RECORD_VERSION", "SAMPLE_DAYS_MAX", "sample_days", "RecordParts",
           "assemble", "RecordFile", "LazyRows"]

RECORD_FORMAT = "shipthermal weather-record outputs"
RECORD_VERSION = 1

SAMPLE_DAYS_MAX = 31
"""Most recorded days whose cell temperatures go into the VTKHDF / VTU series [days]: a
record of up to 31 days keeps all of them (what a record run wrote before it streamed);
a longer one every k-th day, k = ⌈days / 31⌉. The VTKHDF holds every cell at every time:
a year of the frigate at 0.5 m and 30-min outputs would be 13 GB; 31 days are 1.1 GB."""

#: Bytes of one chunk of ``face_temperature`` (rows × faces × 4): a lazy read of two rows
#: reads one or two chunks.
_CHUNK_BYTES = 1 << 20


def sample_days(n_days: int) -> np.ndarray:
    """Indices of the recorded days that go into the sample (:data:`SAMPLE_DAYS_MAX`)."""
    k = max(1, int(np.ceil(n_days / SAMPLE_DAYS_MAX)))
    return np.arange(0, int(n_days), k)


def in_sample(times, days, day: float) -> np.ndarray:
    """Whether each output time [s] belongs to a sampled day (the midnight closing a day
    included)."""
    d = np.asarray(times, float) / day
    start = np.floor(d + 1e-9)
    whole = np.abs(d - np.round(d)) < 1e-9
    return np.isin(start, days) | (whole & np.isin(np.round(d) - 1, days))


class RecordParts:
    """The part files of a record run in ``folder``, one per window, ``part_00000.npz``…

    Each is written to a temporary name and renamed: a part exists whole or not at all.
    """

    def __init__(self, folder):
        self.folder = Path(folder)

    def path(self, index: int) -> Path:
        return self.folder / f"part_{int(index):05d}.npz"

    def write(self, index: int, **arrays) -> Path:
        """Write part ``index`` (arrays by name) atomically."""
        path = self.path(index)
        with atomic_path(path) as tmp:
            np.savez(tmp, **arrays)
        return path

    def drop_range(self, first: int, end: int) -> None:
        """Remove the parts ``first … end − 1``: those a resumed run writes again (to the
        same values), or a fresh run's own (of its segment, when the record is split over
        processes writing into one folder)."""
        for p in self.folder.glob("part_*.npz"):
            if int(first) <= int(p.stem.split("_")[1]) < int(end):
                p.unlink()

    def read(self, index: int) -> dict:
        path = self.path(index)
        if not path.is_file():
            raise InputError("record part", str(path), "is missing (the checkpoint counts it as "
                             "written)", "Start the run afresh (without --resume)")
        with np.load(path) as d:
            return {k: d[k] for k in d.files}


def assemble(parts: RecordParts, n_parts: int, path, *, ship, part_columns, start: str,
             record_days: int, days_done: int, output_interval: float, label: str,
             face_dtype=np.float32) -> Path:
    """Copy parts ``0 … n_parts − 1`` into one HDF5 file at ``path`` (layout in the module
    notes), one part in memory at a time; written to a temporary name and renamed."""
    import h5py

    # sizes first (the headers of the parts only)
    n = s = k = 0
    for i in range(n_parts):
        with np.load(parts.path(i)) as d:
            n += len(d["times"])
            s += len(d["energy_time"])
            k += len(d["sample_times"])
    m = int(ship.n_faces)
    path = Path(path)
    check_room(path, sum(parts.path(i).stat().st_size for i in range(n_parts))
               + np.asarray(ship.vertices).nbytes + 3 * np.asarray(ship.faces).nbytes,
               "the record's outputs")
    with atomic_path(path, ".h5") as tmp:
        with h5py.File(tmp, "w") as f:
            f.attrs.update(format=RECORD_FORMAT, version=RECORD_VERSION, start=start,
                           record_days=int(record_days), days_done=int(days_done),
                           output_interval_s=float(output_interval), label=label)
            rows = max(1, min(n, _CHUNK_BYTES // (4 * max(m, 1))))

            def make(name, shape, dtype, units, chunks=None):
                ds = f.create_dataset(name, shape=shape, dtype=dtype,
                                      chunks=chunks if shape[0] else None)
                ds.attrs["units"] = units
                return ds

            times = make("times", (n,), "f8", "s")
            face = make("face_temperature", (n, m), face_dtype, "K",
                        chunks=(rows, m) if n else None)
            pm = make("part_means", (n, len(part_columns)), "f8", "K")
            pm.attrs["columns"] = np.array(part_columns, dtype=h5py.string_dtype())
            energy = {key: make(f"energy/{key}", (s,), "f8", "s" if key == "time" else "J")
                      for key in EnergyLog.FIELDS}
            first = None
            at = [0, 0, 0]
            for i in range(n_parts):
                d = parts.read(i)
                if first is None:
                    first = d
                    n_cells = d["sample_cell_temperature"].shape[1]
                    n_b = d["sample_face_temperature"].shape[1]
                    st = make("sample/times", (k,), "f8", "s")
                    sc = make("sample/cell_temperature", (k, n_cells), "f4", "K")
                    sf = make("sample/face_temperature", (k, n_b), "f4", "K")
                    sq = make("sample/face_flow", (k, n_b), "f4", "W")
                a, b, c = at
                r = len(d["times"])
                times[a:a + r] = d["times"]
                face[a:a + r] = d["face_temperature"]
                pm[a:a + r] = d["part_means"]
                e = len(d["energy_time"])
                for key in EnergyLog.FIELDS:
                    energy[key][b:b + e] = d[f"energy_{key}"]
                q = len(d["sample_times"])
                st[c:c + q] = d["sample_times"]
                sc[c:c + q] = d["sample_cell_temperature"]
                sf[c:c + q] = d["sample_face_temperature"]
                sq[c:c + q] = d["sample_face_flow"]
                at = [a + r, b + e, c + q]
            g = f.create_group("ship")
            g.create_dataset("vertices", data=np.asarray(ship.vertices, float)).attrs["units"] = "m"
            g.create_dataset("faces", data=np.asarray(ship.faces, np.int64))
            g.create_dataset("face_part", data=np.asarray(ship.face_part, np.int64))
            g.create_dataset("part_names", data=np.array(ship.part_names,
                                                          dtype=h5py.string_dtype()))
    return path


class LazyRows:
    """Rows of a dataset of a :class:`RecordFile`, read as indexed (``rows[k]``,
    ``rows[i:j]``); it keeps its file open (and a temporary file in place) while it is
    used, e.g. by an imaging history the record's result is long gone from."""

    def __init__(self, owner: "RecordFile", dataset):
        self._owner = owner
        self._dataset = dataset
        self.shape = tuple(dataset.shape)
        self.dtype = dataset.dtype

    def __len__(self) -> int:
        return self.shape[0]

    def __getitem__(self, key):
        return self._dataset[key]


class RecordFile:
    """A record's outputs (:func:`assemble`'s file), read lazily.

    Attributes
    ----------
    path : Path
    times : (n,) float
        Output times [s after local midnight of the record's first day].
    face_temperature : LazyRows
        (n, M) outer-surface temperatures [K], read row by row as indexed.
    attrs : dict
        The root attributes (module notes).
    """

    def __init__(self, path):
        import h5py

        self.path = Path(path)
        try:
            # a chunk cache of 16 MB: consecutive frames reuse the chunk they read
            self._file = h5py.File(self.path, "r", rdcc_nbytes=16 << 20)
        except OSError as exc:
            raise InputError("record outputs", str(self.path), f"must be a readable HDF5 file "
                             f"({exc})", "Run the thermal stage again") from None
        f = self._file
        require(f.attrs.get("format") == RECORD_FORMAT, "record outputs", str(self.path),
                f"must be a file of {RECORD_FORMAT!r}")
        self.attrs = dict(f.attrs)
        self.times = f["times"][:]
        self.face_temperature = LazyRows(self, f["face_temperature"])

    def close(self) -> None:
        self._file.close()

    def remove_when_unused(self, folder) -> None:
        """Delete ``folder`` (a temporary one holding this file) once nothing uses the
        file any more: neither this object nor its :class:`LazyRows`."""
        import weakref

        weakref.finalize(self, _close_and_remove, self._file, str(folder))

    @property
    def n_times(self) -> int:
        return int(len(self.times))

    def part_means(self) -> pd.DataFrame:
        """The part-mean table (with air, sea and sea skin) indexed by hour [K]."""
        ds = self._file["part_means"]
        cols = [c.decode() if isinstance(c, bytes) else str(c) for c in ds.attrs["columns"]]
        return pd.DataFrame(ds[:], columns=cols,
                            index=pd.Index(self.times / 3600.0, name="hour"))

    def energy(self) -> EnergyLog:
        """Every solver step of the record."""
        return EnergyLog(*[self._file[f"energy/{k}"][:] for k in EnergyLog.FIELDS])

    def face_temperature_at(self, t: float) -> np.ndarray:
        """Outer-surface temperature per triangle at ``t`` [s] (linear between the two
        output times around it; clamped to the record) [K]."""
        tt = self.times
        k = int(np.clip(np.searchsorted(tt, t, side="right") - 1, 0, len(tt) - 2))
        w = float(np.clip((t - tt[k]) / (tt[k + 1] - tt[k]), 0.0, 1.0))
        rows = np.asarray(self.face_temperature[k:k + 2], dtype=float)
        return (1.0 - w) * rows[0] + w * rows[1]

    @property
    def sample_times(self) -> np.ndarray:
        return self._file["sample/times"][:]

    def sample_row(self, k: int) -> tuple:
        """``(cell temperature, face temperature, face flow)`` of sample row ``k``
        (float64) [K], [K], [W]."""
        s = self._file["sample"]
        return tuple(np.asarray(s[name][k], dtype=float)
                     for name in ("cell_temperature", "face_temperature", "face_flow"))

    def ship_arrays(self) -> dict:
        """``vertices``, ``faces``, ``face_part``, ``part_names`` of the ship."""
        g = self._file["ship"]
        names = tuple(x.decode() if isinstance(x, bytes) else str(x)
                      for x in g["part_names"][:])
        return {"vertices": g["vertices"][:], "faces": g["faces"][:],
                "face_part": g["face_part"][:], "part_names": names}


def _close_and_remove(file, folder: str) -> None:
    import shutil

    file.close()
    shutil.rmtree(folder, ignore_errors=True)
