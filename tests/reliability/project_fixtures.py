"""A project folder as `flexgvt init --data` writes it (plus modes already identified), built once
per test session and copied for each test that mutates it."""

import shutil
from pathlib import Path


DATA = Path(__file__).parents[1] / "data" / "reliability"


def build_base(folder: Path) -> Path:
    """write_example (data/*.uff, reference.json, project.toml) + write_modes_example (modes/*), on one
    BLAS thread (its 1,200 small solves take three times longer with two on a shared machine)."""
    from threadpoolctl import threadpool_limits

    from flexgvt.workflow.template import write_example, write_modes_example
    with threadpool_limits(1):
        write_example(folder)
        write_modes_example(folder)
    return folder


def project_copy(base: Path, dest: Path, reproducer: Path | None = None) -> Path:
    """A copy of the base project folder in ``dest``; with ``reproducer`` (a folder of
    tests/data/reliability/toml), its minimal.toml becomes project.toml and its corrupt_* files are
    put beside it. Returns the project file."""
    shutil.copytree(base, dest)
    if reproducer is not None:
        shutil.copy(reproducer / "minimal.toml", dest / "project.toml")
        for f in reproducer.glob("corrupt_*"):
            shutil.copy(f, dest / f.name)
    return dest / "project.toml"
