"""The decks that crashed or hung flexgvt in the fuzzing trial (tests/data/reliability/bdf/README.md):
read_bdf (then solve_deck) raises a FlexGVTError naming the cause and the card, and
`flexgvt solve deck` prints one line and exits with status 2."""

import time
import warnings
from pathlib import Path

import pytest
from typer.testing import CliRunner

import flexgvt as fg
from flexgvt.cli.main import app
from flexgvt.errors import FileFormatError, FlexGVTError, ModelError
from flexgvt.workflow.deck import solve_deck

DATA = Path(__file__).parents[1] / "data" / "reliability" / "bdf"

# file -> (error class, fragments the message must hold: the file line, the card and id, the cause)
CASES = {
    "crod_node_0.bdf": (ModelError, [":1: CROD 107", "GA/GB = [0, 8]", "give both end grids"]),
    "set1_thru_2147483648.dat": (FileFormatError, [":3: SET1 1 THRU 2147483648", "2,147,483,648 ids",
                                                   "10,000,000"]),
    "cbar_ga_0.bdf": (ModelError, [":1: CBAR 120", "GA/GB = [0, 120]"]),
    "cbar_ga_0_pbarl.blk": (ModelError, [":2: CBAR 8", "GA/GB = [0, 9]"]),
    "mat1_rho_1e308.bdf": (ModelError, [":18: MAT1 1", "field 6 (RHO) = 1e+308", "exceeds 1e+30"]),
    "grid_x_1e300.bdf": (ModelError, [":4: GRID 7", "field 4 (X1) = 1e+300", "exceeds 1e+30"]),
    "grid_id_1e20.bdf": (ModelError, [":1: GRID 99999999999999999999", "outside Nastran's range 1 to 99999999"]),
    "prod_j_1e308.bdf": (ModelError, [":4: PROD 1", "field 5 (J) = 1e+308"]),
    "conm2_x1_1e308.dat": (ModelError, [":5: CONM2 2", "field 6 (X1) = 1e+308"]),
    "cbeam_orientation_integer_0.bdf": (ModelError, [":1: CBEAM 17", "G0 = 0", "give X1, X2, X3 as real numbers"]),
}


def test_every_reproducer_has_a_case():
    assert sorted(p.name for p in DATA.iterdir() if p.suffix != ".md") == sorted(CASES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_reading_and_solving_raises_a_clear_error(name):
    cls, fragments = CASES[name]
    path = DATA / name
    t0 = time.perf_counter()
    with pytest.raises(FlexGVTError) as err, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        solve_deck(fg.io.read_bdf(path, unsupported="warn"))
    assert time.perf_counter() - t0 < 5.0  # the SET1 THRU 2147483648 deck used to take 2.8 GB and never end
    assert type(err.value) is cls, f"{type(err.value).__name__}: {err.value}"
    msg = str(err.value)
    assert str(path) in msg
    for fragment in fragments:
        assert fragment in msg, msg


@pytest.mark.parametrize("name", sorted(CASES))
def test_cli_prints_one_line_and_exits_with_status_2(name):
    result = CliRunner().invoke(app, ["solve", str(DATA / name)])
    assert result.exit_code == 2, result.output
    assert not isinstance(result.exception, Exception) or isinstance(result.exception, SystemExit)
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "Traceback" not in result.output, result.output
    assert CASES[name][1][0] in lines[0]
