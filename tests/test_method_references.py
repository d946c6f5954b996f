"""Every citation of docs/method.md in the project names a section (and case) that exists there;
nothing cites METHOD.md (outside the project), and no script or module reaches a folder beside the
repository (a clone has nothing beside it)."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCES = [ROOT / "README.md", *[p for d in ("src", "tests", "bench", "docs", "examples") for p in (ROOT / d).rglob("*")
                                 if p.suffix in (".py", ".md", ".json", ".toml")]]


def test_citations_resolve():
    method = (ROOT / "docs" / "method.md").read_text(encoding="utf-8")
    sections = {int(n) for n in re.findall(r"^## (\d+)\. ", method, re.M)}
    assert sections == set(range(1, 7))
    part5 = method.split("## 5. ")[1].split("## 6. ")[0]
    cases = {int(n) for n in re.findall(r"^(\d)\. \*\*", part5, re.M)}
    assert cases == set(range(1, 7))
    cited = 0
    for path in SOURCES:
        text = path.read_text(encoding="utf-8", errors="replace")
        where = path.relative_to(ROOT)
        # The tables' origin note and its test name the file the tables once cited.
        if where.as_posix() not in ("tests/test_method_references.py", "tests/data/test_shipped_tables.py",
                                    "src/flexgvt/data/README.md"):
            assert "METHOD.md" not in text, f"{where} cites METHOD.md: cite docs/method.md section N"
        if path.suffix == ".py":  # no path built above the repository's root
            depth = len(where.parts) - 1  # parents[depth] of this file is the root
            for m in re.finditer(r"__file__\)?(?:\.resolve\(\))?\.parents\[(\d+)\]", text):
                assert int(m.group(1)) <= depth, f"{where}: parents[{m.group(1)}] leaves the repository"
            if where.parts[0] in ("src", "bench", "examples"):  # nor a relative path climbing out to a folder
                assert not re.search(r"[\"']\.\./[\w.-]+/", text), where
        for m in re.finditer(r"method\.md(?:\]\([^)]*\))? sections? (\d)(?:-(\d))?(?: case (\d))?", text):
            cited += 1
            first, last, case = m.group(1), m.group(2), m.group(3)
            assert {int(first), int(last or first)} <= sections, (where, m.group(0))
            assert case is None or (first == "5" and int(case) in cases), (where, m.group(0))
    assert cited > 30
