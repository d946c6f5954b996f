"""fg.cases.wingbox: the built-up shell box of the original work (docs/method.md section 5 case 4): its
mass by hand, its first bending and torsion frequencies against closed forms (Euler-Bernoulli
cantilever; Bredt's torsion constant of the thin-walled box)."""

import numpy as np
import pytest

import flexgvt as fg


def test_mass_groups_and_configurations():
    """Skins 2 x 16 x 1 x 8 mm, spars 2 x 16 x 0.16 x 5 mm, 32 ribs 1 x 0.16 x 2 mm at 2851 kg/m^3:
    832.036 kg bare; the carried mass adds 2 x 16 x 7.85 kg."""
    bare = fg.cases.wingbox(element_size=0.25, carried_mass=False)
    case = fg.cases.wingbox(element_size=0.25)
    plates = 2851.0 * (2 * 16 * 1 * 0.008 + 2 * 16 * 0.16 * 0.005 + 32 * 1 * 0.16 * 0.002)
    assert fg.mass_properties(bare.model).mass == pytest.approx(plates, rel=1e-12)
    props = fg.mass_properties(case.model)
    assert props.mass == pytest.approx(plates + 2 * 16 * 7.85, rel=1e-12)
    ribs = 32 * 2851.0 * 0.16 * 0.002  # at y = 0.5 ... 16 (the root is clamped: no rib there), mean 8.25
    np.testing.assert_allclose(props.cg, [0.5, 8.0 + ribs * 0.25 / props.mass, 0.0], atol=1e-9)
    assert [g.name for g in case.model.shells] == ["skin_top", "skin_bottom", "spar_front", "spar_rear", "ribs"]
    assert set(case.configurations) == {"unloaded", "minus_1g", "plus_2_5g", "combined"}
    with pytest.raises(fg.errors.ModelError, match="rib pitch"):
        fg.cases.wingbox(rib_pitch=0.3)


def test_unloaded_frequencies_against_closed_forms():
    """First bending: 1.8751^2 / (2 pi L^2) sqrt(EI / m) with I of the skins and spars about the
    box's mid-plane (0.7179 Hz); first torsion: 1 / (4 L) sqrt(G J / I_p) with Bredt's
    J = 4 A^2 / (sum of wall length / thickness) and the polar inertia of skins, spars, NSM and
    smeared ribs (17.41 Hz). Measured at 0.2 m: 0.718 Hz (+0.0 %) and 17.17 Hz (-1.4 %: the
    section distorts a little between ribs)."""
    case = fg.cases.wingbox(element_size=0.2)
    modes = fg.solve_modes(fg.solve_static(case.model, case.configurations["unloaded"]), 6)
    E, G, L = 69e9, 69e9 / 2.66, 16.0
    inertia = 2 * 1 * 0.008 * 0.08**2 + 2 * 0.005 * 0.16**3 / 12
    m = fg.mass_properties(case.model).mass / L
    f_bending = 1.8751**2 / (2 * np.pi * L**2) * np.sqrt(E * inertia / m)
    J = 4 * (1 * 0.16) ** 2 / (2 * 1 / 0.008 + 2 * 0.16 / 0.005)
    skin = 0.008 * 2851 + 7.85
    Ip = (2 * skin * (1 / 12 + 0.08**2) + 2 * 0.005 * 0.16 * 2851 * (0.25 + 0.16**2 / 12)
          + 32 * 0.16 * 0.002 * 2851 / L * (1 + 0.16**2) / 12)
    f_torsion = np.sqrt(G * J / Ip) / (4 * L)
    assert modes.labels[0] == "1 OOP" and modes.frequencies_hz[0] == pytest.approx(f_bending, rel=0.01)
    k = modes.labels.index("1 T")
    assert modes.frequencies_hz[k] == pytest.approx(f_torsion, rel=0.03)


def test_a_post_buckled_skin_mode_is_labelled_local():
    """At -1 g the coarse box's bottom skin buckles (0.927 g at 0.25 m); on its post-buckled path the
    12th mode (51.0 Hz, measured) is a skin panel's own bending: labelled LOCAL (with OOP as its
    second class), not a global OOP/IP/T mode; the unloaded box's first 12 modes are all global."""
    from flexgvt.fem.static import StaticSettings

    case = fg.cases.wingbox(element_size=0.25)
    with pytest.warns(fg.errors.FlexGVTWarning, match="post-buckled path"):
        buckled = fg.solve_static(case.model, case.configurations["minus_1g"],
                                  settings=StaticSettings(buckling="continue"))
    assert "skin_bottom" in buckled.instability.where
    labels = fg.solve_modes(buckled, 12).labels
    local = [lab for lab in labels if "LOCAL" in lab]
    assert local == ["1 LOCAL/OOP"], labels
    unloaded = fg.solve_modes(fg.solve_static(case.model, case.configurations["unloaded"]), 12).labels
    assert not any("LOCAL" in lab for lab in unloaded), unloaded
