"""The measured mass properties as residuals and constraints of the updating problem, with their
exact derivatives (docs/method.md section 4)."""

from __future__ import annotations

import numpy as np

from ..fem.beam_basis import beam_basis
from ..fem.massprops import rigid_body_basis, system_mass_properties
from ..fem.sensitivity import value_derivative
from ..fem.system import System
from ..model import Configuration, Model
from .derivatives import shared_changes, value_change
from .targets import MassTarget, Objective
from .variables import Parametrisation


class MassResiduals:
    """Mass, cg and inertia of the working model ``work`` (set to each design point) against
    ``target``: relative residuals weighted by ``objective``, the +-mass_limits constraints, and
    their derivatives with respect to the design variables of ``par``."""

    def __init__(self, target: MassTarget | None, objective: Objective, par: Parametrisation, work: Model):
        self.target = target
        self.objective = objective
        self.par = par
        self.work = work
        self.system = System(work, Configuration("mass properties"))
        if target is not None and target.cg is not None:
            mp = self.properties()
            self._cg_scales = mass_spread(mp.mass, mp.inertia, target.cg_scale)
        else:
            self._cg_scales = None

    def properties(self):
        """Mass properties of the working model as it is set (undeformed)."""
        system = self.system = self.system.for_values(self.work, self.system.config)
        positions, R = system.undeformed
        return system_mass_properties(system, positions, R)

    def vector(self, mp) -> tuple[np.ndarray, list[str], np.ndarray]:
        """Mass residuals (relative errors), their names and reference scales."""
        t = self.target
        w = self.objective
        vals, names, refs = [], [], []
        if t is None:
            return np.zeros(0), [], np.zeros(0)
        if t.mass is not None:
            vals.append(w.mass * (mp.mass - t.mass) / t.mass)
            names.append("mass")
            refs.append(t.mass)
        if t.cg is not None:
            for a, c0, scale in zip("xyz", t.cg, self.cg_scales()):
                vals.append(w.cg * (mp.cg["xyz".index(a)] - c0) / scale)
                names.append(f"cg_{a}")
                refs.append(scale)
        if t.inertia is not None:
            for a, i0 in zip(("xx", "yy", "zz"), t.inertia):
                vals.append(w.inertia * (mp.inertia["xyz".index(a[0]), "xyz".index(a[0])] - i0) / i0)
                names.append(f"I{a}")
                refs.append(i0)
        return np.array(vals), names, np.array(refs)

    def constraints(self, mp) -> tuple[np.ndarray, list[str]]:
        """Mass properties within +-mass_limits (relative), as c >= 0."""
        w = self.objective
        if w.mass_limits is None or self.target is None:
            return np.zeros(0), []
        rel, mnames, _ = self.vector(mp)
        rel = rel / self.weights()
        vals = [v for r in rel for v in (w.mass_limits - r, w.mass_limits + r)]
        names = [n for m in mnames for n in (f"{m} <= +{w.mass_limits:g}", f"{m} >= -{w.mass_limits:g}")]
        return np.array(vals), names

    def cg_scales(self) -> np.ndarray:
        """(3,) [m] what each cg error is divided by: the model's rms mass spread about its cg along
        that axis (as given, before any update), at least the target's cg_scale. A length of the
        structure, so the residual does not depend on where the axes' origin is (dividing by the cg
        coordinate made a cg on a symmetry plane a 100 % error per millimetre, and its derivative
        O(1) noise at a round-off reference); the mass-limits band is then that fraction of the
        spread."""
        return self._cg_scales

    def weights(self) -> np.ndarray:
        """The weight of each mass residual (1 where its weight is 0, for the relative limits)."""
        t, w = self.target, self.objective
        out = []
        if t.mass is not None:
            out.append(w.mass)
        if t.cg is not None:
            out += [w.cg] * 3
        if t.inertia is not None:
            out += [w.inertia] * 3
        return np.where(np.array(out) > 0, np.array(out), 1.0)

    def derivatives(self, x: np.ndarray, changes=None) -> np.ndarray:
        """d(mass residuals)/dp from the exact derivative of the undeformed mass matrix, projected on
        the rigid-body motions (the moments m, m cg, I are linear in it); beam variables through
        the element mass blocks per unit value (fem.beam_basis), all at once."""
        if self.target is None:
            return np.zeros((0, len(self.par)))
        design = changes if changes is not None else shared_changes(self.par, self.work, x)
        system = self.system
        X, I3 = system.undeformed
        phi = rigid_body_basis(X)
        rb = np.zeros((len(self.par), 6, 6))
        if design.batched.any():
            basis = beam_basis(system, X, I3, 0.0, design.rows, design.local_units(system.cm.beams), stiffness=False)
            forms = basis.bilinear_mass(basis.element_values(phi))  # (8 k, 6, 6)
            rb += np.asarray(design.DM.T @ forms.reshape(len(forms), 36)).reshape(-1, 6, 6)
        for k in np.flatnonzero(~design.batched):
            change = design.changes[k] if design.changes[k] is not None else \
                value_change(self.par, self.work, x, k, system.config.name)
            dM = value_derivative(system, X, I3, 0.0, change, full_mass=True)[2]
            rb[k] = phi.T @ (dM @ phi)
        return self._chain(np.column_stack([_moments(m) for m in rb]))

    def _chain(self, dmom: np.ndarray) -> np.ndarray:
        """From d(moments) to d(residuals) at the current mass properties."""
        t, w = self.target, self.objective
        mp = self.properties()
        m, c = mp.mass, mp.cg
        dm, dS, dI0 = dmom[0], dmom[1:4], dmom[4:7]
        dc = (dS - c[:, None] * dm[None, :]) / m
        # I_cg,aa = I0_aa - m (|c|^2 - c_a^2)
        dIcg = dI0 - (dm[None, :] * (np.sum(c * c) - c * c)[:, None]
                      + m * (2 * (c @ dc)[None, :] - 2 * c[:, None] * dc))
        rows = []
        if t.mass is not None:
            rows.append(w.mass * dm / t.mass)
        if t.cg is not None:
            for a, scale in enumerate(self.cg_scales()):
                rows.append(w.cg * dc[a] / scale)
        if t.inertia is not None:
            for a, i0 in enumerate(t.inertia):
                rows.append(w.inertia * dIcg[a] / i0)
        return np.array(rows)



def mass_spread(mass: float, inertia, floor: float = 0.0) -> np.ndarray:
    """(3,) [m] the rms distance of the mass [kg] from its cg along x, y, z, sqrt(int (a - a_cg)^2 dm
    / m) = sqrt((I_bb + I_cc - I_aa) / 2m) from Ixx, Iyy, Izz about the cg (inertia: those three, or
    the 3 x 3 tensor) [kg m^2], each at least ``floor``."""
    d = np.asarray(inertia, float)
    d = np.diag(d) if d.ndim == 2 else d
    second = (d.sum() - 2 * d) / (2 * mass) if mass > 0 else np.zeros(3)
    return np.maximum(np.sqrt(np.clip(second, 0.0, None)), floor)


def _moments(Mrb: np.ndarray) -> np.ndarray:
    """(m, m cg (3), diagonal of the inertia about the origin (3)) from a rigid-body mass matrix."""
    mS = Mrb[3:, :3]
    return np.r_[np.trace(Mrb[:3, :3]) / 3, mS[2, 1], mS[0, 2], mS[1, 0], np.diag(Mrb[3:, 3:])]

