"""fem Modes.at(sensors): FE modes at the sensors as a DOF-labelled ModalSet."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.correlation import Sensors
from flexgvt.errors import ModelError
from flexgvt.modal import ModalSet


@pytest.fixture(scope="module")
def modes():
    case = fg.cases.cantilever_strip()
    cfg = next(iter(case.configurations.values()))
    return fg.solve_modes(fg.solve_static(case.model, cfg), 4, label=False)


def test_at_dof_labels_and_at_sensors_agree(modes):
    nodes = modes.node_ids[[3, 7, 9]]
    dofs = np.array([(nodes[0], 3), (nodes[1], -3), (nodes[2], 5)])
    ms = modes.at(dofs)
    assert isinstance(ms, ModalSet) and ms.shapes.shape == (4, 3) and ms.dofs.tolist() == dofs.tolist()
    np.testing.assert_array_equal(ms.frequencies_hz, modes.frequencies_hz)
    np.testing.assert_array_equal(ms.shapes[:, 0], modes.shapes[:, 3, 2])
    np.testing.assert_array_equal(ms.shapes[:, 1], -modes.shapes[:, 7, 2])
    np.testing.assert_array_equal(ms.shapes[:, 2], modes.shapes[:, 9, 4])
    sensors = Sensors.from_outputs(np.array([(nodes[0], 3), (nodes[1], -3)]))
    at_sensors = modes.at(sensors)
    assert at_sensors.dofs.tolist() == dofs[:2].tolist()
    np.testing.assert_allclose(at_sensors.shapes, ms.shapes[:, :2], rtol=1e-12, atol=1e-15)
    # Test modes on the same DOFs in another order correlate with the FE ones through their labels.
    test = ModalSet(ms.frequencies_hz, shapes=ms.shapes[:, ::-1], dofs=dofs[::-1])
    np.testing.assert_allclose(np.diag(test.mac(ms)), 1.0)
    np.testing.assert_allclose(fg.correlation.mac(test, ms), fg.correlation.mac(ms, ms), rtol=1e-12, atol=1e-15)


def test_at_unknown_node_or_scalar_dof_is_refused(modes):
    with pytest.raises(ModelError, match="not in the model"):
        modes.at([(10 ** 6, 3)])
    with pytest.raises(ModelError, match="scalar"):
        modes.at([(int(modes.node_ids[0]), 0)])
