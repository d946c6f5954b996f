"""Fuzz project files: mutated `flexgvt init --data` projects through load_project (which opens and
checks every file they name) and the first steps of `flexgvt run`.

    python bench/fuzz_project.py --n 2400 --seed 1 --timeout 20 --out fuzz-project

Bases: the project `flexgvt init --data` writes (FRFs in data/*.uff, reference.json) and a variant
with modes already identified (modes/outboard.json with key, modes/inboard.csv, modes/outboard.uff,
a test point CSV; flexgvt.workflow.template.write_modes_example). Each case changes one thing: a
value replaced by a wrong type, a negative, a huge number, 0, empty, nan/inf, a string with '[' or
rich markup, a wrong unit, or (for a path) a missing, binary, device, folder, 5,000-character, NUL,
'../' or absolute path; a key deleted or unknown key added; a list item dropped or repeated; or a
named data file corrupted (truncated, lines dropped, bytes changed, numbers replaced). Steps: load_project;
each configuration's modes read (identify_configuration) and mapped to the model (measured); the objective;
PolyMAX identification when the change touched an FRF test table; the free-flying prediction when it
touched the prediction, the suspension or a configuration. Updating itself is not run (every
variable is bound and checked by load_project; one iteration costs seconds).
Outcomes and reproducers as bench/fuzz_uff.py (OUT/summary.json, OUT/reproducers/<group>/).
"""

from __future__ import annotations

import copy
import json
import math
import re
import shutil
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import fuzzlib  # noqa: E402
import fuzz_uff  # noqa: E402

VALUES = ["[", "[/bold]", "", "abc", -1, 0, 1, 2, -1e-3, 1e308, -1e308, 10**18, float("nan"), float("inf"),
          float("-inf"), True, False, [], [-1], ["["], [0.1], {}, {"a": 1}, "17 kg", "1e400", "-5 N/m", "0 Hz",
          "1 m", 3.5, 1e-300, "x" * 300]
PATHS = ["missing.json", "data/outboard.uff", "project.toml", "/proc/self/status", "/dev/null", ".", "data",
         "x" * 5000, "a\x00b", "../outside", "/tmp", "~nouser_zz/x", "modes/outboard.json", "modes/inboard.csv",
         "modes/outboard.uff", "modes/points.csv", "reference.json", "", "data/", "reference.json/x"]
PATH_KEYS = {"frfs", "modes", "points", "reference", "bdf", "directory"}
AREAS = ["model", "suspension_tests", "configurations", "configurations", "configurations", "variables",
         "objective", "optimiser", "prediction", "outputs", "project", "file", "file", "structure"]


# ---------------------------------------------------------------- a small TOML writer (inline tables)
def _toml(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v) if -2**63 <= v < 2**63 else repr(float(v))
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v == math.inf else ("-inf" if v == -math.inf else repr(v)))
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {_toml(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def dumps(doc: dict) -> str:
    """One line per top-level key (line reduction then drops whole tables)."""
    return "\n".join(f"{json.dumps(k)} = {_toml(v)}" for k, v in doc.items()) + "\n"


# ---------------------------------------------------------------- bases
def build_bases(folder: Path) -> dict[str, dict]:
    """Write the init --data project (+ modes files) into ``folder``; returns {name: parsed project}."""
    from flexgvt.workflow.template import write_example, write_modes_example
    write_example(folder)
    write_modes_example(folder)
    return bases_from(folder)


def bases_from(folder: Path) -> dict[str, dict]:
    """The two base projects of a folder build_bases wrote: its project.toml (FRFs identified by
    PolyMAX) and the variant with modes already identified (JSON with key, CSV, UFF 55 check)."""
    frfs = tomllib.loads((folder / "project.toml").read_text())
    modes = copy.deepcopy(frfs)
    out, inb = modes["configurations"]
    out["test"] = {"modes": "modes/outboard.json", "key": "data", "points": "modes/points.csv"}
    inb["test"] = {"modes": "modes/inboard.csv", "points": "case"}
    modes["configurations"].append({"name": "outboard_check", "from": "outboard", "role": "check",
                                    "test": {"modes": "modes/outboard.uff", "points": "case"}})
    return {"frfs": frfs, "modes": modes}


def _leaves(node, path=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(node, list) and node and all(isinstance(x, (dict, list)) for x in node):
        for i, v in enumerate(node):
            yield from _leaves(v, path + (i,))
    else:
        yield path, node


def _containers(node, path=()):
    if isinstance(node, (dict, list)):
        yield path, node
        for k, v in (node.items() if isinstance(node, dict) else enumerate(node)):
            yield from _containers(v, path + (k,))


def _get(doc, path):
    for p in path:
        doc = doc[p]
    return doc


def _corrupt_text(data: bytes, rng) -> tuple[bytes, str]:
    kind = int(rng.integers(4))
    if kind == 0:
        cut = int(rng.integers(0, max(1, len(data))))
        return data[:cut], f"truncated at byte {cut}"
    if kind == 1:
        lines = data.split(b"\n")
        del lines[int(rng.integers(len(lines)))]
        return b"\n".join(lines), "a line deleted"
    if kind == 2:
        nums = list(re.finditer(rb"-?\d+\.?\d*(?:[eE][-+]?\d+)?", data))
        if nums:
            m = nums[int(rng.integers(len(nums)))]
            new = [b"nan", b"1e400", b"-1", b"0", b"[]", b'"x"', b"1e308", b"null", b"[1, [2]]"][int(rng.integers(9))]
            return data[:m.start()] + new + data[m.end():], f"number at byte {m.start()} -> {new.decode()}"
    b = bytearray(data)
    for _ in range(int(rng.integers(1, 6))):
        b[int(rng.integers(len(b)))] = int(rng.integers(0, 256))
    return bytes(b), "random bytes"


def mutate(doc: dict, files: dict[str, bytes], rng) -> tuple[dict, dict[str, bytes], str]:
    """(mutated project, extra files {name: bytes}, description)."""
    doc = copy.deepcopy(doc)
    area = AREAS[int(rng.integers(len(AREAS)))]
    if area == "file":  # a named data file corrupted
        named = sorted({v for _, v in _leaves(doc) if isinstance(v, str) and v in files})
        name = named[int(rng.integers(len(named)))]
        if name.endswith(".uff"):
            data, what = fuzz_uff.mutate(files[name], rng)
        else:
            data, what = _corrupt_text(files[name], rng)
        new = "corrupt_" + name.replace("/", "_")
        for path, v in list(_leaves(doc)):
            if v == name:
                _get(doc, path[:-1])[path[-1]] = new
        return doc, {new: data}, f"{name} corrupted ({what})"
    if area == "structure":
        conts = [(p, c) for p, c in _containers(doc) if p]
        path, c = conts[int(rng.integers(len(conts)))]
        kind = int(rng.integers(4))
        if isinstance(c, dict) and c and kind < 2:
            key = list(c)[int(rng.integers(len(c)))]
            del c[key]
            return doc, {}, f"{_fmt(path)}.{key} deleted"
        if isinstance(c, dict):
            c["colour" if kind == 2 else "Name"] = 1
            return doc, {}, f"unknown key in {_fmt(path)}"
        if c and kind < 2:
            del c[int(rng.integers(len(c)))]
            return doc, {}, f"an item of {_fmt(path)} deleted"
        if c:
            c.append(copy.deepcopy(c[int(rng.integers(len(c)))]))
            return doc, {}, f"an item of {_fmt(path)} repeated"
        return doc, {}, "no change"
    leaves = [(p, v) for p, v in _leaves(doc) if p and p[0] == area] or list(_leaves(doc))
    path, old = leaves[int(rng.integers(len(leaves)))]
    if path[-1] in PATH_KEYS and rng.random() < 0.7:
        value = PATHS[int(rng.integers(len(PATHS)))]
    elif isinstance(old, list) and old and rng.random() < 0.5:  # one item of a list
        value = list(old)
        value[int(rng.integers(len(value)))] = VALUES[int(rng.integers(len(VALUES)))]
    else:
        value = VALUES[int(rng.integers(len(VALUES)))]
    _get(doc, path[:-1])[path[-1]] = value
    return doc, {}, f"{_fmt(path)} = {_toml(value)[:60]}"


def _fmt(path) -> str:
    return "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in path).lstrip(".")


# ---------------------------------------------------------------- the case, in the worker
_WORK: dict[str, Path] = {}


def run_case(payload) -> str:
    """Worker side: the project folder (a copy of the base, once per worker) with this project file and
    its corrupt files; load_project and the first steps."""
    import warnings

    from flexgvt.workflow import identify_configuration, load_project, measured
    from flexgvt.workflow.steps import objective, predict

    base, text, extra, steps = payload
    if base not in _WORK:
        _WORK[base] = Path(tempfile.mkdtemp(prefix="fuzz_project_")) / "p"
        shutil.copytree(base, _WORK[base])
    folder = _WORK[base]
    for f in folder.glob("corrupt_*"):
        f.unlink()
    for name, data in extra.items():
        (folder / name).write_bytes(data)
    (folder / "project.toml").write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        project = load_project(folder / "project.toml")
        objective(project)
        for c in project.spec.configurations:
            if c.test is not None and (c.test.modes is not None or c.name in steps):
                measured(identify_configuration(project, c.name), project)
        if "predict" in steps and project.spec.prediction.free_free:
            predict(project, project.model, n_modes=4)
    return "loaded"


def _steps(doc: dict, what: str) -> tuple[str, ...]:
    steps = []
    for k, c in enumerate(doc.get("configurations", []) if isinstance(doc.get("configurations"), list) else []):
        if isinstance(c, dict) and isinstance(c.get("test"), dict) and "frfs" in c["test"] and \
                (what.startswith(f"configurations[{k}].test") or (what.startswith("data/") and c.get("name") in what)):
            steps.append(str(c.get("name")))
    if what.startswith(("prediction", "suspension_tests", "configurations", "reference.json")):
        steps.append("predict")
    return tuple(steps)


def _clear():
    from flexgvt.errors import FlexGVTError
    return (FlexGVTError,)


def fuzz(n: int, seed: int, timeout: float, out: Path | None = None, base: Path | None = None, reduce: bool = True,
         log=print) -> fuzzlib.Tally:
    """Run ``n`` mutated project files; returns the Tally (and writes OUT/summary.json, OUT/reproducers)."""
    rng = np.random.default_rng(seed)
    if base is None:
        base = Path(tempfile.mkdtemp(prefix="fuzz_project_base_")) / "init-data"
    docs = bases_from(base) if (base / "modes").is_dir() else build_bases(base)
    files = {str(p.relative_to(base)): p.read_bytes() for p in base.rglob("*") if p.is_file()}
    tally = fuzzlib.Tally()
    clear = _clear()
    t0 = time.perf_counter()
    with fuzzlib.Worker(timeout=timeout) as worker:
        for case in range(n):
            which = ("frfs", "modes")[int(rng.integers(2))]
            doc, extra, what = mutate(docs[which], files, rng)
            payload = (str(base), dumps(doc), extra, _steps(doc, what))
            result = worker.run(run_case, payload, clear)
            new = tally.add(f"{case}: {which} base, {what}", result)
            if new and out is not None:
                _save(out / "reproducers" / fuzz_uff._safe(new), payload, result, worker, clear, reduce, log)
            if log and (case + 1) % 200 == 0:
                log(f"{case + 1} cases, {time.perf_counter() - t0:.0f} s: {tally.counts}")
    if out is not None:
        tally.write(out / "summary.json", n=n, seed=seed, timeout_s=timeout,
                    elapsed_s=round(time.perf_counter() - t0, 1))
    return tally


def _save(folder: Path, payload, result, worker, clear, reduce: bool, log) -> None:
    base, text, extra, steps = payload
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "original.toml").write_text(text)
    for name, data in extra.items():
        (folder / name).write_bytes(data)
    (folder / "error.txt").write_text(f"{result['class']} at {result['site']}: {result['message']}\nsteps: {steps}\n"
                                      f"base: {base} (flexgvt init --data + write_modes_example)\n")
    if not reduce or result["outcome"] == "hang":
        return
    key = fuzzlib.site_key(result)

    def still_fails(lines):
        got = worker.run(run_case, (base, "\n".join(lines), extra, steps), clear)
        return got["outcome"] in fuzzlib.Tally.BAD and fuzzlib.site_key(got) == key

    minimal = fuzzlib.reduce_lines(text.splitlines(), still_fails, max_tries=60)
    (folder / "minimal.toml").write_text("\n".join(minimal) + "\n")
    if log:
        log(f"new failure {key}: {len(minimal)} line(s) kept in {folder}")


def main(argv=None) -> int:
    return fuzzlib.main(argv, __doc__, fuzz, n=2400, out="fuzz-project", what="project files",
                        columns=(("loaded, first steps run", "loaded"),))

if __name__ == "__main__":
    sys.exit(main())
