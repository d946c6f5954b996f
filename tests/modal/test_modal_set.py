"""flexgvt.modal: one ModalSet with labelled DOFs (MAC aligned by common DOFs), the MAC kernel, and
the per-point (UFF 55) layout."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.modal import ModalSet, common_dofs, dof_names, mac_rows


def _sets():
    rng = np.random.default_rng(0)
    dofs = np.array([(1, 3), (2, 3), (3, 3), (3, 1), (4, 2)])
    test = ModalSet(np.array([1.0, 2.5, 4.0]), np.full(3, 0.01),
                    rng.standard_normal((3, 5)) + 1j * rng.standard_normal((3, 5)), dofs=dofs)
    fe_shapes = rng.standard_normal((4, 5))
    fe = ModalSet(np.array([0.9, 2.6, 4.1, 7.0]), shapes=fe_shapes, dofs=dofs)
    return test, fe


def test_mac_kernel_closed_forms():
    a = np.array([[1.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
    m = mac_rows(a, a[:2])
    np.testing.assert_allclose(m, [[1.0, 0.5], [0.5, 1.0], [0.0, 0.0]])  # a zero shape has MAC 0
    z = np.array([[1.0 + 1j, 2.0 - 0.5j]])
    assert mac_rows(z, z * np.exp(0.7j) * 3.0)[0, 0] == pytest.approx(1.0)


def test_mac_aligns_by_common_dofs_in_any_order_with_a_missing_dof_and_a_flipped_sign():
    test, fe = _sets()
    hand = mac_rows(test.shapes[:, [0, 1, 2, 4]], fe.shapes[:, [0, 1, 2, 4]])  # DOF (3, 1) left out by hand
    # The FE set in another order, without (3, 1), with (2, 3) read the other way round (2, -3).
    order = [4, 2, 1, 0]
    dofs = fe.dofs[order].copy()
    shapes = fe.shapes[:, order].copy()
    dofs[2, 1], shapes[:, 2] = -3, -shapes[:, 2]
    other = ModalSet(fe.frequencies_hz, shapes=shapes, dofs=dofs)
    np.testing.assert_allclose(test.mac(other), hand, rtol=1e-13)
    np.testing.assert_allclose(fg.correlation.mac(test, other), hand, rtol=1e-13)
    p = fg.correlation.pair(test, other, mac_floor=0.0)
    np.testing.assert_allclose(p.mac_matrix, hand, rtol=1e-13)
    # Positional use is unchanged: same labels in the same order.
    np.testing.assert_allclose(test.mac(fe), mac_rows(test.shapes, fe.shapes), rtol=1e-15)


def test_common_dofs_and_labels():
    ia, ib, sign = common_dofs([(1, 3), (2, -1), (5, 2)], [(2, 1), (1, 3), (7, 3)])
    assert ia.tolist() == [0, 1] and ib.tolist() == [1, 0] and sign.tolist() == [1.0, -1.0]
    assert dof_names([(12, 3), (3, -4), (7, 0)]) == ["12+Z", "3-RX", "7"]
    with pytest.raises(ModelError, match="appears twice"):
        common_dofs([(1, 3), (1, -3)], [(1, 3)])
    with pytest.raises(ModelError, match="no DOF in common"):
        ModalSet([1.0], shapes=[[1.0]], dofs=[(1, 3)]).mac(ModalSet([1.0], shapes=[[1.0]], dofs=[(2, 3)]))
    with pytest.raises(ModelError, match="2 shape columns for 3 DOFs"):
        ModalSet([1.0], shapes=[[1.0, 2.0]], dofs=[(1, 3), (2, 3), (3, 3)])


def test_subset_at_dofs_and_per_point_layout_round_trip():
    rng = np.random.default_rng(2)
    per_point = rng.standard_normal((2, 3, 3))
    ms = ModalSet.from_points([1.0, 2.0], [0.01, 0.02], per_point, [10, 30, 20], [0.1, 0.2], [0.001, 0.002],
                              labels=("a", "b"))
    assert ms.dofs.shape == (9, 2) and ms.point_ids.tolist() == [10, 30, 20]
    ids, back = ms.point_shapes()
    assert ids.tolist() == [10, 30, 20]
    np.testing.assert_array_equal(back, per_point)
    one = ms.subset([1])
    assert one.labels == ("b",) and one.frequency_std_hz.tolist() == [0.2] and one.shapes.shape == (1, 9)
    at = ms.at_dofs([(20, -3), (10, 1), (99, 3)])  # a DOF the set lacks is left out
    assert at.dofs.tolist() == [[20, -3], [10, 1]]
    np.testing.assert_array_equal(at.shapes, np.column_stack([-per_point[:, 2, 2], per_point[:, 0, 0]]))


def test_the_former_types_are_the_one_modal_set():
    from flexgvt.io.uff import ModalResults
    from flexgvt.workflow import Identified

    assert fg.ema.ModalSet is ModalSet and issubclass(Identified, ModalSet)
    ms = ModalResults(np.array([1.0]), np.array([0.02]), np.ones((1, 2, 3)), np.array([5, 6]))
    assert isinstance(ms, ModalSet) and ms.outputs.tolist()[:3] == [[5, 1], [5, 2], [5, 3]]
    named = ModalSet([1.0], name="outboard", source="x.uff").with_info(diagram={"k": 1})
    assert named.configuration == "outboard" and named.diagram == {"k": 1}
    assert named.as_dict()["configuration"] == "outboard"
