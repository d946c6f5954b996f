"""Beam sections of PBAR/PBARL/PBEAM/PBEAML in flexgvt terms.

Axes. Nastran's element x runs from GA to GB, the orientation vector v lies in plane 1 (x-y),
z = x cross v, y = z cross x; I1 = Izz (bending in plane 1), I2 = Iyy, I12 = int(y z dA). flexgvt
reads the element with ``orientation`` = Nastran z, so its local axes equal Nastran's and
Section.Iy = I2, Section.Iz = I1, Ay = K1*A (shear along y, plane 1), Az = K2*A.
A non-zero I12 is taken to principal axes: the orientation is turned to the principal z' and
the principal moments are stored (Nastran ignores K1/K2 when I12 != 0, so no shear flexibility).

PBARL/PBEAML dimensions follow the Nastran beam library figures (element y up the page, z to the
right): BAR DIM1 along z, DIM2 along y. Like Nastran (PBARL remark 4) the shear factors of the
library shapes are computed from the dimensions: 5/6 for BAR, 0.9 for ROD, 0.5 for TUBE, and the
web (or flange) area over the total area for thin-walled shapes. Torsion constants: exact for
ROD/TUBE and BAR (series), thin-wall formulas (Bredt for BOX, sum of b t^3/3 for open shapes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import ModelError
from ...model import CircularTubeSection, GeneralSection, RectangularSection

SUPPORTED_SHAPES = ("ROD", "TUBE", "TUBE2", "BAR", "BOX", "I", "CHAN", "T", "L")


@dataclass(frozen=True)
class SectionData:
    """A flexgvt section plus the principal-axis turn needed to place it on a Nastran element.

    principal: unit 2-vector (cy, cz) giving the flexgvt local z' as cy*y_nastran + cz*z_nastran
    ((0, 1) when I12 = 0).
    """

    section: object
    principal: tuple[float, float] = (0.0, 1.0)


def _shear(k: float | None, A: float) -> float | None:
    """Nastran shear factor -> shear area (None: rigid in shear). Blank, 0 and pyNastran's 1e8 mean rigid."""
    if k is None or k == 0.0 or k >= 1e8:
        return None
    return float(k) * A


def from_properties(where: str, A, I1, I2, I12, J, K1=None, K2=None) -> SectionData:
    """Section from Nastran A, I1, I2, I12, J and shear factors (PBAR/PBEAM convention)."""
    if A is None or not math.isfinite(A) or A <= 0:
        raise ModelError(f"{where}: A={A!r}; a beam needs a cross-section area A > 0. Give it on the property card")
    I1, I2, J = (0.0 if v is None else v for v in (I1, I2, J))  # blank: 0.0, as Nastran
    for name, v in {"I1": I1, "I2": I2, "J": J}.items():
        if not math.isfinite(v) or v < 0:
            raise ModelError(f"{where}: {name}={v!r}; moments of inertia and J must be >= 0 (0: no stiffness in "
                             "that plane or in torsion, held by constraints). Correct the property card")
    I12 = float(I12 or 0.0)
    if not math.isfinite(I12):
        raise ModelError(f"{where}: I12={I12!r} is not a number. Correct the property card")
    for name, k in (("K1", K1), ("K2", K2)):
        if k is not None and not (math.isfinite(k) and k >= 0):
            raise ModelError(f"{where}: {name}={k!r}; shear factors must be >= 0 (blank or 0: rigid in shear). "
                             "Correct the property card")
    if I12 != 0.0:
        if I1 * I2 <= I12 * I12:
            raise ModelError(f"{where}: I1*I2 <= I12^2 ({I1}*{I2} <= {I12}^2) is not a valid section")
        Q = np.array([[I1, I12], [I12, I2]], float)
        lam, vec = np.linalg.eigh(Q)
        b = int(np.argmax(np.abs(vec[1])))
        zdir = vec[:, b] * np.sign(vec[1, b])
        Iy, Iz = float(lam[b]), float(lam[1 - b])
        return SectionData(GeneralSection(A=float(A), Iy=Iy, Iz=Iz, J=float(J), Ip=float(I1 + I2)),
                           (float(zdir[0]), float(zdir[1])))
    return SectionData(GeneralSection(A=float(A), Iy=float(I2), Iz=float(I1), J=float(J), Ay=_shear(K1, A),
                                      Az=_shear(K2, A)))


def to_properties(section, principal=(0.0, 1.0)) -> dict[str, float | None]:
    """Nastran A, I1, I2, I12, J, K1, K2 of a flexgvt section placed with ``principal`` (inverse of the above)."""
    p = section.properties()
    cy, cz = principal
    if (cy, cz) != (0.0, 1.0):
        zdir = np.array([cy, cz])
        ydir = np.array([cz, -cy])
        Q = p["Iy"] * np.outer(zdir, zdir) + p["Iz"] * np.outer(ydir, ydir)
        return {"A": p["A"], "I1": float(Q[0, 0]), "I2": float(Q[1, 1]), "I12": float(Q[0, 1]), "J": p["J"],
                "K1": None, "K2": None}
    return {"A": p["A"], "I1": p["Iz"], "I2": p["Iy"], "I12": 0.0, "J": p["J"],
            "K1": (p["Ay"] / p["A"]) if p["Ay"] else None, "K2": (p["Az"] / p["A"]) if p["Az"] else None}


def _need(where: str, shape: str, dims, n: int) -> list[float]:
    dims = [float(d) for d in dims]
    if len(dims) != n:
        raise ModelError(f"{where}: TYPE {shape} needs {n} dimensions, got {len(dims)}")
    if not all(math.isfinite(d) and d > 0 for d in dims):
        raise ModelError(f"{where}: TYPE {shape} dimensions must be positive numbers, got {dims}")
    return dims


def _parts(rects):
    """A, centroid (y, z), I1 = int (y-yc)^2, I2 = int (z-zc)^2, I12 = int (y-yc)(z-zc) of rectangles
    given as (y0, y1, z0, z1)."""
    rects = np.asarray(rects, float)
    h = rects[:, 1] - rects[:, 0]
    b = rects[:, 3] - rects[:, 2]
    a = h * b
    yc_i = 0.5 * (rects[:, 0] + rects[:, 1])
    zc_i = 0.5 * (rects[:, 2] + rects[:, 3])
    A = a.sum()
    yc, zc = (a * yc_i).sum() / A, (a * zc_i).sum() / A
    I1 = (b * h**3 / 12 + a * (yc_i - yc) ** 2).sum()
    I2 = (h * b**3 / 12 + a * (zc_i - zc) ** 2).sum()
    I12 = (a * (yc_i - yc) * (zc_i - zc)).sum()
    return float(A), float(I1), float(I2), float(I12)


def library_section(where: str, shape: str, dims) -> SectionData:
    """flexgvt section of a PBARL/PBEAML library shape (see the module docstring for axes and factors)."""
    shape = shape.upper()
    if shape == "ROD":
        (r,) = _need(where, shape, dims, 1)
        return SectionData(CircularTubeSection(outer_radius=r))
    if shape == "TUBE":
        ro, ri = _need(where, shape, dims, 2)
        if ri >= ro:
            raise ModelError(f"{where}: TUBE inner radius {ri} must be smaller than the outer radius {ro}")
        return SectionData(CircularTubeSection(outer_radius=ro, inner_radius=ri))
    if shape == "TUBE2":
        ro, t = _need(where, shape, dims, 2)
        if t > ro:
            raise ModelError(f"{where}: TUBE2 thickness {t} exceeds the outer radius {ro}")
        return SectionData(CircularTubeSection(outer_radius=ro, inner_radius=ro - t))
    if shape == "BAR":
        b, h = _need(where, shape, dims, 2)  # DIM1 along z, DIM2 along y
        return SectionData(RectangularSection(width=h, height=b))
    if shape == "BOX":
        b, h, t1, t2 = _need(where, shape, dims, 4)
        if b <= 2 * t2 or h <= 2 * t1:
            raise ModelError(f"{where}: BOX needs DIM1 > 2*DIM4 and DIM2 > 2*DIM3, got {dims}")
        A, I1, I2, _ = _parts([(0, t1, 0, b), (h - t1, h, 0, b), (t1, h - t1, 0, t2), (t1, h - t1, b - t2, b)])
        J = 2 * t1 * t2 * (b - t2) ** 2 * (h - t1) ** 2 / (b * t2 + h * t1 - t2**2 - t1**2)
        return SectionData(GeneralSection(A=A, Iy=I2, Iz=I1, J=J, Ay=2 * t2 * (h - 2 * t1), Az=2 * t1 * (b - 2 * t2)))
    if shape == "I":
        h, a, b, tw, ta, tb = _need(where, shape, dims, 6)
        hw = h - ta - tb
        if hw <= 0 or tw >= min(a, b):
            raise ModelError(f"{where}: I needs DIM1 > DIM5 + DIM6 and DIM4 < DIM2, DIM3, got {dims}")
        zc = 0.5 * max(a, b)
        A, I1, I2, _ = _parts([(0, ta, zc - a / 2, zc + a / 2), (h - tb, h, zc - b / 2, zc + b / 2),
                               (ta, h - tb, zc - tw / 2, zc + tw / 2)])
        J = (a * ta**3 + b * tb**3 + (h - 0.5 * (ta + tb)) * tw**3) / 3.0
        return SectionData(GeneralSection(A=A, Iy=I2, Iz=I1, J=J, Ay=tw * hw, Az=a * ta + b * tb))
    if shape == "CHAN":
        d1, h, tw, tf = _need(where, shape, dims, 4)
        bf, hw = d1 - tw, h - 2 * tf
        if bf <= 0 or hw <= 0:
            raise ModelError(f"{where}: CHAN needs DIM1 > DIM3 and DIM2 > 2*DIM4, got {dims}")
        A, I1, I2, _ = _parts([(0, h, 0, tw), (0, tf, tw, d1), (h - tf, h, tw, d1)])
        J = (2 * (d1 - 0.5 * tw) * tf**3 + (h - tf) * tw**3) / 3.0
        return SectionData(GeneralSection(A=A, Iy=I2, Iz=I1, J=J, Ay=tw * hw, Az=2 * tf * bf))
    if shape == "T":
        d, h, tf, tw = _need(where, shape, dims, 4)
        hw = h - tf
        if hw <= 0 or tw >= d:
            raise ModelError(f"{where}: T needs DIM2 > DIM3 and DIM4 < DIM1, got {dims}")
        A, I1, I2, _ = _parts([(hw, h, 0, d), (0, hw, d / 2 - tw / 2, d / 2 + tw / 2)])
        J = (d * tf**3 + (h - 0.5 * tf) * tw**3) / 3.0
        return SectionData(GeneralSection(A=A, Iy=I2, Iz=I1, J=J, Ay=tw * hw, Az=d * tf))
    if shape == "L":
        d1, d2, t1, t2 = _need(where, shape, dims, 4)
        if d1 <= t2 or d2 <= t1:
            raise ModelError(f"{where}: L needs DIM1 > DIM4 and DIM2 > DIM3, got {dims}")
        A, I1, I2, I12 = _parts([(0, t1, 0, d1), (t1, d2, 0, t2)])
        J = ((d1 - 0.5 * t2) * t1**3 + (d2 - 0.5 * t1) * t2**3) / 3.0
        return from_properties(where, A, I1, I2, I12, J)
    raise ModelError(f"{where}: cross-section TYPE {shape} is not supported (supported: {', '.join(SUPPORTED_SHAPES)})")


def library_dims(section) -> tuple[str, list[float]] | None:
    """(TYPE, DIMs) that reproduce a RectangularSection/CircularTubeSection exactly, else None."""
    if isinstance(section, RectangularSection):
        return "BAR", [section.height, section.width]
    if isinstance(section, CircularTubeSection):
        if section.inner_radius == 0:
            return "ROD", [section.outer_radius]
        return "TUBE", [section.outer_radius, section.inner_radius]
    return None
