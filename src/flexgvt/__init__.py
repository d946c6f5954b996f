"""flexgvt: ground vibration testing and FE model updating of very flexible aircraft.

    import flexgvt as fg
    case = fg.cases.cantilever_strip()
    state = fg.solve_static(case.model, case.configurations["self_weight"])
    modes = fg.solve_modes(state, n_modes=10)
"""

from __future__ import annotations

from . import cases, errors, fem, model
from ._threads import blas_threads
from .errors import FlexGVTError
from .fem import (MassProperties, Modes, ModeTracking, State, StaticSettings, mass_properties, modes_versus_load,
                  solve_linear_static, solve_modes, solve_static, track_modes)
from .model import (CircularTubeSection, Configuration, Cord, DistributedLoad, GeneralSection, Material, Model,
                    NodalLoad, RectangularSection, RodSection, Spring, SpringTable, TaperedSection)

__version__ = "0.1.0"

__all__ = ["CircularTubeSection", "Configuration", "Cord", "DistributedLoad", "FlexGVTError", "GeneralSection",
           "MassProperties", "Material", "Model", "ModeTracking", "Modes", "NodalLoad", "RectangularSection",
           "RodSection", "Spring", "SpringTable", "State", "TaperedSection", "StaticSettings", "blas_threads", "cases",
           "errors",
           "fem", "mass_properties", "model", "modes_versus_load", "solve_linear_static", "solve_modes", "solve_static",
           "track_modes"]


def __getattr__(name: str):
    # Heavier layers load on first use so `import flexgvt` stays fast.
    if name in ("data", "modal", "ema", "io", "correlation", "updating", "suspension", "workflow", "report"):
        import importlib
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'flexgvt' has no attribute {name!r}")
