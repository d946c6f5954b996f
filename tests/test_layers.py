"""The layers of docs/architecture.md hold: every import in src/flexgvt (module-level and inside
functions, absolute and relative) points to its own package or to a layer strictly below, no two
packages or modules import each other in a circle, no package imports another's private names, and
only the face draws. There is no exemption list: a violation is fixed in the code."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "flexgvt"

# Bottom first; a package may import its own modules and any package of a lower row, nothing on
# its row or above (docs/architecture.md, the project design's layer table: imports only point
# down). The facade flexgvt/__init__.py sits above every row and no package imports it.
LAYERS = (
    ("errors", "_threads"),      # the error hierarchy and the thread policy, usable by all
    ("model", "data", "modal"),  # plain data: the structural model; shipped tables; modes and FRFs
    ("io",),                     # file formats: reads into model, never calls the solver
    ("cases",),                  # built-in structures: data, import model, io, data, errors only
    ("fem", "ema"),              # numerics: the structural solver; experimental modal analysis
    ("correlation",),            # MAC, pairing, sensors
    ("updating", "suspension"),  # methods
    ("workflow",),               # a project run: returns results, never renders
    ("report",),                 # renders results of any layer, read only by the face
    ("cli",),                    # the face
)
RANK = {package: rank for rank, row in enumerate(LAYERS) for package in row}
FACADE = "flexgvt"
DRAWING = {"matplotlib", "plotly"}  # imported only by the layers that render
RENDERERS = {"report", "cli"}


def module_name(path: Path, root: Path = SRC) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(source: str, module: str, is_package: bool, modules: set[str]):
    """(target, line, imported names) of every import statement in ``source`` (the whole tree:
    inside functions, classes and conditionals too). Targets are the flexgvt module named, or the
    module a ``from X import y`` resolves y to when y is a module; external imports are kept
    with their top-level name (for the drawing rule)."""
    package = module if is_package else module.rpartition(".")[0]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno, ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                assert base, f"{module}:{node.lineno}: relative import above the flexgvt package"
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                yield (sub if sub in modules else target), node.lineno, (alias.name,)


def top(module: str) -> str:
    """The top-level subpackage (or module) of flexgvt a module belongs to; FACADE for flexgvt itself."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else FACADE


def scan(root: Path = SRC):
    """{module: path} and the list of (source, target, line, names) import edges under ``root``."""
    paths = {module_name(p, root): p for p in sorted(root.rglob("*.py"))}
    modules = set(paths)
    edges = []
    for module, path in paths.items():
        for target, line, names in imports(path.read_text(encoding="utf-8"), module, path.name == "__init__.py",
                                           modules):
            edges.append((module, target, line, names))
    return paths, edges


def owner(target: str, modules: set[str]) -> str:
    """The flexgvt module that defines ``target`` (a module, or a name inside one)."""
    while target not in modules:
        target = target.rpartition(".")[0]
    return target


def violations(root: Path = SRC) -> dict[str, list[str]]:
    paths, edges = scan(root)
    modules = set(paths)
    found: dict[str, list[str]] = {"unknown package": [], "upward or sideways": [], "private name": [],
                                   "drawing below the face": [], "package cycle": [], "module cycle": []}
    package_graph: dict[str, set[str]] = {}
    module_graph: dict[str, set[str]] = {m: set() for m in modules}
    for source, target, line, names in edges:
        where = f"{paths[source].relative_to(root.parent)}:{line}"
        src = top(source)
        if target.split(".")[0] != "flexgvt":
            if target.split(".")[0] in DRAWING and src not in RENDERERS:
                found["drawing below the face"].append(f"{where}: {source} imports {target}")
            continue
        dst = top(target)
        if FACADE != src and (src not in RANK or dst not in RANK and dst != FACADE):
            found["unknown package"].append(f"{where}: {source} -> {target}: place the package in LAYERS")
            continue
        if src == FACADE:  # the facade may import anything (lazily)
            continue
        if src != dst:
            package_graph.setdefault(src, set()).add(dst)
            if dst == FACADE or RANK[dst] >= RANK[src]:
                found["upward or sideways"].append(f"{where}: {source} ({src}) imports {target} ({dst})")
            inner = target.split(".")[2:] + [n for n in names if f"{target}.{n}" not in modules]
            private = [p for p in inner if p.startswith("_")]
            if private and dst != FACADE:
                found["private name"].append(f"{where}: {source} imports {private} of {dst}")
        else:
            dep = owner(target, modules)
            if dep != source:
                module_graph[source].add(dep)
    found["package cycle"] = [" -> ".join(c) for c in cycles(package_graph)]
    found["module cycle"] = [" -> ".join(c) for c in cycles(module_graph)]
    return {kind: v for kind, v in found.items() if v}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one node (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_every_import_points_down_and_nothing_imports_in_a_circle():
    paths, edges = scan()
    # The walk sees the package (not a vacuous pass): every subpackage, and imports inside functions.
    assert {top(m) for m in paths} - {FACADE} == set(RANK) - set()
    assert len(paths) > 100 and len(edges) > 500
    found = violations()
    assert not found, "\n".join(f"{kind}:\n  " + "\n  ".join(v) for kind, v in found.items())


def _package(tmp_path: Path, files: dict[str, str]) -> Path:
    root = tmp_path / "flexgvt"
    for name, text in {"__init__.py": "", **files}.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    for d in {p.parent for p in root.rglob("*.py")}:
        (d / "__init__.py").touch()
    return root


@pytest.mark.parametrize("files, kind", [
    # a function-level relative import from a data layer up into a method layer
    ({"cases/xhale.py": "def f():\n    from .. import updating\n", "updating/__init__.py": ""},
     "upward or sideways"),
    # sideways on one row: ema reaching into fem
    ({"ema/polymax.py": "from ..fem.linsolve import serial_blas\n", "fem/linsolve.py": "serial_blas = 1\n"},
     "upward or sideways"),
    # a package importing the facade
    ({"fem/modes.py": "import flexgvt\n"}, "upward or sideways"),
    # a private name of a lower package
    ({"updating/problem.py": "from ..fem.modes import _rigid_count\n", "fem/modes.py": "_rigid_count = 1\n"},
     "private name"),
    # drawing in a numerics package
    ({"ema/plots.py": "def f():\n    import matplotlib.pyplot\n"}, "drawing below the face"),
    # two modules of one package importing each other, one of them through `from . import x`
    ({"ema/polymax.py": "def f():\n    from . import refine\n", "ema/refine.py": "from .polymax import g\n"},
     "module cycle"),
    # a package __init__ and its submodule (the cases._Case() helper)
    ({"cases/__init__.py": "from .xhale import xhale\nclass Case: pass\n",
      "cases/xhale.py": "def xhale():\n    from . import Case\n"}, "module cycle"),
    # a package not placed in the table
    ({"shells/__init__.py": "from ..fem import x\n", "fem/__init__.py": "x = 1\n"}, "unknown package"),
])
def test_the_checker_finds_each_kind_of_violation(tmp_path, files, kind):
    found = violations(_package(tmp_path, files))
    assert kind in found, found


def test_the_checker_accepts_what_the_layers_allow(tmp_path):
    root = _package(tmp_path, {
        "updating/verify.py": "def f():\n    from ..cases import cantilever_strip\n",  # down to data
        "cases/__init__.py": "from .case import Case\nfrom .xhale import xhale\n",
        "cases/case.py": "class Case: pass\n", "cases/xhale.py": "from .case import Case\n",
        "report/plots.py": "import matplotlib\nfrom ..ema.indicators import cmif\n",
        "ema/indicators.py": "from .._threads import serial_blas\n", "_threads.py": "serial_blas = 1\n",
        "__init__.py": "def __getattr__(name):\n    from . import workflow\n",  # the facade
    })
    assert violations(root) == {}
