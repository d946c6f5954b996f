"""The six real UFF files read as what they are (or refused with what they hold); describe_uff; the
coordinate-system convention (2420 rows = local axes, 18 by three points, chained) and its evidence."""

from pathlib import Path

import numpy as np
import pytest

from flexgvt.errors import FileFormatError
from flexgvt.io.uff import describe_uff, read_time_histories, read_uff

DATA = Path(__file__).parents[1] / "data" / "uff"
TESTLAB = DATA / "TestLab 161 164 18 15 82.uff"
NX = DATA / "NX simulation output.uff"
OROS = DATA / "mesh_Oros-modal_uff15_uff2412.uff"
ARTEMIS = DATA / "Artemis export - Geometry RPBC_setup_05_14102016_105117.uff"


def _turning_angles_deg(geometry):
    """Angles between consecutive segments of a chain of 2-node elements, walked from one end."""
    adj = {}
    for _, _, (a, b) in geometry.elements:
        adj.setdefault(a, []).append(b)
        adj.setdefault(b, []).append(a)
    path = [next(n for n, v in adj.items() if len(v) == 1)]
    while len(path) < len(adj):
        path.append(next(m for m in adj[path[-1]] if m not in path))
    P = geometry.xyz[[geometry.index(n) for n in path]]
    d = np.diff(P, axis=0)
    d /= np.linalg.norm(d, axis=1)[:, None]
    return np.degrees(np.arccos(np.clip(np.sum(d[1:] * d[:-1], axis=1), -1, 1)))


def test_testlab_geometry_with_per_point_displacement_systems():
    data = read_uff(TESTLAB)
    g = data.geometry
    assert len(g.point_ids) == 36 and len(g.coordinate_systems) == 36 and data.units["length"] == 1.0
    assert [name for name, _ in g.traces] == ["Massif", "Stator", "Dalle"]
    np.testing.assert_allclose(g.xyz[0], [-2.4, -0.95, 0.0])
    np.testing.assert_allclose(g.xyz[g.index(19)], [-1.75, 0.81, 0.1])
    # Each point's local +Z (dataset 18: +x point at -X, +xz point below) is its surface's outward
    # normal: down into the base block (1-6), -Y and +Y on the two faces of the stator (7-18 at y = 0,
    # 19-30 at y = 0.81), up on the slab (31-36).
    z = np.array([g.direction(p, 3) for p in g.point_ids])
    np.testing.assert_allclose(z[:6], [[0, 0, -1]] * 6, atol=1e-6)
    np.testing.assert_allclose(z[6:18], [[0, -1, 0]] * 12, atol=1e-6)
    np.testing.assert_allclose(z[18:30], [[0, 1, 0]] * 12, atol=1e-6)
    np.testing.assert_allclose(z[30:], [[0, 0, 1]] * 6, atol=1e-6)
    np.testing.assert_allclose(g.direction(1, -1), [1, 0, 0], atol=1e-6)  # local -X of point 1 is global +X
    with pytest.raises(FileFormatError, match="it holds .*36 points.*3 trace lines.*test geometry only"):
        _ = data.frfs


def test_nx_geometry_is_a_straight_line_of_beams_and_its_modes_read():
    data = read_uff(NX)
    g = data.geometry
    assert len(g.point_ids) == 18 and len(g.elements) == 17 and data.units["length"] == 1000.0
    assert {e[1] for e in g.elements} == {11} and "global" in g.notes[0]
    np.testing.assert_allclose(g.xyz[0], [0.0209409, 0.0130694, 0.0396833], rtol=1e-6)  # mm -> m
    assert _turning_angles_deg(g).max() < 1e-6  # a straight line of 17 beam elements along Z
    # Evidence for NX writing global coordinates: through each node's own system (either reading of
    # the matrix) the line kinks by tens of degrees.
    kinked = read_uff(NX, coordinates="definition").geometry
    assert _turning_angles_deg(kinked).max() > 30
    modes = data.modes
    assert modes.n_modes == 176
    np.testing.assert_allclose(modes.frequencies_hz[:5], [23383.2, 23384.1, 37317.1, 54308.9, 54313.4])
    assert modes.dofs[:4].tolist() == [[3992, 1], [3992, 2], [3992, 3], [9581, 1]]
    # NX writes the 2414 vectors in global components too: at every node of every mode the vector
    # lies along that node's local z axis (rows-as-axes reading of 2420: the sensor's measuring axis,
    # as TestLab's +Z) to 1e-13; the mode DOFs are global X, Y, Z.
    ids, pts = modes.point_shapes()
    z = np.array([g.axes[g.index(i)][2] for i in ids])
    norm = np.linalg.norm(pts, axis=2)
    cos = np.abs(np.einsum("mnk,nk->mn", pts, z))[norm > 0] / norm[norm > 0]
    assert 1 - cos.min() < 1e-12
    np.testing.assert_allclose(pts[0, 0], [0.0195655, 13.0354, -1.92335e-7], rtol=1e-5)  # node 3992, mode 1
    turned = read_uff(NX, coordinates="definition").modes.point_shapes()[1]
    assert not np.allclose(turned, pts, atol=1e-3)


def test_oros_and_artemis_geometry_with_elements():
    oros = read_uff(OROS).geometry
    assert len(oros.point_ids) == 96 and len(oros.elements) == 72 and {e[1] for e in oros.elements} == {44}
    assert "no units dataset 164" in oros.notes[-1]
    np.testing.assert_allclose(oros.xyz[0], [-51.619, 51.619, 50.0], rtol=1e-4)  # CS 1 is the global one
    art = read_uff(ARTEMIS).geometry
    assert len(art.point_ids) == 74 and len(art.traces) == 2 and len(art.elements) == 108
    assert set(np.unique([n for _, _, nodes in art.elements for n in nodes])) <= set(art.point_ids.tolist())


@pytest.mark.parametrize("name", ["Sample_UFF58_ascii.uff", "Sample_UFF58b_bin.uff"])
def test_time_records_read_and_refused_as_frfs_with_what_they_hold(name):
    data = read_uff(DATA / name)
    with pytest.raises(FileFormatError, match=r"no FRF .* 1 time response \(58 type 1\).*flexgvt ema frf"):
        _ = data.frfs
    th = read_time_histories(DATA / name)
    assert th.data.shape == (1, 79292) and th.units == ("Pa",)
    assert th.sample_rate_hz == pytest.approx(1 / 1.52588e-05, rel=1e-5)
    with pytest.raises(FileFormatError, match="no channel is marked as a force"):
        th.signals()


def test_describe_uff_names_datasets_functions_and_geometry():
    text = str(describe_uff(NX))
    assert "2414 x176" in text and "18 coordinate systems" in text and "17 elements" in text and "176 modes" in text
    t = describe_uff(TESTLAB)
    assert t.counts == {15: 1, 18: 1, 82: 3, 151: 1, 164: 1} and t.n_points == 36 and t.truncated is None
    s = describe_uff(DATA / "Sample_UFF58b_bin.uff")
    assert s.functions == (("time response", "0+X", "0 (scalar)", 79292),)
    with pytest.raises(FileFormatError, match="it holds .*176 modes.*read_uff\\(path\\).modes"):
        _ = read_uff(NX).frfs
    with pytest.raises(FileFormatError, match="no modes .* it holds .*time response"):
        read_uff(DATA / "Sample_UFF58_ascii.uff").require_modes()


def _write_cs_file(tmp_path, cs_block, node_block):
    path = tmp_path / "cs.uff"
    path.write_text("    -1\n   164\n         1  SI                     2\n"
                    "  1.00000000000000000D+00  1.00000000000000000D+00  1.00000000000000000D+00\n"
                    "  2.73150000000000000D+02\n    -1\n" + cs_block + node_block)
    return path


def test_2420_rows_are_local_axes_and_row_4_the_origin(tmp_path):
    import pyuff

    c, s = np.cos(0.3), np.sin(0.3)
    R = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])  # local x, y, z axes in global (rows)
    o = np.array([1.0, 2.0, 3.0])
    path = tmp_path / "cs.uff"
    uff = pyuff.UFF(str(path))
    uff.write_sets([pyuff.prepare_2420(Part_UID=1, Part_Name="p", CS_sys_labels=[7], CS_types=[0], CS_colors=[1],
                                       CS_names=["CS7"], CS_matrices=[np.vstack([R, o])]),
                    pyuff.prepare_2411(node_nums=[1, 2], def_cs=[7, 0], disp_cs=[7, 0], color=[1, 1],
                                       x=[2.0, 0.5], y=[0.0, 0.5], z=[0.0, 0.5])], mode="add")
    g = read_uff(path, coordinates="definition").geometry
    np.testing.assert_allclose(g.xyz[0], o + 2.0 * R[0], atol=1e-12)  # local (2, 0, 0) is 2 along local x
    np.testing.assert_allclose(g.xyz[1], [0.5, 0.5, 0.5])
    np.testing.assert_allclose(g.direction(1, 2), R[1], atol=1e-12)
    np.testing.assert_allclose(g.direction(2, -3), [0, 0, -1])


def test_18_chained_through_its_reference_system_and_non_cartesian_refused(tmp_path):
    import pyuff

    path = tmp_path / "cs18.uff"
    uff = pyuff.UFF(str(path))
    # CS 1: origin (1, 0, 0), x along global +Y, xz plane containing global +Z.
    # CS 2 in CS 1: origin 2 along CS 1's x, its x along CS 1's -x.
    uff.write_sets([pyuff.prepare_18(cs_num=[2, 1], cs_type=[0, 0], ref_cs_num=[1, 0], color=[1, 1], method=[1, 1],
                                     cs_name=["B", "A"], ref_o=[[2, 0, 0], [1, 0, 0]], x_point=[[1, 0, 0], [1, 1, 0]],
                                     xz_point=[[1, 0, 1], [1, 0, 1]]),
                    pyuff.prepare_15(node_nums=[5], def_cs=[2], disp_cs=[2], color=[1], x=[1.0], y=[0.0], z=[0.0])],
                   mode="add")
    g = read_uff(path).geometry
    np.testing.assert_allclose(g.coordinate_systems[1].R, [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-12)
    np.testing.assert_allclose(g.coordinate_systems[2].origin, [1, 2, 0], atol=1e-12)
    np.testing.assert_allclose(g.xyz[0], [1, 1, 0], atol=1e-12)  # 1 along CS 2's x = global -Y
    np.testing.assert_allclose(g.direction(5, 1), [0, -1, 0], atol=1e-12)
    text = path.read_text().replace("         2         0         1", "         2         1         1", 1)
    path.write_text(text)
    with pytest.raises(FileFormatError, match="node 5: definition coordinate system 2 is cylindrical"):
        read_uff(path)


def test_geometry_with_turned_displacement_axes_written_and_read_back(tmp_path):
    from flexgvt.io.uff import write_uff

    g = read_uff(TESTLAB).geometry
    back = read_uff(write_uff(tmp_path / "geo.uff", geometry=g)).geometry
    np.testing.assert_allclose(back.xyz, g.xyz, atol=1e-5)
    np.testing.assert_allclose(back.axes, g.axes, atol=1e-5)  # dataset 18 points are E13.5
