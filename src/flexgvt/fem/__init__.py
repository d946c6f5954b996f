"""Numerics: the geometrically nonlinear structural solver and modal analysis."""

from .labels import energy_fractions, label_modes, mac_matrix
from .massprops import MassProperties, mass_properties
from .modes import Modes, solve_modes
from .static import IterationRecord, State, StaticSettings, solve_linear_static, solve_static
from .system import System
from .tracking import ModeTracking, modes_versus_load, track_modes

__all__ = ["IterationRecord", "MassProperties", "ModeTracking", "Modes", "State", "StaticSettings", "System",
           "energy_fractions", "label_modes", "mac_matrix", "mass_properties", "modes_versus_load",
           "solve_linear_static", "solve_modes", "solve_static", "track_modes"]
