"""Built-in ships: parts, areas, closure, orientation, waterline, size."""

import numpy as np
import pytest

from shipthermal.geometry import (MAIN_PARTS, cargo_ship, frigate, main_part, patrol_boat)
from shipthermal.geometry.parts import boundary_edges


@pytest.fixture(scope="module")
def default_frigate():
    return frigate()


@pytest.fixture(scope="module")
def coarse_ships():
    return [frigate(1.0), patrol_boat(0.6), cargo_ship(1.5)]


def test_default_frigate_size_and_face_count(default_frigate):
    s = default_frigate
    assert s.n_faces >= 50_000, s.n_faces
    ext = np.ptp(s.vertices, axis=0)
    # Overall length and beam are built exactly at the deck edge; the only tolerance is
    # float round-off of the boolean union (manifold3d works in float64).
    assert ext[0] == pytest.approx(132.0, abs=1e-6)
    assert ext[1] == pytest.approx(15.0, abs=1e-6)
    assert 120 <= s.length <= 140 and 14 <= s.beam <= 16 and 4 <= s.draught <= 5


@pytest.mark.parametrize("k", range(3))
def test_every_face_in_one_part_and_areas_sum(coarse_ships, k):
    s = coarse_ships[k]
    assert s.face_part.shape == (s.n_faces,)
    assert s.face_part.min() >= 0 and s.face_part.max() < len(s.part_names)
    assert set(MAIN_PARTS) <= set(s.part_names)
    assert {main_part(n) for n in s.part_names} == set(MAIN_PARTS)
    # The parts partition the faces, so their areas add up to the total up to summation
    # round-off (relative 1e-12).
    parts = s.part_areas()
    assert sum(parts.values()) == pytest.approx(s.total_area, rel=1e-12)
    assert sum(s.main_part_areas().values()) == pytest.approx(s.total_area, rel=1e-12)
    # An independent area from trimesh.
    assert s.to_trimesh().area == pytest.approx(s.total_area, rel=1e-12)


@pytest.mark.parametrize("k", range(3))
def test_closed_and_outward(coarse_ships, k):
    s = coarse_ships[k]
    open_e, nonman = boundary_edges(s.faces)
    assert len(open_e) == 0 and len(nonman) == 0
    assert s.is_watertight
    mesh = s.to_trimesh()
    assert mesh.is_winding_consistent
    assert s.signed_volume > 0
    assert mesh.volume == pytest.approx(s.signed_volume, rel=1e-10)
    # Independent check of "outward": points just outside / inside the largest faces
    # must be outside / inside the solid (trimesh's ray-parity containment test).
    big = np.argsort(-s.face_areas)[:200]
    eps = 1e-3 * s.length
    c, n = s.face_centroids[big], s.face_normals[big]
    assert not mesh.contains(c + eps * n).any()
    assert mesh.contains(c - eps * n).all()


@pytest.mark.parametrize("k", range(3))
def test_waterline_split_exact_at_draught(coarse_ships, k):
    s = coarse_ships[k]
    wet = s.faces[s.part_mask("hull_wetted")]
    dry = s.faces[s.part_mask("hull_dry")]
    # The split cuts triangles on z = 0 exactly (new vertices are set to 0.0), so the
    # tolerance is zero; one edge length is the allowed deviation.
    assert s.vertices[wet, 2].max() <= 0.0
    assert s.vertices[dry, 2].min() >= 0.0
    # The keel lies at -draught: built exactly (the boolean keeps hull vertices).
    assert s.vertices[:, 2].min() == pytest.approx(-s.draught, abs=1e-9)
    # No non-hull part reaches below the waterline.
    other = s.faces[~s.part_mask("hull")]
    assert s.vertices[other, 2].min() > 0


def test_waterline_follows_draught():
    a, b = frigate(2.0, draught=4.0), frigate(2.0, draught=5.0)
    for s, t in ((a, 4.0), (b, 5.0)):
        assert s.vertices[:, 2].min() == pytest.approx(-t, abs=1e-9)
        assert s.vertices[s.faces[s.part_mask("hull_wetted")], 2].max() <= 0.0
    assert b.part_areas()["hull_wetted"] > a.part_areas()["hull_wetted"]


def _submerged_volume(s):
    # Divergence theorem with F = (0, 0, z): the waterplane (z = 0) adds nothing, and
    # ∫ z n_z dA over a flat triangle is exactly z_centroid n_z A.
    m = s.part_mask("hull_wetted")
    zc = s.face_centroids[m, 2]
    return float(np.sum(zc * s.face_normals[m, 2] * s.face_areas[m]))


@pytest.mark.parametrize("k", range(3))
def test_submerged_volume_against_manifold_trim(coarse_ships, k):
    from manifold3d import Manifold, Mesh64

    s = coarse_ships[k]
    vol = _submerged_volume(s)
    solid = Manifold(Mesh64(vert_properties=np.array(s.vertices), tri_verts=s.faces.astype(np.uint64)))
    below = solid.trim_by_plane((0.0, 0.0, -1.0), 0.0)      # keeps z <= 0, capped
    # Both are exact for the same triangles; the tolerance covers round-off.
    assert vol == pytest.approx(below.volume(), rel=1e-9)
    # Block coefficient V / (L_wl B_wl T) of a plausible hull form: frigates and patrol
    # boats about 0.45-0.52, full cargo ships 0.75-0.85 (Principles of Naval Architecture,
    # Vol. I, typical values); the bands are wide because the form is generic.
    wl = s.vertices[np.abs(s.vertices[:, 2]) == 0.0]       # waterline vertices
    cb = vol / (np.ptp(wl[:, 0]) * np.ptp(wl[:, 1]) * s.draught)
    expected = {"frigate": (0.42, 0.56), "patrol_boat": (0.38, 0.56), "cargo_ship": (0.7, 0.88)}[s.name]
    assert expected[0] <= cb <= expected[1], cb


def test_edge_length_controls_resolution():
    a, b = frigate(2.0), frigate(1.0)
    # Halving the edge length roughly quadruples the triangle count (surface mesh).
    assert 3.0 < b.n_faces / a.n_faces < 5.0
    # Geometry converges: areas within 1 % between the two resolutions (curved hull).
    assert b.total_area == pytest.approx(a.total_area, rel=1e-2)


def test_bad_parameters_raise():
    from shipthermal.errors import InputError
    from shipthermal.geometry import Block

    with pytest.raises(InputError, match="must fit on the deck"):
        frigate(2.0, blocks=[Block("superstructure", 0, 10, 20.0, 3.0)])
    with pytest.raises(InputError, match="superstructure"):
        frigate(2.0, blocks=[Block("deck_house", 0, 10, 5.0, 3.0)])
    with pytest.raises(InputError, match="length"):
        frigate(2.0, length=2000.0)


@pytest.mark.parametrize("k", range(3))
def test_superstructure_stands_on_the_deck(coarse_ships, k):
    s = coarse_ships[k]
    sup = s.vertices[s.faces[s.part_mask("superstructure")]].reshape(-1, 3)
    # Deckhouses are united with the hull: nothing of them is left below the deck
    # (freeboard amidships; the deck only rises forward).
    assert sup[:, 2].min() >= s.freeboard - 1e-9
    deck = s.vertices[s.faces[s.part_mask("deck")]].reshape(-1, 3)
    assert deck[:, 2].min() == pytest.approx(s.freeboard, abs=1e-9)


@pytest.mark.parametrize("length,beam,draught,freeboard", [
    (120.0, 14.0, 4.0, 4.5), (140.0, 16.0, 5.0, 6.0), (130.0, 15.0, 4.5, 5.0)])
def test_parameter_variations_stay_closed_and_exact(length, beam, draught, freeboard):
    s = frigate(2.0, length=length, beam=beam, draught=draught, freeboard=freeboard)
    assert s.is_watertight and s.signed_volume > 0
    assert s.to_trimesh().is_winding_consistent
    ext = np.ptp(s.vertices, axis=0)
    assert ext[0] == pytest.approx(length, abs=1e-6) and ext[1] == pytest.approx(beam, abs=1e-6)
    assert s.vertices[:, 2].min() == pytest.approx(-draught, abs=1e-9)
    assert s.vertices[s.faces[s.part_mask("hull_wetted")], 2].max() <= 0.0
    assert s.vertices[s.faces[s.part_mask("deck")], 2].min() == pytest.approx(freeboard, abs=1e-9)


def test_one_lookup_policy_for_per_part_values():
    """Part, then main part, then 'hull' for the hull's parts: the one policy of every
    per-part table (scenario, overrides, parameter sets, emissivity keys)."""
    from shipthermal.errors import InputError
    from shipthermal.geometry.parts import part_key, part_keys, part_value

    assert part_keys("hull_dry_bow") == ("hull_dry_bow", "hull_dry", "hull")
    assert part_keys("hull") == ("hull",)
    assert part_keys("superstructure_funnel") == ("superstructure_funnel", "superstructure")
    table = {"hull": 1.0, "deck": 2.0, "superstructure_funnel": 3.0}
    assert part_key(table, "hull_wetted") == "hull"
    assert part_key(table, "superstructure_mast") is None
    assert part_value(table, "superstructure_funnel") == 3.0
    with pytest.raises(InputError, match="has no absorptivity"):
        part_value(table, "superstructure", "absorptivity")
