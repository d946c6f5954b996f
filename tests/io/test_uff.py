"""UFF reading and writing: real files from other tools, round trips, malformed and corrupt files."""

from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import FileFormatError
from flexgvt.io.uff import FRFs, ModalResults, TestGeometry, write_uff

DATA = Path(__file__).parents[1] / "data" / "uff"


def test_real_geometry_files_from_test_systems():
    testlab = fg.io.read_uff(DATA / "TestLab 161 164 18 15 82.uff")
    assert len(testlab.geometry.point_ids) == 36 and testlab.units["length"] == 1.0
    np.testing.assert_allclose(testlab.geometry.xyz[0], [-2.4, -0.95, 0.0])
    assert len(fg.io.read_uff(DATA / "mesh_Oros-modal_uff15_uff2412.uff").geometry.point_ids) == 96
    assert len(fg.io.read_uff(DATA / "Artemis export - Geometry RPBC_setup_05_14102016_105117.uff").geometry.xyz) == 74
    # NX writes mm (164 length factor 1000, to divide by): coordinates come back in metres.
    nx = fg.io.read_uff(DATA / "NX simulation output.uff")
    assert nx.units["length"] == 1000.0 and np.abs(nx.geometry.xyz).max() < 1.0


def test_binary_58b_time_record():
    data = fg.io.read_uff(DATA / "Sample_UFF58b_bin.uff")
    (f,) = data.functions
    assert f.kind == "time response" and len(f.x) == 79292 and np.all(np.diff(f.x) > 0)
    with pytest.raises(FileFormatError, match="no FRF"):
        _ = data.frfs


@pytest.mark.parametrize("binary", [False, True])
def test_round_trip_geometry_frfs_and_modes(tmp_path, binary):
    rng = np.random.default_rng(0)
    f = np.linspace(0.05, 20.0, 400)
    H = rng.standard_normal((400, 3, 2)) + 1j * rng.standard_normal((400, 3, 2))
    frfs = FRFs(f, H, np.array([[1, 3], [2, 3], [3, -1]]), np.array([[1, 3], [3, 2]]))
    geo = TestGeometry(np.array([1, 2, 3]), rng.standard_normal((3, 3)))
    modes = ModalResults(np.array([0.4, 1.23]), np.array([0.07, 0.01]), rng.standard_normal((2, 3, 3)),
                         np.array([1, 2, 3]))
    path = write_uff(tmp_path / "gvt.uff", geometry=geo, frfs=frfs, modes=modes, binary=binary)
    back = fg.io.read_uff(path)
    tol = 0 if binary else 1e-10
    np.testing.assert_allclose(back.frfs.H, H, rtol=tol, atol=1e-10 * (not binary))
    np.testing.assert_allclose(back.frfs.frequencies_hz, f, rtol=1e-12)
    np.testing.assert_array_equal(back.frfs.outputs, frfs.outputs)
    np.testing.assert_allclose(back.geometry.xyz, geo.xyz, rtol=1e-5)  # dataset 15 holds coordinates as E13.5
    np.testing.assert_allclose(back.modes.frequencies_hz, [0.4, 1.23])
    np.testing.assert_allclose(back.modes.damping_ratio, [0.07, 0.01])
    np.testing.assert_allclose(back.modes.shapes, modes.shapes, rtol=1e-5)  # dataset 55 real data are E13.5


def test_nan_is_refused_when_writing_and_reading(tmp_path):
    f = np.linspace(1, 10, 10)
    H = np.ones((10, 1, 1), complex)
    frfs = FRFs(f, H, np.array([[5, 3]]), np.array([[1, 3]]))
    bad = FRFs(f, np.where(np.arange(10)[:, None, None] == 4, np.nan, H), frfs.outputs, frfs.inputs)
    with pytest.raises(FileFormatError, match="cannot write FRFs containing NaN"):
        write_uff(tmp_path / "w.uff", frfs=bad)
    path = write_uff(tmp_path / "nan.uff", frfs=frfs)
    lines = path.read_text().splitlines()
    last = max(i for i, line in enumerate(lines) if "1.00000000000e+00" in line)
    lines[last] = lines[last].replace("1.00000000000e+00", "              nan", 1)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(FileFormatError, match=r"NaN .* 5\+Z / 1\+Z"):
        fg.io.read_uff(path)


def test_missing_file_and_non_uff_file(tmp_path):
    with pytest.raises(FileFormatError, match="no such file"):
        fg.io.read_uff(tmp_path / "absent.uff")
    junk = tmp_path / "junk.uff"
    junk.write_text("this is not a universal file\n1 2 3\n")
    with pytest.raises(FileFormatError):
        fg.io.read_uff(junk)


def test_fuzzed_files_fail_cleanly_or_read(tmp_path):
    """Truncated, line-dropped and byte-flipped variants of real files: either they read, or they raise
    FileFormatError naming the file; never another exception."""
    rng = np.random.default_rng(7)
    sources = [DATA / "TestLab 161 164 18 15 82.uff", DATA / "mesh_Oros-modal_uff15_uff2412.uff"]
    src = tmp_path / "frf_src.uff"
    write_uff(src, frfs=FRFs(np.linspace(1, 5, 30), np.ones((30, 2, 1), complex), np.array([[1, 3], [2, 3]]),
                             np.array([[1, 3]])))
    sources.append(src)
    outcomes = {"read": 0, "error": 0}
    for k in range(60):
        text = sources[k % len(sources)].read_bytes()
        mode = k % 3
        if mode == 0:
            text = text[: int(rng.integers(1, len(text)))]
        elif mode == 1:
            lines = text.split(b"\n")
            del lines[int(rng.integers(0, len(lines)))]
            text = b"\n".join(lines)
        else:
            b = bytearray(text)
            for _ in range(5):
                b[int(rng.integers(0, len(b)))] = int(rng.integers(32, 127))
            text = bytes(b)
        path = tmp_path / f"fuzz{k}.uff"
        path.write_bytes(text)
        try:
            fg.io.read_uff(path)
            outcomes["read"] += 1
        except FileFormatError as exc:
            assert str(path) in str(exc)
            outcomes["error"] += 1
    assert outcomes["error"] > 0


def test_ragged_datasets_name_the_dataset(tmp_path):
    """flexgvt's own UFF with a node line dropped from a mode (dataset 55) or from the geometry
    (dataset 15): a FileFormatError naming the dataset and the counts, not a numpy ValueError."""
    rng = np.random.default_rng(3)
    geo = TestGeometry(np.array([1, 2, 3]), rng.standard_normal((3, 3)))
    modes = ModalResults(np.array([0.4, 1.23]), np.array([0.07, 0.01]), rng.standard_normal((2, 3, 3)),
                         np.array([1, 2, 3]))
    lines = write_uff(tmp_path / "m.uff", geometry=geo, modes=modes).read_text().splitlines()
    node_lines = [i for i, ln in enumerate(lines) if ln.split() == ["3"]]  # mode data: node id, then values
    cut = lines[:node_lines[-1]] + lines[node_lines[-1] + 2:]
    (tmp_path / "ragged55.uff").write_text("\n".join(cut) + "\n")
    with pytest.raises(FileFormatError, match=r"dataset 4 \(type 55\): modal datasets 55 do not share one point list"):
        fg.io.read_uff(tmp_path / "ragged55.uff")
    geo_line = next(i for i, ln in enumerate(lines) if ln.split()[:1] == ["2"] and len(ln.split()) == 7)
    lines[geo_line] = lines[geo_line][:60]
    (tmp_path / "short15.uff").write_text("\n".join(lines) + "\n")
    with pytest.raises(FileFormatError, match=r"dataset 2 \(type 15\)"):
        fg.io.read_uff(tmp_path / "short15.uff")


def test_unusable_paths_are_file_format_errors(tmp_path):
    with pytest.raises(FileFormatError, match="NUL"):
        fg.io.read_uff(str(tmp_path / "a\x00b.uff"))
    with pytest.raises(FileFormatError, match="cannot be opened"):
        fg.io.read_uff(tmp_path / ("x" * 5000 + ".uff"))
    with pytest.raises(FileFormatError, match="no such file"):
        fg.io.read_uff(tmp_path)
