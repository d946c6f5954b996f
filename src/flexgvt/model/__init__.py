"""Plain data: the structural model and test configurations. No numerics here."""

from .components import (ConcentratedMass, Cord, DistributedLoad, InterpolationLink, LinearConstraint, NodalLoad,
                         RigidLink, Spring)
from .configuration import STANDARD_GRAVITY, Configuration, parse_dofs
from .material import Material
from .model import BeamGroup, Model
from .shells import AnisotropicMaterial, Laminate, OrthotropicMaterial, Ply, ShellGroup, ShellProperty
from .spring_table import SpringTable
from .section import (CircularTubeSection, GeneralSection, RectangularSection, RodSection, TaperedSection,
                      end_properties, rectangle_torsion_constant)

__all__ = ["BeamGroup", "CircularTubeSection", "AnisotropicMaterial", "ConcentratedMass", "Configuration", "Cord",
           "DistributedLoad", "GeneralSection", "Laminate", "OrthotropicMaterial", "Ply", "ShellGroup",
           "ShellProperty", "InterpolationLink", "LinearConstraint", "Material", "Model", "NodalLoad",
           "RectangularSection", "RodSection", "RigidLink", "Spring", "SpringTable", "STANDARD_GRAVITY",
           "TaperedSection", "end_properties", "parse_dofs", "rectangle_torsion_constant"]
