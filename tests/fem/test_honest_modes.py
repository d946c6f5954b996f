"""Modes that are not elastic modes say so (issue 32, "honest results"): an unstable state's
negative eigenvalues, mechanisms of a supported structure, and a model whose values are in another
unit system than the one it was read in."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import FlexGVTWarning

E, L, B, H = 70e9, 2.0, 0.05, 0.01


def _column(section=None, n: int = 20):
    model = fg.Model()
    ids = model.add_nodes(np.c_[np.zeros(n + 1), np.zeros(n + 1), np.linspace(0.0, L, n + 1)])
    model.add_beams(np.c_[ids[:-1], ids[1:]], material=fg.Material("Al", E=E, nu=0.33, rho=2700.0),
                    section=section or fg.RectangularSection(width=B, height=H), orientation=(1.0, 0.0, 0.0))
    return model, ids


def _quiet(function, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = function(*args, **kwargs)
    return out, [str(w.message) for w in caught if issubclass(w.category, FlexGVTWarning)]


def test_a_column_compressed_past_buckling_is_unstable_not_an_elastic_mode():
    model, ids = _column()
    p_cr = np.pi ** 2 * E * (B * H ** 3 / 12) / (4 * L ** 2)  # clamped-free Euler load, weak axis
    cfg = fg.Configuration("past buckling", fixed={ids[0]: "123456"},
                           forces=(fg.NodalLoad(ids[-1], force=(0.0, 0.0, -1.5 * p_cr)),))
    state = fg.solve_static(model, cfg)  # the straight column: an equilibrium, an unstable one
    modes, said = _quiet(fg.solve_modes, state, n_modes=4)
    assert modes.frequencies_hz[0] < 0
    assert modes.labels[0].startswith("unstable 1") and "OOP" not in modes.labels[0].split("(")[0]
    assert not any(lab.startswith("unstable") for lab, f in zip(modes.labels, modes.frequencies_hz) if f > 0)
    assert len(modes.cautions) == 1 and "unstable" in modes.cautions[0] and "buckled" in modes.cautions[0]
    assert said == list(modes.cautions)
    # Below the buckling load the same column is stable and says nothing.
    below = fg.Configuration("below", fixed={ids[0]: "123456"},
                             forces=(fg.NodalLoad(ids[-1], force=(0.0, 0.0, -0.5 * p_cr)),))
    modes, said = _quiet(fg.solve_modes, fg.solve_static(model, below), n_modes=4)
    assert modes.frequencies_hz.min() > 0 and not modes.cautions and not said


def test_a_missing_stiffness_on_a_clamped_beam_is_a_mechanism_not_a_rigid_mode():
    # A section typo: Iz = 5e-81 leaves one bending plane with no stiffness on a clamped beam.
    typo = fg.GeneralSection(A=B * H, Iy=B * H ** 3 / 12, Iz=5e-81, J=1e-9)
    model, ids = _column(typo)
    cfg = fg.Configuration("clamped", fixed={ids[0]: "123456"})
    modes, said = _quiet(fg.solve_modes, fg.solve_static(model, cfg), n_modes=6)
    zero = np.abs(modes.frequencies_hz) <= 1e-6 * np.abs(modes.frequencies_hz).max()
    assert zero.any()
    assert all(lab.startswith("mechanism") for lab in np.array(modes.labels)[zero])
    assert not any(lab.startswith("RB") for lab in modes.labels)
    assert len(said) == 1 and "mechanism" in said[0] and "node " in said[0] and "rigid-body motion(s)" in said[0]
    # The same beam with its section right has none.
    model, ids = _column()
    modes, said = _quiet(fg.solve_modes, fg.solve_static(model, cfg), n_modes=6)
    assert not modes.cautions and not said


def test_a_free_structure_keeps_its_rigid_modes_without_a_word():
    model, ids = _column()
    modes, said = _quiet(fg.solve_modes, fg.solve_static(model, fg.Configuration("free")), n_modes=9)
    assert (modes.frequencies_hz == 0).sum() == 6 and not modes.cautions and not said
    assert sum(lab.startswith("RB") for lab in modes.labels) == 6


@pytest.mark.parametrize("n_modes", [4])
def test_a_mm_model_read_as_si_is_named(n_modes):
    # The beam in mm-t-s values (mm, N/mm^2, t/mm^3) solved as if they were SI.
    model = fg.Model()
    ids = model.add_nodes(np.c_[np.zeros(21), np.linspace(0.0, 2000.0, 21), np.zeros(21)])
    model.add_beams(np.c_[ids[:-1], ids[1:]], material=fg.Material("Al", E=70e3, nu=0.33, rho=2.7e-9),
                    section=fg.RectangularSection(width=50.0, height=10.0), orientation=(0.0, 0.0, 1.0))
    cfg = fg.Configuration("1 g", fixed={ids[0]: "123456"}, gravity=1.0)
    state, said = _quiet(fg.solve_static, model, cfg)
    assert any("mm-t-s" in c for c in state.cautions) and said == list(state.cautions)


def test_solve_prints_the_cautions_once_with_every_bracket_shown(tmp_path):
    from typer.testing import CliRunner

    from flexgvt.cli.main import app

    lines = ["SOL 103", "CEND", "SUBCASE 1", "  SPC = 1", "  LOAD = 10", "  METHOD = 1", "BEGIN BULK",
             "EIGRL,1,,,4", "MAT1,1,70000.,,0.33,2.7-9", "PBAR,1,1,500.,4166.7,104166.7,10000.",
             "GRAV,10,,9810.,0.,0.,-1.", "SPC1,1,123456,1"]
    lines += [f"GRID,{i + 1},,0.,{100.0 * i},0." for i in range(21)]
    lines += [f"CBAR,{i + 1},1,{i + 1},{i + 2},0.,0.,1." for i in range(20)] + ["ENDDATA"]
    deck = tmp_path / "mm.bdf"
    deck.write_text("\n".join(lines) + "\n")
    out = CliRunner().invoke(app, ["solve", str(deck), "--json", str(tmp_path / "r.json")], env={"COLUMNS": "400"})
    assert out.exit_code == 0, out.output
    text = " ".join(out.output.split())  # the console wraps at its width
    assert text.count("look like another unit system") == 1 and 'units = "mm-t-s" under [model]' in text
    import json
    saved = json.loads((tmp_path / "r.json").read_text())["configurations"]["subcase_1"]
    assert any("mm-t-s" in c for c in saved["cautions"])
    out = CliRunner().invoke(app, ["solve", str(deck), "--units", "mm-t-s"], env={"COLUMNS": "400"})
    assert out.exit_code == 0 and "warning" not in out.output


def test_the_built_in_cases_look_like_si():
    # The HALE wing's stiffness-defined beam has an equivalent density of 0.75 kg/m^3: not a unit slip.
    for name in ("cantilever_strip", "strip_366", "hale_wing", "xhale"):
        case = getattr(fg.cases, name)()
        for config in case.configurations.values():
            state, said = _quiet(fg.solve_static, case.model, config)
            assert not any("unit system" in c for c in state.cautions), (name, config.name, said)


def _plate(tilt_deg: float, nx: int = 20, ny: int = 4):
    """A 1 m x 0.2 m x 2 mm aluminium plate of quads, turned by tilt_deg about x (90: vertical, in
    the x-z plane, where cos(90 deg) = 6e-17 turns the massless drilling rotations into global R2
    with round-off masses of 1e-40 of their rotary inertia)."""
    model = fg.Model("plate")
    x, y = np.linspace(0.0, 1.0, nx + 1), np.linspace(0.0, 0.2, ny + 1)
    Y, X = np.meshgrid(y, x, indexing="ij")
    a = np.radians(tilt_deg)
    ids = model.add_nodes(np.c_[X.ravel(), Y.ravel() * np.cos(a), Y.ravel() * np.sin(a)]).reshape(ny + 1, nx + 1)
    quads = [[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]] for j in range(ny) for i in range(nx)]
    model.add_shells(quads, material=fg.Material("Al", E=E, nu=0.33, rho=2700.0), thickness=0.002)
    return model, ids


def test_a_vertical_shell_plate_has_the_flat_plates_modes_free_and_damped():
    """Round-off masses on rotated drilling DOFs once set the eigen-solvers' scale (largest K_ii /
    M_ii, 1e45 instead of 1e13): the free-free vertical plate came out with -6e15 Hz 'unstable'
    modes, and a clamped one with a damper had five 0 Hz 'mechanisms' instead of its modes."""
    flat, _ = _quiet(fg.solve_modes, fg.solve_static(_plate(0.0)[0], fg.Configuration("free")), 10)
    for tilt in (90.0, 37.0):
        modes, notes = _quiet(fg.solve_modes, fg.solve_static(_plate(tilt)[0], fg.Configuration("free")), 10)
        assert not notes
        assert np.count_nonzero(modes.frequencies_hz == 0.0) == 6
        np.testing.assert_allclose(modes.frequencies_hz[6:], flat.frequencies_hz[6:], rtol=1e-7)
    results = {}
    for tilt in (0.0, 90.0):
        model, ids = _plate(tilt)
        tip = int(ids[0, -1])
        model.add_spring(tip, None, stiffness=500.0, damping=0.05)  # translations and rotations
        state = fg.solve_static(model, fg.Configuration("clamped", fixed={int(n): "123456" for n in ids[:, 0]}))
        damped, notes = _quiet(fg.solve_modes, state, 5)
        undamped, _ = _quiet(fg.solve_modes, state, 5, damped=False)
        assert not notes and not any("mechanism" in lab for lab in damped.labels)
        assert damped.damping_ratio.max() < 0.01
        np.testing.assert_allclose(damped.frequencies_hz, undamped.frequencies_hz, rtol=1e-4)  # zeta^2 / 2
        results[tilt] = damped.frequencies_hz
    np.testing.assert_allclose(results[90.0], results[0.0], rtol=1e-7)


def test_real_roots_of_the_damped_problem_are_labelled_overdamped_not_given_a_class():
    """A 5 N m s/rad damper on the tip node's rotations (scalar damping: all six components) acts on
    DOFs with almost no mass: two real roots near k / c (the spring's 500 N m/rad over 5 N m s/rad:
    16 Hz) appear among the modes. They are 'overdamped k', named in a caution, and the elastic
    modes keep their classes' numbering (the first torsion is '1 T', not '2 T')."""
    model, ids = _plate(0.0)
    model.add_spring(int(ids[0, -1]), None, stiffness=500.0, damping=5.0)
    state = fg.solve_static(model, fg.Configuration("clamped", fixed={int(n): "123456" for n in ids[:, 0]}))
    modes, notes = _quiet(fg.solve_modes, state, 6)
    slow = [k for k, lab in enumerate(modes.labels) if lab.startswith("overdamped")]
    assert [modes.labels[k] for k in slow] == ["overdamped 1", "overdamped 2"]
    np.testing.assert_allclose(modes.damping_ratio[slow], 1.0, atol=1e-9)
    assert all(100 / (2 * np.pi) < modes.frequencies_hz[k] < 1.1 * 100 / (2 * np.pi) for k in slow)
    assert "1 T" in modes.labels and "2 T" not in modes.labels
    assert len(notes) == 1 and "overdamped" in notes[0]
    from flexgvt.correlation.pairing import labels_compatible
    assert not labels_compatible("1 T", "overdamped 1")
