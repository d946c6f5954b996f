"""UFF reproducers of the fuzzing trial (tests/data/reliability/uff): each raises a FileFormatError
naming the file and the dataset, and `flexgvt ema identify` prints it as one line with exit status
2 (they were a KeyError or ValueError traceback with status 1)."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

import flexgvt as fg
from flexgvt.cli.main import app
from flexgvt.errors import FileFormatError

UFF = Path(__file__).parents[1] / "data" / "reliability" / "uff"
CASES = {  # file: (dataset named in the message, what it says)
    "KeyError_flexgvt_io_uff_py_179__read_uff_/original.uff": ("dataset 1 (type 58)", "no ordinate data"),
    "ValueError_flexgvt_io_uff_py_173__read_uff_/minimal.uff":
        ("dataset 1 (type 15)", "0 values of z coordinates for 1"),
    "ValueError_flexgvt_io_uff_py_173__read_uff_/original.uff":
        ("dataset 2 (type 15)", "95 values of z coordinates for 96"),
    "ValueError_flexgvt_io_uff_py_212___modes_/original.uff":
        ("dataset 12 (type 55)", "40 values of shape values for 79"),
    "ValueError_flexgvt_io_uff_py_226___modes_/original.uff":
        ("dataset 9 (type 55)", "23 values of shape values for 46"),
    "ValueError_flexgvt_io_uff_py_212___modes_/minimal.uff": ("dataset 2 (type 15)", "node ids must be integers"),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_reproducer_raises_a_file_format_error(name, tmp_path):
    path = UFF / name
    where, says = CASES[name]
    with pytest.raises(FileFormatError) as err:
        fg.io.read_uff(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}: {where}: ") and says in msg, msg
    result = CliRunner().invoke(app, ["ema", "identify", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert result.output.startswith("error: ") and result.output.count("\n") == 1, result.output
    assert says in result.output


def test_the_unchanged_files_still_read():
    """The binary 58b file the first reproducer was mutated from reads (a time record)."""
    data = fg.io.read_uff(Path(__file__).parents[1] / "data" / "uff" / "Sample_UFF58b_bin.uff")
    assert data.functions[0].kind == "time response" and len(data.functions[0].data) == 79292
