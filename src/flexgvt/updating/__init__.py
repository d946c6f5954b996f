"""FE model updating against several deformed configurations at once (docs/method.md section 4).

    v = [fg.updating.beam(f"E{r}", f"region{r}", "E") for r in (1, 2, 3)]
    data = [fg.updating.Measured("self_weight", frequencies_hz=[...]), ...]
    result = fg.updating.update(model, configurations, data, v)
"""

from .derivatives import StateDerivatives, eigenvalue_derivatives, eigenvector_derivatives, state_derivatives
from .problem import ConfigurationPoint, DesignPointFailure, Point, UpdatingProblem
from .settings import OptimiserSettings, UncertaintySettings
from .targets import MassTarget, Measured, Objective
from .variables import Parametrisation, Variable, beam, case_variables, cord, mass, shell, spring

__all__ = ["ConfigurationPoint", "DesignPointFailure", "MassTarget", "Measured", "Objective", "OptimiserSettings",
           "UncertaintySettings",
           "Parametrisation", "Point", "StateDerivatives", "UpdatingProblem", "Variable", "beam", "case_variables",
           "cord", "eigenvalue_derivatives", "eigenvector_derivatives", "mass", "shell", "spring", "state_derivatives"]
from .result import UpdateResult  # noqa: E402
from .runner import update  # noqa: E402

from .store import ResultsStore  # noqa: E402
from .verify import Onset, Protocol, Verification, verification_protocol, verify, verify_seeds  # noqa: E402

__all__ += ["Onset", "Protocol", "ResultsStore", "UpdateResult", "Verification", "update", "verification_protocol",
            "verify", "verify_seeds"]
