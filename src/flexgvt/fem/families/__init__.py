"""Element families: each one unit with its data, kernels, mass, damping, applied loads, sensitivity
blocks and DOF needs (see base.Family and docs/architecture.md, "Element families")."""

from .base import Derivative, ElementTerms, Family, element_dofs
from .beam import BeamFamily
from .cord import CordFamily, Cords
from .mass import PointMassFamily, PointMasses
from .segments import CordSegmentFamily, SegmentOutput
from .shell import ShellFamily
from .spring import SPRING_CLAMP_RATIO, SPRING_WARN_RATIO, SpringFamily, Springs

__all__ = ["SPRING_CLAMP_RATIO", "SPRING_WARN_RATIO", "BeamFamily", "CordFamily", "CordSegmentFamily", "Cords",
           "Derivative", "SegmentOutput",
           "ElementTerms", "Family", "PointMassFamily", "PointMasses", "ShellFamily", "SpringFamily", "Springs",
           "element_dofs"]
