"""Check a report page in headless Chromium: console errors, every plotly plot drawn, a screenshot.

    run = start_chromium(Path("report.html"), workdir, screenshot=Path("shot.png"))
    check = finish(run)        # PageCheck(errors=[...], plots=[(id, drew_svg, has_webgl_canvas), ...])
"""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass
from html.parser import HTMLParser
from pathlib import Path

from ..errors import FlexGVTError

FLAGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
         "--enable-logging=stderr", "--v=0", "--virtual-time-budget=15000", "--hide-scrollbars"]


@dataclass(frozen=True)
class PageCheck:
    """errors: console lines reporting an error; plots: (div id, drew its svg layers, has a WebGL
    canvas) per plotly div of the rendered DOM."""

    errors: list[str]
    plots: list[tuple[str, bool, bool]]

    @property
    def undrawn(self) -> list[str]:
        return [p[0] for p in self.plots if not p[1]]


def chromium() -> str | None:
    """Path of Debian's chromium, or None."""
    return shutil.which("chromium")


def start_chromium(page: Path, workdir: Path, screenshot: Path | None = None,
                   window: tuple[int, int] = (1280, 2000)) -> subprocess.Popen:
    """Chromium rendering ``page`` in the background with its own profile (several can run at once)."""
    exe = chromium()
    if exe is None:
        raise FlexGVTError("chromium is not installed (Debian: apt-get install chromium)")
    workdir.mkdir(parents=True, exist_ok=True)
    extra = [f"--screenshot={screenshot}", f"--window-size={window[0]},{window[1]}"] if screenshot else []
    return subprocess.Popen([exe, *FLAGS, f"--user-data-dir={workdir / 'profile'}", *extra, "--dump-dom",
                             Path(page).resolve().as_uri()], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def console_errors(stderr: str) -> list[str]:
    """Console messages that are errors: Chromium logs every console message as
    `...:INFO:CONSOLE:<line>] "<message>", source: ...`; uncaught exceptions start with "Uncaught"."""
    return [ln for ln in stderr.splitlines() if "CONSOLE" in ln and re.search(r"Uncaught|Error", ln)]


class _Plots(HTMLParser):
    """Per plotly div of the dumped DOM: [id, has a main-svg, has a canvas (3D, WebGL)]."""

    def __init__(self):
        super().__init__()
        self.stack: list[int | None] = []
        self.plots: list[list] = []

    def handle_starttag(self, tag, attrs):
        cls = (dict(attrs).get("class") or "").split()
        owner = next((s for s in reversed(self.stack) if s is not None), None)
        if "plotly-graph-div" in cls:
            self.plots.append([dict(attrs).get("id"), False, False])
            owner = len(self.plots) - 1
        if owner is not None:
            self.plots[owner][1] |= "main-svg" in cls
            self.plots[owner][2] |= tag == "canvas"
        if tag == "div":
            self.stack.append(owner if "plotly-graph-div" in cls else None)

    def handle_endtag(self, tag):
        if tag == "div" and self.stack:
            self.stack.pop()


def finish(proc: subprocess.Popen, timeout: float = 120.0) -> PageCheck:
    """Wait for a start_chromium run and parse what it rendered."""
    stdout, stderr = proc.communicate(timeout=timeout)
    parser = _Plots()
    parser.feed(stdout)
    return PageCheck(console_errors(stderr), [tuple(p) for p in parser.plots])


def check_page(page: Path, workdir: Path, screenshot: Path | None = None) -> PageCheck:
    """Render ``page`` and check it (see PageCheck)."""
    return finish(start_chromium(page, workdir, screenshot))
