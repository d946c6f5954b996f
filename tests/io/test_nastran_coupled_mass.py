"""Nastran's coupled beam mass (PARAM,COUPMASS) as read_bdf builds it.

MSC Nastran's CBEAM under COUPMASS has cubic (consistent) bending mass but lumped axial and torsional
mass: the strut-braced wing deck (tests/data/bdf/pynastran/strut_wing, MSC/NASTRAN 4/28/98) gives
Nastran's first 14 elastic modes to 3e-7 with it, and misses its 5.85 Hz strut mode (a 7.08 Hz
mode instead) and moves others by up to 2e-4 with consistent axial and torsional mass.
"""

import warnings

import numpy as np
import pytest
import scipy.linalg

import flexgvt as fg
from flexgvt.workflow import solve_deck

E, NU, RHO, L = 70e9, 0.3, 2700.0, 1.0
A, I1, I2, J = 1e-4, 1e-9, 2e-9, 2.5e-9


def cantilever_deck(tmp_path, card: str) -> fg.io.BdfDeck:
    """One CBEAM (or CBAR) clamped at grid 1; three subcases free only the axial, only the torsional,
    and only the plane-1 bending (v = z: T3, R2) DOFs of grid 2."""
    prop = (f"PBEAM   1       1       {A:<8.1e}{I1:<8.1e}{I2:<8.1e}0.0     {J:<8.1e}\n"
            "+       \n+       0.0     0.0\n") if card == "CBEAM" else \
        f"PBAR    1       1       {A:<8.1e}{I1:<8.1e}{I2:<8.1e}{J:<8.1e}\n"
    text = ("SOL 103\nCEND\nMETHOD = 1\nSUBCASE 1\n  SPC = 1\nSUBCASE 2\n  SPC = 2\nSUBCASE 3\n  SPC = 3\n"
            "BEGIN BULK\nPARAM   COUPMASS1\nEIGRL   1                       2\n"
            "GRID    1               0.0     0.0     0.0\nGRID    2               1.0     0.0     0.0\n"
            f"{card:<8}1       1       1       2       0.0     0.0     1.0\n" + prop +
            f"MAT1    1       {E:<8.2e}        {NU:<8}{RHO:<8}\n"
            "SPC1    1       123456  1\nSPC1    1       23456   2\n"
            "SPC1    2       123456  1\nSPC1    2       12356   2\n"
            "SPC1    3       123456  1\nSPC1    3       1246    2\nENDDATA\n")
    path = tmp_path / f"{card.lower()}.bdf"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path)


def first_frequencies(deck) -> dict[str, np.ndarray]:
    return {name: r.modes.frequencies_hz for name, r in solve_deck(deck, n_modes=2).items()}


def cubic_bending_hz(EI: float, m: float) -> np.ndarray:
    """Clamped-free single Euler element, tip (w, theta): consistent (cubic) mass, no rotary inertia."""
    K = EI / L**3 * np.array([[12.0, -6 * L], [-6 * L, 4 * L**2]])
    M = m / 420 * np.array([[156.0, -22 * L], [-22 * L, 4 * L**2]])
    return np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)) / (2 * np.pi)


def test_cbeam_coupled_mass_lumps_axial_and_torsion_keeps_cubic_bending(tmp_path):
    deck = cantilever_deck(tmp_path, "CBEAM")
    assert deck.mass == "consistent" and deck.model.beams[0].mass == "consistent-bending"
    f = first_frequencies(deck)
    m, G = RHO * A * L, E / (2 * (1 + NU))
    assert f["subcase_1"][0] == pytest.approx(np.sqrt(E * A / L / (m / 2)) / (2 * np.pi), rel=1e-9)  # not m/3
    assert f["subcase_2"][0] == pytest.approx(np.sqrt(G * J / L / (RHO * (I1 + I2) * L / 2)) / (2 * np.pi),
                                              rel=1e-9)
    assert f["subcase_3"] == pytest.approx(cubic_bending_hz(E * I1, m), rel=1e-9)  # plane 1 (v = z): I1


def test_cbar_coupled_mass_stays_consistent(tmp_path):
    """CBAR under COUPMASS: linear axial mass (as read_bdf has always built it; no deck with CBAR axial
    motion and an f06 has been found to check it), cubic bending, no torsional inertia: the torsion-only
    subcase has no mass on its free DOFs, which is an error, not an empty list of modes."""
    deck = cantilever_deck(tmp_path, "CBAR")
    with pytest.raises(fg.errors.ModelError, match="free DOFs carry no mass"):
        solve_deck(deck, n_modes=2, configurations=["subcase_2"])
    f = {name: r.modes.frequencies_hz
         for name, r in solve_deck(deck, n_modes=2, configurations=["subcase_1", "subcase_3"]).items()}
    assert f["subcase_1"][0] == pytest.approx(np.sqrt(3 * E / RHO) / L / (2 * np.pi), rel=1e-9)
    assert f["subcase_3"] == pytest.approx(cubic_bending_hz(E * I1, RHO * A * L), rel=1e-9)
