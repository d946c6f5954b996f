"""Reference routes to parameter derivatives for the tests: a beam group's d(residual), dK, dM by
the complex-step group derivative and fem.sensitivity.value_derivative, and first-order frequency
derivatives at a fixed state (the updating layer's own, flexgvt.updating.derivatives, supersedes
both in the package; the tests compare the two routes). Imported by name: pyproject's pytest
pythonpath holds this folder."""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from flexgvt.errors import ModelError
from flexgvt.fem.sensitivity import ValueChange, groups_derivatives, value_derivative
from flexgvt.fem.static import State


@dataclass(frozen=True)
class ParameterDerivative:
    """d(residual)/dp (reduced, (n_free,)), dK/dp and dM/dp (reduced sparse) at a state."""

    parameter: str
    group: str
    residual: np.ndarray
    stiffness: sp.csc_matrix
    mass: sp.csc_matrix


def group_derivatives(group, parameter: str, L: np.ndarray) -> tuple:
    """Exact (complex-step) derivatives with respect to ``parameter`` of a beam group's kernel
    coefficients (k, 8), mass per length (k, 2) and inertia per length (k, 2, 3) (see group_values)."""
    return groups_derivatives([(group, parameter, L)])[0]


def beam_parameter_derivative(state: State, group: str, parameter: str) -> ParameterDerivative:
    """Exact d(residual), dK, dM with respect to ``parameter`` (E, G, rho, width, height) of the
    beam groups named ``group`` (the ``name=`` of add_beams; every group of that name moves
    together, each with its own material and section), at ``state``.

    Applied gravity loads change with rho (beam weight) and are included in d(residual).
    """
    system = state.system
    model = state.model
    cm = system.cm
    if not np.any(cm.beam_group_names == group):
        raise ModelError(f"no beam group named '{group}' in model '{model.name}'; groups: "
                         f"{sorted(set(cm.beam_group_names.tolist()))}")
    starts = np.cumsum([0] + [len(g.ids) for g in model.beams])
    parts = [(np.arange(starts[k], starts[k + 1]), g) for k, g in enumerate(model.beams) if g.name == group]
    rows = np.concatenate([r for r, _ in parts])
    values = [group_derivatives(g, parameter, cm.beams.L0[r]) for r, g in parts]
    dcoeff, dmass, dinertia = (np.concatenate([v[i] for v in values]) for i in range(3))
    d_res, dK, dM = value_derivative(system, state.positions, state.rotations, state.load_factor,
                                     ValueChange(beams=(rows, dcoeff, dmass, dinertia)))
    return ParameterDerivative(parameter, group, d_res, dK, dM)


def frequency_derivatives(modes, derivative: ParameterDerivative) -> np.ndarray:
    """d(frequency_hz)/dp of real modes, d lambda = phi^T (dK - lambda dM) phi (mass-normalised phi),
    holding the static state fixed (the state's own change with p belongs to the updating layer:
    du/dp = -K^-1 d(residual)/dp, then dK/du along it)."""
    system = modes.state.system
    phi = np.stack([system.reduce_displacement(s.reshape(-1)) for s in modes.shapes], axis=1)
    lam = modes.eigenvalues
    dlam = np.einsum("ij,ij->j", phi, (0.5 * (derivative.stiffness + derivative.stiffness.T)) @ phi) \
        - lam * np.einsum("ij,ij->j", phi, derivative.mass @ phi)
    f = modes.frequencies_hz
    return np.where(f > 0, dlam / (8 * np.pi**2 * np.where(f > 0, f, 1.0)), 0.0)
