"""The one place for cards no family reads: which are ignored on purpose (non-structural, methods,
DMIG not selected) and which are reported unsupported, with their ids."""

from __future__ import annotations

import re

import numpy as np

from ._deck import Deck, Findings
from ._parse import MATERIAL_NAMESPACE, PROPERTY_NAMESPACE

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
                  "DLOAD", "TLOAD1", "TLOAD2", "RLOAD1", "RLOAD2", "TABLED2", "TABLED3", "TABLED4",
                  "TABDMP1", "TABRND1", "TABRNDG", "DAREA", "DELAY", "DPHASE", "RANDPS", "NLCNTLG", "MONDSP1", "EPOINT",
                  "AECOMP", "AECOMPL", "PLOTEL", "UXVEC", "AEDW", "AEFORCE", "AEPRESS", "SPLINRB"}
# Case control selectors of DMIG matrices (direct matrix input).
DMIG_SELECTORS = ("K2GG", "M2GG", "B2GG", "K42GG", "K2PP", "M2PP", "B2PP")
# Element types flexgvt does not have, with what to use instead (named in read_bdf's one error).
ELEMENT_HINTS = {
    "CQUAD8": "8-node quads: remesh with CQUAD4", "CTRIA6": "6-node triangles: remesh with CTRIA3",
    "CQUAD": "remesh with CQUAD4", "CQUADX": "axisymmetric: model the full shell with CQUAD4",
    "CTRIAX": "axisymmetric: model the full shell with CTRIA3", "CTRIAX6": "axisymmetric: model with CTRIA3",
    "CSHEAR": "shear panels: replace with CQUAD4 on a membrane PSHELL (MID1 only)",
    "CHEXA": "solids: replace with shells (CQUAD4/CTRIA3) or beams", "CPENTA": "solids: replace with shells or beams",
    "CTETRA": "solids: replace with shells or beams", "CPYRAM": "solids: replace with shells or beams",
    "CTUBE": "use CROD/PROD with the tube's A and J", "PLOAD2": "plate pressure is not yet a load in flexgvt",
    "PLOAD4": "plate pressure is not yet a load in flexgvt",
}


def unsupported_hints(names) -> str:
    """'; CQUAD8: 8-node quads: remesh with CQUAD4 ...' for the unsupported names that have a hint."""
    found = [f"{n}: {ELEMENT_HINTS[n]}" for n in sorted(names) if n in ELEMENT_HINTS]
    return (" (" + "; ".join(found) + ")") if found else ""


def _natural(x):
    s = str(x)
    return (0, int(s)) if s.isdigit() else (1, s)


def classify_dmig(deck: Deck, log: Findings) -> None:
    """DMIG matrices: Nastran adds one to the model only where the case control selects it (K2GG,
    M2GG, B2GG, K42GG on the structure; K2PP, M2PP, B2PP on the structure plus extra points).
    A DMIG selected by none, or only by the p-set matrices with every row and column on an
    EPOINT (extra points carry no structure: e.g. a 1 on a dynamic-load point), leaves the
    structure's static and modal solution unchanged: noted. Any other use is unsupported."""
    bdf = deck.bdf
    dmigs = getattr(bdf, "dmig", None) or {}
    if not dmigs:
        return
    epoints = set(int(e) for e in (getattr(bdf, "epoints", None) or {}))
    selected: dict[str, set[str]] = {}
    ccd = getattr(bdf, "case_control_deck", None)
    for subcase in (ccd.subcases.values() if ccd is not None else []):
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
            log.note(f"{deck.at('DMIG', name)}: not selected by K2GG/M2GG/B2GG/K2PP/M2PP/B2PP in any "
                              "subcase: ignored, as Nastran does")
        elif uses <= {"K2PP", "M2PP", "B2PP"} and points <= epoints:
            log.note(f"{deck.at('DMIG', name)}: selected by {'/'.join(sorted(uses))} on extra points "
                              f"(EPOINT {', '.join(map(str, sorted(points)))}) only: no effect on the structure")
        else:
            on = "extra points and grids" if points & epoints else "the structure's grids"
            log.skip(f"DMIG ({'/'.join(sorted(uses))} on {on}: direct matrix input)", str(name))

def list_other_cards(deck: Deck, log: Findings, read_cards: frozenset[str]) -> None:
    """Every card no family reads: ignored with a note (non-structural, unused
    properties and materials, DMIG not selected) or recorded unsupported with its ids."""
    bdf = deck.bdf
    used_pids = {getattr(e, "pid", None) for e in list(bdf.elements.values()) + list(bdf.masses.values())}
    used_mids = {getattr(p, "mid", None) for p in bdf.properties.values() if getattr(p, "pid", None) in used_pids}
    for p in bdf.properties.values():
        used_mids.update(getattr(p, "mids", []) or [])
    classify_dmig(deck, log)
    skipped = sorted(name for name in bdf.card_count if name in NON_STRUCTURAL)
    if skipped:
        log.note(f"non-structural cards ignored: {', '.join(skipped)}")
    for name, count in bdf.card_count.items():
        if name in read_cards or name in IGNORED_CARDS or name in NON_STRUCTURAL or \
                name in log.unsupported or name == "DMIG":
            continue
        ids = sorted({ident for (n, ident) in deck.index.places if n == name}, key=_natural)
        if name in PROPERTY_NAMESPACE or name in MATERIAL_NAMESPACE:
            used = used_pids if name in PROPERTY_NAMESPACE else used_mids
            unused = [i for i in ids if i.isdigit() and int(i) not in used]
            if unused:
                log.note(f"{name} {', '.join(unused)} not used by any element: ignored")
            ids = [i for i in ids if i not in unused]
            if not ids:
                continue
        log.unsupported.setdefault(name, []).extend(ids or [f"{count} card(s)"])
    for card in getattr(bdf, "reject_cards", []) or []:
        name = str(card[0]).upper().rstrip("*") if card else "?"
        log.unsupported.setdefault(name, []).append(str(card[1]) if len(card) > 1 else "?")
