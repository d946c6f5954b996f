"""ModalSet: one set of modes with labelled DOFs, whatever produced it (EMA identification, a UFF 55
file, a table of identified modes, FE modes at the sensors: flexgvt.fem.Modes.at)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import ModelError
from .dofs import as_dofs, common_dofs, dof_array
from .mac import mac_rows


def _no_dofs() -> np.ndarray:
    return np.zeros((0, 2), int)


@dataclass(frozen=True, eq=False)
class ModalSet:
    """Modes with their DOF labels (SDynPy's shape array that carries its DOFs).

    frequencies_hz, damping_ratio (n_modes,) [Hz, -]; shapes (n_modes, n_dofs) real or complex, or
    None (frequencies only); dofs (n_dofs, 2): (point/node id, direction code +-1..6, 0 scalar) of
    each shape column (empty when unlabelled; ``outputs`` is the same array); participation
    (n_modes, n_inputs) and residues (n_modes, n_dofs, n_inputs) of an identification, with the
    inputs' DOFs; frequency_std_hz, damping_std (n_modes,) standard deviations where known
    (maximum-likelihood refinement, repeated tests, a file), else None; labels: names of the
    modes; name: the configuration (or test) they belong to; source: where they come from;
    stabilisation, frfs: the PolyMAX diagram and the FRFs of an identification; info: the
    diagnostics of the function that made the set (e.g. refine's RefineInfo as info['refine'])."""

    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray | None = None
    shapes: np.ndarray | None = None
    participation: np.ndarray | None = None
    residues: np.ndarray | None = None
    dofs: np.ndarray = field(default_factory=_no_dofs)
    inputs: np.ndarray = field(default_factory=_no_dofs)
    frequency_std_hz: np.ndarray | None = None  # (n_modes,) standard deviation [Hz]
    damping_std: np.ndarray | None = None  # (n_modes,) standard deviation of the damping ratio
    labels: tuple[str, ...] = ()
    name: str = ""
    source: str = ""
    stabilisation: Any = field(default=None, repr=False)
    frfs: Any = field(default=None, repr=False)
    info: dict = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        f = np.asarray(self.frequencies_hz)
        if f.ndim != 1:
            raise ModelError(f"ModalSet '{self.name}': frequencies_hz must be one value per mode, got shape {f.shape}")
        object.__setattr__(self, "frequencies_hz", f)
        z = np.zeros(len(f)) if self.damping_ratio is None else np.asarray(self.damping_ratio)
        if z.shape != f.shape:
            raise ModelError(f"ModalSet '{self.name}': {z.size} damping ratios for {len(f)} frequencies")
        object.__setattr__(self, "damping_ratio", z)
        object.__setattr__(self, "dofs", as_dofs(self.dofs, f"ModalSet '{self.name}' dofs"))
        object.__setattr__(self, "inputs", as_dofs(self.inputs, f"ModalSet '{self.name}' inputs"))
        object.__setattr__(self, "labels", tuple(self.labels))
        if self.shapes is not None:
            s = np.asarray(self.shapes)
            if s.ndim != 2 or len(s) != len(f):
                raise ModelError(f"ModalSet '{self.name}': shapes must be (n_modes={len(f)}, n_dofs), got {s.shape}")
            if len(self.dofs) and s.shape[1] and s.shape[1] != len(self.dofs):
                raise ModelError(f"ModalSet '{self.name}': {s.shape[1]} shape columns for {len(self.dofs)} DOFs")
            object.__setattr__(self, "shapes", s)

    # Names the other former mode-set types used for the same fields.
    @property
    def outputs(self) -> np.ndarray:
        """The DOFs of the shape columns (the output channels of an identification)."""
        return self.dofs

    @property
    def configuration(self) -> str:
        """The configuration these modes belong to (``name``)."""
        return self.name

    @property
    def diagram(self) -> dict | None:
        """The stabilisation diagram's plain data kept with an identification (info['diagram'])."""
        return self.info.get("diagram")

    @property
    def n_modes(self) -> int:
        return len(self.frequencies_hz)

    def with_info(self, **info) -> ModalSet:
        """A copy with ``info`` entries added."""
        return replace(self, info={**self.info, **info})

    def subset(self, keep) -> ModalSet:
        """The modes ``keep`` (indices or a boolean mask), everything per mode taken along."""
        keep = np.arange(self.n_modes)[np.asarray(keep)] if np.ndim(keep) else np.atleast_1d(keep)
        pick = (lambda a: None if a is None else np.asarray(a)[keep])  # noqa: E731
        labels = tuple(self.labels[k] for k in keep if k < len(self.labels))
        return replace(self, frequencies_hz=self.frequencies_hz[keep], damping_ratio=self.damping_ratio[keep],
                       shapes=pick(self.shapes), participation=pick(self.participation), residues=pick(self.residues),
                       frequency_std_hz=pick(self.frequency_std_hz), damping_std=pick(self.damping_std), labels=labels)

    def at_dofs(self, dofs) -> ModalSet:
        """The shapes at ``dofs`` (n, 2): the common DOFs in the order given, a DOF read the other way
        (opposite direction code) with the opposite sign; DOFs this set lacks are left out."""
        ia, ib, sign = common_dofs(dofs, self.dofs)
        shapes = None if self.shapes is None else self.shapes[:, ib] * sign
        return replace(self, shapes=shapes, dofs=as_dofs(dofs)[ia], residues=None)

    def mac(self, other: ModalSet) -> np.ndarray:
        """(n_modes, other.n_modes) MAC over the DOFs both sets have (aligned by their labels, signs
        included); by position when either set has no labels."""
        A, B = aligned_shapes(self, other)
        return mac_rows(A, B)

    def point_shapes(self) -> tuple[np.ndarray, np.ndarray]:
        """(point ids (n_points,), shapes (n_modes, n_points, 3 or 6)) of the DOFs laid out per point
        (UFF 55): translations only unless a rotation is among the DOFs; missing DOFs are 0."""
        if self.shapes is None or not len(self.dofs):
            raise ModelError(f"ModalSet '{self.name}': no labelled shapes to lay out per point")
        dofs = self.dofs.astype(np.int64)
        if np.any(dofs[:, 1] == 0):
            raise ModelError(f"ModalSet '{self.name}': scalar DOFs (direction 0) have no place in a per-point layout")
        points, first = np.unique(dofs[:, 0], return_index=True)
        points = points[np.argsort(first)]  # in order of first appearance
        row = {int(p): k for k, p in enumerate(points)}
        width = 6 if np.any(np.abs(dofs[:, 1]) > 3) else 3
        out = np.zeros((self.n_modes, len(points), width), dtype=self.shapes.dtype)
        for k, (p, d) in enumerate(dofs):
            out[:, row[int(p)], abs(d) - 1] += np.sign(d) * self.shapes[:, k]
        return points, out

    @property
    def point_ids(self) -> np.ndarray:
        """The points of the DOFs in order of first appearance."""
        ids, first = np.unique(self.dofs[:, 0], return_index=True)
        return ids[np.argsort(first)]

    @classmethod
    def from_points(cls, frequencies_hz, damping_ratio, shapes, point_ids, frequency_std_hz=None,
                    damping_std=None, **kwargs) -> ModalSet:
        """From per-point shapes (n_modes, n_points, k), k = 3 translations or 6 with rotations (UFF 55)."""
        s = np.asarray(shapes)
        ids = np.asarray(point_ids)
        if s.ndim != 3 or s.shape[1] != len(ids) or not 1 <= s.shape[2] <= 6:
            raise ModelError(f"ModalSet.from_points: shapes must be (n_modes, {len(ids)} points, 3 or 6), "
                             f"got {s.shape}")
        dofs = dof_array(np.repeat(ids, s.shape[2]), np.tile(np.arange(1, s.shape[2] + 1), len(ids)))
        return cls(frequencies_hz, damping_ratio, s.reshape(len(s), -1), dofs=dofs,
                   frequency_std_hz=frequency_std_hz, damping_std=damping_std, **kwargs)

    def as_dict(self) -> dict:
        """JSON layout (read back by flexgvt.workflow.read_modes)."""
        out = {"configuration": self.name, "source": self.source,
               "frequencies_hz": self.frequencies_hz.tolist(), "damping_ratio": self.damping_ratio.tolist(),
               "labels": list(self.labels)}
        if self.frequency_std_hz is not None:
            out["frequency_std_hz"] = np.asarray(self.frequency_std_hz).tolist()
        if self.damping_std is not None:
            out["damping_std"] = np.asarray(self.damping_std).tolist()
        if self.shapes is not None:
            out["outputs"] = np.asarray(self.dofs).astype(int).tolist()
            out["shapes_real"] = np.real(self.shapes).tolist()
            out["shapes_imag"] = np.imag(self.shapes).tolist()
        return out


def aligned_shapes(a, b) -> tuple[np.ndarray, np.ndarray]:
    """The shapes (n_a, n) and (n_b, n) of two mode sets over their common DOFs: by label when both
    carry DOF labels (and differ), else by position."""
    A, B = np.asarray(a.shapes), np.asarray(b.shapes)
    da, db = np.asarray(getattr(a, "dofs", ())), np.asarray(getattr(b, "dofs", ()))
    if da.size and db.size and not (da.shape == db.shape and np.array_equal(da, db)):
        ia, ib, sign = common_dofs(da, db)
        if not len(ia):
            raise ModelError("the two mode sets have no DOF in common; map the test points to the FE nodes "
                             "(same ids and directions)")
        return A[:, ia], B[:, ib] * sign
    if A.shape[1] != B.shape[1]:
        raise ModelError(f"mode sets of {A.shape[1]} and {B.shape[1]} DOFs without DOF labels to align them by")
    return A, B
