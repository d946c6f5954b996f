"""Suspension: characterise each suspension point, model it, and remove it (docs/method.md sections 2-3).

    point = fg.suspension.identify_block(mass=0.80, frequency_hz=0.40, damping_ratio=0.07)
    point.stiffness, point.damping                      # 5.08 N/m, 0.28 N s/m
    fg.suspension.series(195.0, *[195.0] * 9)           # ten springs in series: 19.5 N/m
    fg.suspension.support_correction(1.26, 0.035, 0.40, 0.07)
    fg.suspension.remove_suspension(model, hung, n_modes=12, proposed=bungees)
"""

from .identify import SuspensionPoint, identify_block, modulus_from_tip_load
from .networks import Bungee, Line, LineElement, parallel, series
from .planning import (Attachment, Layout, LayoutResult, assess, driving_point, driving_residues,
                       effective_independence, layout_configuration, place_sensors, plan_suspension, rank)
from .removal import Removal, remove_suspension
from .support import SupportCorrection, support_correction, two_mass_model

__all__ = ["Attachment", "Bungee", "Layout", "LayoutResult", "Line", "LineElement", "Removal", "assess",
           "driving_point", "driving_residues", "effective_independence", "rank", "layout_configuration",
           "place_sensors", "plan_suspension", "SupportCorrection", "SuspensionPoint", "identify_block",
           "modulus_from_tip_load", "parallel", "remove_suspension", "series", "support_correction", "two_mass_model"]
