"""Identified modes read as test data (CSV, JSON, UFF 55), quantities with units, bad files."""

import json

import numpy as np
import pytest

from flexgvt.errors import ModelError
from flexgvt.io.uff import ModalResults, write_uff
from flexgvt.workflow import ProjectError, read_modes
from flexgvt.workflow.units import quantity


@pytest.mark.parametrize("text, dim, value", [
    (17.59, "stiffness", 17.59), ("17.59 N/m", "stiffness", 17.59), ("1.759 N/cm", "stiffness", 175.9),
    ("800 g", "mass", 0.8), ("4.32 GPa", "modulus", 4.32e9), ("0.94 N s/m", "damping", 0.94),
    ("10 deg", "angle", np.pi / 18), ("2700 kg/m^3", "density", 2700.0), ("5 N m/rad", "rotational_stiffness", 5.0),
    ("9.81 m/s^2", "acceleration", 9.81), ("250 mm", "length", 0.25)])
def test_quantities(text, dim, value):
    assert quantity(text, dim) == pytest.approx(value)


@pytest.mark.parametrize("text, dim, match", [
    ("17.59 kg", "stiffness", "unit mismatch"), ("3 furlongs", "length", "unknown unit"),
    ("fast", "frequency", "not a number"), (True, "mass", "expected a mass"), ("nan kg", "mass", "not a number")])
def test_bad_quantities(text, dim, match):
    with pytest.raises(ModelError, match=match):
        quantity(text, dim)


def test_csv_json_uff_agree(tmp_path):
    f = np.array([0.96, 2.71, 4.25])
    z = np.array([0.02, 0.015, 0.01])
    shapes = np.array([[1.0, 0.5, -0.2, 0.1], [0.3, -1.0, 0.4, 0.2], [0.1, 0.2, 1.0, -0.5]])
    outputs = [(1, 3), (2, 3), (3, 3), (3, 1)]
    head = "mode,frequency_hz,damping_ratio,label," + ",".join(f"{p}+{'XYZ'[d - 1]}" for p, d in outputs)
    rows = [f"{k + 1},{f[k]},{z[k]},m{k + 1}," + ",".join(str(v) for v in shapes[k]) for k in range(3)]
    (tmp_path / "m.csv").write_text("\n".join([head] + rows) + "\n")
    a = read_modes(tmp_path / "m.csv")
    assert np.allclose(a.frequencies_hz, f) and np.allclose(a.damping_ratio, z) and a.labels == ("m1", "m2", "m3")
    assert np.allclose(a.shapes, shapes) and a.outputs.tolist() == [list(o) for o in outputs]
    (tmp_path / "m.json").write_text(json.dumps({"lab": {"outboard": {"measured_hz": f.tolist()}}}))
    b = read_modes(tmp_path / "m.json", key="lab.outboard")
    assert np.allclose(b.frequencies_hz, f) and b.shapes is None
    full = np.zeros((3, 3, 3))
    for k, (p, d) in enumerate(outputs):
        full[:, p - 1, d - 1] = shapes[:, k]
    write_uff(tmp_path / "m.uff", modes=ModalResults(f, z, full, np.array([1, 2, 3])))
    c = read_modes(tmp_path / "m.uff")
    assert np.allclose(c.frequencies_hz, f) and np.allclose(c.damping_ratio, z)
    # The UFF holds every translation of every point; the CSV's channels are a subset of them.
    for k, (p, d) in enumerate(outputs):
        col = c.outputs.tolist().index([p, d])
        assert np.allclose(c.shapes[:, col], shapes[:, k])


@pytest.mark.parametrize("name, text, match", [
    ("a.json", "{not json", "not valid JSON"), ("b.json", '{"x": [1]}', "no 'frequencies_hz'"),
    ("c.csv", "mode,f\n1,2\n", "no 'frequency_hz' column"), ("d.csv", "mode,frequency_hz\n1,abc\n", "line 2"),
    ("e.txt", "1 2 3", "must be UFF"), ("f.json", '{"frequencies_hz": [1, 2], "damping_ratio": [0.1]}', "agree")])
def test_bad_mode_files(tmp_path, name, text, match):
    (tmp_path / name).write_text(text)
    with pytest.raises(ProjectError, match=match):
        read_modes(tmp_path / name)


def test_identify_is_the_deprecated_name_of_identify_configuration(monkeypatch):
    import flexgvt.workflow.identification as ident

    monkeypatch.setattr(ident, "identify_configuration", lambda project, name: ("identified", name))
    with pytest.warns(DeprecationWarning, match="identify_configuration"):
        assert ident.identify(None, "outboard") == ("identified", "outboard")


def test_identified_is_a_modal_set_whose_measured_method_is_deprecated(tmp_path, monkeypatch):
    import flexgvt.workflow.identification as ident
    from flexgvt.modal import ModalSet

    (tmp_path / "m.json").write_text(json.dumps({"frequencies_hz": [1.0, 2.0]}))
    item = read_modes(tmp_path / "m.json", "outboard")
    assert isinstance(item, ModalSet) and item.configuration == "outboard"
    monkeypatch.setattr(ident, "measured", lambda it, project: ("measured", it.name))
    with pytest.warns(DeprecationWarning, match=r"flexgvt.workflow.measured\(item, project\)"):
        assert item.measured(None) == ("measured", "outboard")


def test_csv_comment_lines(tmp_path):
    """'#' lines (a table's source) are skipped anywhere; a bad line's number counts them."""
    path = tmp_path / "gvt.csv"
    path.write_text("# source: the original work, Table 5.8\nmode,frequency_hz,label\n1,2.49,OOP 1\n"
                    "  # a note between rows\n2,7.15,IP 1/RB\n")
    m = read_modes(path)
    assert list(m.frequencies_hz) == [2.49, 7.15] and m.labels == ("OOP 1", "IP 1/RB") and m.shapes is None
    path.write_text("# source\nmode,frequency_hz\n1,2.49\n# note\n2,x\n")
    with pytest.raises(ProjectError, match="line 5: not a number"):
        read_modes(path)
