"""One result object per function: refine and select_ml return a ModalSet carrying their
diagnostics in ``info``; the old return_info flag still gives the old tuple, with a warning."""

import numpy as np
import pytest

from flexgvt.ema import ModalModel, RefineInfo, polymax, refine, select_ml, synthesize_frfs
from flexgvt.modal import FRFs, ModalSet


@pytest.fixture(scope="module")
def frfs():
    rng = np.random.default_rng(4)
    model = ModalModel(np.array([1.2, 3.4]), np.array([0.02, 0.015]), rng.standard_normal((2, 5)))
    return synthesize_frfs(model, np.linspace(0.05, 6, 600), list(range(5)), [0], snr_db=40, seed=2)


def test_refine_and_select_ml_return_one_modal_set_with_info(frfs):
    assert isinstance(frfs, FRFs) and frfs.outputs.shape == (5, 2)
    stab = polymax(frfs, max_order=16)
    ms = select_ml(stab)
    assert isinstance(ms, ModalSet) and ms.frequency_std_hz is not None
    np.testing.assert_allclose(ms.frequencies_hz, [1.2, 3.4], rtol=5e-3)
    assert {"candidates", "kept", "refine", "threshold", "log"} <= set(ms.info)
    assert isinstance(ms.info["refine"], RefineInfo) and ms.info["kept"]
    again = refine(frfs, ms)
    assert isinstance(again.info["refine"], RefineInfo) and np.array_equal(again.dofs, frfs.outputs)
    with pytest.warns(DeprecationWarning, match=r"refine\(return_info=True\) is deprecated"):
        out, info = refine(frfs, ms, return_info=True)
    np.testing.assert_array_equal(out.frequencies_hz, again.frequencies_hz)
    assert info.cost == again.info["refine"].cost
    with pytest.warns(DeprecationWarning, match=r"select_ml\(return_info=True\)"):
        old, details = select_ml(stab, return_info=True)
    np.testing.assert_array_equal(old.frequencies_hz, ms.frequencies_hz)
    assert details["threshold"] == ms.info["threshold"]
