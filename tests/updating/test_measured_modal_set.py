"""updating.Measured composes a ModalSet: built from one (its DOFs giving the sensors) and giving one
back with the sensors' DOF labels."""

import numpy as np

from flexgvt import updating as up
from flexgvt.modal import ModalSet


def test_measured_from_and_to_a_modal_set():
    dofs = np.array([(3, 3), (5, -3), (7, 2)])
    ms = ModalSet(np.array([1.5, 4.0]), np.array([0.01, 0.02]), np.array([[1.0, 0.5, 0.1], [0.2, -1.0, 0.3]]),
                  dofs=dofs, frequency_std_hz=np.array([0.01, 0.03]), labels=("bend", "twist"))
    m = up.Measured.from_modal_set("hung", ms)
    assert m.labels == ("bend", "twist") and m.sensors.nodes.tolist() == [3, 5, 7]
    back = m.modal_set
    assert back.name == "hung" and back.dofs.tolist() == dofs.tolist()
    np.testing.assert_array_equal(back.shapes, ms.shapes)
    np.testing.assert_array_equal(back.frequency_std_hz, ms.frequency_std_hz)
    np.testing.assert_allclose(back.mac(ms), ms.mac(ms))
    only_f = up.Measured.from_modal_set("free", ModalSet(np.array([2.0, 3.0])))
    assert only_f.shapes is None and only_f.modal_set.shapes is None
