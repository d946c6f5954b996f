"""Guyan reduction (fem.reduction, solve_modes(..., reduction=...)): exact where the omitted DOFs carry
no mass, Rayleigh's static-shape result for a cantilever reduced to its tip, stiffer (never lower)
otherwise, and a singular omitted stiffness named."""

import numpy as np
import pytest

import flexgvt as fg
from fem_builders import straight_beam
from flexgvt.errors import ModelError, SolverError

E, RHO, W, H, L = 70e9, 2700.0, 0.05, 0.003, 1.5


def _cantilever(n=10, rho=RHO):
    model, ids = straight_beam(n, length=L, material=fg.Material("Al", E=E, nu=0.33, rho=rho))
    return model, ids, fg.Configuration("clamped", fixed={int(ids[0]): "123456"})


def test_omitting_massless_dofs_is_exact():
    """A massless cantilever carrying point masses at every second node: omitting every DOF of the
    nodes without mass and every rotation leaves the modes unchanged (to round-off), shapes included."""
    model, ids, config = _cantilever(12, rho=0.0)
    heavy = ids[2::2]
    for i in heavy:
        model.add_mass(int(i), 0.1)
    state = fg.solve_static(model, config)
    full = fg.solve_modes(state, 8, damped=False)
    omit = {int(i): "123456" for i in ids[1::2]} | {int(i): "456" for i in heavy}
    reduced = fg.solve_modes(state, 8, damped=False, reduction={"OMIT": omit})
    np.testing.assert_allclose(reduced.frequencies_hz, full.frequencies_hz, rtol=1e-9)
    sign = np.sign(np.einsum("kij,kij->k", reduced.shapes, full.shapes))[:, None, None]  # distinct modes
    np.testing.assert_allclose(sign * reduced.shapes, full.shapes, atol=1e-8 * np.abs(full.shapes).max())
    # The same set named the other way round (ASET: what is kept) is the same reduction.
    kept = fg.solve_modes(state, 8, damped=False, reduction={"ASET": {int(i): "123" for i in heavy}})
    np.testing.assert_allclose(kept.frequencies_hz, reduced.frequencies_hz, rtol=1e-12)


def test_cantilever_reduced_to_its_tip_is_rayleighs_static_shape():
    """ASET = the tip's transverse DOFs: one mode per bending plane at Rayleigh's frequency with the
    static deflection shape, sqrt(3 EI / L^3 / (33/140 m L)) (the cubic static shape is exact in the
    cubic elements with their consistent mass), 1.46 % above the exact first bending frequency."""
    model, ids, config = _cantilever()
    state = fg.solve_static(model, config)
    modes = fg.solve_modes(state, 2, damped=False, reduction={"ASET": {int(ids[-1]): "13"}})
    m = RHO * W * H
    expected = sorted(np.sqrt(3 * E * I / L**3 / (33 / 140 * m * L)) / (2 * np.pi)
                      for I in (W * H**3 / 12, H * W**3 / 12))
    np.testing.assert_allclose(modes.frequencies_hz, expected, rtol=1e-9)
    exact = 1.8751**2 / (2 * np.pi) * np.sqrt(E * W * H**3 / 12 / (m * L**4))
    assert modes.frequencies_hz[0] / exact - 1 == pytest.approx(0.0146, abs=2e-4)
    tip = modes.shapes[0, -1]  # mass-normalised: the tip's generalised mass is 33/140 m L
    assert abs(tip[2]) == pytest.approx(1 / np.sqrt(33 / 140 * m * L), rel=1e-9)


def test_reduced_frequencies_lie_above_the_full_ones():
    model, ids, config = _cantilever(20)
    state = fg.solve_static(model, config)
    full = fg.solve_modes(state, 6, damped=False).frequencies_hz
    reduced = fg.solve_modes(state, 6, damped=False, reduction={"ASET": {int(i): "123" for i in ids[4::4]}})
    f = reduced.frequencies_hz
    assert np.all(f >= full * (1 - 1e-12))
    assert f[0] == pytest.approx(full[0], rel=1e-4)  # five nodes' translations describe the first mode well


def test_bad_reduction_sets_are_named():
    model, ids, config = _cantilever()
    state = fg.solve_static(model, config)
    with pytest.raises(ModelError, match="grid 999 is not a node"):
        fg.solve_modes(state, 2, damped=False, reduction={"ASET": {999: "3"}})
    with pytest.raises(ModelError, match="components"):
        fg.solve_modes(state, 2, damped=False, reduction={"OMIT": {int(ids[3]): "7"}})
    free = fg.solve_static(model, fg.Configuration("free"))
    # Only the translations of one node kept: the free beam's rotations about it are omitted, unrestrained.
    with pytest.raises(SolverError, match="K_oo"):
        fg.solve_modes(free, 2, damped=False, reduction={"ASET": {int(ids[0]): "123"}})


DECK = """SOL 103
CEND
METHOD = 1
SPC = 1
BEGIN BULK
EIGRL,1,,,4
{grids}
{bars}
PBEAM,1,1,1.e-4,1.e-8,2.e-8,,1.e-8
MAT1,1,7.e10,,0.3,2700.
SPC1,1,123456,1
ASET1,3,11
ENDDATA
"""


def test_deck_with_aset_is_solved_reduced_as_nastran(tmp_path):
    """A Nastran cantilever (10 CBEAM, 1 m, lumped mass as Nastran's default) with ASET1 3 on its tip:
    solve_deck reduces it to one DOF: the tip stiffness (bending and PBEAM's default shear) over the
    lumped masses weighted by the static deflection shape (a hand computation: the rotations carry
    no lumped mass)."""
    import warnings

    from flexgvt.workflow import solve_deck

    path = tmp_path / "aset.bdf"
    path.write_text(DECK.format(grids="\n".join(f"GRID,{i + 1},,{0.1 * i!r},0.,0." for i in range(11)),
                                bars="\n".join(f"CBEAM,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(10))))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = fg.io.read_bdf(path)
    assert deck.options["ASET"] == {11: "3"}
    modes = next(iter(solve_deck(deck).values())).modes
    x = np.linspace(0, 1, 11)
    m = 2700.0 * 1e-4 * 0.1 * np.r_[0.5, np.ones(9), 0.5]
    EI, GA = 7e10 * 1e-8, 7e10 / 2.6 * 1e-4  # PBEAM's K1 blank: shear factor 1, shear area A
    w = (x**2 / 2 - x**3 / 6) / EI + x / GA  # the deflection under a unit tip force
    k = 1 / w[-1]
    m_r = np.sum(m * (w / w[-1]) ** 2)
    assert modes.frequencies_hz == pytest.approx([np.sqrt(k / m_r) / (2 * np.pi)], rel=1e-9)
