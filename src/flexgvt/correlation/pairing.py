"""One-to-one pairing of measured and analytical modes: MAC first, frequency as tie-break, a MAC
floor below which a measured mode stays unpaired; without shapes, by frequency among the modes of
the measured mode's family (its label: "5 OOP" is out-of-plane bending). Every measured mode left
unpaired carries its reason (Unpaired)."""

from __future__ import annotations

import re
from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..errors import ModelError
from .mac import _pair_shapes, mac_of

TIE_BREAK = 0.01  # weight of the frequency closeness |ln(f_a / f_m)| (capped at 1) against MAC
UNSEEN = 1e-6  # a mode whose reading at the sensors is below this fraction of its amplitude is not seen
_FORBIDDEN = 1e6  # cost of a pair the frequency ratio, the labels or the sensors rule out

# Words of a mode label -> its family (flexgvt.fem.labels.CLASSES); a word not listed says nothing.
_FAMILY_WORDS = {
    "OOP": ("oop", "out-of-plane", "outofplane", "flap", "flapwise", "flatwise", "vertical"),
    "IP": ("ip", "in-plane", "inplane", "chord", "chordwise", "edgewise", "lag", "lead-lag", "leadlag"),
    "T": ("t", "torsion", "torsional", "twist"),
    "EXT": ("ext", "extension", "axial"),
    "RB": ("rb", "rigid", "pendulum", "plunge", "heave", "roll", "pitch", "yaw", "suspension"),
    # a distributed cord's own modes (fem.labels: 'k bungee surge', 'k bungee string')
    "CORD": ("bungee", "surge", "string", "cord"),
    # a real root of the damped problem (fem.labels: 'overdamped k'): it never pairs a vibration mode
    "OVERDAMPED": ("overdamped",),
}
_WORD_FAMILY = {w: fam for fam, words in _FAMILY_WORDS.items() for w in words}
REASONS = ("no_mode_in_range", "label_mismatch", "not_seen", "mac_below_floor", "taken")


def label_families(label: str) -> frozenset[str]:
    """The mode families a label names: '5 OOP' -> {OOP}, '1 T/OOP' -> {T, OOP}, 'RB plunge' -> {RB},
    'torsion 2' -> {T}; empty when it names none ('mode 3', '')."""
    words = re.findall(r"[a-z]+(?:-[a-z]+)*", str(label).lower())
    return frozenset(_WORD_FAMILY[w] for w in words if w in _WORD_FAMILY)


def labels_compatible(measured: str, analytical: str) -> bool:
    """False when both labels name families and share none (a measured OOP mode never pairs an FE IP
    mode); True otherwise (a label that names no family constrains nothing)."""
    a, b = label_families(measured), label_families(analytical)
    return not (a and b) or bool(a & b)


@dataclass(frozen=True)
class Unpaired:
    """A measured mode left unpaired and why. reason: 'no_mode_in_range' (no analytical mode within
    the frequency ratio), 'label_mismatch' (those in range are of another family), 'not_seen' (the
    sensors see none of those in range, or the measured shape is zero), 'mac_below_floor' (best MAC
    below the floor), 'taken' (its candidates paired with other measured modes). best_*: the
    analytical mode the text names (1-based), its MAC, frequency [Hz] and label."""

    mode: int
    reason: str
    text: str
    measured_hz: float
    label: str = ""
    best_mode: int | None = None
    best_mac: float | None = None
    best_hz: float | None = None
    best_label: str = ""
    configuration: str = ""

    def to_dict(self) -> dict:
        return asdict(self)

    def __str__(self) -> str:
        where = f"configuration '{self.configuration}', " if self.configuration else ""
        name = f" ({self.label})" if self.label else ""
        return f"{where}measured mode {self.mode}{name} at {self.measured_hz:.4g} Hz: {self.text}"


def explain_unpaired(i: int, fm: np.ndarray, fa: np.ndarray, paired: np.ndarray, *, usable: np.ndarray,
                     in_range: np.ndarray, label_ok: np.ndarray | None = None, seen: np.ndarray | None = None,
                     macm: np.ndarray | None = None, mac_floor: float = 0.0, measured_zero: bool = False,
                     measured_labels=(), analytical_labels=(), max_frequency_ratio: float | None = None,
                     configuration: str = "") -> Unpaired:
    """Why measured mode ``i`` is unpaired. paired: (n_measured,) analytical index or -1; usable: the
    analytical modes that may pair at all (elastic); in_range (n_measured, n_analytical): within the
    frequency ratio; label_ok: label families compatible; seen: (n_analytical,) the sensors see the
    mode; macm: MAC matrix (None without shapes)."""
    ml = measured_labels[i] if i < len(measured_labels) else ""
    al = lambda j: analytical_labels[j] if j < len(analytical_labels) else ""  # noqa: E731

    def out(reason, text, j=None):
        return Unpaired(i + 1, reason, text, float(fm[i]), ml, None if j is None else int(j) + 1,
                        None if j is None or macm is None else float(macm[i, j]),
                        None if j is None else float(fa[j]), "" if j is None else al(j), configuration)

    def name(j):
        return f"FE mode {j + 1}" + (f" ({al(j)})" if al(j) else "") + f" at {fa[j]:.4g} Hz"

    idx = np.flatnonzero(usable)
    ratio = "" if max_frequency_ratio is None else f" within a factor {max_frequency_ratio:g}"
    if measured_zero:
        return out("not_seen", "its measured shape is zero at every sensor: check the channels of this mode")
    cand = idx[in_range[i, idx]]
    if not len(cand):
        if not len(idx):
            return out("no_mode_in_range", "no elastic FE mode was analysed: analyse more modes (n_modes)")
        near = idx[np.argmin(np.abs(np.log(np.maximum(fa[idx], 1e-300) / fm[i])))]
        return out("no_mode_in_range", f"no FE mode{ratio} of its frequency (nearest: {name(near)}); analyse more "
                   "modes (n_modes), or widen max_frequency_ratio if the model is that far off", near)
    if label_ok is not None:
        same = cand[label_ok[i, cand]]
        if not len(same):
            near = cand[np.argmin(np.abs(np.log(fa[cand] / fm[i])))]
            fam = "/".join(sorted(label_families(ml)))
            return out("label_mismatch", f"no FE mode of its family ({fam}){ratio} of its frequency; the nearest "
                       f"in range is {name(near)}: check the label, or analyse more modes", near)
        cand = same
    if seen is not None:
        visible = cand[seen[cand]]
        if not len(visible):
            return out("not_seen", f"the sensors see none of the {len(cand)} FE mode(s){ratio} of its frequency "
                       "(their shapes are ~0 at the sensors): check the sensors' mapping to FE nodes and their "
                       "directions", cand[np.argmin(np.abs(np.log(fa[cand] / fm[i])))])
        cand = visible
    taken = {int(j): k for k, j in enumerate(paired) if j >= 0}
    if macm is not None:
        best = cand[np.argmax(macm[i, cand])]
        if macm[i, best] < mac_floor:
            return out("mac_below_floor", f"best MAC {macm[i, best]:.2f} with {name(best)}, below the floor "
                       f"{mac_floor:g}: a mode the model lacks, a poorly identified shape, or test points mapped to "
                       "the wrong FE nodes", best)
        k = taken.get(int(best))
        return out("taken", f"its best match {name(best)} (MAC {macm[i, best]:.2f}) is paired with measured mode "
                   f"{k + 1 if k is not None else '?'}, and no other FE mode{ratio} reaches the MAC floor "
                   f"{mac_floor:g}", best)
    best = cand[np.argmin(np.abs(np.log(fa[cand] / fm[i])))]
    k = taken.get(int(best))
    return out("taken", f"every FE mode{ratio} of its frequency that may pair is paired with another measured mode "
               f"(nearest: {name(best)}, paired with measured mode {k + 1 if k is not None else '?'}): analyse more "
               "modes (n_modes) or check the labels", best)


def _log_ratio(fm: np.ndarray, fa: np.ndarray) -> np.ndarray:
    """|ln(f_a / f_m)| (n_measured, n_analytical); 0 where a frequency is not positive."""
    ok = (fa[None, :] > 0) & (fm[:, None] > 0)
    r = np.abs(np.log(np.where(fa[None, :] > 0, fa[None, :], 1.0) / np.where(fm[:, None] > 0, fm[:, None], 1.0)))
    return np.where(ok, np.nan_to_num(r, nan=0.0), 0.0)


def _in_range(fm, fa, max_frequency_ratio) -> np.ndarray:
    if max_frequency_ratio is None:
        return np.ones((len(fm), len(fa)), bool)
    if not max_frequency_ratio > 1.0:
        raise ModelError(f"pair: max_frequency_ratio={max_frequency_ratio} must be > 1")
    return ~(_log_ratio(fm, fa) > np.log(max_frequency_ratio))


def label_matrix(measured_labels, analytical_labels, n_measured: int, n_analytical: int) -> np.ndarray | None:
    """(n_measured, n_analytical) label compatibility, or None when no measured label names a family."""
    ml = [measured_labels[i] if i < len(measured_labels) else "" for i in range(n_measured)]
    if not any(label_families(x) for x in ml):
        return None
    al = [analytical_labels[j] if j < len(analytical_labels) else "" for j in range(n_analytical)]
    return np.array([[labels_compatible(a, b) for b in al] for a in ml], bool).reshape(n_measured, n_analytical)


@dataclass(frozen=True)
class Pairing:
    """measured, analytical: paired indices (n_pairs,); mac and frequency_error ((f_a - f_m) / f_m)
    of each pair (mac NaN when paired by frequency); unpaired: measured modes left unpaired;
    mac_matrix: the full (n_measured, n_analytical) MAC (None by frequency); reasons: an Unpaired
    per unpaired mode."""

    measured: np.ndarray
    analytical: np.ndarray
    mac: np.ndarray
    frequency_error: np.ndarray
    unpaired: tuple[int, ...]
    mac_matrix: np.ndarray | None
    measured_hz: np.ndarray
    analytical_hz: np.ndarray
    labels: tuple[str, ...] = ()
    reasons: tuple[Unpaired, ...] = ()

    def table(self) -> list[dict]:
        """Rows for a report: every measured mode, paired or not (with the reason when not)."""
        rows = []
        lookup = dict(zip(self.measured.tolist(), range(len(self.measured))))
        why = {u.mode - 1: u for u in self.reasons}
        for i, fm in enumerate(self.measured_hz):
            k = lookup.get(i)
            if k is None:
                best = None if self.mac_matrix is None else float(self.mac_matrix[i].max(initial=0.0))
                rows.append({"measured_mode": i + 1, "measured_hz": float(fm), "analytical_mode": None,
                             "analytical_hz": None, "error_percent": None, "mac": best, "label": "unpaired",
                             "reason": why[i].text if i in why else ""})
                continue
            j = int(self.analytical[k])
            rows.append({"measured_mode": i + 1, "measured_hz": float(fm), "analytical_mode": j + 1,
                         "analytical_hz": float(self.analytical_hz[j]),
                         "error_percent": 100 * float(self.frequency_error[k]),
                         "mac": None if np.isnan(self.mac[k]) else float(self.mac[k]),
                         "label": self.labels[j] if j < len(self.labels) else "", "reason": ""})
        return rows

    def report(self) -> str:
        if not self.unpaired:
            return f"{len(self.measured)} measured modes paired"
        return (f"{len(self.measured)} paired; {len(self.unpaired)} left unpaired:\n"
                + "\n".join(f"  {u}" for u in self.reasons))


def _finish(rows, cols, fm, fa, n_measured, macm, labels, kw, zero=None) -> Pairing:
    """The Pairing of the pairs (rows, cols), with the reasons of the measured modes left out."""
    paired = np.full(n_measured, -1)
    paired[rows] = cols
    err = (fa[cols] - fm[rows]) / np.where(fm[rows] != 0, fm[rows], np.nan)
    mac = macm[rows, cols] if macm is not None else np.full(len(rows), np.nan)
    reasons = tuple(explain_unpaired(i, fm, fa, paired, macm=macm, analytical_labels=labels,
                                     measured_zero=zero is not None and bool(zero[i]), **kw)
                    for i in np.flatnonzero(paired < 0))
    return Pairing(rows, cols, mac, err, tuple(u.mode - 1 for u in reasons), macm, fm, fa, labels, reasons)


def pair(measured, modes, sensors=None, mac_floor: float = 0.5, exclude_rigid: bool = True,
         max_frequency_ratio: float | None = 2.0, seen: np.ndarray | None = None,
         configuration: str = "") -> Pairing:
    """Pair measured modes (ModalSet or (n, n_rows) array with frequencies given by ``measured``'s
    frequencies_hz) with analytical ones (fem Modes, reduced to the sensors).

    The assignment maximises the sum of MAC - 0.01 min(|ln(f_a / f_m)|, 1) (scipy's
    linear_sum_assignment): MAC decides, frequency only breaks near-ties. exclude_rigid leaves out
    analytical modes at 0 Hz (rigid-body modes of a free model); a suspended model's pendulum and
    plunge modes have frequencies and pair with measured suspension modes like any other.
    max_frequency_ratio: an analytical mode more than this factor away in frequency never pairs
    (a few sensors can see a far mode's tiny motion with a high MAC; None: no limit). seen:
    (n_analytical,) whether the sensors see each analytical mode (default: its reading is above
    1e-6 of its largest amplitude when ``modes`` carries full shapes, of the largest reading among
    the modes otherwise); an unseen mode never pairs. Unpaired modes carry their reasons
    (Pairing.reasons)."""
    A, B, _ = _pair_shapes(measured, modes, sensors)
    fm = np.asarray(getattr(measured, "frequencies_hz", np.full(len(A), np.nan)), float)
    fa = np.asarray(getattr(modes, "frequencies_hz", np.full(len(B), np.nan)), float)
    if not 0.0 <= mac_floor <= 1.0:
        raise ModelError(f"pair: mac_floor={mac_floor} must lie in [0, 1]")
    macm = mac_of(A, B)
    usable = np.ones(len(B), bool)
    if exclude_rigid and np.isfinite(fa).all():
        usable &= fa > 0
    if seen is None:
        seen = sensors_see(B, getattr(modes, "shapes", None))
    seen = np.asarray(seen, bool)
    a_norm = np.linalg.norm(A, axis=1)
    zero = a_norm <= 1e-12 * max(a_norm.max(initial=0.0), 1e-300)
    closeness = np.minimum(_log_ratio(fm, fa), 1.0)
    in_range = _in_range(fm, fa, max_frequency_ratio)
    allowed = usable[None, :] & in_range & seen[None, :] & ~zero[:, None]
    score = np.where(allowed, macm - TIE_BREAK * closeness, -1.0)
    rows, cols = linear_sum_assignment(-score) if len(A) and usable.any() else (np.zeros(0, int), np.zeros(0, int))
    keep = (macm[rows, cols] >= mac_floor) & allowed[rows, cols]
    labels = tuple(getattr(modes, "labels", ()) or ())
    return _finish(rows[keep], cols[keep], fm, fa, len(A), macm, labels, dict(
        usable=usable, in_range=in_range, seen=seen, mac_floor=mac_floor,
        measured_labels=tuple(getattr(measured, "labels", ()) or ()), max_frequency_ratio=max_frequency_ratio,
        configuration=configuration), zero)


def sensors_see(readings: np.ndarray, full=None) -> np.ndarray:
    """(n_modes,) whether the sensors see each mode: its reading norm (rows of ``readings``) above
    1e-6 of its largest amplitude in ``full`` ((n_modes, ...) full shapes), or without them of the
    largest reading norm among the modes."""
    norm = np.linalg.norm(np.asarray(readings), axis=1)
    if full is not None and np.ndim(full) >= 2 and len(full) == len(norm):
        scale = np.abs(np.asarray(full)).reshape(len(norm), -1).max(axis=1)
    else:
        scale = np.full(len(norm), norm.max(initial=0.0))
    return norm > UNSEEN * scale


def pair_by_frequency(measured_hz, analytical_hz, *, measured_labels=(), analytical_labels=(),
                      max_frequency_ratio: float | None = 2.0, seen: np.ndarray | None = None,
                      usable: np.ndarray | None = None, configuration: str = "") -> Pairing:
    """Pair measured modes without shapes by frequency: least squares on log frequency among the
    analytical modes that may pair: elastic (f > 0, or ``usable``), seen by the sensors (``seen``),
    within ``max_frequency_ratio`` and, when the labels name mode families ('5 OOP', '2 T'), of the
    measured mode's family (a measured OOP mode never pairs an FE IP mode, however close). Unpaired
    modes carry their reasons."""
    fm = np.asarray(measured_hz, float)
    fa = np.asarray(analytical_hz, float)
    usable = (fa > 0) if usable is None else np.asarray(usable, bool) & (fa > 0)
    in_range = _in_range(fm, fa, max_frequency_ratio)
    label_ok = label_matrix(measured_labels, analytical_labels, len(fm), len(fa))
    allowed = usable[None, :] & in_range
    if seen is not None:
        allowed &= np.asarray(seen, bool)[None, :]
    if label_ok is not None:
        allowed &= label_ok
    # Squared: the sum of |log| is the same for every assignment of a cluster lying on one side of
    # the measured frequencies, so the order would be left to round-off.
    cost = np.where(allowed, _log_ratio(fm, fa) ** 2, _FORBIDDEN)
    rows, cols = linear_sum_assignment(cost) if len(fm) and len(fa) else (np.zeros(0, int), np.zeros(0, int))
    keep = allowed[rows, cols]
    return _finish(rows[keep], cols[keep], fm, fa, len(fm), None, tuple(analytical_labels), dict(
        usable=usable, in_range=in_range, label_ok=label_ok, seen=None if seen is None else np.asarray(seen, bool),
        measured_labels=tuple(measured_labels), max_frequency_ratio=max_frequency_ratio,
        configuration=configuration))
