"""The result of an updating run: the updated model, per-configuration tables, MAC matrices,
design-variable table, convergence history and the identifiability report."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from ..model import Configuration, Model
from .problem import Point, UpdatingProblem
from .settings import renamed

RANK_TOLERANCE = 1e-6  # singular values below this fraction of the largest count as unseen


@dataclass
class UpdateResult:
    """model: the updated model (a new object; the input model is untouched); configurations: the
    configurations at the updated point (cord values changed where variables set them); x: the
    normalised design point; variables: design-variable table; tables: {configuration: rows of
    measured, initial, updated, errors, MAC}; mac: {configuration: (initial, updated) MAC
    matrices (measured x analytical) or None}; history: one row per accepted iterate;
    identifiability: sensitivity rank, condition number, unseen variables, standard deviations;
    unpaired: {"initial" / "updated": {configuration: reasons (flexgvt.correlation.Unpaired as
    dicts) of the measured modes left unpaired}}; warnings: what the run warned about; stages: one
    row per solve when unconstrained variables were held and the problem solved again."""

    model: Model
    configurations: dict[str, Configuration]
    x: np.ndarray
    variables: list[dict]
    tables: dict[str, list[dict]]
    mac: dict
    history: list[dict]
    identifiability: dict
    initial: Point
    final: Point
    method: str
    message: str
    success: bool
    seconds: float
    solves: int
    gradients: int
    starts: list[dict] = field(default_factory=list)
    unpaired: dict = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    stages: list[dict] = field(default_factory=list)

    def summary(self) -> str:
        lines = [f"updating ({self.method}): objective {self.initial.objective:.4g} -> {self.final.objective:.4g} in "
                 f"{len(self.history) - 1} iterations, {self.solves} solves, {self.gradients} gradients, "
                 f"{self.seconds:.2f} s ({self.message})"]
        for name, rows in self.tables.items():
            e0 = [abs(r["initial_error_percent"]) for r in rows if r["updated_hz"] is not None]
            e1 = [abs(r["updated_error_percent"]) for r in rows if r["updated_hz"] is not None]
            lines.append(f"  {name}: max |error| {max(e0, default=0):.3f} % -> {max(e1, default=0):.3f} %")
            for r in rows:
                if r.get("unpaired_reason"):
                    lines.append(f"    measured mode {r['mode']} unpaired: {r['unpaired_reason']}")
        if str(self.identifiability.get("sigma_source", "")).startswith("none"):
            lines.append("  standard deviations unknown: no more residuals than variables and no measured standard "
                         "deviations (give frequency_std_hz, or fewer variables)")
        for title, group in (("held at their initial value, the data do not constrain them",
                              [r for r in self.variables if r.get("fixed")]),
                             ("not identifiable, left free (unidentifiable='free')",
                              [r for r in self.variables if not r.get("fixed") and not r.get("identifiable", True)])):
            if group:
                lines.append(f"  {len(group)} variable(s) {title}:")
                lines += [f"    {r['name']}: {r['reason']}" for r in group]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """A JSON-ready dictionary (the documented --json layout)."""
        return jsonable({"method": self.method, "message": self.message, "success": self.success,
                "seconds": self.seconds, "solves": self.solves, "gradients": self.gradients, "x": self.x.tolist(),
                "objective": {"initial": self.initial.objective, "final": self.final.objective},
                "variables": self.variables, "configurations": self.tables,
                "mac": {n: None if m is None else {"initial": m[0].tolist(), "updated": m[1].tolist()}
                        for n, m in self.mac.items()},
                "identifiability": {k: (v.tolist() if isinstance(v, np.ndarray) else v)
                                    for k, v in self.identifiability.items()},
                "history": [{k: v for k, v in row.items() if k != "residuals"} for row in self.history],
                "starts": self.starts, "unpaired": self.unpaired, "warnings": self.warnings,
                "stages": self.stages})

    def as_dict(self) -> dict:
        """Deprecated: to_dict()."""
        renamed("UpdateResult.as_dict()", "UpdateResult.to_dict()")
        return self.to_dict()


def jsonable(value):
    """numpy scalars and arrays inside dicts and lists -> plain Python (json.dumps takes the result)."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def configuration_tables(problem: UpdatingProblem, initial: Point, final: Point, pairing=None) -> dict[str, list[dict]]:
    """{configuration: one row per measured mode}: measured, initial and updated frequencies and
    errors, MAC, and the reason a mode is unpaired at the updated point (``pairing``: the
    problem's PairingPolicy, which explains it)."""
    out = {}
    for cfg in problem.configurations:
        meas = problem.measured[cfg.name]
        a, b = initial.configurations[cfg.name], final.configurations[cfg.name]
        labels_b = b.labels
        why = {u.mode - 1: u.text for u in (pairing.explain(meas, b) if pairing is not None else ())}
        rows = []
        for i, fm in enumerate(meas.frequencies_hz):
            ia, ib = a.paired[i], b.paired[i]
            f0 = float(a.frequencies_hz[ia]) if ia >= 0 else None
            f1 = float(b.frequencies_hz[ib]) if ib >= 0 else None
            rows.append({
                "mode": i + 1, "label": meas.labels[i] if i < len(meas.labels) else (labels_b[ib] if ib >= 0 else ""),
                "measured_hz": float(fm),
                "measured_std_hz": None if meas.frequency_std_hz is None else float(meas.frequency_std_hz[i]),
                "initial_mode": int(ia) + 1 if ia >= 0 else None, "initial_hz": f0,
                "initial_error_percent": None if f0 is None else 100 * (f0 - fm) / fm,
                "updated_mode": int(ib) + 1 if ib >= 0 else None, "updated_hz": f1,
                "updated_error_percent": None if f1 is None else 100 * (f1 - fm) / fm,
                "initial_mac": None if np.isnan(a.mac[i]) else float(a.mac[i]),
                "updated_mac": None if np.isnan(b.mac[i]) else float(b.mac[i]),
                "paired": bool(ib >= 0), "unpaired_reason": why.get(i)})
        out[cfg.name] = rows
    return out


def identifiability(problem: UpdatingProblem, point: Point, max_relative_std: float = 0.5) -> dict:
    """Rank and condition of the (weighted, normalised) sensitivity matrix, the directions the data
    cannot see, and which variables the data constrain (judge): sigma from the measured frequency
    standard deviations where given, else from the residual (s^2 = |r|^2 / (m - n))."""
    J = point.data_jacobian  # what the data see (a prior's rows would make every variable look identified)
    names = problem.par.names
    m, n = J.shape
    s, vt, null, rank = _null(J)
    cond = float(s[0] / s[-1]) if len(s) and s[-1] > 0 and len(s) == n else float("inf")
    # Directions of the design space the data do not see (components above 0.1 listed).
    combinations = [{names[k]: float(row[k]) for k in np.flatnonzero(np.abs(row) > 0.1)} for row in null]
    sigma2, source = _residual_variance(problem, point, m, n)
    s_inv = np.zeros(n)
    s_inv[:rank] = 1 / s[:rank]
    verdict = judge(J, sigma2, names, max_relative_std, [b.variable.shifts for b in problem.par.bindings])
    return {"rank": rank, "n_variables": n, "n_residuals": m, "condition_number": cond,
            "singular_values": s, "unidentifiable": [names[k] for k in np.flatnonzero(~verdict["identifiable"])],
            "unseen_combinations": combinations, "std_normalised": verdict["std"],
            "identifiable": verdict["identifiable"], "reasons": verdict["reasons"],
            "covariance": (vt.T * s_inv**2) @ vt * sigma2,
            "max_relative_std": max_relative_std, "sigma_source": source}


def _null(J: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """(singular values, V^T (n, n: the unseen directions too when there are fewer rows than
    columns), the rows of V^T the data do not see, rank) of J."""
    _, s, vt = np.linalg.svd(J, full_matrices=True)
    rank = int(np.sum(s > RANK_TOLERANCE * max(s.max(initial=0.0), 1e-300)))
    return s, vt, vt[rank:], rank


def _spread(J: np.ndarray, sigma2: float) -> np.ndarray:
    """The standard deviations sqrt(sigma^2 diag (J^T J)^+) of full-rank columns J."""
    s, vt, _, rank = _null(J)
    s_inv = np.zeros(J.shape[1])
    s_inv[:rank] = 1 / s[:rank]
    return np.sqrt(np.clip(np.diag((vt.T * s_inv**2) @ vt * sigma2), 0, None))


def judge(J: np.ndarray, sigma2: float, names, max_relative_std: float, shifts=None) -> dict:
    """Which variables the data constrain, from the sensitivity matrix J (weighted residuals per
    normalised variable, x = 1 initial), in three steps:

    1. no sensitivity: a column whose norm is below 1e-6 of the largest (changing the variable
       changes no residual);
    2. seen only together with others: QR with column pivoting (subset selection) keeps, one by
       one, the column with the most sensitivity not already explained by those kept, while that
       is above 1e-6 of the first's (ties: the earlier variable); a column left out is a
       combination of kept ones;
    3. not constrained: when the largest standard deviation sqrt(sigma^2 (J^T J)^-1)_kk of the
       kept variables exceeds ``max_relative_std`` (a fraction of the initial value; of the scale
       for offsets), that variable goes and step 2 is made again without it.

    sigma2 NaN (no redundancy and no measured standard deviations): the stds are unknown (NaN) and
    step 3 is left out. Returns identifiable (n,) bool, std (n,): the kept variables' with the
    others held, a removed one's when it went (inf for steps 1-2), reasons (n,) str ('' when
    identifiable)."""
    n = J.shape[1]
    shifts = [False] * n if shifts is None else list(shifts)
    col = np.linalg.norm(J, axis=0)
    top = col.max(initial=0.0)
    std = np.full(n, np.inf)
    reasons = [""] * n
    sensitive = col > RANK_TOLERANCE * top
    for k in np.flatnonzero(~sensitive):
        reasons[k] = (f"no sensitivity: changing it changes no residual (|dr/dx| {col[k]:.1e} against {top:.2g} for "
                      f"'{names[int(np.argmax(col))]}')" if top > 0 else "no sensitivity: no residual depends on it")
    loose = np.zeros(n, bool)  # left out in step 3
    while True:
        S = np.flatnonzero(sensitive & ~loose)
        keep = np.zeros(n, bool)
        if not len(S):
            break
        _, R, piv = scipy.linalg.qr(J[:, S], mode="economic", pivoting=True)
        d = np.abs(np.diag(R))
        rank = int(np.sum(d > RANK_TOLERANCE * d[0]))
        keep[S[piv[:rank]]] = True
        K = np.flatnonzero(keep)
        s_std = _spread(J[:, K], sigma2)
        w = int(np.argmax(s_std)) if np.all(np.isfinite(s_std)) else 0
        if not np.isfinite(s_std[w]) or s_std[w] <= max_relative_std:  # unknown sigma: steps 1-2 only
            std[K] = s_std
            break
        k = int(K[w])
        loose[k] = True
        std[k] = s_std[w]
        of = " of its scale" if shifts[k] else ""
        reasons[k] = (f"std +-{100 * s_std[w]:.0f} %{of}: the data do not constrain it (limit "
                      f"+-{100 * max_relative_std:.0f} %)")
    kept = np.flatnonzero(keep)
    for k in np.flatnonzero(sensitive & ~loose & ~keep):
        c = np.linalg.lstsq(J[:, kept], J[:, k], rcond=None)[0] * col[kept]
        partners = [names[kept[t]] for t in np.argsort(-np.abs(c)) if abs(c[t]) > 0.1 * np.abs(c).max()][:4]
        reasons[k] = (f"seen only together with {', '.join(repr(p) for p in partners)}: its effect on the data "
                      "is a combination of theirs")
    return {"identifiable": keep, "std": std, "reasons": reasons}


def _residual_variance(problem: UpdatingProblem, point: Point, m: int, n: int) -> tuple[float, str]:
    stds = [meas.frequency_std_hz / meas.frequencies_hz for meas in problem.measured.values()
            if meas.frequency_std_hz is not None]
    if stds and np.any(np.concatenate(stds) > 0):
        rel = np.concatenate(stds)
        weights = np.concatenate([problem.blocks.frequency_weights(meas) for meas in problem.measured.values()
                                  if meas.frequency_std_hz is not None])
        # Weighted residuals w (f - fm)/fm have standard deviation w sd/fm each: their common value.
        return float(np.median((problem.objective.frequency * weights * rel) ** 2)), "measured standard deviations"
    if m - n >= MIN_RESIDUAL_DOF:
        return float(point.data_residuals @ point.data_residuals / (m - n)), "residual (m - n degrees of freedom)"
    if m > n:
        return float("nan"), (f"none ({m - n} degree(s) of freedom in the residual, fewer than {MIN_RESIDUAL_DOF}, "
                              "and no measured standard deviations): standard deviations unknown")
    return float("nan"), "none (no redundancy and no measured standard deviations): standard deviations unknown"


# Fewer residuals beyond the variables than this and the residual does not estimate sigma: with one
# degree of freedom the 95 % range of s^2 / sigma^2 spans 1e-3 to 5, so a variable's std (and which
# variables are held for it) would follow chance.
MIN_RESIDUAL_DOF = 3


def variable_table(problem: UpdatingProblem, x: np.ndarray, ident: dict) -> list[dict]:
    """One row per design variable: initial and final physical values, change and standard
    deviation in % (of the initial value; of the scale for offsets at 0), whether the data
    constrain it and, when not, why."""
    rows = []
    for k, (b, xi) in enumerate(zip(problem.par.bindings, x)):
        v = b.variable
        p0 = float(np.mean(b.initial))
        p1 = float(np.mean(problem.par.physical(b, xi)))
        std_n = float(ident["std_normalised"][k])
        scale = v.scale if v.shifts else p0
        std = std_n * abs(scale) if np.isfinite(std_n) else None
        rel = None if std is None else (100 * std / abs(p0) if p0 else 100 * std_n)
        rows.append({"name": v.name, "kind": v.kind, "attribute": v.attribute,
                     "targets": [str(t) for t in b.indices], "initial": p0, "final": p1,
                     "x": float(xi), "change_percent": 100 * (p1 - p0) / p0 if p0 else None,
                     "lower": float(v.bounds[0]), "upper": float(v.bounds[1]),
                     "at_bound": bool(np.isclose(xi, v.bounds[0], atol=1e-6) or np.isclose(xi, v.bounds[1], atol=1e-6)),
                     "std_normalised": std_n, "std": std, "std_percent": rel,
                     "identifiable": bool(ident["identifiable"][k]), "fixed": False,
                     "reason": ident["reasons"][k]})
    return rows
