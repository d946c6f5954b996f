"""flexgvt.data: the measured tables shipped with the package, their source lines and errors."""

import fnmatch
import hashlib
import re
import tomllib
from importlib import resources
from pathlib import Path

import pytest

import flexgvt as fg
from flexgvt.errors import FileFormatError, FlexGVTError

ROOT = Path(__file__).resolve().parents[2]
TABLES = ("a3tb_wt", "strip_366_gvt", "xhale_lab_gvt")


def test_names_and_contents():
    assert fg.data.names() == list(TABLES)
    strip = fg.data.load("strip_366_gvt")
    for layout in ("outboard", "inboard"):
        assert len(strip[layout]["undamped_hz"]) == 15 == len(strip[layout]["original_tuned_model_hz"])
    xhale = fg.data.load("xhale_lab_gvt")
    assert len(xhale["labels"]) == 8 and all(len(xhale[c]["measured_hz"]) == 8 for c in ("outboard", "inboard"))
    assert "missing_for_rebuild" in fg.data.load("a3tb_wt")
    strip["outboard"]["undamped_hz"][0] = -1.0  # a new dict on every call: the next load is untouched
    assert fg.data.load("strip_366_gvt")["outboard"]["undamped_hz"][0] > 0


def test_no_figure_edited():
    """Each file is the one handed over (SHA-256 in the README beside it) but for 'METHOD.md' ->
    'docs/method.md' in its text."""
    folder = resources.files("flexgvt.data")
    readme = folder.joinpath("README.md").read_text(encoding="utf-8")
    recorded = dict(re.findall(r"^\| `(\w+)\.json` \|.*\| ([0-9a-f]{64}) \|$", readme, re.M))
    assert sorted(recorded) == list(TABLES)
    for name, digest in recorded.items():
        text = folder.joinpath(f"{name}.json").read_text(encoding="utf-8").replace("docs/method.md", "METHOD.md")
        assert hashlib.sha256(text.encode()).hexdigest() == digest, name


def test_sources():
    for name in TABLES:
        line = fg.data.source(name)
        assert f"{name}.json" in line and "published" in line and "\n" not in line


@pytest.mark.parametrize("bad", ["strip", "STRIP_366_GVT", "strip_366_gvt.json", "", None, 3])
def test_unknown_name(bad):
    for call in (fg.data.load, fg.data.source):
        with pytest.raises(fg.data.UnknownTableError) as err:
            call(bad)
        assert isinstance(err.value, FlexGVTError) and all(n in str(err.value) for n in TABLES)


def test_packaged():
    """pyproject's package data covers every file shipped beside the loader (else a wheel lacks it)."""
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    patterns = setuptools["package-data"]["flexgvt.data"]
    files = [p.name for p in resources.files("flexgvt.data").iterdir() if p.is_file() and not p.name.endswith(".py")]
    assert len(files) == 4 and all(any(fnmatch.fnmatch(f, p) for p in patterns) for f in files), files


def test_read_own_table(tmp_path):
    good = tmp_path / "t.json"
    good.write_text('{"outboard": {"undamped_hz": [1.0]}}')
    assert fg.data.read(good) == {"outboard": {"undamped_hz": [1.0]}}
    cases = {"missing.json": None, "folder": "dir", "broken.json": '{"a": [1, 2', "list.json": "[1, 2]",
             "binary.json": b"\xff\xfe\x00{", "empty.json": ""}
    for name, content in cases.items():
        path = tmp_path / name
        if content == "dir":
            path.mkdir()
        elif isinstance(content, bytes):
            path.write_bytes(content)
        elif content is not None:
            path.write_text(content)
        with pytest.raises(FileFormatError) as err:
            fg.data.read(path)
        assert str(path) in str(err.value) and "\n" not in str(err.value), name
    with pytest.raises(FileFormatError, match=r"'nul\\x00.json': cannot be read"):
        fg.data.read("nul\0.json")
    with pytest.raises(FileFormatError) as err:
        fg.data.read(tmp_path / ("x" * 5000 + ".json"))
    assert len(str(err.value)) < 300 and "characters" in str(err.value)
