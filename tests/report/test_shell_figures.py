"""The CLI's matplotlib figures of a shell model (flexgvt solve --out): a built-up box has a whole
section of nodes at every span station, so its static shape and mode shapes are drawn by section
(centroid line, the band the section spans, each section's rigid twist), not node by node in
storage order (which drew the wingbox as a zigzag over its depth and chord)."""

import numpy as np

import flexgvt as fg
from flexgvt.report import plots


def test_a_wingbox_is_drawn_section_by_section():
    case = fg.cases.wingbox(element_size=0.5)
    state = fg.solve_static(case.model, case.configurations["minus_1g"])
    fig = plots.static_shape([state], "wingbox")
    side = fig.axes[0]
    undeformed, deformed = side.lines[0], side.lines[1]
    stations = np.unique(np.round(case.model.xyz[:, 1], 6))
    assert len(deformed.get_xdata()) == len(stations) < len(case.model.node_ids) / 4
    np.testing.assert_allclose(undeformed.get_ydata(), 0.0, atol=1e-12)  # the box's centroid line
    y, z = deformed.get_xdata(), deformed.get_ydata()
    assert np.all(np.diff(y) > 0) and np.all(np.diff(z) < 1e-9) and z[-1] < -0.5  # hangs, monotonic
    modes = fg.solve_modes(state, 4)
    fig = plots.mode_shapes(modes, 4, "wingbox")
    first = fig.axes[0].lines[0].get_ydata()  # z of the first bending, section by section
    assert len(first) == len(stations) and abs(first[-1]) == 1.0 and np.all(np.diff(np.abs(first)) >= -1e-9)
