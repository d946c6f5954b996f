"""The report's stage sections (a staged updating): one section per stage in order, with its summary,
fixed inputs, design variables, mass properties and frequency tables and their CSVs; rendered in
headless Chromium without console errors, every plot drawn."""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest

from flexgvt.errors import ReportError
from flexgvt.report import ReportContent, StageSection, write_report


def _rows(errors_before, errors_after):
    return [{"mode": k + 1, "label": f"{k + 1} OOP", "measured_hz": 1.0 + k, "initial_hz": (1.0 + k) * (1 + a / 100),
             "updated_hz": (1.0 + k) * (1 + b / 100), "initial_error_percent": a, "updated_error_percent": b}
            for k, (a, b) in enumerate(zip(errors_before, errors_after))]


def _content() -> ReportContent:
    stages = [
        StageSection("components", [("data", "none (fixed inputs only)")],
                     fixed=[{"name": "E_spar", "kind": "shell", "attribute": "E", "before": 64.75e9, "value": 45e9,
                             "change_percent": -30.5}]),
        StageSection("shaker table <GVT>", [("data", "clamped"), ("objective", "0.03 -> 1e-4")],
                     variables=[{"name": "E_pa12", "initial": 1.8e9, "updated": 1.36e9, "change_percent": -24.5,
                                 "bounds": (0.75, 1.25)}],
                     frequencies={"clamped": _rows([3.0, -8.0, 5.0], [0.2, -0.1, 0.3])},
                     mass=[{"property": "mass [kg]", "measured": 4.1, "initial": 4.3, "updated": 4.12}]),
        StageSection("wind tunnel", variables=[{"name": "k_root", "initial": 1e3, "updated": 2e3}],
                     frequencies={"papa": _rows([1.0, 2.0], [0.1, -0.2])}, notes=["papa: measured mode 3 unpaired"]),
    ]
    return ReportContent("stages", summary=[("stages", "1. components -> 2. shaker table -> 3. wind tunnel")],
                         stages=stages)


def test_each_stage_is_a_section_in_order_with_its_tables(tmp_path):
    page = write_report(_content(), tmp_path)
    html = page.read_text(encoding="utf-8")
    titles = re.findall(r"<h2>(Stage [^<]*)</h2>", html)
    assert titles == ["Stage 1 of 3: components", "Stage 2 of 3: shaker table &lt;GVT&gt;", "Stage 3 of 3: wind tunnel"]
    assert html.index("Fixed inputs") < html.index("Mass properties") < html.index("Frequencies: papa")
    assert "papa: measured mode 3 unpaired" in html
    tables = sorted(p.name for p in (tmp_path / "tables").iterdir())
    assert any(n.endswith("_fixed_inputs.csv") and n.startswith("stage-1") for n in tables)
    assert any(n.endswith("_clamped_frequencies.csv") and n.startswith("stage-2") for n in tables)
    with open(next((tmp_path / "tables").glob("stage-2*_variables.csv")), newline="") as f:
        assert next(csv.DictReader(f))["name"] == "E_pa12"
    assert any(p.name.startswith("stage-3") for p in (tmp_path / "figures").iterdir())


def test_stages_must_be_stage_sections():
    with pytest.raises(ReportError, match="StageSection"):
        ReportContent("x", stages=[{"name": "one"}])


def test_the_stage_sections_render_in_chromium(tmp_path):
    from flexgvt.report.browser import check_page, chromium
    if chromium() is None:
        pytest.skip("chromium not installed: apt-get install chromium")
    page = write_report(_content(), tmp_path / "out", figures=False, tables=False)
    check = check_page(page, tmp_path, screenshot=tmp_path / "shot.png")
    assert check.errors == [] and len(check.plots) == 2 and check.undrawn == []
    from matplotlib.image import imread
    shot = imread(tmp_path / "shot.png")
    assert shot.shape[0] > 500 and np.std(shot[..., :3]) > 0.05  # drawn, not a blank page
