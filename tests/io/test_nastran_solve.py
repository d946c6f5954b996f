"""Models read from bulk data solve like the same models built in Python.

The CBAR orientation check: a cantilever with unequal I1/I2 and a skew v vector must give the
frequencies of the Python model whose local z is Nastran's z = x cross v, and its softest bending
mode must move along Nastran's y (the plane of v), which is where I1 (the smaller) acts.
"""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import solve_deck
from flexgvt.model import GeneralSection, Material, Model

E, RHO, NU = 7.0e10, 2700.0, 0.3
A, I1, I2, J = 1.5e-4, 1.0e-8, 4.0e-8, 2.0e-8
L, N = 1.2, 12
V = np.array([0.0, 1.0, 1.0])  # skew orientation vector, plane 1 at 45 degrees


def cantilever_deck(tmp_path, coupmass=True) -> str:
    lines = ["SOL 103", "CEND", "SPC = 1", "METHOD = 1", "BEGIN BULK", "EIGRL,1,,,6"]
    if coupmass:
        lines.append("PARAM,COUPMASS,1")
    for i in range(N + 1):
        lines.append(f"GRID,{i + 1},,{L * i / N!r},0.,0.")
    for i in range(N):
        lines.append(f"CBAR,{100 + i},7,{i + 1},{i + 2},{V[0]},{V[1]},{V[2]}")
    lines += [f"PBAR,7,3,{A},{I1},{I2},{J}", f"MAT1,3,{E},,{NU},{RHO}", "SPC1,1,123456,1", "ENDDATA"]
    path = tmp_path / "cantilever.bdf"
    path.write_text("\n".join(lines) + "\n")
    return path


def python_cantilever(mass="consistent") -> tuple[Model, fg.Configuration]:
    model = Model("python")
    ids = model.add_nodes(np.column_stack([np.linspace(0, L, N + 1), np.zeros(N + 1), np.zeros(N + 1)]))
    z = np.cross([1.0, 0, 0], V)  # Nastran z = x cross v, worked out by hand: (0, -1, 1)
    assert z == pytest.approx([0, -1, 1])
    model.add_beams(np.column_stack([ids[:-1], ids[1:]]), Material("Al", E=E, nu=NU, rho=RHO),
                    GeneralSection(A=A, Iy=I2, Iz=I1, J=J, Ip=0.0), orientation=z, rotary_inertia=False, mass=mass)
    return model, fg.Configuration("clamped", fixed={int(ids[0]): "123456"})


def test_skew_cbar_matches_the_python_beam(tmp_path):
    deck = fg.io.read_bdf(cantilever_deck(tmp_path))
    nas = fg.solve_modes(fg.solve_static(deck.model, deck.configurations["cantilever"]), 6)
    model, cfg = python_cantilever()
    py = fg.solve_modes(fg.solve_static(model, cfg), 6)
    assert nas.frequencies_hz == pytest.approx(py.frequencies_hz, rel=1e-9)
    # the softest bending mode moves in plane 1, along Nastran y = v / |v|
    tip = nas.shapes[0, -1, :3]
    assert abs(tip @ V) / (np.linalg.norm(tip) * np.linalg.norm(V)) == pytest.approx(1.0, abs=1e-6)
    # and matches Euler-Bernoulli with I1 (12 consistent elements: well within 0.1 %)
    f1 = 1.8751040687**2 / (2 * np.pi * L**2) * np.sqrt(E * I1 / (RHO * A))
    assert nas.frequencies_hz[0] == pytest.approx(f1, rel=1e-3)
    f2 = 1.8751040687**2 / (2 * np.pi * L**2) * np.sqrt(E * I2 / (RHO * A))
    assert nas.frequencies_hz[1] == pytest.approx(f2, rel=1e-3)


def test_lumped_mass_without_coupmass(tmp_path):
    deck = fg.io.read_bdf(cantilever_deck(tmp_path, coupmass=False))
    assert deck.mass == "lumped" and deck.model.beams[0].mass == "lumped"
    nas = fg.solve_modes(fg.solve_static(deck.model, deck.configurations["cantilever"]), 4)
    model, cfg = python_cantilever(mass="lumped")
    py = fg.solve_modes(fg.solve_static(model, cfg), 4)
    assert nas.frequencies_hz == pytest.approx(py.frequencies_hz, rel=1e-9)


SUSPENDED = """SOL 103
CEND
METHOD = 1
SUBCASE 1
  SPC = 1
  LOAD = 2
BEGIN BULK
EIGRL,1,,,8
PARAM,WTMASS,1.
{grids}
{bars}
PBARL,1,1,,BAR
,0.0508,0.0032
MAT1,1,6.89e10,,0.33,2700.
CELAS2,201,5.06,3,3
CELAS2,202,5.19,{tip3},3
CDAMP2,211,0.28,3,3
CONM2,301,{mid},,0.01,0.,0.02,0.
SPC1,1,1246,{mid}
GRAV,2,,9.81,0.,0.,-1.
ENDDATA
"""


def test_suspended_strip_static_and_prestressed_modes_match_python(tmp_path):
    """Self-weight on two soft springs (docs/method.md section 2 figures): nonlinear static and modes about it."""
    n, length = 20, 3.66
    x = np.linspace(-length / 2, length / 2, n + 1)
    mid, tip3 = n // 2 + 1, n - 1
    grids = "\n".join(f"GRID,{i + 1},,{xi!r},0.,0." for i, xi in enumerate(x))
    bars = "\n".join(f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(n))
    path = tmp_path / "strip.bdf"
    path.write_text(SUSPENDED.format(grids=grids, bars=bars, mid=mid, tip3=tip3))
    deck = fg.io.read_bdf(path, cbar_torsional_inertia=True)  # the Python twin below has rho*Ip
    nas_state = fg.solve_static(deck.model, deck.configurations["subcase_1"])
    nas = fg.solve_modes(nas_state, 8)

    model = Model("strip")
    ids = model.add_nodes(np.column_stack([x, np.zeros_like(x), np.zeros_like(x)]))
    model.add_beams(np.column_stack([ids[:-1], ids[1:]]), Material("Al", E=6.89e10, nu=0.33, rho=2700.0),
                    fg.RectangularSection(width=0.0032, height=0.0508), orientation=(0, -1, 0),
                    rotary_inertia=False, mass="lumped")
    model.add_spring(3, None, stiffness=[0, 0, 5.06, 0, 0, 0], damping=[0, 0, 0.28, 0, 0, 0])
    model.add_spring(tip3, None, stiffness=[0, 0, 5.19, 0, 0, 0])
    model.add_mass(mid, 0.01, offset=(0, 0.02, 0))
    cfg = fg.Configuration("py", fixed={mid: "1246"}, gravity=1.0, g=9.81)
    py_state = fg.solve_static(model, cfg)
    py = fg.solve_modes(py_state, 8)
    assert nas_state.displacements == pytest.approx(py_state.displacements, rel=1e-9, abs=1e-12)
    assert nas.frequencies_hz == pytest.approx(py.frequencies_hz, rel=1e-8)
    assert nas.damping_ratio == pytest.approx(py.damping_ratio, rel=1e-5, abs=1e-10)  # complex eigensolver tolerance


def test_solve_deck_runs_every_subcase():
    from pathlib import Path
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = solve_deck(Path(__file__).parents[1] / "data" / "bdf" / "all_cards.bdf")
    assert list(results) == ["gravity", "tip loads"]  # the subcases' LABELs
    for res in results.values():
        assert len(res.modes.frequencies_hz) == 6  # EIGRL ND
        assert np.all(res.modes.frequencies_hz > 0)
