"""Write flexgvt models as Nastran bulk data: into a copy of the user's deck, or as a compact deck.

Both writers go family by family (_write_beams, _write_plates, _write_masses, _write_springs, _write_rigid,
_write_cases), in the order the reader reads them.
"""

from __future__ import annotations

import contextlib
import copy
import io
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from ...errors import ModelError
from ...model import Configuration, Model
from ._common import Units, get_units
from ._parse import QuietLog
from ._read import BdfDeck
from ._write_beams import check_one_mass_formulation, update_beams, write_beams
from ._write_cases import write_configurations
from ._write_common import Numbering
from ._write_masses import update_masses, write_masses
from ._write_plates import add_as_ctria3, update_plates, write_plates
from ._write_rigid import check_rigid, write_rigid
from ._write_springs import update_springs, write_springs


def _quiet_write(bdf, path: Path, size: int) -> None:
    with contextlib.redirect_stdout(io.StringIO()):
        bdf.write_bdf(str(path), size=size, is_double=False, enddata=True)



# --------------------------------------------------------------------------- template
_EDITED = ("materials", "properties", "elements", "masses")  # the card groups the template writer edits


def _copy_deck(bdf):
    """A copy of a pyNastran deck to write into: the deck object and the card groups the template
    writer edits or adds to are deep copies; every other card group (loads, aero, monitor points,
    plot elements...) is shared, untouched. pyNastran cannot deep-copy some cards (PLOTEL, TLOAD2
    with an integer phase, MONPNT1 with a long label: the glider deck fmondsp.dat has them all;
    CTRIAR, whose written TFLAG its reader rejects: copied as CTRIA3, see _write_plates)."""
    other = {name: value for name, value in vars(bdf).items()
             if isinstance(value, (dict, list)) and name not in _EDITED}
    elements = dict(bdf.elements)
    triar = {eid: e for eid, e in elements.items() if e.type == "CTRIAR"}
    for name in other:
        setattr(bdf, name, {})
    for eid in triar:
        del bdf.elements[eid]
    try:
        new = copy.deepcopy(bdf)
    finally:
        for name, value in other.items():
            setattr(bdf, name, value)
        bdf.elements.clear()
        bdf.elements.update(elements)
    add_as_ctria3(new, triar)
    for name, value in other.items():
        setattr(new, name, copy.copy(value))
    return new



def _write_into_template(model: Model, path: Path, deck: BdfDeck, size: int) -> list[str]:
    bdf = _copy_deck(deck.bdf)
    bdf.log = QuietLog()
    notes: list[str] = []
    tmodel = deck.model
    if sorted(model.node_ids.tolist()) != sorted(tmodel.node_ids.tolist()):
        raise ModelError("write_bdf: the model's node ids differ from the template deck's; write without template= "
                         "for a model with a different mesh")
    if not np.allclose(model.xyz[np.argsort(model.node_ids)], tmodel.xyz[np.argsort(tmodel.node_ids)],
                       rtol=0, atol=1e-9 * max(1.0, float(np.abs(tmodel.xyz).max()))):
        raise ModelError("write_bdf: node coordinates differ from the template deck; geometry changes are not "
                         "written into a template (write without template=)")
    next_pid = max(list(bdf.properties) + [0]) + 1
    update_beams(bdf, model, deck, notes)
    update_masses(bdf, model, deck, notes)
    update_springs(bdf, model, deck, next_pid)
    check_rigid(model, deck)
    update_plates(bdf, model, deck, notes)
    _quiet_write(bdf, path, size)
    return notes


# --------------------------------------------------------------------------- compact
def _write_compact(model: Model, path: Path, configurations: Iterable[Configuration] | None, u: Units,
                   size: int, n_modes: int) -> list[str]:
    from pyNastran.bdf.bdf import BDF

    notes: list[str] = []
    bdf = BDF(log=QuietLog())
    bdf.sol = 103
    bdf.executive_control_lines = ["SOL 103"]
    node_ids = model.node_ids
    for nid, x in zip(node_ids.tolist(), model.xyz / u.length):
        bdf.add_grid(int(nid), [float(v) for v in x])
    xyz = dict(zip(node_ids.tolist(), model.xyz))
    check_one_mass_formulation(model)  # one PARAM,COUPMASS for beams, rods and shells
    eid_used = write_beams(bdf, model, u, xyz, notes)
    eid_used |= {int(e) for g in model.shells for e in g.ids}
    ids = Numbering(eid=max(eid_used | {0}) + 1, pid=len(model.beams) + 1)
    write_plates(bdf, model, u, ids)
    write_masses(bdf, model, u, ids)
    write_springs(bdf, model, u, xyz, ids)
    write_rigid(bdf, model, u, ids)
    elem_nodes = {int(e): (int(a), int(b)) for g in model.beams for e, (a, b) in zip(g.ids, g.nodes)}
    write_configurations(bdf, list(configurations or []), u, n_modes, elem_nodes, bool(model.constraints))
    _quiet_write(bdf, path, size)
    return notes


def write_bdf(model: Model, path: str | Path, template: BdfDeck | None = None, *,
              configurations: Iterable[Configuration] | None = None,
              units: str | Units = "SI", size: int = 16, n_modes: int = 10) -> Path:
    """Write ``model`` as Nastran bulk data to ``path``; returns the path.

    template: a BdfDeck from read_bdf. Its deck is written back (case control, loads, constraints,
    comments and every card flexgvt does not touch kept as pyNastran writes them; INCLUDEs are
    merged into the one file) with the model's material, beam section, concentrated mass and
    spring/damper values. A MAT1 or spring property shared by groups that now differ is split
    into copies with new ids; a PBARL/PBEAML whose values no longer fit its shape becomes an
    equivalent PBAR/PBEAM. The deck's units and PARAM,WTMASS are kept.
    Shells: changed PSHELL/PCOMP/PCOMPG and material values go into their cards (a property shared by
    groups that now differ is split), THETA, ZOFFS and corner thicknesses into the elements.
    Without template: a compact deck (GRID, CBAR + PBAR/PBARL + MAT1, CQUAD4/CTRIA3 + PSHELL/PCOMP/
    PCOMPG + MAT1/MAT2/MAT8, CONM2, CELAS2/CDAMP2 or
    CBUSH, RBE2, RBE3, MPC) in ``units``, with one SUBCASE per entry of ``configurations`` (SPC1, GRAV,
    FORCE/MOMENT, PLOAD1 combined by LOAD) and an EIGRL for ``n_modes``.
    size: 16 (large field, default: 12 significant digits, so updated values survive) or 8 (small field).
    """
    path = Path(path)
    if template is not None:
        if configurations is not None:
            raise ModelError("write_bdf: configurations= is for compact decks; a template keeps its own case "
                             "control and loads")
        notes = _write_into_template(model, path, template, size)
    else:
        notes = _write_compact(model, path, configurations, get_units(units), size, n_modes)
    if notes:
        warnings.warn(f"{path}: " + "; ".join(notes), stacklevel=2)
    return path
