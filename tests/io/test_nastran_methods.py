"""EIGRL/EIGR of the deck honoured by solve_deck and `flexgvt solve`: ND, window V1-V2 (only the
modes inside reported, as Nastran), normalisation MASS/MAX/POINT; ASET named in a warning; the
deprecated io alias of solve_deck forwards."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import solve_deck

DECK = """SOL 103
CEND
METHOD = {sid}
SPC = 1
BEGIN BULK
{method}
{grids}
{bars}
PBEAM,1,1,1.e-4,1.e-8,2.e-8,,1.e-8
MAT1,1,7.e10,,0.3,2700.
SPC1,1,123456,1
{extra}
ENDDATA
"""


def deck(tmp_path, method, sid=1, extra=""):
    grids = "\n".join(f"GRID,{i + 1},,{0.1 * i!r},0.,0." for i in range(11))
    bars = "\n".join(f"CBEAM,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(10))
    path = tmp_path / "cantilever.bdf"
    path.write_text(DECK.format(sid=sid, method=method, grids=grids, bars=bars, extra=extra))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path)


def modes_of(d, **kw):
    return next(iter(solve_deck(d, **kw).values())).modes


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    return modes_of(deck(tmp_path_factory.mktemp("ref"), "EIGRL,1,,,30"))


def test_eigrl_nd_gives_that_many_modes(tmp_path, reference):
    m = modes_of(deck(tmp_path, "EIGRL,1,,,7"))
    assert m.frequencies_hz == pytest.approx(reference.frequencies_hz[:7], rel=1e-9)


def test_eigrl_window_reports_only_the_modes_inside(tmp_path, reference):
    f = reference.frequencies_hz
    v1, v2 = 0.5 * (f[2] + f[3]), 0.5 * (f[10] + f[11])  # modes 4..11
    m = modes_of(deck(tmp_path, f"EIGRL,1,{v1!r},{v2!r}"))
    assert m.frequencies_hz == pytest.approx(f[3:11], rel=1e-9)
    m = modes_of(deck(tmp_path, f"EIGRL,1,{v1!r},{v2!r},3"))  # ND caps the window: the lowest 3 in it
    assert m.frequencies_hz == pytest.approx(f[3:6], rel=1e-9)


def test_eigr_giv_uses_nd_before_the_window(tmp_path, reference):
    """pt145's EIGR GIV 0.-0.1 Hz with ND = 6: Nastran computes 6 vectors whatever the window."""
    m = modes_of(deck(tmp_path, "EIGR,1,GIV,0.,0.1,,6"))
    assert m.frequencies_hz == pytest.approx(reference.frequencies_hz[:6], rel=1e-9)


def test_max_and_point_normalisation(tmp_path, reference):
    m = modes_of(deck(tmp_path, "EIGRL,1,,,5,,,,MAX"))
    flat = m.shapes.reshape(5, -1)
    assert np.max(flat, axis=1) == pytest.approx(np.ones(5)) and np.all(np.max(np.abs(flat), axis=1) <= 1 + 1e-12)
    ref = reference.shapes[:5].reshape(5, -1)
    assert np.allclose(flat * (ref[np.arange(5), np.argmax(np.abs(ref), axis=1)])[:, None], ref)
    m = modes_of(deck(tmp_path, "EIGR,1,LAN,,,,5\n,POINT,11,3"))
    moves = np.abs(reference.shapes[:5, -1, 2]) > 1e-6 * np.abs(reference.shapes[:5]).reshape(5, -1).max(axis=1)
    assert 0 < moves.sum() < 5
    assert m.shapes[moves, -1, 2] == pytest.approx(np.ones(moves.sum()))  # tip z = 1
    assert np.max(m.shapes[~moves].reshape((~moves).sum(), -1), axis=1) == pytest.approx(1.0)  # MAX where it is still


def test_mass_normalisation_is_unchanged(tmp_path, reference):
    m = modes_of(deck(tmp_path, "EIGRL,1,,,4,,,,MASS"))
    assert np.allclose(np.abs(m.shapes), np.abs(reference.shapes[:4]))


def test_aset_is_named_in_a_warning(tmp_path):
    path = tmp_path / "aset.bdf"
    grids = "\n".join(f"GRID,{i + 1},,{0.1 * i!r},0.,0." for i in range(11))
    bars = "\n".join(f"CBEAM,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(10))
    path.write_text(DECK.format(sid=1, method="EIGRL,1,,,4", grids=grids, bars=bars, extra="ASET1,3,6,11"))
    with pytest.warns(UserWarning, match="ASET1 .Guyan reduction.*solve_deck reduces the model"):
        fg.io.read_bdf(path)


def test_io_no_longer_solves_and_says_where_solving_went():
    """io never calls the solver (the layers of docs/architecture.md): the deprecated io alias of
    solve_deck is gone and its name points to flexgvt.workflow.solve_deck."""
    with pytest.raises(AttributeError, match="use flexgvt.workflow.solve_deck"):
        _ = fg.io.solve_deck
    assert "solve_deck" not in fg.io.__all__ and not hasattr(fg.io.nastran, "solve_deck")
