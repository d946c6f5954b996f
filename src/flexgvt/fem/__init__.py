"""Numerics: the geometrically nonlinear structural solver and modal analysis."""

from .labels import ModeTracking, energy_fractions, label_modes, mac_matrix, track_modes
from .massprops import MassProperties, mass_properties
from .modes import Modes, solve_modes
from .static import IterationRecord, State, StaticSettings, solve_linear_static, solve_static
from .system import System
from .tracking import modes_versus_load

__all__ = ["IterationRecord", "MassProperties", "ModeTracking", "Modes", "State", "StaticSettings", "System",
           "energy_fractions", "label_modes", "mac_matrix", "mass_properties", "modes_versus_load",
           "solve_linear_static", "solve_modes", "solve_static", "track_modes"]
