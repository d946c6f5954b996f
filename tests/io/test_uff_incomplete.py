"""Files cut off in transfer, missing FRF channels and dropping the incomplete ones."""

import warnings

import numpy as np
import pytest

from flexgvt.errors import FileFormatError, FlexGVTWarning
from flexgvt.io.uff import FRFs, describe_uff, read_uff, write_uff


def _frf_file(tmp_path, binary=False):
    rng = np.random.default_rng(1)
    f = np.linspace(1.0, 20.0, 40)
    H = rng.standard_normal((40, 3, 2)) + 1j * rng.standard_normal((40, 3, 2))
    frfs = FRFs(f, H, np.array([[1, 3], [2, 3], [3, 3]]), np.array([[1, 3], [9, 2]]))
    return write_uff(tmp_path / ("f58b.uff" if binary else "f.uff"), frfs=frfs, binary=binary)


def _datasets(lines):
    marks = [i for i, ln in enumerate(lines) if ln.strip() == "-1"]
    return [(marks[k], marks[k + 1]) for k in range(0, len(marks) - 1, 2)]


@pytest.mark.parametrize("binary", [False, True])
def test_cut_off_file_names_its_last_complete_dataset(tmp_path, binary):
    path = _frf_file(tmp_path, binary)
    data = path.read_bytes()
    # cut in the header of the fifth dataset (164, then six 58s)
    opening = [k for k in range(len(data)) if data.startswith(b"    -1\n    58", k)][3]
    start5 = data.count(b"\n", 0, opening) + 1
    path.write_bytes(data[:opening + 200])
    with pytest.raises(FileFormatError, match=rf"ends inside dataset 5 \(type 58, starting at line {start5}\).*"
                                              r"last complete dataset is 4 \(type 58, lines \d+-\d+\)"):
        read_uff(path)
    d = describe_uff(path)
    assert d.truncated and d.counts == {58: 3, 164: 1} and "cut off" in str(d)


def test_missing_channel_names_the_pairs_and_can_be_dropped(tmp_path):
    path = _frf_file(tmp_path)
    lines = path.read_text().split("\n")
    blocks = _datasets(lines)
    a, b = blocks[3]  # 164, then (1, 1), (1, 9), (2, 1): drop response 2+Z / reference 1+Z
    path.write_text("\n".join(lines[:a] + lines[b + 1:]))
    data = read_uff(path)
    with pytest.raises(FileFormatError, match=r"incomplete: 1 of 6 .* 2\+Z / 1\+Z;.*drop_incomplete=True"):
        _ = data.frfs
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        kept = read_uff(path, drop_incomplete=True)
    assert kept.dropped == ("response 2+Z: no FRF for reference 1+Z",)
    assert any(issubclass(w.category, FlexGVTWarning) and "2+Z" in str(w.message) for w in caught)
    frfs = kept.frfs
    assert frfs.outputs.tolist() == [[1, 3], [3, 3]] and frfs.inputs.tolist() == [[1, 3], [9, 2]]


def test_a_missing_reference_is_dropped_rather_than_every_response(tmp_path):
    path = _frf_file(tmp_path)
    lines = path.read_text().split("\n")
    blocks = _datasets(lines)
    # reference 9-Y missing for responses 1 and 2 (datasets 3 and 5): dropping it keeps all responses
    keep = [ln for k, (a, b) in enumerate(blocks) if k not in (2, 4) for ln in lines[a:b + 1]]
    path.write_text("\n".join(keep) + "\n")
    kept = read_uff(path, drop_incomplete=True)
    assert kept.dropped == ("reference 9+Y: no FRF for 2 of 3 responses (1+Z, 2+Z)",)
    assert kept.frfs.H.shape == (40, 3, 1)
