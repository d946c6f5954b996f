"""Test points onto FE nodes: nearest node with distances, far and shared points, measured directions."""

import warnings

import numpy as np
import pytest

from flexgvt.correlation import Sensors, map_points, map_test_geometry, sensors_from_test
from flexgvt.errors import FlexGVTWarning, ModelError
from flexgvt.io.uff import TestGeometry

NODES = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0, 0], [3.0, 0, 0], [4.0, 0, 0]])
NODE_IDS = np.array([10, 20, 30, 40, 50])


def test_nearest_node_with_a_table_of_distances():
    pts = np.array([[0.02, 0.01, 0.0], [2.0, 0.05, 0.0], [3.97, 0.0, 0.0]])
    m = map_points([1, 2, 3], pts, NODE_IDS, NODES, tolerance=0.05)
    assert m.node_map == {1: 10, 2: 30, 3: 50}
    np.testing.assert_allclose(m.distances, [np.hypot(0.02, 0.01), 0.05, 0.03])
    assert m.tolerance == pytest.approx(0.2)  # 5 % of the 4 m model
    assert [r["status"] for r in m.table()] == ["ok", "ok", "ok"] and m.table()[1]["distance_m"] == pytest.approx(0.05)


def test_far_points_and_shared_nodes_are_reported():
    pts = np.array([[1.0, 0.5, 0.0], [2.0, 0.0, 0.0]])
    with pytest.raises(ModelError, match=r"1 test point\(s\) farther than 0.2 m .* point 1 -> node 20 at 0.5 m.*units"):
        map_points([1, 2], pts, NODE_IDS, NODES)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = map_points([1, 2], pts, NODE_IDS, NODES, on_far="warn")
    assert m.far == (1,) and any(issubclass(w.category, FlexGVTWarning) for w in caught)
    two = np.array([[2.05, 0, 0], [1.96, 0, 0]])
    with pytest.warns(FlexGVTWarning, match=r"node 30: points \[7, 8\]"):
        m = map_points([7, 8], two, NODE_IDS, NODES)
    assert m.shared == {30: [7, 8]} and {r["status"] for r in m.table()} == {"shared"}
    with pytest.raises(ModelError, match="one id per position"):
        map_points([1], two, NODE_IDS, NODES)


def test_a_dof_at_an_angle_is_projected_on_its_global_direction():
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    axes = np.array([np.eye(3), [[c, 0, -s], [0, 1, 0], [s, 0, c]]])  # point 2 turned 30 deg about Y
    geo = TestGeometry(np.array([1, 2]), np.array([[1.0, 0, 0], [3.0, 0, 0.1]]), axes)
    m = map_points(geo.point_ids, geo.xyz, NODE_IDS, NODES)
    sensors = sensors_from_test([(1, 3), (2, 3), (2, -1)], geo, m)
    np.testing.assert_allclose(sensors.directions, [[0, 0, 1], [s, 0, c], [-c, 0, s]], atol=1e-12)
    np.testing.assert_allclose(sensors.offsets[1], [0, 0, 0.1])
    # A node moving 1 m along global Z reads cos 30 on the turned sensor; along X, sin 30.
    shape = np.zeros(6 * len(NODE_IDS))
    shape[6 * 3 + 2] = 1.0
    shape[6 * 3 + 0] = 1.0
    np.testing.assert_allclose(sensors.matrix(NODE_IDS) @ shape, [0, s + c, -c + s], atol=1e-12)
    assert isinstance(sensors, Sensors) and sensors.names == ["1+Z", "2+Z", "2-X"]
    with pytest.raises(ModelError, match="not a translation"):
        sensors_from_test([(1, 4)], geo, m)


def test_test_geometry_onto_a_model():
    import flexgvt as fg

    model = fg.model.Model()
    model.add_nodes(NODES, NODE_IDS)
    geo = TestGeometry(np.array([5, 6]), np.array([[0.99, 0.0, 0.0], [3.02, 0.01, 0.0]]))
    m = map_test_geometry(geo, model)
    assert m.node_map == {5: 20, 6: 40} and np.all(m.distances < 0.03)
