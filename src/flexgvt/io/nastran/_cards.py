"""Card classification: which bulk cards flexgvt reads, ignores (non-structural) or refuses."""

from __future__ import annotations

import re

import numpy as np

BEAM_CARDS = ("CBAR", "CBEAM")
ROD_CARDS = ("CROD", "CONROD")
BEAM_PROPERTIES = ("PBAR", "PBARL", "PBEAM", "PBEAML")
SUPPORTED_ELEMENTS = BEAM_CARDS + ROD_CARDS + ("CONM2", "CONM1", "CELAS1", "CELAS2", "CDAMP1", "CDAMP2", "CVISC",
                                               "CBUSH", "RBE2", "RBE3", "RBAR")
SUPPORTED_PROPERTIES = BEAM_PROPERTIES + ("PROD", "PELAS", "PDAMP", "PVISC", "PBUSH")
SUPPORTED_LOADS = ("FORCE", "MOMENT", "GRAV", "PLOAD1", "SPCD")
# Cards that carry no structure or are read through the case control (methods, solution controls).
IGNORED_CARDS = {"ENDDATA", "PARAM", "EIGRL", "EIGR", "NLPARM", "NLPCI", "MDLPRM", "DTI", "TSTEPNL", "TSTEP", "FREQ",
                 "FREQ1", "FREQ2", "NLSTEP", "USET", "USET1"}
# Cards that do not change the structure, its constraints or static loads (aerodynamics, design
# optimisation, dynamic loading, output): ignored with one note naming them.
NON_STRUCTURAL = {"AERO", "AEROS", "CAERO1", "CAERO2", "CAERO3", "CAERO4", "CAERO5", "PAERO1", "PAERO2", "PAERO3",
                  "PAERO4", "PAERO5", "SPLINE1", "SPLINE2", "SPLINE3", "SPLINE4", "SPLINE5", "SET1", "SET2", "SET3",
                  "AELIST", "AESURF", "AESURFS", "AESTAT", "AELINK", "AEPARM", "AEFACT", "TRIM", "TRIM2", "FLUTTER",
                  "FLFACT", "MKAERO1", "MKAERO2", "MONPNT1", "MONPNT2", "MONPNT3", "CSSCHD", "GUST", "DIVERG",
                  "DESVAR", "DVPREL1", "DVPREL2", "DVMREL1", "DVMREL2", "DVCREL1", "DVCREL2", "DVGRID", "DRESP1",
                  "DRESP2", "DRESP3", "DCONSTR", "DCONADD", "DOPTPRM", "DEQATN", "DTABLE", "DLINK", "DSCREEN",
                  "DLOAD", "TLOAD1", "TLOAD2", "RLOAD1", "RLOAD2", "TABLED1", "TABLED2", "TABLED3", "TABLED4",
                  "TABDMP1", "TABRND1", "TABRNDG", "DAREA", "DELAY", "DPHASE", "RANDPS", "NLCNTLG", "MONDSP1", "EPOINT",
                  "AECOMP", "AECOMPL", "PLOTEL", "UXVEC", "AEDW", "AEFORCE", "AEPRESS", "SPLINRB"}
# Case control selectors of DMIG matrices (direct matrix input).
DMIG_SELECTORS = ("K2GG", "M2GG", "B2GG", "K42GG", "K2PP", "M2PP", "B2PP")
# Static (Guyan) reduction sets: flexgvt solves the full model (named in a note).
REDUCTION_CARDS = {"ASET", "ASET1", "OMIT", "OMIT1"}
# Bulk cards flexgvt reads (anything else present in the deck is reported as unsupported).
READ_CARDS = set(SUPPORTED_ELEMENTS + SUPPORTED_PROPERTIES + SUPPORTED_LOADS) | {
    "GRID", "GRDSET", "MAT1", "CORD2R", "CORD2C", "CORD2S", "CORD1R", "CORD1C", "CORD1S", "SPC", "SPC1", "SPCADD",
    "LOAD", "MPC", "MPCADD", "SUPORT", "SUPORT1", "CMASS1", "CMASS2", "PMASS"}
# Cards read by pyNastran into dictionaries we inspect, mapped to where unsupported ones are listed.
# Id namespaces as pyNastran keeps them (Nastran accepts, e.g., an RBAR and a CONM2 with the same id).
ELEMENT_NAMESPACE = ("CBAR", "CBEAM", "CROD", "CONROD", "CTUBE", "CQUAD4", "CTRIA3", "CQUAD8", "CTRIA6", "CQUADR",
                     "CTRIAR", "CSHEAR", "CHEXA", "CPENTA", "CTETRA", "CELAS1", "CELAS2", "CELAS3", "CELAS4", "CDAMP1",
                     "CDAMP2", "CDAMP3", "CDAMP4", "CVISC", "CBUSH", "CBUSH1D", "CGAP")
MASS_NAMESPACE = ("CONM1", "CONM2", "CMASS1", "CMASS2", "CMASS3", "CMASS4")
RIGID_NAMESPACE = ("RBE2", "RBE3", "RBAR", "RBE1", "RROD", "RSPLINE")
PROPERTY_NAMESPACE = ("PBAR", "PBARL", "PBEAM", "PBEAML", "PROD", "PTUBE", "PSHELL", "PCOMP", "PCOMPG", "PSHEAR",
                      "PSOLID", "PELAS", "PDAMP", "PVISC", "PBUSH", "PBUSH1D", "PGAP", "PMASS")
MATERIAL_NAMESPACE = ("MAT1", "MAT2", "MAT8", "MAT9")
COORD_NAMESPACE = ("CORD2R", "CORD2C", "CORD2S", "CORD1R", "CORD1C", "CORD1S")
STRUCTURAL_PARAMS_IGNORED = {"G": "structural damping (PARAM,G) is not modelled",
                             "W3": "PARAM,W3 (structural damping reference) is not modelled",
                             "W4": "PARAM,W4 (element damping reference) is not modelled"}



def _supported_shapes():
    from ._sections import SUPPORTED_SHAPES
    return SUPPORTED_SHAPES


def _natural(x):
    s = str(x)
    return (0, int(s)) if s.isdigit() else (1, s)




class CardsMixin:
    """Part of the bulk data reader (see _read._Reader)."""

    def classify_dmig(self) -> None:
        """DMIG matrices: Nastran adds one to the model only where the case control selects it (K2GG,
        M2GG, B2GG, K42GG on the structure; K2PP, M2PP, B2PP on the structure plus extra points).
        A DMIG selected by none, or only by the p-set matrices with every row and column on an
        EPOINT (extra points carry no structure: e.g. a 1 on a dynamic-load point), leaves the
        structure's static and modal solution unchanged: noted. Any other use is unsupported."""
        bdf = self.bdf
        dmigs = getattr(bdf, "dmig", None) or {}
        if not dmigs:
            return
        epoints = set(int(e) for e in (getattr(bdf, "epoints", None) or {}))
        selected: dict[str, set[str]] = {}
        deck = getattr(bdf, "case_control_deck", None)
        for subcase in (deck.subcases.values() if deck is not None else []):
            for key, value in subcase.params.items():
                if key in DMIG_SELECTORS:
                    text = str(value).upper().split("=", 1)[-1]
                    for name in re.findall(r"[A-Z][A-Z0-9_]*", text):
                        selected.setdefault(name, set()).add(key)
        for name, matrix in sorted(dmigs.items()):
            uses = selected.get(str(name).upper(), set())
            pairs = [np.asarray(matrix.GCj, dtype=object).reshape(-1, 2),
                     np.asarray(matrix.GCi, dtype=object).reshape(-1, 2)]
            points = {int(g) for block in pairs for g, _ in block}
            if not uses:
                self.notes.append(f"{self.at('DMIG', name)}: not selected by K2GG/M2GG/B2GG/K2PP/M2PP/B2PP in any "
                                  "subcase: ignored, as Nastran does")
            elif uses <= {"K2PP", "M2PP", "B2PP"} and points <= epoints:
                self.notes.append(f"{self.at('DMIG', name)}: selected by {'/'.join(sorted(uses))} on extra points "
                                  f"(EPOINT {', '.join(map(str, sorted(points)))}) only: no effect on the structure")
            else:
                on = "extra points and grids" if points & epoints else "the structure's grids"
                self.skip(f"DMIG ({'/'.join(sorted(uses))} on {on}: direct matrix input)", str(name))

    # ----------------------------------------------------------------- everything else
    def list_other_cards(self) -> None:
        bdf = self.bdf
        used_pids = {getattr(e, "pid", None) for e in list(bdf.elements.values()) + list(bdf.masses.values())}
        used_mids = {getattr(p, "mid", None) for p in bdf.properties.values() if getattr(p, "pid", None) in used_pids}
        for p in bdf.properties.values():
            used_mids.update(getattr(p, "mids", []) or [])
        reduced = sorted(name for name in bdf.card_count if name in REDUCTION_CARDS)
        if reduced:
            self.notes.append(f"{'/'.join(reduced)} (Guyan reduction to an analysis set) not applied: flexgvt solves "
                              "the full model, so the higher modes will differ from Nastran's (the reduced model is "
                              "stiffer; the lowest modes agree when the set is well chosen)")
        self.classify_dmig()
        skipped = sorted(name for name in bdf.card_count if name in NON_STRUCTURAL)
        if skipped:
            self.notes.append(f"non-structural cards ignored: {', '.join(skipped)}")
        for name, count in bdf.card_count.items():
            if name in READ_CARDS or name in IGNORED_CARDS or name in NON_STRUCTURAL or name in REDUCTION_CARDS or \
                    name in self.unsupported or name == "DMIG":
                continue
            ids = sorted({ident for (n, ident) in self.index.places if n == name}, key=_natural)
            if name in PROPERTY_NAMESPACE or name in MATERIAL_NAMESPACE:
                used = used_pids if name in PROPERTY_NAMESPACE else used_mids
                unused = [i for i in ids if i.isdigit() and int(i) not in used]
                if unused:
                    self.notes.append(f"{name} {', '.join(unused)} not used by any element: ignored")
                ids = [i for i in ids if i not in unused]
                if not ids:
                    continue
            self.unsupported.setdefault(name, []).extend(ids or [f"{count} card(s)"])
        for card in getattr(self.bdf, "reject_cards", []) or []:
            name = str(card[0]).upper().rstrip("*") if card else "?"
            self.unsupported.setdefault(name, []).append(str(card[1]) if len(card) > 1 else "?")
