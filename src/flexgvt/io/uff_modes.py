"""Modes from dataset 2414 (analysis results): normal modes (analysis type 2) with data at nodes, per
node in its displacement coordinate system -> global axes (NX: already global, docs/uff.md)."""

from __future__ import annotations

import numpy as np

from ..errors import FileFormatError
from ..modal import ModalSet


def _frequency_hz(s: dict, where: str) -> float:
    """Record 12: (time, frequency [Hz], eigenvalue [rad^2/s^2], modal mass, viscous, hysteretic damping)
    for normal modes (I-DEAS 2414 chart). The frequency field, else sqrt(eigenvalue)/2 pi."""
    try:
        f = float(s.get("record12_field2", s.get("frequency", 0.0)) or 0.0)
        eig = float(s.get("record12_field3", s.get("eigenvalue", 0.0)) or 0.0)
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: the frequency or eigenvalue field is not a number") from None
    if not (np.isfinite(f) and np.isfinite(eig)):
        raise FileFormatError(f"{where}: the frequency or eigenvalue is not finite")
    if f == 0.0 and eig > 0:
        f = float(np.sqrt(eig) / (2 * np.pi))
    if f < 0:
        raise FileFormatError(f"{where}: negative frequency {f:g} Hz")
    return f


def modes_2414(sets, path, geometry, components_global: bool = False) -> ModalSet | None:
    """ModalSet (DOFs (node, 1..3) global translations, or 1..6 with rotations) from 2414 datasets:
    components in each node's displacement system turned to global, or taken as global
    (components_global: NX writes them so, docs/uff.md)."""
    if not sets:
        return None
    freqs, damps, shapes = [], [], []
    ids = None
    for k, s in sets:
        where = f"{path}: dataset {k + 1} (type 2414)"
        atype, loc = s.get("analysis_type"), s.get("dataset_location")
        if atype != 2 or loc != 1:
            raise FileFormatError(f"{where}: analysis type {atype}, data location {loc}: flexgvt reads normal modes "
                                  "(analysis type 2) with data at nodes (location 1) from 2414; export those")
        nodes = s.get("node_nums")
        values = s.get("data_at_node")
        if nodes is None or values is None:
            raise FileFormatError(f"{where}: no data at nodes; re-export the modes")
        nodes = np.asarray(nodes).astype(np.int64)
        dtype = s.get("data_type")
        complex_ = dtype in (5, 6)
        nv = s.get("number_of_data_values_for_the_data_component")
        width = nv * (2 if complex_ else 1) if isinstance(nv, (int, np.integer)) else -1
        if nv not in (3, 6) or any(len(v) != width for v in values) or len(values) != len(nodes):
            raise FileFormatError(f"{where}: {nv} values per node (3 translations or 6 with rotations expected, "
                                  f"{width} numbers each); re-export the modes")
        v = np.array(values, float)
        if not np.all(np.isfinite(v)):
            raise FileFormatError(f"{where}: NaN or infinite shape values")
        local = v[:, 0::2] + 1j * v[:, 1::2] if complex_ else v
        if complex_ and np.all(local.imag == 0):
            local = local.real
        if geometry is not None and len(geometry.point_ids) and not components_global:
            R = np.array([geometry.axes[geometry.index(int(n))] for n in nodes])
        else:
            R = np.broadcast_to(np.eye(3), (len(nodes), 3, 3))
        glob = np.concatenate([np.einsum("ni,nij->nj", local[:, a:a + 3], R) for a in range(0, nv, 3)], axis=1)
        if ids is None:
            ids = nodes
        elif not np.array_equal(nodes, ids) or glob.shape[1] != shapes[0].shape[1]:
            raise FileFormatError(f"{where}: the modes do not share one node list and layout; export every mode "
                                  "on the same nodes")
        freqs.append(_frequency_hz(s, where))
        try:
            damps.append(float(s.get("record12_field5", 0.0) or 0.0))
        except (TypeError, ValueError):
            raise FileFormatError(f"{where}: the damping field is not a number") from None
        shapes.append(glob)
    return ModalSet.from_points(np.array(freqs), np.array(damps), np.array(shapes), ids, source=str(path))
