"""CBAR/CBEAM offsets (WA/WB), pin flags 456 and CBUSH between distinct points, against closed
forms: each becomes an end node on a rigid link, as Nastran's rigid offsets, released ends and
CBUSH spring-location arms are."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import solve_deck

E, NU, RHO = 7.0e10, 0.3, 2700.0
B, H, L = 0.05, 0.01, 1.0  # PBARL BAR: DIM1 along element z, DIM2 along y
I_Y = B * H**3 / 12  # bending in x-z (H along z with v along y)


def read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path)


def strip_deck(n, extra="", first_bar_tail="", offsets="", case="SUBCASE 1\n  SPC = 1\n  LOAD = 2\n"):
    """n CBARs along x (v along y, so the 10 mm DIM2... H lies along z), clamped at grid 1."""
    lines = ["SOL 101", "CEND", case.rstrip(), "BEGIN BULK", f"MAT1,1,{E},,{NU},{RHO}", "PBARL,5,1,,BAR",
             f",{H},{B}"]
    for i in range(n + 1):
        lines.append(f"GRID,{i + 1},,{L * i / n:.6f},0.,0.")
    for i in range(n):
        tail = first_bar_tail if i == 0 else ""
        lines.append(f"CBAR,{101 + i},5,{i + 1},{i + 2},0.,1.,0.{tail}")
        if offsets:
            lines.append(offsets)
    lines.append("SPC1,1,123456,1")
    return "\n".join(lines) + "\n" + extra + "ENDDATA\n"


def test_eccentric_axial_load_bends_the_offset_beam(tmp_path):
    """Grids on z = 0, the bar on z = e (WA = WB = (0, 0, e)): an axial tip force P on the grid
    line bends the bar by the moment P e, tip deflection P e L^2 / (2 E I) (linear)."""
    e, P = 0.02, 100.0
    path = tmp_path / "offset.bdf"
    path.write_text(strip_deck(10, offsets=f",,,0.,0.,{e},0.,0.,{e}", extra=f"FORCE,2,11,,{P},1.,0.,0.\n"))
    deck = read(path)
    assert len(deck.end_nodes) == 20 and all(n > 11 for n in deck.end_nodes.values())
    cfg = deck.configurations["subcase_1"]
    state = fg.solve_linear_static(deck.model, cfg)
    tip = deck.model.index_of([11])[0]
    assert state.displacements[tip, 2] == pytest.approx(P * e * L**2 / (2 * E * I_Y), rel=1e-9)
    # The bar's end nodes sit on z = e; the clamped grid's rigid arm holds the bar's root.
    ends = deck.model.index_of([deck.end_nodes[("CBAR", 101, "A")], deck.end_nodes[("CBAR", 110, "B")]])
    np.testing.assert_allclose(deck.model.xyz[ends], [[0, 0, e], [L, 0, e]], atol=1e-12)


def test_offset_cantilever_has_the_plain_cantilever_frequencies(tmp_path):
    """A rigid offset at a clamped root and a massless tip arm change no frequency."""
    freqs = []
    for offsets in ("", ",,,0.,0.03,0.01,0.,0.03,0.01"):
        path = tmp_path / f"cant{len(offsets)}.bdf"
        path.write_text(strip_deck(20, offsets=offsets, case="SUBCASE 1\n  SPC = 1\n  METHOD = 1\n",
                                   extra="EIGRL,1,,,6\n"))
        freqs.append(next(iter(solve_deck(read(path)).values())).modes.frequencies_hz[:6])
    np.testing.assert_allclose(freqs[1], freqs[0], rtol=1e-9)
    beta = 1.8751040687
    f1 = beta**2 / (2 * np.pi * L**2) * np.sqrt(E * I_Y / (RHO * B * H))
    assert freqs[0][0] == pytest.approx(f1, rel=2e-3)  # the mesh and shear flexibility, not the offsets


def test_pin_flag_456_makes_a_pinned_end(tmp_path):
    """A bar clamped at both grids whose first element releases its rotations at end A (PA = 456)
    vibrates as a pinned-clamped beam: (beta L)^2 = 15.4182 against 22.3733 clamped-clamped."""
    n = 40
    text = strip_deck(n, first_bar_tail="\n,456", case="SUBCASE 1\n  SPC = 1\n  METHOD = 1\n",
                      extra=f"SPC1,1,123456,{n + 1}\nEIGRL,1,,,4\n")
    path = tmp_path / "pinned.bdf"
    path.write_text(text)
    deck = read(path)
    assert [link.components for link in deck.model.rigid_links] == ["123"]
    modes = next(iter(solve_deck(deck).values())).modes
    scale = np.sqrt(E * I_Y / (RHO * B * H)) / (2 * np.pi * L**2)
    bending_xz = [f for f, shape in zip(modes.frequencies_hz, modes.shapes) if np.abs(shape[:, 2]).max() > 0.5 *
                  np.abs(shape[:, :3]).max()]
    assert bending_xz[0] == pytest.approx(15.4182 * scale, rel=2e-3)


def test_cbush_between_distinct_points_acts_at_its_spring_location(tmp_path):
    """Grid A clamped, grid B at distance d along a skew line, a CBUSH between them (S = 0.5,
    element x from A to B, y from v): a force F along element y at B moves B by
    F / K2 + F d^2 / (4 K6) (the spring at mid-span, rigid arms on both sides)."""
    d, K2, K6, F = 0.4, 2.0e5, 3.0e3, 50.0
    c, s = np.cos(0.5), np.sin(0.5)
    ey = np.array([-s, c, 0.0])
    text = "\n".join(["SOL 101", "CEND", "SUBCASE 1", "  SPC = 1", "  LOAD = 2", "BEGIN BULK",
                      "GRID,1,,0.,0.,0.", f"GRID,2,,{d * c:.12f},{d * s:.12f},0.",
                      f"CBUSH,7,8,1,2,{ey[0]:.12f},{ey[1]:.12f},0.", f"PBUSH,8,K,1.e9,{K2},1.e9,1.e7,1.e7,{K6}",
                      "SPC1,1,123456,1", f"FORCE,2,2,,{F},{ey[0]:.12f},{ey[1]:.12f},0.", "ENDDATA"]) + "\n"
    path = tmp_path / "bush.bdf"
    path.write_text(text)
    deck = read(path)
    state = fg.solve_linear_static(deck.model, deck.configurations["subcase_1"])
    b = deck.model.index_of([2])[0]
    along = state.displacements[b, :3] @ ey  # v = ey: element y (Nastran z = x cross v, y = z cross x)
    assert along == pytest.approx(F / K2 + F * d**2 / (4 * K6), rel=1e-6)
    # Round trip through a compact deck keeps the arms.
    out = fg.io.write_bdf(deck.model, tmp_path / "bush_compact.bdf", configurations=list(deck.configurations.values()))
    again = read(out)
    st2 = fg.solve_linear_static(again.model, next(iter(again.configurations.values())))
    np.testing.assert_allclose(st2.displacements[again.model.index_of([2])[0]], state.displacements[b], rtol=1e-9)


def test_mpc_lever_from_bulk_data_and_back(tmp_path):
    """Two equal parallel cantilevers, tip deflections tied by MPC w_B = 2 w_A (the dependent term
    on a grid whose CD is turned 90 degrees about x: its component 2 is basic z): a tip force P
    on A gives w_A = P / (5 k), 1/k = L^3 / (3 E I) + L / (kappa G A) (PBARL BAR keeps shear, 5/6)."""
    n, P = 10, 3.0
    lines = ["SOL 101", "CEND", "MPC = 7", "SUBCASE 1", "  SPC = 1", "  LOAD = 2", "BEGIN BULK",
             f"MAT1,1,{E},,{NU},{RHO}", "PBARL,5,1,,BAR", f",{H},{B}", "CORD2R,4,0,0.,0.,0.,0.,-1.,0.", ",1.,0.,0."]
    for i in range(n + 1):
        lines.append(f"GRID,{i + 1},,{L * i / n:.6f},0.,0.")
        lines.append(f"GRID,{101 + i},,{L * i / n:.6f},0.2,0.{',4' if i == n else ''}")
    for i in range(n):
        lines.append(f"CBAR,{i + 1},5,{i + 1},{i + 2},0.,1.,0.")
        lines.append(f"CBAR,{101 + i},5,{101 + i},{102 + i},0.,1.,0.")
    lines += ["SPC1,1,123456,1,101", f"MPC,7,{101 + n},2,1.,{n + 1},3,-2.", f"MPC,7,{100 + n},4,1.,{n},4,-1.",
              f"FORCE,2,{n + 1},,{P},0.,0.,-1.",
              "MPC,9,1,1,1.,2,1,-1.", "ENDDATA"]
    path = tmp_path / "lever.bdf"
    path.write_text("\n".join(lines) + "\n")
    deck = read(path)
    assert [c.terms for c in deck.model.constraints] == [((101 + n, 3, 1.0), (n + 1, 3, -2.0)),
                                                         ((100 + n, 4, 1.0), (n, 4, -1.0))]
    assert any("MPC set(s) [9] selected by no subcase" in note for note in deck.notes)
    state = fg.solve_linear_static(deck.model, deck.configurations["subcase_1"])
    k = 1 / (L**3 / (3 * E * I_Y) + L / (5 / 6 * E / (2 * (1 + NU)) * B * H))
    wa, wb = state.displacements[deck.model.index_of([n + 1, 101 + n]), 2]
    assert wa == pytest.approx(-P / (5 * k), rel=1e-9) and wb == pytest.approx(2 * wa, rel=1e-12)
    out = fg.io.write_bdf(deck.model, tmp_path / "lever_compact.bdf", configurations=list(deck.configurations.values()))
    again = read(out)
    assert again.model.constraints == deck.model.constraints
