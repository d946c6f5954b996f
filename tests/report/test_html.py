"""The HTML report: files, CSVs, escaping, offline; rendered in headless Chromium (console errors,
every plot drawn, screenshot not blank)."""

from __future__ import annotations

import csv
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from flexgvt.errors import ReportError
from flexgvt.report import (
    ConfigurationSection,
    Geometry,
    ModeShape,
    ReportContent,
    StabilisationData,
    write_report,
)
from flexgvt.report.browser import chromium, finish, start_chromium

LABEL = "1B <b>bold</b>"  # must come out escaped


def _beam(n: int = 20, span: float = 8.0) -> Geometry:
    y = np.linspace(0.0, span, n)
    xyz = np.column_stack([np.zeros(n), y, np.zeros(n)])
    # a beam along the span plus a small chordwise cross member at the tip
    xyz = np.vstack([xyz, [[-0.3, span, 0.0], [0.3, span, 0.0]]])
    edges = [(i, i + 1) for i in range(n - 1)] + [(n - 1, n), (n - 1, n + 1)]
    return Geometry(xyz, np.array(edges))


def _section(name: str, sag: float, rng: np.random.Generator) -> ConfigurationSection:
    und = _beam()
    y = und.xyz[:, 1] / und.xyz[:, 1].max()
    dfm = Geometry(und.xyz + np.column_stack([0 * y, 0 * y, -sag * y**2]), und.edges)
    n_modes = 4
    labels = [LABEL, "1T", "2B", "1IP"]
    fe = np.array([1.2, 3.4, 5.9, 7.1]) * (1 + sag / 10)
    test = fe * (1 + rng.normal(0, 0.03, n_modes))
    updated = test * (1 + rng.normal(0, 0.003, n_modes))
    shapes = []
    for k in range(n_modes):
        d = np.zeros((len(und.xyz), 3))
        if k in (0, 2):
            d[:, 2] = np.sin((k + 1) * np.pi * y / 2)
        elif k == 1:
            d[:, 2] = y * und.xyz[:, 0] + 0.1 * y
        else:
            d[:, 0] = y**2
        shapes.append(d)
    pts = np.arange(2, 22, 3)
    modes = [ModeShape(label=labels[k], analytical_hz=updated[k], measured_hz=test[k], mac=0.9 + 0.01 * k,
                       displacement=shapes[k], measured_xyz=dfm.xyz[pts],
                       measured_displacement=-3.0 * shapes[k][pts] + rng.normal(0, 0.02, (len(pts), 3)))
             for k in range(n_modes)]
    mac0 = np.clip(np.eye(n_modes) * 0.8 + rng.uniform(0, 0.2, (n_modes, n_modes)), 0, 1)
    mac1 = np.clip(np.eye(n_modes) * 0.95 + rng.uniform(0, 0.05, (n_modes, n_modes)), 0, 1)
    table = [dict(mode=k + 1, label=labels[k], measured_hz=test[k], initial_hz=fe[k], updated_hz=updated[k],
                  initial_error_percent=100 * (fe[k] / test[k] - 1),
                  updated_error_percent=100 * (updated[k] / test[k] - 1),
                  mac_initial=mac0[k, k], mac_updated=None if k == 3 else mac1[k, k])
             for k in range(n_modes)]
    f = np.linspace(0.5, 9.0, 400)
    indicator = sum(1.0 / np.abs(fk**2 - f**2 + 0.05j * fk * f) for fk in test)
    orders = np.repeat(np.arange(4, 40, 2), n_modes + 2)
    poles = np.tile(np.r_[test, 2.3, 8.5], len(orders) // (n_modes + 2)) * (1 + rng.normal(0, 0.004, len(orders)))
    stable = rng.uniform(size=len(orders)) > 0.3
    stab = StabilisationData(f, indicator, orders, poles, stable, selected_hz=test)
    return ConfigurationSection(name, und, dfm, table, mac0, mac1, labels, [f"FE {lab}" for lab in labels],
                                stab, modes)


def synthetic_content() -> ReportContent:
    rng = np.random.default_rng(7)
    variables = [dict(name=f"EI_{k} <i>", initial=1.0e4 * (k + 1), updated=1.0e4 * (k + 1) * (1 + 0.05 * k),
                      change_percent=5.0 * k, std_percent=None if k == 4 else 0.5 + 0.3 * k, bounds=(0.5, 2.0))
                 for k in range(5)]
    evol = dict(load_factors=np.linspace(0, 1, 6),
                frequencies_hz=np.outer(1 + 0.2 * np.linspace(0, 1, 6), [1.2, 3.4, 5.9]), labels=["1B", "1T", "2B"])
    prediction = [dict(mode=k + 1, label=lab, free_hz=f, truth_hz=None if k == 2 else f * 1.01,
                       error_percent=None if k == 2 else -0.99, bungee_hz=0.3)
                  for k, (lab, f) in enumerate([("1B", 1.1), ("1T", 3.3), ("2B", 5.7)])]
    return ReportContent(
        title="Synthetic <wing> report", summary=[("model", "beam & tip"), ("objective", "1.2e-2 -> 3.4e-5")],
        configurations=[_section("outboard <a>", 0.4, rng), _section("inboard", 0.8, rng)],
        variables=variables, history=list(np.geomspace(1.0, 1e-5, 12)), load_evolution=evol,
        prediction=prediction, prediction_title="Free-flying prediction", notes=["a <note> & more"])


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    return write_report(synthetic_content(), tmp_path_factory.mktemp("report"))


def test_files_tables_and_escaping(report):
    out = report.parent
    pngs = sorted(p.name for p in (out / "figures").glob("*.png"))
    for stem in ("outboard_a_deformed", "outboard_a_mac", "outboard_a_frequency_errors", "inboard_deformed",
                 "inboard_stabilisation", "design_variables", "history", "frequency_vs_load"):
        assert f"{stem}.png" in pngs
    with open(out / "tables" / "inboard_frequencies.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 4 and rows[0]["label"] == LABEL and rows[3]["mac_updated"] == ""
    assert float(rows[1]["measured_hz"]) > 0
    with open(out / "tables" / "design_variables.csv", newline="") as fh:
        assert len(list(csv.DictReader(fh))) == 5
    with open(out / "tables" / "prediction.csv", newline="") as fh:
        assert [r["truth_hz"] == "" for r in csv.DictReader(fh)] == [False, False, True]
    text = report.read_text()
    assert not re.search(r"<script[^>]*\bsrc\s*=", text, re.IGNORECASE)  # nothing loaded from outside
    assert not re.search(r"<link[^>]*https?://", text, re.IGNORECASE)
    assert text.count("plotly.js v") >= 1 and text.count("window.PlotlyConfig") == 1  # embedded once
    assert "<b>bold</b>" not in text and "1B &lt;b&gt;bold&lt;/b&gt;" in text
    assert "Synthetic &lt;wing&gt; report" in text and "a &lt;note&gt; &amp; more" in text


def test_bad_shapes_raise():
    with pytest.raises(ReportError, match="xyz"):
        Geometry(np.zeros((4, 2)), np.zeros((0, 2)))
    with pytest.raises(ReportError, match="edges"):
        Geometry(np.zeros((4, 3)), [[0, 4]])
    with pytest.raises(ReportError, match="mac_initial"):
        ConfigurationSection("c", _beam(), _beam(), mac_initial=np.eye(3), measured_labels=["a", "b"],
                             analytical_labels=["a", "b"])


def test_empty_parts_left_out(tmp_path):
    g = _beam()
    content = ReportContent("bare", configurations=[ConfigurationSection("only", g, g)])
    text = write_report(content, tmp_path).read_text()
    assert "Stabilisation" not in text and "Design variables" not in text and text.count('class="plot"') == 1
    assert [p.name for p in (tmp_path / "figures").iterdir()] == ["only_deformed.png"]



def test_local_modes_are_explained_where_a_table_has_them(tmp_path):
    g = _beam()
    row = dict(mode=1, label="1 OOP", measured_hz=1.0, initial_hz=1.01, updated_hz=1.0, initial_error_percent=1.0,
               updated_error_percent=0.0)
    texts = [write_report(ReportContent("box", configurations=[ConfigurationSection(
        "c", g, g, [row, dict(row, mode=2, label=label)])]), tmp_path / label[2:].replace("/", "_")).read_text()
        for label in ("2 OOP", "1 LOCAL/OOP")]
    assert "LOCAL: a mode whose energy is mostly local" not in texts[0]
    assert "LOCAL: a mode whose energy is mostly local" in texts[1]

# ---------------------------------------------------------------- headless Chromium

def _start(page: Path, workdir: Path, *args: str) -> subprocess.Popen:
    if chromium() is None:
        pytest.skip("chromium not installed: apt-get install chromium")
    shot = Path(args[0].split("=", 1)[1]) if args else None
    return start_chromium(page, workdir, screenshot=shot)


def _dom_check(proc: subprocess.Popen) -> tuple[list[str], list]:
    check = finish(proc)
    return check.errors, [list(p) for p in check.plots]


@pytest.fixture(scope="module")
def rendered(report, tmp_path_factory):
    """The report (DOM + 1280x2000 screenshot) and a broken copy (a thrown error; plot2 cannot be
    drawn), rendered side by side: {"good": (errors, plots), "broken": ..., "shot": png path}."""
    work = tmp_path_factory.mktemp("chromium")
    text, n = re.subn(r'Plotly\.newPlot\((\s*)"plot2"', r'Plotly.newPlotTypo(\1"plot2"', report.read_text())
    assert n == 1
    broken = work / "broken.html"
    broken.write_text(text)
    shot = work / "shot.png"
    (work / "a").mkdir()
    (work / "b").mkdir()
    good = _start(report, work / "a", f"--screenshot={shot}")
    bad = _start(broken, work / "b")
    return {"good": _dom_check(good), "broken": _dom_check(bad), "shot": shot}


def test_chromium_renders_every_plot(report, rendered):
    n_divs = len(re.findall(r'class="plotly-graph-div"', report.read_text()))
    errors, plots = rendered["good"]
    assert errors == []
    assert len(plots) == n_divs == 13  # 2 x (shape, stabilisation, MAC, errors, modes) + 3
    assert [p[0] for p in plots if not p[1]] == []  # every plot drew its svg layers
    assert sum(p[2] for p in plots) == 4  # the 3D ones (2 shapes, 2 animations) a WebGL canvas


def test_chromium_check_can_fail(rendered):
    """The broken copy must fail both checks: an uncaught error, plot2 not drawn."""
    errors, plots = rendered["broken"]
    assert any("Uncaught" in e for e in errors)
    assert [p[0] for p in plots if not p[1]] == ["plot2"]


def test_chromium_screenshot_not_blank(rendered):
    import matplotlib.image

    img = matplotlib.image.imread(rendered["shot"])
    assert img.shape[:2] == (2000, 1280)
    assert float(img[..., :3].std()) > 0.05  # a blank page: 0; this report: about 0.2
    # the WebGL deformed shape (first plot, below the header) is drawn: its blue line is there
    blue = np.abs(img[300:900, :, :3] - np.array([0x1F, 0x5F, 0xBF]) / 255).max(axis=-1) < 0.08
    assert blue.sum() > 300


def test_chromium_plays_a_mode_animation(report, tmp_path):
    """The animated mode shapes move: Plotly.animate to a frame at the peak of the cycle changes the
    analytical wireframe by that frame's displacement (checked in the page, headless)."""
    text = report.read_text()
    div = re.search(r"Plotly\.addFrames\('(plot\d+)'", text).group(1)
    probe = """<script>
window.addEventListener('load', function () {
  var gd = document.getElementById('%s');
  var frames = gd._transitionData._frames, half = 0;
  while (half < frames.length && !/f8$/.test(frames[half].name)) half++;
  var before = gd.data[1].z.slice(), target = frames[half].data[0].z, expect = 0;
  for (var i = 0; i < target.length; i++)
    if (target[i] !== null) expect = Math.max(expect, Math.abs(target[i] - before[i]));
  Plotly.animate(gd, [frames[half].name],
                 {mode: 'immediate', frame: {duration: 0, redraw: true}, transition: {duration: 0}})
    .then(function () {
      var after = gd.data[1].z, moved = 0;
      for (var i = 0; i < after.length; i++)
        if (after[i] !== null) moved = Math.max(moved, Math.abs(after[i] - before[i]));
      var out = document.createElement('pre'); out.id = 'probe';
      out.textContent = 'expect=' + expect + ' moved=' + moved;
      document.body.appendChild(out);
    });
});
</script>""" % div
    page = tmp_path / "probe.html"
    page.write_text(text.replace("</body>", probe + "</body>"))
    proc = _start(page, tmp_path / "chromium")
    stdout, _ = proc.communicate(timeout=120)
    got = re.search(r'<pre id="probe">expect=([0-9.e+-]+) moved=([0-9.e+-]+)', stdout)
    assert got, "the probe did not run"
    expect, moved = float(got.group(1)), float(got.group(2))
    assert expect > 0 and moved == pytest.approx(expect, rel=1e-9)


# ---------------------------------------------------------------- design variables, FRFs, auto-MAC, COMAC

def _variables():
    """Four variables: one moved 3 % +- 1 %, one at its bound, one with a +-2434 % sigma, one the data cannot see."""
    return [dict(name="E_root", unit="Pa", initial=7e10, updated=7.21e10, change_percent=3.0, std_percent=1.0,
                 bounds=(0.8, 1.2), at_bound=False, identifiable=True),
            dict(name="k_tail", unit="N/m", initial=1e4, updated=2e4, change_percent=100.0, std_percent=4.0,
                 bounds=(0.5, 2.0), at_bound=True, identifiable=True),
            dict(name="G_tip", unit="Pa", initial=2.6e10, updated=2.5e10, change_percent=-4.0, std_percent=2434.0,
                 bounds=(0.9, 1.1), at_bound=False, identifiable=True),
            dict(name="rho_tip", unit="kg/m^3", initial=1600.0, updated=1650.0, change_percent=3.1, std_percent=None,
                 bounds=(0.9, 1.1), at_bound=False, identifiable=False)]


def test_design_variable_chart_keeps_a_huge_sigma_from_squashing_the_others():
    from flexgvt.report.figures import variable_bars

    d = variable_bars(_variables())
    assert d["status"] == ["identifiable", "at bound", "sigma > bounds", "not identifiable"]
    assert d["names"] == ["E_root [Pa]", "k_tail [N/m]", "G_tip [Pa]", "rho_tip [kg/m^3]"]
    # the +-2434 % bar is drawn to its +-10 % bounds and flagged; the axis is set by the 100 % change
    assert d["shown"][2] == pytest.approx(10.0) and list(d["clipped"]) == [False, False, True, False]
    assert d["range"] == pytest.approx((-14.0 - 0.15 * 118.0, 104.0 + 0.5 * 118.0))  # room above for the sigmas
    alone = variable_bars([dict(r, bounds=None) for r in _variables()[:1] + _variables()[2:3]])
    assert alone["shown"][1] == pytest.approx(2 * 5.0) and alone["range"][1] < 20  # no bounds: twice the largest change


def test_frf_auto_mac_and_comac_sections_render(tmp_path):
    from flexgvt.report import FRFComparison

    f = np.linspace(0.5, 9.0, 300)
    H = np.column_stack([1 / (fk**2 - f**2 + 0.05j * fk * f) for fk in (1.2, 3.4)])
    comp = FRFComparison("10+Z", f, H, 1.01 * H, ["sum over outputs", "driving point 10+Z"],
                         np.linspace(1, 0, 300), np.linspace(1, 0, 300),
                         [{"output": "3+X", "frac": 0.61234}, {"output": "median of 4 outputs", "frac": 0.99}],
                         np.array([1.2, 3.4]))
    with pytest.raises(ReportError, match="measured"):
        FRFComparison("r", f, H[:10], H, ["a", "b"])
    g = _beam()
    sec = ConfigurationSection("wing", g, g, auto_mac=np.array([[1.0, 0.2], [0.2, 1.0]]), frfs=[comp],
                               comac=[{"sensor": "1+Z", "node": 3, "comac": 0.97}, {"sensor": "2+X", "node": 4,
                                                                                  "comac": 0.41}],
                               setup={"sensors": [{"point": 1, "node": 3, "directions": "+Z", "arm_m": (0, 0, 0)}]},
                               test_modes=[{"mode": 1, "frequency_hz": 1.2, "frequency_std_hz": 0.00123,
                                            "damping_percent": 1.5, "mpc": 0.9987, "mpd_deg": 2.34}],
                               notes=["mode 2 is unpaired: MAC below the floor"])
    text = write_report(ReportContent("t", configurations=[sec], variables=_variables()), tmp_path).read_text()
    for title in ("Test set-up: sensors", "Test modes", "Measured and synthesised FRFs", "Auto-MAC of the test modes",
                  "COMAC per sensor", "wing: reference 10+Z", "mode 2 is unpaired: MAC below the floor"):
        assert title in text
    assert ">0.0012<" in text and ">0.999<" in text and ">2.3<" in text  # std to 2 digits, MPC 3 decimals, deg 0.1
    pngs = {p.name for p in (tmp_path / "figures").iterdir()}
    assert {"wing_frfs.png", "wing_auto_mac.png", "wing_comac.png", "design_variables.png"} <= pngs
    with open(tmp_path / "tables" / "wing_frf_fit_10_Z.csv", newline="") as fh:
        assert next(csv.DictReader(fh))["frac"] == "0.612"
    with open(tmp_path / "tables" / "design_variables.csv", newline="") as fh:
        assert [r["unit"] for r in csv.DictReader(fh)] == ["Pa", "N/m", "Pa", "kg/m^3"]


def test_an_identifiable_variable_without_a_sigma_is_not_called_unidentifiable():
    """No more residuals than variables (no sigma at all): the identifiable ones read 'sigma unknown'
    (or 'at bound'), not 'not identifiable' beside identifiable = yes."""
    from flexgvt.report.figures import STATUS_COLOURS, design_variables, variable_bars

    rows = [dict(name=n, change_percent=c, std_percent=None, bounds=(0.8, 1.2), at_bound=b, identifiable=i)
            for n, c, b, i in (("E", -10.6, False, True), ("rho", 5.0, True, True), ("G", 20.0, True, False))]
    d = variable_bars(rows)
    assert d["status"] == ["sigma unknown", "at bound", "not identifiable"]
    assert "sigma unknown" in STATUS_COLOURS
    design_variables(rows)  # the PNG's legend takes the new status
