"""Correlation of measured and analytical modes: sensors (FE shapes reduced to test points and
sensor directions), MAC, auto-MAC, COMAC, cross-orthogonality and one-to-one pairing.

    measured = stab.select()                       # flexgvt.ema ModalSet
    modes = fg.solve_modes(state, 20)              # flexgvt.fem Modes
    fg.correlation.mac(measured, modes)            # sensors from the ModalSet's outputs
    pairs = fg.correlation.pair(measured, modes)   # pairs.table(), pairs.reasons
"""

from .mac import auto_mac, comac, cross_orthogonality, mac, mac_of, shapes_of, subspace_mac
from .pairing import Pairing, Unpaired, label_families, labels_compatible, pair, pair_by_frequency, sensors_see
from .sensors import PointMap, Sensor, Sensors, map_points, map_test_geometry, sensors_from_test

__all__ = ["Pairing", "PointMap", "Unpaired", "label_families", "labels_compatible", "pair_by_frequency",
           "sensors_see", "Sensor", "Sensors", "map_points", "map_test_geometry", "sensors_from_test",
           "auto_mac", "comac", "cross_orthogonality", "mac", "mac_of", "pair",
           "shapes_of", "subspace_mac"]
