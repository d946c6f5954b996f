"""Shared by the bench scripts: machine description, rewriting one section of docs/benchmarks.md, and
loading an example script as a module."""

from __future__ import annotations

import importlib.util
import os
import platform
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"


def machine_info(packages=("numpy", "scipy", "numba", "flexgvt", "openseespy", "sdypy-EMA")):
    """(cpu name, cores available, {package: version}); flexgvt's version carries the git commit."""
    cpu = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                                check=False).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "src"], cwd=ROOT, capture_output=True, text=True,
                               check=False).stdout.strip()
        commit += " (+ uncommitted src changes)" if dirty else ""
    except OSError:
        commit = "?"
    from importlib.metadata import PackageNotFoundError, version
    vers = {"python": platform.python_version()}
    for name in packages:
        try:
            vers[name] = version(name) + (f" @ {commit}" if name == "flexgvt" else "")
        except PackageNotFoundError:
            pass
    return cpu, len(os.sched_getaffinity(0)), vers


def write_section(title: str, text: str, path: Path = DOC) -> None:
    """Replace (or append) the section headed ``title`` of a markdown file, keeping every other section."""
    old = (path.read_text() if path.exists()
           else "# Benchmarks\n\nScripts in bench/ print these tables; numbers below are from their last run.\n")
    pattern = re.compile(rf"^{re.escape(title)}\n.*?(?=^## |\Z)", re.S | re.M)
    if pattern.search(old):
        new = pattern.sub(lambda _: text.rstrip() + "\n\n", old)
    else:
        new = old.rstrip() + "\n\n" + text.rstrip() + "\n"
    path.write_text(new.rstrip() + "\n")


def load_example(relative: str, name: str):
    """examples/<relative> (a script with main(argv)) as a module named ``name``, for its functions."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / relative)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
