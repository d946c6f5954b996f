"""Nonlinear (table) springs in bulk data: CBUSH + PBUSHT KN, CELAS1 + PELAST TKNID and CBUSH1D +
PBUSH1D SPRING TABLE with TABLED1 force-deflection tables; Nastran's sign conventions; round trips
through write_bdf (compact and template); malformed tables refused with the card's place."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.rotations import expm_so3
from flexgvt.io.nastran import UnsupportedCardsError
from flexgvt.model import SpringTable

TABLE = """TABLED1 {tid}
        -1.     -300.   0.      0.      1.      250.    ENDT
"""
DECK = """SOL 103
CEND
BEGIN BULK
GRID    1               0.      0.      0.
GRID    2               1.      0.      0.
GRID    3               1.      0.      0.
CBUSH   10      20      2       3                               0
PBUSH   20      K       100.    250.    300.    4.      5.      6.
PBUSHT  20      KN      0       501     0       0       0       0
CBUSH   11      20      1                                       0
CELAS1  30      40      1       3
CELAS1  31      40      2       3       3       3
PELAS   40      250.
PELAST  40                      502
CBUSH1D 50      60      1       2
PBUSH1D 60      250.
        SPRING  TABLE   503
""" + "".join(TABLE.format(tid=t) for t in (501, 502, 503, 777))


def _read(tmp_path, text=DECK, name="t.bdf"):
    path = tmp_path / name
    path.write_text(text + "ENDDATA\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path)


def _force(spring, c, d):
    return spring.table_scale[c] * spring.tables[c].evaluate(d)[0]


def test_cards_read_with_nastrans_senses(tmp_path):
    """The table's f(-1) = -300, f(1) = 250. Flexgvt's deflection is b relative to a (a grounded
    spring's: its node's motion). CBUSH GA-GB and CBUSH1D GA-GB: U = U(GB) - U(GA), the same; a
    grounded CBUSH: U = -U(GA), mirrored; grounded CELAS1: F = f(u1), the same; CELAS1 G1-G2:
    F = f(u1 - u2), mirrored."""
    deck = _read(tmp_path)
    by = dict(zip(deck.spring_sources, deck.model.springs))
    d = np.array([-1.0, 1.0])
    np.testing.assert_allclose(_force(by[("CBUSH", 10)], 1, d), [-300, 250])
    np.testing.assert_allclose(_force(by[("CBUSH", 11)], 1, d), [-250, 300])
    np.testing.assert_allclose(_force(by[("CELAS1", 30)], 2, d), [-300, 250])
    np.testing.assert_allclose(_force(by[("CELAS1", 31)], 2, d), [-250, 300])
    cb1 = by[("CBUSH1D", 50)]
    np.testing.assert_allclose(_force(cb1, 0, d), [-300, 250])
    np.testing.assert_allclose(cb1.frame[:, 0], [1, 0, 0])
    assert by[("CBUSH", 10)].stiffness[[0, 2, 5]].tolist() == [100.0, 300.0, 6.0]  # linear ones stay
    assert any("TABLED1 777 not used by a spring" in n for n in deck.notes)
    assert not any("linear rate" in n for n in deck.notes)  # every rate is its table's slope at 0


def test_rate_unlike_the_table_is_noted(tmp_path):
    deck = _read(tmp_path, DECK.replace("PELAS   40      250.", "PELAS   40      100."))
    assert any("CELAS1 30: component 3's linear rate 100" in n and "follows the table" in n for n in deck.notes)


@pytest.mark.parametrize("table, message", [
    ("TABLED1 501\n        0.      0.      -1.     -300.   1.      250.    ENDT\n", "increase strictly"),
    ("TABLED1 501\n        0.      0.      ENDT\n", "at least two"),
    ("TABLED1 501\n        -1.     -300.   1.      250.    ENDT\n", "preload"),
    ("TABLED1 501     LOG     LINEAR\n        1.      0.      2.      250.    ENDT\n", "LINEAR/LINEAR"),
    ("TABLED1 501" + " " * 21 + "1\n        -1.     -300.   0.      0.      1.      250.    "
     "ENDT\n", "EXTRAP=1"),
    ("TABLED2 501     0.\n        -1.     -300.   0.      0.      1.      250.    ENDT\n", "must be a TABLED1"),
    ("", "not in the deck"),
])
def test_malformed_tables_name_their_card(tmp_path, table, message):
    text = DECK.replace(TABLE.format(tid=501), table)
    with pytest.raises(ModelError, match=message) as info:
        _read(tmp_path, text)
    assert "t.bdf" in str(info.value)


def test_unread_pbush1d_forms_are_unsupported(tmp_path):
    text = DECK.replace("        SPRING  TABLE   503\n", "        SPRING  TABLE   503\n        DAMPER  TABLE   777\n")
    with pytest.raises(UnsupportedCardsError, match="PBUSH1D"):
        fg.io.read_bdf(_write(tmp_path, text))
    with pytest.raises(ModelError, match="compression table"):
        _read(tmp_path, DECK.replace("SPRING  TABLE   503", "SPRING  TABLE   503     501"))


def _write(tmp_path, text):
    path = tmp_path / "u.bdf"
    path.write_text(text + "ENDDATA\n")
    return path


def _model():
    """Table springs of every written form: grounded and two-node in basic axes (CELAS1), grounded
    and coincident two-node in turned axes (CBUSH), one scaled, rotations and translations."""
    m = fg.Model("table springs")
    ids = [int(i) for i in m.add_nodes([[0, 0, 0], [1, 0, 0], [1, 0, 0], [2, 0, 0]])]
    al = fg.Material("al massless", 70e9, 0.0, nu=0.3)  # point masses: the deck's mass model is not the question
    m.add_beams([[ids[0], ids[1]], [ids[2], ids[3]]], al, fg.RectangularSection(0.03, 0.005), rotary_inertia=False,
                mass="lumped")
    for i in ids:
        m.add_mass(i, 0.2, inertia=np.eye(3) * 1e-4)
    t1 = SpringTable.make([-0.02, 0, 0.01, 0.03], [-500, 0, 150, 900])
    t2 = SpringTable.make([-0.3, 0, 0.2], [-40, 0, 10])
    Q = expm_so3(np.array([0.2, 0.1, -0.3]))
    m.add_spring(ids[0], None, stiffness=[1e5, 0, 0, 0, 20, 30], tables={2: t1, 3: t1, 4: t2}, name="g")
    m.add_spring(ids[1], ids[2], stiffness=[0, 1e4, 0, 5, 0, 8], tables={1: t1, 3: t1, 5: t2}, name="ab")
    m.add_spring(ids[3], None, stiffness=[1e5, 0, 2e5, 0, 0, 0], tables={2: t1, 4: t2, 5: t2, 6: t2}, frame=Q)
    m.add_spring(ids[1], ids[2], tables={6: t2}, frame=Q)
    m.set_spring(0, stiffness=np.r_[1e5, 2 * m.springs[0].stiffness[1], m.springs[0].stiffness[2:]])
    load = fg.Configuration("tip", forces=[fg.NodalLoad(ids[3], force=(30.0, -40.0, 60.0), moment=(2.0, 3.0, -1.0))])
    return m, load


def _solve(model, cfg):
    state = fg.solve_static(model, cfg, settings=fg.StaticSettings(tolerance=1e-12))
    return state.displacements, fg.solve_modes(state, 6, label=False).frequencies_hz


@pytest.mark.parametrize("units", ["SI", "mm-N-t-s"])
def test_compact_round_trip(tmp_path, units):
    """Written as CELAS1 + PELAS + PELAST and CBUSH + PBUSH + PBUSHT (tables scaled, mirrored where
    Nastran's sense differs) and read back: the same forces at every deflection, the same static
    state and loaded modes."""
    model, cfg = _model()
    path = fg.io.write_bdf(model, tmp_path / "c.bdf", units=units)
    text = path.read_text()
    assert "PELAST" in text and "PBUSHT" in text and "TABLED1" in text
    back = fg.io.read_bdf(path, units=units).model
    d = np.linspace(-0.05, 0.05, 23)
    for s in model.springs:
        for c in [c for c in range(6) if s.stiffness[c] or s.tables[c] is not None]:
            mine = [r for r in back.springs if (r.node_a, r.node_b) == (s.node_a, s.node_b)
                    and np.allclose(r.frame, s.frame) and (r.stiffness[c] or r.tables[c] is not None)]
            assert len(mine) == 1
            r = mine[0]
            want = s.stiffness[c] * d if s.tables[c] is None else _force(s, c, d)
            got = r.stiffness[c] * d if r.tables[c] is None else _force(r, c, d)
            np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-9 * np.abs(want).max())
    x0, f0 = _solve(model, cfg)
    x1, f1 = _solve(back, cfg)
    assert np.abs(x0).max() > 1e-3  # the springs are loaded into their tables
    np.testing.assert_allclose(x1, x0, rtol=0, atol=1e-9 * np.abs(x0).max())
    np.testing.assert_allclose(f1, f0, rtol=1e-8)


def test_template_round_trip_with_scaled_tables(tmp_path):
    """Scaled springs (updating's spring variables) go back as new TABLED1s with the scaled forces
    and the linear rates as the scaled slopes at zero; the deck's own tables stay."""
    deck = _read(tmp_path)
    model = deck.model
    for i, s in enumerate(model.springs):
        model.set_spring(i, stiffness=s.stiffness * (1.5 + i))
    path = fg.io.write_bdf(model, tmp_path / "w.bdf", template=deck)
    back = _read(tmp_path, path.read_text().replace("ENDDATA", ""), "w2.bdf")
    d = np.linspace(-2, 2, 21)
    assert back.spring_sources == deck.spring_sources
    for s, r in zip(model.springs, back.model.springs):
        for c in range(6):
            if s.tables[c] is None:
                assert r.tables[c] is None and r.stiffness[c] == pytest.approx(s.stiffness[c], rel=1e-12)
            else:
                np.testing.assert_allclose(_force(r, c, d), _force(s, c, d), rtol=1e-12, atol=1e-10)
                assert r.tables[c].name != s.tables[c].name  # a new TABLED1
    assert not any("linear rate" in n for n in back.notes)
    for tid in (501, 502, 503):
        assert f"TABLED1*             {tid}" in path.read_text() or f"TABLED1 {tid}" in path.read_text()
