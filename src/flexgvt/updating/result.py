"""The result of an updating run: the updated model, per-configuration tables, MAC matrices,
design-variable table, convergence history and the identifiability report."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

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
    identifiability: sensitivity rank, condition number, unseen variables, standard deviations."""

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

    def summary(self) -> str:
        lines = [f"updating ({self.method}): objective {self.initial.objective:.4g} -> {self.final.objective:.4g} in "
                 f"{len(self.history) - 1} iterations, {self.solves} solves, {self.gradients} gradients, "
                 f"{self.seconds:.2f} s ({self.message})"]
        for name, rows in self.tables.items():
            e0 = [abs(r["initial_error_percent"]) for r in rows if r["updated_hz"] is not None]
            e1 = [abs(r["updated_error_percent"]) for r in rows if r["updated_hz"] is not None]
            lines.append(f"  {name}: max |error| {max(e0, default=0):.3f} % -> {max(e1, default=0):.3f} %")
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
                "starts": self.starts})

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


def configuration_tables(problem: UpdatingProblem, initial: Point, final: Point) -> dict[str, list[dict]]:
    out = {}
    for cfg in problem.configurations:
        meas = problem.measured[cfg.name]
        a, b = initial.configurations[cfg.name], final.configurations[cfg.name]
        labels_b = b.labels
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
                "paired": bool(ib >= 0)})
        out[cfg.name] = rows
    return out


def identifiability(problem: UpdatingProblem, point: Point) -> dict:
    """Rank and condition of the (weighted, normalised) sensitivity matrix, the variables the data
    cannot see, and the covariance of the variables: sigma^2 (J^T J)^+ with sigma from the
    measured frequency standard deviations where given, else from the residual (s^2 = |r|^2 /
    (m - n))."""
    J = point.jacobian
    names = problem.par.names
    m, n = J.shape
    u, s, vt = np.linalg.svd(J, full_matrices=False)
    rank = int(np.sum(s > RANK_TOLERANCE * max(s.max(initial=0.0), 1e-300)))
    cond = float(s[0] / s[-1]) if len(s) and s[-1] > 0 else float("inf")
    unseen, combinations = [], []
    if rank < n:
        # Directions of the design space the data do not see: a variable taking part in one
        # (more than 10 % of its weight) cannot be told apart from the others in it.
        null = vt[rank:]
        share = np.sum(null**2, axis=0)
        unseen = [names[k] for k in np.flatnonzero(share > 0.1)]
        combinations = [{names[k]: float(c) for k in np.flatnonzero(np.abs(row) > 0.1) for c in [row[k]]}
                        for row in null]
    sigma2, source = _residual_variance(problem, point, m, n)
    s_inv = np.where(s > RANK_TOLERANCE * max(s.max(initial=0.0), 1e-300), 1 / np.where(s > 0, s, 1), 0.0)
    cov = (vt.T * s_inv**2) @ vt * sigma2
    std = np.sqrt(np.clip(np.diag(cov), 0, None))
    std = np.where(np.isin(names, unseen), np.inf, std)
    return {"rank": rank, "n_variables": n, "n_residuals": m, "condition_number": cond,
            "singular_values": s, "unidentifiable": unseen, "unseen_combinations": combinations,
            "std_normalised": std, "covariance": cov,
            "sigma_source": source}


def _residual_variance(problem: UpdatingProblem, point: Point, m: int, n: int) -> tuple[float, str]:
    stds = [meas.frequency_std_hz / meas.frequencies_hz for meas in problem.measured.values()
            if meas.frequency_std_hz is not None]
    if stds and np.any(np.concatenate(stds) > 0):
        rel = np.concatenate(stds)
        weights = np.concatenate([problem.blocks.frequency_weights(meas) for meas in problem.measured.values()
                                  if meas.frequency_std_hz is not None])
        # Weighted residuals w (f - fm)/fm have standard deviation w sd/fm each: their common value.
        return float(np.median((problem.objective.frequency * weights * rel) ** 2)), "measured standard deviations"
    if m > n:
        return float(point.residuals @ point.residuals / (m - n)), "residual (m - n degrees of freedom)"
    return 0.0, "none (no redundancy and no measured standard deviations)"


def variable_table(problem: UpdatingProblem, x: np.ndarray, ident: dict) -> list[dict]:
    rows = []
    for k, (b, xi) in enumerate(zip(problem.par.bindings, x)):
        v = b.variable
        p0 = float(np.mean(b.initial))
        p1 = float(np.mean(problem.par.physical(b, xi)))
        std_n = float(ident["std_normalised"][k])
        scale = v.scale if v.shifts else p0
        rows.append({"name": v.name, "kind": v.kind, "attribute": v.attribute,
                     "targets": [str(t) for t in b.indices], "initial": p0, "final": p1,
                     "x": float(xi), "change_percent": 100 * (p1 - p0) / p0 if p0 else None,
                     "lower": float(v.bounds[0]), "upper": float(v.bounds[1]),
                     "at_bound": bool(np.isclose(xi, v.bounds[0], atol=1e-6) or np.isclose(xi, v.bounds[1], atol=1e-6)),
                     "std_normalised": std_n, "std": std_n * abs(scale) if np.isfinite(std_n) else None,
                     "identifiable": v.name not in ident["unidentifiable"]})
    return rows
