"""CMASS1/CMASS2 on rotational components of grids in a rotated displacement system: an inertia
about the rotated axis (the reader crashed with AttributeError: 'CMASS2' object has no attribute
'nid' before); on a translational component they are named unsupported."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.io.nastran import UnsupportedCardsError

HEAD = "SOL 103\nCEND\nSPC = 1\nBEGIN BULK\n"
BEAM = """GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.,5
CORD2R,5,,0.,0.,0.,0.,0.,1.,
,1.,1.,0.
CBAR,10,1,1,2,0.,0.,1.
PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8
MAT1,1,7.e10,,0.3,2700.
SPC1,1,123456,1
"""


def test_rotational_scalar_masses_in_a_rotated_cd_become_inertia(tmp_path):
    path = tmp_path / "cmass.bdf"
    path.write_text(HEAD + BEAM + "CMASS2,20,0.5,2,4\nCMASS1,21,7,2,6\nPMASS,7,0.25\nENDDATA\n")
    deck = fg.io.read_bdf(path)
    J = sum(m.inertia for m in deck.model.masses)
    # CD 5: x' = (1, 1, 0)/sqrt(2) (its xz-plane point (1, 1, 0)), z' = z: component 4 about x', 6 about z.
    a = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    np.testing.assert_allclose(J, 0.5 * np.outer(a, a) + 0.25 * np.diag([0, 0, 1.0]), atol=1e-12)
    assert sum(m.mass for m in deck.model.masses) == 0.0


def test_translational_scalar_mass_is_named_unsupported(tmp_path):
    path = tmp_path / "cmass_t.bdf"
    path.write_text(HEAD + BEAM + "CMASS2,20,0.5,2,2\nENDDATA\n")
    with pytest.raises(UnsupportedCardsError, match="CMASS2 \\(translational component"):
        fg.io.read_bdf(path)


def test_updated_scalar_masses_are_written_into_the_template(tmp_path):
    """write_bdf(template=) raised AttributeError ('CMASS2' object has no attribute 'cid') for a
    changed CMASS; now the value goes back into CMASS2 and PMASS (split when shared)."""
    from nastran_helpers import rebuild

    path = tmp_path / "cmass.bdf"
    path.write_text(HEAD + BEAM + "CMASS2,20,0.5,2,4\nCMASS1,21,7,2,6\nCMASS1,22,7,2,5\nPMASS,7,0.25\nENDDATA\n")
    deck = fg.io.read_bdf(path)
    updated = rebuild(deck.model, mass={0: 2.0, 1: 3.0})  # CMASS2 20 and CMASS1 21 (PMASS 7 shared with 22)
    out = fg.io.write_bdf(updated, tmp_path / "out.bdf", template=deck)
    again = fg.io.read_bdf(out)
    for a, b in zip(again.model.masses, updated.masses):
        np.testing.assert_allclose(a.inertia, b.inertia, rtol=1e-12, atol=1e-15)
    assert again.mass_sources[:2] == [("CMASS2", 20), ("CMASS1", 21)]
    assert len({again.bdf.elements.get(e, again.bdf.masses.get(e)).pid for e in (21, 22)}) == 2
    off_axis = rebuild(deck.model)
    off_axis.masses[0].inertia[0, 2] = 0.1
    with pytest.raises(fg.errors.ModelError, match="CMASS2 20: the updated mass is no longer an inertia"):
        fg.io.write_bdf(off_axis, tmp_path / "bad.bdf", template=deck)
    assert deck.bdf.properties_mass[7].mass == 0.25  # the template deck itself is unchanged
