"""Settings defined once: each setting's type, default, unit, limits and description is a field of a
frozen dataclass (``setting(...)`` metadata). ``flexgvt.updating.update`` takes its defaults from
these dataclasses, the project file's tables are generated from them (flexgvt.workflow.schema) and
validated into them, and docs/settings.md is generated from them.

    opt = fg.updating.OptimiserSettings(max_iterations=200)
    fg.updating.update(model, configurations, measured, variables, **opt.to_dict())
"""

from __future__ import annotations

import math
import warnings
from dataclasses import MISSING, asdict, dataclass, field, fields
from typing import Any

from ..errors import ModelError

UNIDENTIFIABLE = ("fix", "free")
METHODS = ("least_squares", "lm", "dogbox", "trf", "slsqp", "trust-constr", "nelder-mead")


def setting(default: Any = MISSING, doc: str = "", *, unit: str = "", ge: float | None = None,
            gt: float | None = None, le: float | None = None, choices: tuple | None = None,
            size: int | None = None) -> Any:
    """A dataclass field with its description ``doc``, SI ``unit`` ('' when dimensionless), limits
    (ge, gt, le: >=, >, <=) and ``choices``; ``size``: a tuple of that many values."""
    meta = {"doc": doc, "unit": unit, "ge": ge, "gt": gt, "le": le, "choices": choices, "size": size}
    return field(default=default, metadata=meta)


def check_settings(obj: Any, where: str) -> None:
    """ModelError naming ``where`` and the field when a value breaks its field's limits or choices."""
    for f in fields(obj):
        md, value = f.metadata, getattr(obj, f.name)
        if "doc" not in md or value is None:
            continue
        if md["choices"] is not None and value not in md["choices"]:
            raise ModelError(f"{where}: {f.name} '{value}' must be one of {md['choices']}")
        values = value if md["size"] is not None else (value,)
        if md["size"] is not None and len(values) != md["size"]:
            raise ModelError(f"{where}: {f.name} must hold {md['size']} values, got {len(values)}")
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            for bound, ok, text in ((md["ge"], lambda a, b: a >= b, ">="), (md["gt"], lambda a, b: a > b, ">"),
                                    (md["le"], lambda a, b: a <= b, "<=")):
                if bound is not None and not (math.isfinite(v) and ok(v, bound)):
                    raise ModelError(f"{where}: {f.name} = {v!r} must be finite and {text} {bound:g}")


def renamed(old: str, new: str, stacklevel: int = 3) -> None:
    """The DeprecationWarning of an old name (keyword, method) that still works: it names the new one."""
    warnings.warn(f"{old} is deprecated; use {new}", DeprecationWarning, stacklevel=stacklevel)


def described(cls: type) -> list:
    """The fields of settings dataclass ``cls`` that carry a description (the documented settings)."""
    return [f for f in fields(cls) if "doc" in f.metadata]


@dataclass(frozen=True)
class OptimiserSettings:
    """How flexgvt.updating.update optimises (the project file's [optimiser] table)."""

    method: str = setting("least_squares", "least_squares (Levenberg-Marquardt, continued inside the bounds by "
                          "dogbox when needed), lm (its alias), dogbox, trf, slsqp, trust-constr or nelder-mead",
                          choices=METHODS)
    starts: int = setting(1, "multi-start count: x0 = 1 plus seeded uniform points inside the bounds; the best "
                          "run wins (of runs equal to the tolerance, the one nearest x0)", ge=1, le=100)
    seed: int = setting(0, "seed of the multi-start points")
    max_iterations: int = setting(100, "iteration budget of one run (function evaluations for the least-squares "
                                  "methods, iterations for slsqp and trust-constr, (n + 1) times it in "
                                  "evaluations for nelder-mead)", ge=1)
    tolerance: float = setting(1e-10, "convergence tolerance on the cost, the step and the gradient (SciPy's "
                               "ftol, xtol, gtol)", gt=0)
    n_modes: int | None = setting(None, "modes analysed per configuration (default: the measured ones + 6)", ge=1)
    min_paired_fraction: float = setting(0.5, "refuse to start (UpdatingError) when fewer than this fraction of a "
                                         "configuration's measured modes pair with the initial model's; 0: never "
                                         "refuse (the unpaired modes are still reported)", ge=0, le=1)
    unidentifiable: str = setting("fix", "variables the data do not constrain (no sensitivity, seen only together "
                                  "with others, or a relative standard deviation above max_relative_std): 'fix' "
                                  "keeps them at their initial value and solves again without them; 'free' "
                                  "leaves them free and only flags them", choices=UNIDENTIFIABLE)
    max_relative_std: float = setting(0.5, "a variable whose standard deviation exceeds this fraction of its "
                                      "initial value (of its scale for offsets) is not identifiable (0.5: the "
                                      "+-2 sigma band spans zero to twice the value)", gt=0)

    def __post_init__(self) -> None:
        check_settings(self, "optimiser settings")

    def to_dict(self) -> dict:
        """The settings as keywords of flexgvt.updating.update."""
        return asdict(self)


UNCERTAINTY_METHODS = ("linear", "mcmc", "none")


@dataclass(frozen=True)
class UncertaintySettings:
    """Confidence bounds of the predicted frequencies (the project file's [prediction.uncertainty]
    table; flexgvt.updating.uncertainty)."""

    method: str = setting("linear", "linear: the updated variables' covariance (Laplace approximation, the "
                          "Jacobian's) through the predictions' exact sensitivities; mcmc: posterior samples "
                          "of the same residuals (emcee, pip install 'flexgvt[mcmc]'); none: no bounds",
                          choices=UNCERTAINTY_METHODS)
    confidence: float = setting(0.95, "level of the two-sided interval", gt=0, le=0.999)
    prior: str = setting("bounds", "bounds: each variable's prior is uniform on its bounds (the linear route "
                         "uses its variance), so directions the data do not see keep that spread; none: "
                         "data only (a prediction that depends on an unseen direction is unbounded)",
                         choices=("bounds", "none"))
    scale_to_fit: bool = setting(True, "widen the measured standard deviations by chi^2 per degree of freedom "
                                 "of the fit when the residual is larger than they explain")
    walkers: int = setting(32, "mcmc: ensemble walkers (at least 2 n_variables + 2 are used)", ge=2)
    steps: int = setting(400, "mcmc: steps of each walker (each step solves every updated configuration "
                         "once per walker)", ge=2)
    burn: int = setting(200, "mcmc: steps discarded as burn-in", ge=0)
    thin: int = setting(10, "mcmc: keep every thin-th step of the chain", ge=1)
    samples: int = setting(100, "mcmc: posterior samples whose predictions give the interval", ge=2)
    seed: int = setting(0, "mcmc: seed of the walkers' start and moves")

    def __post_init__(self) -> None:
        check_settings(self, "uncertainty settings")
        if self.steps <= self.burn:
            raise ModelError(f"uncertainty settings: steps ({self.steps}) must exceed burn ({self.burn})")

    def to_dict(self) -> dict:
        return asdict(self)
