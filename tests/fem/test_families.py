"""The element-family protocol: every family of a System is a fem.families.Family, and System's
residual, tangent, mass and damping are the families' element terms scattered onto the DOFs
(the assembler adds nothing of its own but the nodal loads)."""

import numpy as np
import scipy.sparse as sp

import flexgvt as fg
from fem_builders import perturbed_state, straight_beam
from flexgvt.fem.families import Family, element_dofs
from flexgvt.fem.system import System


def _all_families():
    """A free strip with a tip mass, a grounded spring and dashpot, and two heavy cords (one along an element)."""
    model, ids = straight_beam(8)
    model.add_mass(int(ids[-1]), 0.05, offset=(0.01, 0.0, 0.0))
    model.add_spring(int(ids[3]), None, stiffness=[0, 0, 50.0, 0, 0, 0], damping=[0, 0, 0.2, 0, 0, 0])
    cords = (fg.Cord(node=int(ids[1]), anchor=(0.0, 0.2, 1.0), stiffness=40.0, unstretched_length=0.6, damping=0.1,
                     mass=0.01),
             fg.Cord(node=int(ids[5]), node_b=int(ids[6]), along=0.05, anchor=(0.0, 1.2, 1.0), stiffness=40.0,
                     unstretched_length=0.6, mass=0.01))
    cfg = fg.Configuration("hung", suspension=cords, gravity=1.0,
                           forces=[fg.NodalLoad(int(ids[4]), force=(0.0, 0.0, -0.1))])
    return System(model, cfg)


def _scatter(system, per_family, n):
    out = np.zeros(n)
    for family, v in zip(system.families, per_family):
        np.add.at(out, element_dofs(family.nodes).reshape(-1), v.reshape(-1))
    return out


def test_every_family_satisfies_the_protocol():
    system = _all_families()
    assert [f.name for f in system.families] == ["beam", "mass", "cord", "spring"]
    for family in system.families:
        assert isinstance(family, Family)
        assert element_dofs(family.nodes).shape[1] == 6 * family.nodes.shape[1]
    # the heavy cords' moving third is handed to the point masses: 1 tip mass + 1 + 2 cord shares
    assert len(system.masses.nodes) == 4
    assert system.has_damping


def test_system_terms_are_the_families_terms_scattered():
    system = _all_families()
    x, R = perturbed_state(system, 3)
    lam = 0.7
    n = 6 * system.n_nodes
    terms = [f.terms(x, R, lam, True) for f in system.families]
    r_full, K_full, M_full = system.full_state(x, R, lam)
    g = _scatter(system, [t.forces for t in terms], n)
    np.testing.assert_allclose(r_full, g - lam * system.applied, rtol=0, atol=1e-12 * np.abs(g).max())
    # the applied loads: the families' (beam weight, the cords' hanging sixth) plus the nodal load
    f = np.zeros((system.n_nodes, 6))
    for family in system.families:
        family.add_applied(f, system.config, system.config.gravity_vector)
    assert np.abs(system.applied - f.reshape(-1)).max() > 0  # the nodal load is the assembler's
    rows = [element_dofs(fam.nodes) for fam in system.families]

    def assembled(values):
        r = np.concatenate([np.repeat(d, d.shape[1], axis=1).reshape(-1) for d in rows])
        c = np.concatenate([np.tile(d, (1, d.shape[1])).reshape(-1) for d in rows])
        return sp.coo_matrix((np.concatenate([v.reshape(-1) for v in values]), (r, c)), shape=(n, n)).toarray()

    K = assembled([t.tangent for t in terms])
    np.testing.assert_allclose(K_full.toarray(), K, rtol=0, atol=1e-12 * np.abs(K).max())
    M = assembled([fam.mass_values(x, R) for fam in system.families])
    np.testing.assert_allclose(M_full.toarray(), M, rtol=0, atol=1e-12 * np.abs(M).max())
    C = assembled([fam.damping_values(x, R) for fam in system.families])
    np.testing.assert_allclose(system.damping_matrix(x, R).toarray(), C[np.ix_(system.dof_map >= 0,
                                                                                system.dof_map >= 0)],
                               rtol=0, atol=1e-12 * np.abs(C).max())
