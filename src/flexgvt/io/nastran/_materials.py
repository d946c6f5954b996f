"""Materials: MAT1 -> flexgvt Material (SI, PARAM,WTMASS on the density)."""

from __future__ import annotations

import math

from ...errors import ModelError
from ...model import Material, Model
from ._deck import Deck, Family, Findings, Parts


def read_materials(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """Every MAT1 as a Material (other material cards are left to the families that use them)."""
    u = deck.units
    materials: dict[int, Material] = {}
    for mid, mat in sorted(deck.bdf.materials.items()):
        if mat.type != "MAT1":
            continue
        where = deck.at("MAT1", mid)
        E, G, nu, rho = mat.e, mat.g, mat.nu, mat.rho or 0.0
        if not E:
            raise ModelError(f"{where}: E is blank or zero; flexgvt beams need Young's modulus")
        if not G and not nu:
            raise ModelError(f"{where}: G and NU are both blank, which Nastran reads as G = 0 (no torsional or "
                             "shear stiffness); give G or NU")
        consistent = G and nu is not None and nu != -1 and math.isclose(G, E / (2 * (1 + nu)), rel_tol=1e-6)
        # E and G given with NU blank: Nastran takes NU = E/2G - 1 whatever its value (a beam's
        # equivalent properties often give NU outside (-1, 0.5); only E and G act on a beam).
        use_nu = not G or (consistent and -1 < nu < 0.5)
        kwargs = {"nu": float(nu)} if use_nu else {"G": float(G) * u.stress}
        if G and nu is not None and not consistent and -1 < nu < 0.5:
            kwargs["nu"] = float(nu)
        if getattr(mat, "ge", 0.0):
            log.note(f"{where}: structural damping GE={mat.ge} is not modelled")
        try:
            materials[mid] = Material(f"MAT1_{mid}", E=float(E) * u.stress, rho=float(rho) * u.density * deck.wtmass,
                                      **kwargs)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
    return Parts(materials=materials)


FAMILY = Family("materials", ("MAT1",), read_materials)
