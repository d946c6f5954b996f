"""Model-level shell data: materials, properties, laminates, shell groups and their checks."""

import numpy as np
import pytest

from flexgvt.errors import ModelError
from flexgvt.model import (AnisotropicMaterial, Laminate, Material, Model, OrthotropicMaterial, Ply, RodSection,
                           ShellProperty)

AL = Material("al", E=70e9, rho=2700.0, nu=0.33)
CFRP = OrthotropicMaterial("cfrp", 150e9, 9e9, 0.3, 5e9, rho=1600.0)


def square(n=2):
    m = Model("plate")
    xy = [[i, j, 0.0] for j in range(n + 1) for i in range(n + 1)]
    m.add_nodes(np.array(xy, float) * 0.1)
    quads = [[j * (n + 1) + i + 1, j * (n + 1) + i + 2, (j + 1) * (n + 1) + i + 2, (j + 1) * (n + 1) + i + 1]
             for j in range(n) for i in range(n)]
    return m, np.array(quads)


def test_design_api_line_material_and_thickness():
    m, quads = square()
    ids = m.add_shells(quads, material=AL, thickness=0.002, name="skin")
    assert ids.tolist() == [1, 2, 3, 4] and m.n_shells == 4
    g = m.shells[m.shell_group("skin")]
    assert g.property == ShellProperty("skin", 0.002, AL, AL, shear=AL)
    assert g.property.shear_ratio == pytest.approx(5 / 6) and g.mass == "lumped"
    assert g.theta.tolist() == [0.0] * 4 and g.material_axis is None and g.corner_thickness is None
    # beams and shells share one element numbering
    assert m.add_beams([[1, 2]], AL, RodSection(1e-4)).tolist() == [5]


def test_groups_revision_copy_and_set():
    m, quads = square()
    lam = Laminate("lam", [Ply(CFRP, 1e-4, 0.0), Ply(CFRP, 1e-4, 90.0)], lam="sym")
    r0 = m.revision
    m.add_shells(quads[:2], lam, name="a", theta=[0.0, 30.0], zoffs=0.001, mass="consistent")
    m.add_shells(quads[2:, :3], material=AL, thickness=0.001, name="b", corner_thickness=[[1e-3, 2e-3, 3e-3]] * 2)
    assert m.revision == r0 + 2 and lam.lam == "SYM" and lam.thickness == pytest.approx(4e-4)
    c = m.copy()
    c.set_shell_group(0, Laminate("thicker", [Ply(CFRP, 2e-4)]))
    assert m.shells[0].property is lam and c.shells[0].property.name == "thicker" and c.revision == m.revision + 1
    assert m.shells[0].theta.tolist() == [0.0, 30.0] and m.shells[1].nodes.shape == (2, 3)
    with pytest.raises(ModelError, match="a Laminate cannot become a ShellProperty"):
        c.set_shell_group(0, ShellProperty.isotropic(AL, 0.001))
    with pytest.raises(ModelError, match="2 shell groups are named 'x'"):
        m.add_shells(quads[:1], material=AL, thickness=1e-3, name="x")
        m.add_shells(quads[1:2], material=AL, thickness=1e-3, name="x")
        m.shell_group("x")


@pytest.mark.parametrize("elements, match", [
    ([[1, 2, 2, 4]], r"element 1 \(nodes \[1, 2, 2, 4\]\) repeats a node"),
    ([[1, 2, 99]], "node 99 does not exist"),
    ([[1, 2, 3]], "has zero area"),
    ([[1, 2, 5, 4], [1, 6, 5, 8]], r"quadrilateral 2 \(nodes \[1, 6, 5, 8\]\) is not convex"),
    ([[1, 2, 5, 4, 7]], r"shape \(n, 3\) or \(n, 4\)"),
])
def test_bad_elements_are_named(elements, match):
    m, _ = square()
    with pytest.raises(ModelError, match=match):
        m.add_shells(elements, material=AL, thickness=0.001)


def test_bad_properties_say_what_to_do():
    m, quads = square()
    with pytest.raises(ModelError, match="thickness=0 must be a finite positive"):
        m.add_shells(quads, material=AL, thickness=0)
    with pytest.raises(ModelError, match="give property=.*or material= and thickness="):
        m.add_shells(quads, material=AL)
    with pytest.raises(ModelError, match=r"corner_thickness of element 2 \(nodes \[2, 3, 6, 5\]\)"):
        m.add_shells(quads[:2], material=AL, thickness=1e-3, corner_thickness=[[1e-3] * 4, [1e-3, -1e-3, 1e-3, 1e-3]])
    with pytest.raises(ModelError, match=r"element 1 \(nodes \[1, 2, 5, 4\]\) is \[0.0, 0.0, 0.0, 0.0\]; each must be "
                       ">= 0 and at least one positive"):
        m.add_shells(quads[:1], material=AL, thickness=1e-3, corner_thickness=[[0.0] * 4])
    tapered = m.add_shells(quads[:1], material=AL, thickness=1e-3, corner_thickness=[[0.0, 0.0, 1e-3, 1e-3]])
    assert m.shells[-1].corner_thickness.tolist() == [[0.0, 0.0, 1e-3, 1e-3]] and len(tapered) == 1
    with pytest.raises(ModelError, match="laminate 'l': ply 2 has no material"):
        Laminate("l", [Ply(CFRP, 1e-4), Ply(None, 1e-4)])
    with pytest.raises(ModelError, match="laminate 'l': ply 1 thickness=0.0"):
        Laminate("l", [Ply(CFRP, 0.0)])
    with pytest.raises(ModelError, match="has no plies"):
        Laminate("l", [])
    with pytest.raises(ModelError, match="no membrane and no bending material"):
        ShellProperty("p", 0.001, None)
    with pytest.raises(ModelError, match="plies of MAT8 go in a Laminate"):
        ShellProperty("p", 0.001, CFRP)
    with pytest.raises(ModelError, match="not positive semi-definite"):
        AnisotropicMaterial("m2", 1e9, 5e9, 0.0, 1e9, 0.0, 1e9)
    with pytest.raises(ModelError, match="not a stable ply"):
        OrthotropicMaterial("m8", 1e9, 100e9, 0.5, 1e9)
    with pytest.raises(ModelError, match="has no thickness; give corner_thickness"):
        m.add_shells(quads, ShellProperty("nothick", None, AL, AL))
    with pytest.raises(ModelError, match="theta or material_axis, not both"):
        m.add_shells(quads, material=AL, thickness=1e-3, theta=10.0, material_axis=(1, 0, 0))
