"""A warped quad (corners off one plane) is accepted, as Nastran's CQUAD4 is, and an extremely
warped one is named in a warning (model.shells.WARP_LIMIT, 2h / sqrt(A) = 0.2)."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.model import Material
from flexgvt.model.shells import WARP_LIMIT, quad_warp

AL = Material("al", 70e9, 2700.0, nu=0.3)


def twisted_beam(nx, ny):
    """MacNeal & Harder's twisted beam (L 12, width 1.1, 90 deg twist) as an fg.Model of nx x ny quads."""
    s, t = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1))
    xyz = np.c_[12 * s.ravel(), ((t - 0.5) * 1.1 * np.cos(np.pi / 2 * s)).ravel(),
                ((t - 0.5) * 1.1 * np.sin(np.pi / 2 * s)).ravel()]
    ids = np.arange(1, s.size + 1).reshape(s.shape)
    model = fg.Model("twisted")
    model.add_nodes(xyz, ids=ids.ravel())
    quads = np.array([[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]]
                      for j in range(ny) for i in range(nx)])
    return model, quads


def test_warp_of_a_quad():
    """0 for a flat quad (any shape, any orientation); a unit square with corners at +-h: 2h."""
    flat = np.array([[[0, 0, 0], [2, 0.1, 0], [2.2, 1.5, 0], [-0.1, 1.2, 0]]], float)
    turn = np.linalg.qr(np.random.default_rng(1).standard_normal((3, 3)))[0]
    assert quad_warp(flat @ turn.T)[0] < 1e-14
    h = 0.07
    square = np.array([[[0, 0, h], [1, 0, -h], [1, 1, h], [0, 1, -h]]], float)
    assert quad_warp(square)[0] == pytest.approx(2 * h, rel=1e-12)


@pytest.mark.parametrize("nx, ny", [(12, 2), (3, 1)])
def test_the_twisted_beam_meshes_pass(nx, ny):
    """MacNeal-Harder's 12 x 2 mesh (warp 0.049; within 1 % of both references) and a 3 x 1 one
    (0.138, 30 deg of twist per element; its tip deflections 1.6 % and 2.8 % off) add without a warning."""
    model, quads = twisted_beam(nx, ny)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model.add_shells(quads, material=AL, thickness=0.32)
    assert quad_warp(model.xyz[model.index_of(quads.ravel()).reshape(quads.shape)]).max() < WARP_LIMIT


def test_an_extremely_warped_quad_is_named():
    """The twisted beam as two quads along (45 deg of twist each: warp 0.17) passes; a unit square
    beside a quad with one corner lifted by 0.6 of its side (warp 0.265, corners 0.138 off their mean
    plane) is named with its warp and corner height."""
    model, quads = twisted_beam(2, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model.add_shells(quads, material=AL, thickness=0.32)
    model = fg.Model("warped")
    model.add_nodes([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0.6], [2, 1, 0]])
    expected = (r"add_shells \(skin\): 1 quadrilateral\(s\) warped beyond 2h/sqrt\(A\) = 0.2, the most element 2 "
                r"\(nodes \[2, 5, 6, 3\]\): 0.265, its corners 0.138 m off")
    with pytest.warns(fg.errors.FlexGVTWarning, match=expected):
        model.add_shells([[1, 2, 3, 4], [2, 5, 6, 3]], material=AL, thickness=0.002, name="skin")
    assert model.n_shells == 2  # accepted: the warning is advice
