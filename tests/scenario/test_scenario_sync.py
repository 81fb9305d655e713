"""Keep the scenario in sync with its sources: mirrored constants, schema, docs, examples.

The scenario mirrors a few allowed values from modules that are slow to import (so loading
stays fast); each mirror is compared with its source here, so a change there fails here.
"""

import dataclasses
import re
import tomllib
from pathlib import Path

import pytest

from shipthermal.app import scenario as S
from shipthermal.app.scenario import values as V

ROOT = Path(__file__).resolve().parents[2]


# ---- mirrored constants -------------------------------------------------------------------
def test_environment_mirrors():
    from shipthermal.environment import Environment, Weather, climatology, sky
    from shipthermal.environment import weather as wmod

    assert V.CLEAR_SKY_MODELS == tuple(sorted(sky.CLEAR_SKY_MODELS))
    assert V.CLOUD_MODELS == tuple(sorted(sky.CLOUD_MODELS))
    assert V.CLOUD_UNITS == tuple(sorted(wmod._CLOUD_SCALE))
    from shipthermal.environment import station

    assert V.WEATHER_FORMATS == ("auto",) + tuple(sorted(station.STATION_FORMATS))
    assert V.MAX_GAP_HOURS == station.MAX_GAP_HOURS
    assert all(station.guess_format(f"x{suffix}") == fmt
               for suffix, fmt in V.WEATHER_SUFFIXES.items())
    assert V.DALIAN == {"latitude": climatology.DALIAN["latitude"],
                        "longitude": climatology.DALIAN["longitude"],
                        "time_zone": climatology.DALIAN["tz"]}
    for season in S.SEASONS:
        assert V.CLIMATE_DATES[season] == climatology.climate_day(season).date
        assert int(V.CLIMATE_DATES[season][5:7]) in V.CLIMATE_MONTHS[season]
    # decompositions: exactly the ones Environment accepts (a constant weather record and a
    # fixed Linke turbidity keep this cheap)
    import pandas as pd

    w = Weather(time=pd.date_range("2023-07-15", periods=2, freq="h", tz="Etc/GMT-8"),
                temp_air=290.0, relative_humidity=70.0, wind_speed=3.0, wind_direction=0.0,
                cloud_cover=0.5, temp_sea=290.0)
    for d in V.DECOMPOSITIONS:
        Environment(38.9, 121.6, w, decomposition=d, linke_turbidity=3.0)
    with pytest.raises(Exception, match="decomposition"):
        Environment(38.9, 121.6, w, decomposition="disc", linke_turbidity=3.0)
    # the scenario's latitude range is the Environment's
    spec = S.Location.__dataclass_fields__["latitude"].metadata["spec"]
    Environment(spec.hi, 0.0, w, linke_turbidity=3.0)
    with pytest.raises(Exception, match="latitude"):
        Environment(spec.hi + 0.1, 0.0, w, linke_turbidity=3.0)
    spec = S.ShipSettings.__dataclass_fields__["speed"].metadata["spec"]
    Environment(38.9, 121.6, w, ship_speed=spec.hi, linke_turbidity=3.0)
    with pytest.raises(Exception, match="ship_speed"):
        Environment(38.9, 121.6, w, ship_speed=spec.hi + 0.1, linke_turbidity=3.0)


def test_imaging_mirrors():
    from imaging import atmosphere
    from imaging.atmosphere import core, load_table
    from imaging.background import kriging
    from imaging.sensor import PAPER_SENSOR

    # one band list and one parser for both stages (shipthermal.parameters)
    assert S.parse_band is atmosphere.parse_band and V.BANDS is atmosphere.BANDS
    assert S.SEASONS == tuple(core.SEASONS)
    assert V.MAX_VIEW_ZENITH == core.MAX_VIEW_ZENITH
    assert V.PAPER_SENSOR == dataclasses.asdict(PAPER_SENSOR)
    assert V.VARIOGRAM_MODELS == tuple(sorted(kriging.VARIOGRAM_MODELS))
    from imaging.background import met

    assert V.MET_UNITS == met.MET_UNITS
    # the band limits the parser accepts are those the tables reach, to within one 5 cm-1
    # grid step (at 14.5 µm that is 14.5**2 * 5e-4 = 0.105 µm; at 2.9 µm 0.004 µm)
    lo, hi = V.ATMOSPHERE_WAVELENGTH_UM
    wl = load_table().wavelength_um
    assert abs(wl.min() - lo) <= lo ** 2 * 5e-4 and abs(wl.max() - hi) <= hi ** 2 * 5e-4


def test_geometry_mirrors():
    from shipthermal.geometry import BUILTIN_SHIPS, io

    assert V.BUILTIN_SHIP_NAMES == tuple(sorted(BUILTIN_SHIPS))
    assert V.MESH_EXTENSIONS == tuple(sorted(io._TRIMESH_EXT | io._PYVISTA_EXT))
    assert set(V.MESH_WITH_PART_ARRAY) == io._PYVISTA_EXT
    spec = S.ShipFiles.__dataclass_fields__["units"].metadata["spec"]
    assert set(spec.choices) == set(io.UNITS)
    spec = S.ShipParticulars.__dataclass_fields__["length"].metadata["spec"]
    assert (spec.lo, spec.hi) == io.SHIP_LENGTH_RANGE

    # ---- CAD meshes (named parts, repair limit)
    from shipthermal.geometry import cad

    assert V.MESH_WITH_PART_NAMES == tuple(sorted(cad.SCENE_EXTENSIONS))
    assert V.MAX_REPAIR_CHANGE == cad.MAX_REPAIR_CHANGE


# ---- schema ---------------------------------------------------------------------------------
def _all_fields(cls, prefix=""):
    for f in dataclasses.fields(cls):
        if f.metadata.get("internal"):
            continue
        spec = f.metadata["spec"]
        key = f"{prefix}.{f.name}" if prefix else f.name
        yield key, spec
        if spec.kind == "section":
            yield from _all_fields(spec.cls, key)
        if spec.kind == "layups":
            yield from _all_fields(S.LayerSpec, key + ".<part>[i]")


def test_schema_lists_every_field():
    keys = S.schema_keys()
    table = S.schema_markdown()
    fields = list(_all_fields(S.Scenario))
    assert len(fields) > 90
    for key, spec in fields:
        shown = f"[{key}]" if spec.kind == "section" else key
        assert any(k == shown or k.startswith(shown + ".<") for k in keys), key
        assert spec.doc, f"{key} has no description"
    # one table row per key, each row has 6 cells
    rows = [l for l in table.splitlines()[2:]]
    assert len(rows) == len(keys)
    assert all(l.count(" | ") >= 5 for l in rows)


def test_docs_table_is_current():
    text = (ROOT / "docs" / "SCENARIO.md").read_text(encoding="utf-8")
    m = re.search(r"<!-- schema:begin -->\n(.*)<!-- schema:end -->", text, re.S)
    assert m, "docs/SCENARIO.md lost its schema markers"
    assert m.group(1) == S.schema_markdown(), \
        "regenerate: shipthermal schema (between the markers)"


def _flatten(d, prefix=""):
    for k, v in d.items():
        key = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            yield from _flatten(v, key)
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                yield from _flatten(item, key + "[i]")
        else:
            yield key


def _pattern(key):
    out = re.escape(key).replace(re.escape("<part>"), r"[A-Za-z_]+")
    return re.compile("^" + out.replace(re.escape("<band>"), r"[0-9.\-]+") + "$")


@pytest.mark.parametrize("season", S.SEASONS)
def test_example_keys_are_documented(season):
    # every key in the example, and every key the commented alternatives show, is in the
    # schema (commented lines are un-commented to check them)
    text = S.example_path(season).read_text(encoding="utf-8")
    patterns = [_pattern(k.replace("<part>[i]", "<part>[i]")) for k in S.schema_keys()]
    raw = tomllib.loads(text)
    for key in _flatten(raw):
        key = re.sub(r"\.(\w+)\[i\]", r".\1[i]", key)
        assert any(p.match(key) for p in patterns), key
    section, checked = "", 0
    for line in text.splitlines():
        header = re.match(r"^(?:# )?\[([a-z_.]+)\]", line)
        if header:                       # a real or a commented-out [section]
            section = header.group(1)
            continue
        if not re.match(r"^# [a-z_]+ = ", line):
            continue
        checked += 1
        key = line[2:].split("=")[0].strip()
        full = f"{section}.{key}" if section else key
        assert any(p.match(full) or p.match(full + ".hull") or p.match(full + ".deck")
                   or p.match(full + "[i].material") for p in patterns), full
    assert checked >= 15   # the alternatives are really looked at


def test_package_ships_the_examples():
    for season in S.SEASONS:
        p = S.example_path(season)
        assert p.is_file() and p.parent.name == "scenarios"
