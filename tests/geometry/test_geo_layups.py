"""Plate layups, masses and compartment temperatures against hand-computed values."""

import numpy as np
import pytest

from shipthermal.geometry import frigate
from shipthermal.geometry.layups import (compartment_temperatures, default_layups, outer_media)
from shipthermal.materials import Layer, Layup


@pytest.fixture(scope="module")
def ship():
    return frigate(2.0)


def test_default_layups_thickness_and_areal_mass(ship):
    L = ship.layups
    # Hand-computed: thickness sums; areal mass Σ ρ t with ρ steel 7850, paint 1200,
    # deck covering 1200, mineral wool 100, aluminium 5083 2660 kg/m3.
    assert L["hull_wetted"].thickness == pytest.approx(0.0143, abs=1e-12)
    assert L["hull_wetted"].areal_mass == pytest.approx(0.0003 * 1200 + 0.014 * 7850, rel=1e-12)   # 110.26
    assert L["hull_dry"] is L["hull_wetted"]
    assert L["deck"].thickness == pytest.approx(0.013, abs=1e-12)
    assert L["deck"].areal_mass == pytest.approx(0.003 * 1200 + 0.010 * 7850, rel=1e-12)          # 82.10
    assert L["superstructure"].thickness == pytest.approx(0.0563, abs=1e-12)
    assert L["superstructure"].areal_mass == pytest.approx(0.36 + 0.006 * 7850 + 0.05 * 100, rel=1e-12)  # 52.46
    assert L["superstructure_funnel"] == L["superstructure"]
    assert L["superstructure_mast"].areal_mass == pytest.approx(0.36 + 0.008 * 7850, rel=1e-12)
    # Cells through the thickness: paint 1, steel 1, wool 4.
    assert [l.cells for l in L["superstructure"].layers] == [1, 1, 4]
    assert [l.material for l in L["deck"].layers] == ["deck_covering", "mild_steel"]


def test_part_masses_are_area_times_areal_mass(ship):
    areas = ship.part_areas()
    masses = ship.part_masses()
    hand = {"hull_wetted": 110.26, "hull_dry": 110.26, "deck": 82.10, "superstructure": 52.46,
            "superstructure_funnel": 52.46, "superstructure_gun": 52.46, "superstructure_mast": 63.16}
    for name, a in areas.items():
        assert masses[name] == pytest.approx(a * hand[name], rel=1e-9), name
    # Heat capacity per area of the hull: ρc t = 1200*1800*0.0003 + 7850*440*0.014.
    hc = ship.part_heat_capacities()["hull_dry"] / areas["hull_dry"]
    assert hc == pytest.approx(648.0 + 48356.0, rel=1e-12)


def test_aluminium_option_and_overrides():
    names = ("hull_wetted", "hull_dry", "deck", "superstructure", "superstructure_funnel")
    lay = default_layups(names, superstructure_material="aluminium_5083")
    assert lay["superstructure"].areal_mass == pytest.approx(0.36 + 0.006 * 2660 + 5.0, rel=1e-12)
    custom = Layup((Layer("mild_steel", 0.012, 3),), name="thin hull")
    lay = default_layups(names, {"hull": custom, "superstructure": [("aluminium_5083", 0.008, 2)],
                                 "superstructure_funnel": [("mild_steel", 0.010, 2)]})
    assert lay["hull_wetted"] is custom and lay["hull_dry"] is custom
    assert lay["superstructure"].thickness == pytest.approx(0.008)
    assert lay["superstructure_funnel"].thickness == pytest.approx(0.010)
    from shipthermal.errors import InputError
    with pytest.raises(InputError):
        default_layups(names, {"keel": custom})
    with pytest.raises(InputError, match="unknown material"):
        default_layups(names, {"deck": [("teak_wood", 0.05, 1)]})


def test_ship_with_layups_and_temperatures(ship):
    s2 = ship.with_layups({"deck": [("mild_steel", 0.008, 2)]})
    assert s2.layups["deck"].areal_mass == pytest.approx(0.008 * 7850)
    assert s2.layups["hull_dry"] is ship.layups["hull_dry"]
    s3 = ship.with_compartment_temperature({"superstructure": 300.0})
    assert s3.compartment_temperature["superstructure_funnel"] == 300.0
    assert s3.compartment_temperature["deck"] == pytest.approx(295.15)


def test_compartment_temperature_defaults_and_media():
    names = ("hull_wetted", "hull_dry", "deck", "superstructure")
    t = compartment_temperatures(names)
    assert all(v == pytest.approx(273.15 + 22.0) for v in t.values())     # ISO 7547 winter
    assert compartment_temperatures(names, season="summer")["deck"] == pytest.approx(300.15)
    from shipthermal.errors import InputError
    with pytest.raises(InputError):
        compartment_temperatures(names, {"deck": 22.0})                 # °C given for K
    assert outer_media(names) == {"hull_wetted": "sea", "hull_dry": "air", "deck": "air",
                                  "superstructure": "air"}


def test_box_barge_masses_by_hand(tmp_path):
    # Fully hand-computed: a 100 x 12 x 10 m box barge, keel at z = -4 m, deck = the top face,
    # hull = the rest, draught 4 m. Areas: deck 100*12 = 1200 m2; hull bottom 1200 + sides
    # 2*(100 + 12)*10 = 3440 m2, of which wetted 1200 + 2*112*4 = 2096 m2, dry 1344 m2.
    # Areal masses (materials table: steel 7850, paint 1200, deck covering 1200 kg/m3):
    # hull 0.3 mm paint + 14 mm steel = 0.36 + 109.9 = 110.26 kg/m2;
    # deck 3 mm covering + 10 mm steel = 3.6 + 78.5 = 82.10 kg/m2.
    # Masses: wetted 2096*110.26 = 231 104.96 kg, dry 1344*110.26 = 148 189.44 kg,
    # deck 1200*82.10 = 98 520 kg; total 477 814.40 kg. Heat capacity of the deck:
    # 1200 * (0.003*1200*1400 + 0.010*7850*440) = 1200 * 39 580 = 47 496 000 J/K.
    import numpy as np
    import trimesh

    from shipthermal.geometry.io import ReadShipSettings, read_ship

    m = trimesh.creation.box((100.0, 12.0, 10.0))
    v = np.array(m.vertices) + [0.0, 0.0, 1.0]
    f = np.array(m.faces)
    top = np.array(m.face_normals)[:, 2] > 0.5
    names = np.where(top, "deck", "hull")
    path = tmp_path / "barge.ply"
    trimesh.Trimesh(v, f, process=False).export(path)
    ship, _ = read_ship(path, units="m", part_map=names, settings=ReadShipSettings(draught=4.0))
    masses = ship.part_masses()
    assert masses["hull_wetted"] == pytest.approx(231_104.96, rel=1e-12)
    assert masses["hull_dry"] == pytest.approx(148_189.44, rel=1e-12)
    assert masses["deck"] == pytest.approx(98_520.0, rel=1e-12)
    assert sum(masses.values()) == pytest.approx(477_814.40, rel=1e-12)
    assert ship.part_heat_capacities()["deck"] == pytest.approx(47_496_000.0, rel=1e-12)


def test_one_steel_cell_follows_the_day_of_two():
    """The default plates take one steel cell (module docstring: heat crosses them in ~15 s,
    a 300 s step cannot see inside). Against two steel cells a patrol boat's summer day moves
    by far less than its 0.1 K-level step error (frigate at 0.5 m: 6.4e-3 K)."""
    from shipthermal.diurnal import DiurnalSettings, run_diurnal
    from shipthermal.environment import Environment, climate_day
    from shipthermal.geometry import patrol_boat

    def steel(layer):
        return getattr(layer.material, "name", layer.material) == "mild_steel"

    ship = patrol_boat(edge_length=3.0)
    assert all(l.cells == 1 for lay in ship.layups.values() for l in lay.layers if steel(l))
    two = ship.with_layups({
        name: Layup(tuple(Layer(l.material, l.thickness, 2 if steel(l) else l.cells)
                          for l in lay.layers)) for name, lay in ship.layups.items()})
    env = Environment.from_climate_day(climate_day("summer"), ship_heading=90.0)
    s = DiurnalSettings(time_step=300.0, output_interval=1800.0, rays_per_face=32,
                        samples_per_face=8, spinup_max_days=1, spinup_tolerance=1.0)
    one_run = run_diurnal(ship, env, s, progress=False)
    two_run = run_diurnal(two, env, s, progress=False, traced=one_run.forcing.traced)
    assert two_run.graph.n_cells > one_run.graph.n_cells
    d = np.max(np.abs(one_run.results.face_temperature - two_run.results.face_temperature))
    print(f"patrol boat: {one_run.graph.n_cells} vs {two_run.graph.n_cells} cells, "
          f"faces within {d:.2e} K")
    assert d < 0.02
