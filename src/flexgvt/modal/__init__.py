"""Plain modal data shared by every layer: ModalSet (modes with labelled DOFs), FRFs (with
coherence and variance), DOF labels and the one MAC kernel.

    ms = fg.modal.ModalSet(f, zeta, shapes, dofs=[(12, 3), (13, 3)])   # (id, direction code)
    ms.mac(fe.at(sensors))           # MAC over the DOFs both have, aligned by label
"""

from .dofs import as_dofs, common_dofs, dof_array, dof_names
from .frfs import FRFs
from .mac import mac_columns, mac_paired, mac_rows
from .modal_set import ModalSet, aligned_shapes

__all__ = ["FRFs", "ModalSet", "aligned_shapes", "as_dofs", "common_dofs", "dof_array", "dof_names", "mac_columns",
           "mac_paired", "mac_rows"]
