"""One exception hierarchy for flexgvt.

Every message says what was wrong, where (file, line, entity id) and what to do.
"""

from __future__ import annotations


class FlexGVTError(Exception):
    """Base class of every error flexgvt raises on purpose."""


class ModelError(FlexGVTError, ValueError):
    """The structural model or a configuration is invalid (missing data, bad ids, NaN...)."""


class SolverError(FlexGVTError, RuntimeError):
    """A numerical solution failed (singular system, no convergence...)."""


class ConvergenceError(SolverError):
    """Newton-Raphson did not converge.

    ``state`` holds the last converged state (nothing computed is lost) and
    ``history`` the convergence record up to the failure.
    """

    def __init__(self, message: str, state=None, history=None):
        super().__init__(message)
        self.state = state
        self.history = history


class InstabilityError(ConvergenceError):
    """The load path lost stability (StaticSettings(buckling="stop")): ``state`` holds the last
    stable equilibrium, ``instability`` where and how it was lost (fem.stability.Instability)."""

    def __init__(self, message: str, state=None, history=None, instability=None):
        super().__init__(message, state, history)
        self.instability = instability


class SingularModelError(SolverError):
    """The stiffness matrix is singular: the model is under-constrained or has a mechanism."""


class FileFormatError(FlexGVTError, ValueError):
    """A file (UFF, bulk data, project) is malformed, truncated or unsupported."""


class EMAError(FlexGVTError, ValueError):
    """Experimental modal analysis could not proceed with the given data or settings."""


class UpdatingError(FlexGVTError, ValueError):
    """Model updating cannot start on the given data (too few measured modes pair with the model)."""


class ReportError(FlexGVTError, ValueError):
    """Report content is inconsistent (array shapes, missing labels) or cannot be written."""


class FlexGVTWarning(UserWarning):
    """A result was computed but looks physically doubtful (a cord stretched past its allowance, a
    displacement larger than the structure, a spring that spoils the conditioning): read the message."""
