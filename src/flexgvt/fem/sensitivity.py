"""Derivatives of the residual, tangent and mass matrix with respect to material and section
parameters of a beam group, and spring rates: the foundation of gradient-based updating.

The beam kernel is linear in its coefficients s = (EA, GJ, kd_y, ko_y, kd_z, ko_z) and the
mass matrix in (rho A, rho Ip, rho Iy, rho Iz), so d(residual, K)/dp is the same kernel
evaluated with ds/dp, and dM/dp the same mass assembly with the derivative mass terms: one
element pass per parameter, exact, at any (deformed) state.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ..model import RectangularSection
from .beam import beam_forces, beam_mass_matrices, local_mass_matrices
from .static import State

BEAM_PARAMETERS = ("E", "G", "rho", "width", "height")


@dataclass(frozen=True)
class ParameterDerivative:
    """d(residual)/dp (reduced, (n_free,)), dK/dp and dM/dp (reduced sparse) at a state."""

    parameter: str
    group: str
    residual: np.ndarray
    stiffness: sp.csc_matrix
    mass: sp.csc_matrix


def _section_props_derivative(section, parameter: str) -> dict[str, float]:
    """d(A, Iy, Iz, J, Ip, Ay, Az)/d(width or height) of a rectangular section (complex step, exact)."""
    if not isinstance(section, RectangularSection):
        raise ModelError(f"derivative with respect to '{parameter}' needs a RectangularSection")
    h = 1e-30
    b, t = section.width, section.height
    db, dt = (1j * h, 0.0) if parameter == "width" else (0.0, 1j * h)
    bc, tc = b + db, t + dt
    A = bc * tc
    n = 2 * np.arange(50) + 1
    if b >= t:
        J = bc * tc**3 / 3 * (1 - 192 / np.pi**5 * tc / bc * np.sum(np.tanh(n * np.pi * bc / (2 * tc)) / n**5))
    else:
        J = tc * bc**3 / 3 * (1 - 192 / np.pi**5 * bc / tc * np.sum(np.tanh(n * np.pi * tc / (2 * bc)) / n**5))
    shear = 5 / 6 * A if section.shear else 0.0 * A
    props = {"A": A, "Iy": bc * tc**3 / 12, "Iz": tc * bc**3 / 12, "J": J, "Ip": A * (bc * bc + tc * tc) / 12,
             "Ay": shear, "Az": shear}
    return {k: float(np.imag(v) / h) for k, v in props.items()}


def _group_derivatives(model, group, parameter, L):
    """d(section stiffness (EA, GJ, EIy, EIz, Phi_y, Phi_z))/dp and d(rhoA, rhoIp, rhoIy, rhoIz)/dp, per element."""
    mat, sec = group.material, group.section
    p = sec.properties()
    E, G, rho = mat.E, mat.shear_modulus, mat.rho
    rot = 1.0 if group.rotary_inertia else 0.0
    n = len(L)
    dp = {k: 0.0 for k in p}
    dE = dG = drho = 0.0
    if parameter == "E":
        dE = 1.0
        dG = 0.0 if mat.G is not None else 1.0 / (2 * (1 + mat.nu))
    elif parameter == "G":
        dG = 1.0
    elif parameter == "rho":
        drho = 1.0
    elif parameter in ("width", "height"):
        dp = _section_props_derivative(sec, parameter)
    else:
        raise ModelError(f"unknown beam parameter '{parameter}'; choose one of {BEAM_PARAMETERS}")

    def phi_and_derivative(I, dI, As, dAs):
        if As <= 0:
            return np.zeros(n), np.zeros(n)
        phi = 12 * E * I / (G * As * L**2)
        dphi = phi * ((dE / E if dE else 0.0) + dI / I - (dG / G if dG else 0.0) - dAs / As)
        return phi, dphi

    phy, dphy = phi_and_derivative(p["Iy"], dp["Iy"], p["Az"], dp["Az"])
    phz, dphz = phi_and_derivative(p["Iz"], dp["Iz"], p["Ay"], dp["Ay"])
    dsec = np.column_stack([np.full(n, dE * p["A"] + E * dp["A"]), np.full(n, dG * p["J"] + G * dp["J"]),
                            np.full(n, dE * p["Iy"] + E * dp["Iy"]), np.full(n, dE * p["Iz"] + E * dp["Iz"]),
                            dphy, dphz])
    section = np.column_stack([np.full(n, E * p["A"]), np.full(n, G * p["J"]), np.full(n, E * p["Iy"]),
                               np.full(n, E * p["Iz"]), phy, phz])
    dmass = np.column_stack([np.full(n, drho * p["A"] + rho * dp["A"]), np.full(n, drho * p["Ip"] + rho * dp["Ip"]),
                             np.full(n, rot * (drho * p["Iy"] + rho * dp["Iy"])),
                             np.full(n, rot * (drho * p["Iz"] + rho * dp["Iz"]))])
    return section, dsec, dmass


def _coefficient_derivative(section: np.ndarray, dsec: np.ndarray, L: np.ndarray) -> np.ndarray:
    """d(EA, GJ, kd_y, ko_y, kd_z, ko_z) from d(EA, GJ, EIy, EIz, Phi_y, Phi_z)."""
    out = np.zeros((len(L), 6))
    out[:, 0], out[:, 1] = dsec[:, 0], dsec[:, 1]
    for col, (i_ei, i_phi) in ((2, (2, 4)), (4, (3, 5))):
        EI, phi = section[:, i_ei], section[:, i_phi]
        dEI, dphi = dsec[:, i_ei], dsec[:, i_phi]
        out[:, col] = (4 + phi) / (L * (1 + phi)) * dEI - 3 * EI / (L * (1 + phi) ** 2) * dphi
        out[:, col + 1] = (2 - phi) / (L * (1 + phi)) * dEI - 3 * EI / (L * (1 + phi) ** 2) * dphi
    return out


def beam_parameter_derivative(state: State, group: str, parameter: str) -> ParameterDerivative:
    """Exact d(residual), dK, dM with respect to ``parameter`` (E, G, rho, width, height) of the
    beam group named ``group`` (the ``name=`` of add_beams), at ``state``.

    Applied gravity loads change with rho (beam weight) and are included in d(residual).
    """
    system = state.system
    model = state.model
    cm = system.cm
    mask = cm.beam_group_names == group
    if not mask.any():
        raise ModelError(f"no beam group named '{group}' in model '{model.name}'; groups: "
                         f"{sorted(set(cm.beam_group_names.tolist()))}")
    grp = next(g for g in model.beams if g.name == group)
    b = cm.beams
    L = b.L0[mask]
    section, dsec, dmass = _group_derivatives(model, grp, parameter, L)
    coeff = np.zeros_like(b.stiffness)
    coeff[mask] = _coefficient_derivative(section, dsec, L)
    x, R = state.positions, state.rotations
    data = replace(b, stiffness=coeff)
    g, K, _ = beam_forces(x, R, data, True)
    zero_pts = [np.zeros((len(system.masses.nodes), 6, 6)), np.zeros((len(system.cord_nodes), 6, 6)),
                np.zeros((len(system.springs.b), 12, 12))]
    g_full = system._scatter([g] + [z[:, :, 0] for z in zero_pts]).reshape(-1, 6)
    # Weight of the group (lumped), scaled by the load factor, enters the applied loads.
    dw = np.zeros(len(b.L0))
    dw[mask] = dmass[:, 0] * L
    gvec = system.config.gravity_vector * state.load_factor
    np.add.at(g_full, (b.nodes[:, 0], slice(0, 3)), -0.5 * dw[:, None] * gvec[None, :])
    np.add.at(g_full, (b.nodes[:, 1], slice(0, 3)), -0.5 * dw[:, None] * gvec[None, :])
    T = system.transformation(x, R) if system.has_links else None
    d_res = system.reduce_vector(g_full.reshape(-1), T)
    dK = system.pattern.assemble([K] + zero_pts)
    mass_terms = np.zeros((len(b.L0), 4))
    mass_terms[mask] = dmass
    dlocal = local_mass_matrices(replace(b, mass_per_length=mass_terms[:, 0], inertia_per_length=mass_terms[:, 1:]))
    dM = system.pattern.assemble([beam_mass_matrices(x, R, b, dlocal)] + zero_pts)
    if system.has_links:
        dK = (T.T @ dK @ T).tocsc()
        dM = (T.T @ dM @ T).tocsc()
    return ParameterDerivative(parameter, group, d_res, dK, dM)


def frequency_derivatives(modes, derivative: ParameterDerivative) -> np.ndarray:
    """d(frequency_hz)/dp of real modes, d lambda = phi^T (dK - lambda dM) phi (mass-normalised phi),
    holding the static state fixed (the state's own change with p belongs to the updating layer:
    du/dp = -K^-1 d(residual)/dp, then dK/du along it)."""
    system = modes.state.system
    T = system.transformation(modes.state.positions, modes.state.rotations) if system.has_links else None
    phi = np.stack([system.reduce_vector(s.reshape(-1), T) for s in modes.shapes], axis=1)
    lam = modes.eigenvalues
    dlam = np.einsum("ij,ij->j", phi, (0.5 * (derivative.stiffness + derivative.stiffness.T)) @ phi) \
        - lam * np.einsum("ij,ij->j", phi, derivative.mass @ phi)
    f = modes.frequencies_hz
    return np.where(f > 0, dlam / (8 * np.pi**2 * np.where(f > 0, f, 1.0)), 0.0)
