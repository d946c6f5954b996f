"""fg.cases.wingbox against CalculiX S8R on the same plates (issue 31): the converged references
stored in tests/data/wingbox_ccx.json (bench/ccx_wingbox.py: source command, ccx version, mesh
sequence, date), and CalculiX re-run live on a coarse mesh where ccx is installed.

The loaded configurations are post-buckled; both solvers carry the same imperfection of the
compressed skin (a function of position, bench/ccx_wingbox.py), so they follow the same path.
Global modes (OOP, IP, T by the cross-sections' rigid motion) are paired by MAC at the box's
corners every metre; local skin modes are not (docs/shells.md, "Against CalculiX")."""

import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg

sys.path.insert(0, str(Path(__file__).parents[2] / "bench"))

from ccx_wingbox import corners_every_metre, global_pairs, run_calculix, run_flexgvt  # noqa: E402

REF = json.loads((Path(__file__).parents[1] / "data" / "wingbox_ccx.json").read_text())


def _reference(name: str) -> dict:
    r = REF["reference"][name]
    return {**r, "shapes": np.asarray(r["shapes"])}


def _flexgvt(size: float, name: str, n_modes: int) -> dict:
    f = run_flexgvt(size, name, n_modes)
    f["shapes"] = corners_every_metre(f["shapes"])
    return f


def test_mass_and_unloaded_modes_against_converged_calculix():
    """Mass within 0.5 % of CalculiX's (EMAS of its elements) and the first 10 unloaded modes within
    1 % of its S8R at 0.1 m (0.25 -> 0.1 m moved them by 0.01-0.38 %), each paired by MAC > 0.99 with
    the same class, flexgvt at 0.0625 m. Measured: mass -0.0002 %, modes +0.02 to +0.31 % (at 0.1 m
    flexgvt's mode 10 is +0.95 %, too near the bound for a test)."""
    ref = _reference("unloaded")
    f = _flexgvt(0.0625, "unloaded", 15)
    assert f["mass_kg"] == pytest.approx(REF["mass_kg"], rel=0.005)
    pairs = global_pairs(f, ref, 10)
    assert [p["reference_mode"] for p in pairs] == list(range(1, 11))
    for p in pairs:
        assert p["mac"] > 0.99 and p["test_class"] == p["reference_class"], p
        assert abs(p["difference_percent"]) < 1.0, p


@pytest.mark.parametrize("name", ["minus_1g", "plus_2_5g", "combined"])
def test_loaded_against_converged_calculix(name):
    """-1 g, 2.5 g and the combined case (post-buckled, same imperfection): tip deflection within 2 %
    and the first 5 global modes within 2 % (MAC > 0.9, same class) of CalculiX S8R at 0.1 m, flexgvt
    at REF['flexgvt_mesh'] (0.05 m). Both solvers soften as the meshes resolve the wrinkles; CalculiX
    0.125 -> 0.1 m moved the tip by +0.3 % / +1.1 % and the first bending by -0.3 % / -1.4 % at -1 g /
    2.5 g (docs/shells.md, 'Against CalculiX S8R'). Measured: tip +0.06 % / -0.76 % / +0.07 %, modes
    within 0.15 % / 0.74 % / 0.17 % (about 35 s CPU each with PARDISO; the combined case as re-sized
    on 27 Nov)."""
    ref = _reference(name)
    assert ref["element_size"] <= 0.1, "the stored loaded reference must be the converged CalculiX mesh"
    f = _flexgvt(REF["flexgvt_mesh"], name, 15)
    assert f["tip_w_m"] == pytest.approx(ref["tip_w_m"], rel=0.02)
    for p in global_pairs(f, ref, 5):
        assert p["mac"] > 0.9 and p["test_class"] == p["reference_class"], p
        assert abs(p["difference_percent"]) < 2.0, p


def test_calculix_live_on_a_coarse_mesh():
    """CalculiX re-run at 0.5 m (4 x 2 x 32 quads) where ccx is installed: flexgvt's four-node quads
    against its eight-node S8R on the same plates, unloaded; the first four modes (bending, in-plane)
    within 1 % (measured +0.16 to +0.61 %; first torsion -3.1 % at this mesh, not checked)."""
    if shutil.which("ccx") is None:
        pytest.skip("CalculiX (ccx) is not installed (Debian: apt-get install calculix-ccx); the stored "
                    "references are still checked by the other tests here")
    case = fg.cases.wingbox(element_size=0.5)
    c = run_calculix(0.5, "unloaded", 6, case=case)
    f = run_flexgvt(0.5, "unloaded", 8, case=case)
    pairs = global_pairs(f, c, 4)
    assert [p["reference_mode"] for p in pairs] == [1, 2, 3, 4]
    for p in pairs:
        assert p["mac"] > 0.99 and p["test_class"] == p["reference_class"], p
        assert abs(p["difference_percent"]) < 1.0, p
