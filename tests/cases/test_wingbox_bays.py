"""fg.cases.wingbox(skin_bays=True): one shell group per skin and rib bay, the same elements, mass
and stiffness as the two-skin box, addressable by the local study's variables."""

import numpy as np
import pytest

import flexgvt as fg


def test_skin_bays_split_the_skins_without_changing_the_box():
    whole = fg.cases.wingbox(element_size=0.5)
    bays = fg.cases.wingbox(element_size=0.5, skin_bays=True)
    names = [g.name for g in bays.model.shells]
    assert names[:2] == ["skin_top_bay01", "skin_top_bay02"] and names[32] == "skin_bottom_bay01"
    assert names[-3:] == ["spar_front", "spar_rear", "ribs"] and len(names) == 2 * 32 + 3
    assert bays.references["groups"] == names and bays.references["bays"] == 32
    for g in (bays.model.shells[0], bays.model.shells[33]):  # the root bay on top, the second at the bottom
        y = bays.model.xyz[bays.model.index_of(g.nodes.ravel()), 1]
        bay = int(g.name[-2:])
        assert (y.min(), y.max()) == pytest.approx((0.5 * (bay - 1), 0.5 * bay))
    quads = [np.sort(np.concatenate([g.nodes for g in c.model.shells]), axis=1) for c in (whole, bays)]
    np.testing.assert_array_equal(*(q[np.lexsort(q.T[::-1])] for q in quads))
    assert fg.mass_properties(bays.model).mass == pytest.approx(fg.mass_properties(whole.model).mass, rel=1e-13)
    f = [fg.solve_modes(fg.solve_static(c.model, c.configurations["unloaded"]), 3).frequencies_hz
         for c in (whole, bays)]
    np.testing.assert_allclose(f[1], f[0], rtol=1e-8)  # the assembly's order differs: round-off
