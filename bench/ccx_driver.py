"""CalculiX (ccx) driver shared by the benchmarks and the tests: S8R input decks of an fg.Model's
shell quads, runs with CPU accounting, and readers of the .dat and .frd files.

    deck = s8r_deck(model, fixed_nodes, steps=[Frequency(15)])
    run = run_ccx(deck, "unloaded")            # CcxRun: frequencies, shapes, prints, CPU and wall [s]

S8R: each 4-node quad becomes an 8-node quad with mid-side nodes (numbered after the model's
largest node id; the model's own ids are kept). A shell group's non-structural mass becomes a
raised density of its own material (rho + nsm / t: the same mass and gravity load; the rotary
inertia of the carried mass through the thickness differs, negligibly for thin plates).
``imperfection`` offsets the corner and mid-side nodes by a function of position (the same
stress-free geometry a flexgvt Configuration.imperfection gives at the corner nodes).

Needs ``ccx`` on the path (Debian: apt-get install calculix-ccx); runs with OMP_NUM_THREADS=2.
"""

from __future__ import annotations

import resource
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

G0 = 9.80665  # [m/s^2]


@dataclass(frozen=True)
class Static:
    """A geometrically nonlinear (NLGEOM) static step under gravity ``gravity_g`` (3 components in g,
    as a *DLOAD GRAV on every element), incremented from ``first`` to at most ``largest`` of the load."""

    gravity_g: tuple[float, float, float]
    first: float = 0.1
    largest: float = 0.25
    print_nodes: tuple[int, ...] = ()  # node ids whose displacements go to the .dat (last increment read)
    loads: tuple[tuple[int, int, float], ...] = ()  # (node id, DOF 1-6, value [N or N m]) as *CLOAD


@dataclass(frozen=True)
class Frequency:
    """``n`` modes (a PERTURBATION step about the previous static step's state when there is one)."""

    n: int


@dataclass
class CcxRun:
    frequencies_hz: np.ndarray
    shapes: dict[int, np.ndarray]  # node id -> (n_modes, 3) modal translations (last n_modes DISP blocks)
    displacements: dict[int, np.ndarray]  # node id -> (3,) last printed static displacement [m]
    reaction: np.ndarray  # (3,) total reaction force of the fixed nodes at the end of the static step [N]
    mass_kg: float  # the elements' mass (EMAS of a static step; nan without one)
    cpu_s: float
    wall_s: float
    peak_rss_mb: float
    version: str = ""
    files: dict[str, str] = field(default_factory=dict)


def have_ccx() -> bool:
    return shutil.which("ccx") is not None


def version() -> str:
    """CalculiX's version line ('This is Version 2.20')."""
    p = subprocess.run(["ccx", "-v"], capture_output=True, text=True)
    return " ".join(line.strip() for line in p.stdout.splitlines() if "Version" in line)


def _lines(ids) -> list[str]:
    ids = list(ids)
    return [", ".join(map(str, ids[k:k + 12])) for k in range(0, len(ids), 12)]


def s8r_deck(model, fixed: list[int] | np.ndarray, steps: list, imperfection: Callable | None = None,
             tip_set: list[int] | None = None) -> tuple[str, dict]:
    """The CalculiX input of ``model``'s shell quads as S8R (isotropic ShellProperty groups), the
    nodes ``fixed`` clamped (with the mid-side nodes between two of them), and ``steps`` (Static,
    Frequency). imperfection(xyz (n, 3)) -> offsets (n, 3) [m] of the stress-free geometry.
    Returns the deck and {'mid': {(a, b): id}, 'n_nodes': count}."""
    ids = np.asarray(model.node_ids)
    xyz0 = np.asarray(model.xyz, float)
    pos = {int(n): k for k, n in enumerate(ids)}
    next_id = int(ids.max()) + 1
    mid: dict[tuple[int, int], int] = {}
    mid_xyz = []
    blocks, materials = [], []
    eid = 0
    for g, group in enumerate(model.shells):
        prop = group.property
        mat = prop.membrane
        if group.nodes.shape[1] != 4 or not hasattr(mat, "E") or prop.thickness is None:
            raise ValueError(f"s8r_deck: shell group '{group.name}' is not isotropic quads of one thickness")
        name = f"G{g}"
        rho = mat.rho + prop.nsm / prop.thickness
        nu = mat.nu if mat.nu is not None else mat.E / (2 * mat.G) - 1
        materials += [f"*MATERIAL, NAME=M{g}", "*ELASTIC", f"{mat.E:.10g}, {nu:.10g}", "*DENSITY", f"{rho:.10g}",
                      f"*SHELL SECTION, ELSET={name}, MATERIAL=M{g}", f"{prop.thickness:.10g}"]
        blocks.append(f"*ELEMENT, TYPE=S8R, ELSET={name}")
        for q in group.nodes:
            eid += 1
            m = []
            for c in range(4):
                a, b = int(q[c]), int(q[(c + 1) % 4])
                key = (min(a, b), max(a, b))
                if key not in mid:
                    mid[key] = next_id
                    next_id += 1
                    mid_xyz.append(0.5 * (xyz0[pos[a]] + xyz0[pos[b]]))
                m.append(mid[key])
            blocks.append(", ".join(str(v) for v in [eid, *map(int, q), *m]))
    all_ids = np.r_[ids, np.arange(int(ids.max()) + 1, next_id)]
    xyz = np.vstack([xyz0, np.array(mid_xyz).reshape(-1, 3)])
    if imperfection is not None:
        xyz = xyz + imperfection(xyz)
    lines = ["*NODE"] + [f"{n}, {x:.12g}, {y:.12g}, {z:.12g}" for n, (x, y, z) in zip(all_ids, xyz)]
    lines += blocks
    at_fixed = {int(n) for n in fixed}
    root = sorted(at_fixed | {v for (a, b), v in mid.items() if a in at_fixed and b in at_fixed})
    lines += ["*NSET, NSET=ROOT"] + _lines(root)
    lines += ["*ELSET, ELSET=EALL"] + _lines([f"G{g}" for g in range(len(model.shells))])
    lines += materials + ["*BOUNDARY", "ROOT, 1, 6"]
    static = False
    for step in steps:
        if isinstance(step, Static):
            g = np.asarray(step.gravity_g, float)
            norm = float(np.linalg.norm(g))
            d = g / norm
            lines += ["*STEP, NLGEOM, INC=500", "*STATIC", f"{step.first:g}, 1.0, 1e-6, {step.largest:g}", "*DLOAD",
                      f"EALL, GRAV, {G0 * norm:.10g}, {d[0]:.10g}, {d[1]:.10g}, {d[2]:.10g}",
                      "*NODE PRINT, NSET=ROOT, TOTALS=ONLY", "RF", "*EL PRINT, ELSET=EALL, TOTALS=ONLY", "EMAS"]
            if step.loads:
                lines[-6:-6] = ["*CLOAD"] + [f"{n}, {d}, {v:.10g}" for n, d, v in step.loads]
            if step.print_nodes:
                lines[lines.index("*NSET, NSET=ROOT"):lines.index("*NSET, NSET=ROOT")] = \
                    ["*NSET, NSET=PRINTED"] + _lines(step.print_nodes)
                lines += ["*NODE PRINT, NSET=PRINTED", "U"]
            lines += ["*END STEP"]
            static = True
        else:
            lines += ["*STEP, PERTURBATION" if static else "*STEP", "*FREQUENCY", f"{step.n}",
                      "*NODE FILE, OUTPUT=2D", "U", "*END STEP"]
    return "\n".join(lines) + "\n", {"mid": mid, "n_nodes": len(all_ids)}


def read_frequencies(dat: Path) -> np.ndarray:
    """Frequencies [Hz] of the last eigenvalue table of a CalculiX .dat file."""
    text = dat.read_text().splitlines()
    start = max(k for k, line in enumerate(text) if "E I G E N V A L U E   O U T P U T" in line)
    out = []
    for line in text[start + 1:]:
        parts = line.split()
        if len(parts) == 5 and parts[0].isdigit():
            out.append(float(parts[3]))
        elif out and not line.strip():
            break
    return np.array(out)


def read_printed(dat: Path, heading: str) -> list[list[float]]:
    """Rows (node id then values) of the last block of the .dat file whose heading starts with
    ``heading``, before any eigenvalue output (print requests carry over into a frequency step,
    which prints them for every mode)."""
    text = dat.read_text().splitlines()
    eigen = [k for k, line in enumerate(text) if "E I G E N V A L U E" in line]
    text = text[:eigen[0]] if eigen else text
    starts = [k for k, line in enumerate(text) if line.strip().startswith(heading)]
    if not starts:
        return []
    rows = []
    for line in text[starts[-1] + 1:]:
        parts = line.split()
        if parts and all(_number(p) for p in parts):
            rows.append([float(p) for p in parts])
        elif rows:
            break
    return rows


def _number(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def read_frd_displacements(frd: Path) -> list[dict[int, list[float]]]:
    """Every DISP block of a .frd file: {node id: [ux, uy, uz]}."""
    blocks, current = [], None
    with frd.open() as f:
        for line in f:
            if line.startswith(" -4  DISP"):
                current = {}
            elif current is not None and line.startswith(" -1"):
                current[int(line[3:13])] = [float(line[13 + 12 * k:25 + 12 * k]) for k in range(3)]
            elif current is not None and line.startswith(" -3"):
                blocks.append(current)
                current = None
    return blocks


class CcxTimeout(RuntimeError):
    """CalculiX stopped after ``timeout`` seconds of wall time (cpu_s: its CPU seconds by then)."""

    def __init__(self, message: str, cpu_s: float, wall_s: float):
        super().__init__(message)
        self.cpu_s, self.wall_s = cpu_s, wall_s


def read_frd_nodes(frd: Path) -> dict[int, np.ndarray]:
    """The node coordinates block of a .frd file (the expanded nodes of shells included)."""
    out, inside = {}, False
    with frd.open() as f:
        for line in f:
            if line.startswith("    2C"):
                inside = True
            elif inside and line.startswith(" -1"):
                out[int(line[3:13])] = np.array([float(line[13 + 12 * k:25 + 12 * k]) for k in range(3)])
            elif inside and line.startswith(" -3"):
                break
    return out


def _deck_nodes(deck: str) -> dict[int, np.ndarray]:
    out, inside = {}, False
    for line in deck.splitlines():
        if line.startswith("*"):
            inside = line.strip().upper() == "*NODE"
        elif inside:
            parts = line.split(",")
            out[int(parts[0])] = np.array([float(v) for v in parts[1:4]])
    return out


def _mid_surface(blocks: list[dict], frd: Path, deck: str, nodes: list[int]) -> dict[int, int]:
    """frd node id of each shell node: itself, or (when CalculiX wrote its expanded 3-D nodes, as it does
    in a PERTURBATION step) the expanded node at the shell node's own position (mid-surface)."""
    missing = [n for n in nodes if n not in blocks[0]]
    if not missing:
        return {n: n for n in nodes}
    from scipy.spatial import cKDTree
    frd_xyz = read_frd_nodes(frd)
    have = np.array([n for n in blocks[0] if n in frd_xyz])
    tree = cKDTree(np.array([frd_xyz[n] for n in have]))
    mine = _deck_nodes(deck)
    d, k = tree.query(np.array([mine[n] for n in missing]))
    if d.max() > 1e-7:
        raise RuntimeError(f"ccx: no expanded node at shell node {missing[int(np.argmax(d))]} ({d.max():.3g} m off)")
    out = {n: n for n in nodes if n in blocks[0]}
    out.update({n: int(have[j]) for n, j in zip(missing, k)})
    return out


def run_ccx(deck: str, name: str, keep: Path | None = None, threads: int = 2, nice: int = 0,
            shapes_of: list[int] | None = None, timeout: float | None = None) -> CcxRun:
    """Run ``deck`` as ``name``.inp in a temporary folder (or ``keep``); CPU seconds from the child's
    rusage (all its threads). shapes_of: node ids whose modal translations are read (None: all).
    timeout: wall seconds, then CcxTimeout with the CPU seconds spent."""
    if not have_ccx():
        raise RuntimeError("CalculiX (ccx) is not installed: apt-get install calculix-ccx")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(keep or tmp)
        work.mkdir(parents=True, exist_ok=True)
        (work / f"{name}.inp").write_text(deck)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t = time.perf_counter()
        cmd = (["nice", "-n", str(nice)] if nice else []) + ["ccx", name]
        proc = subprocess.Popen(cmd, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                env={"OMP_NUM_THREADS": str(threads), "PATH": "/usr/bin:/bin"})
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            raise CcxTimeout(f"ccx {name} stopped after {timeout:g} s wall ({cpu:.0f} s CPU)", cpu,
                             time.perf_counter() - t) from None
        p = subprocess.CompletedProcess(cmd, proc.returncode, stdout, stderr)
        wall = time.perf_counter() - t
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if p.returncode != 0 or "*ERROR" in p.stdout:
            tail = "\n".join((p.stdout + p.stderr).splitlines()[-15:])
            raise RuntimeError(f"ccx {name} failed (return code {p.returncode}):\n{tail}")
        return read_run(work, name, deck, shapes_of,
                        (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), wall,
                        after.ru_maxrss / 1024)


def read_run(work: Path, name: str, deck: str, shapes_of: list[int] | None = None, cpu_s: float = float("nan"),
             wall_s: float = float("nan"), peak_rss_mb: float = float("nan")) -> CcxRun:
    """The results of a finished run of ``deck`` as ``name`` in folder ``work``."""
    dat, frd = work / f"{name}.dat", work / f"{name}.frd"
    freq = read_frequencies(dat) if "*FREQUENCY" in deck else np.zeros(0)
    shapes = {}
    if len(freq):
        blocks = read_frd_displacements(frd)[-len(freq):]
        nodes = [int(n) for n in (shapes_of if shapes_of is not None else sorted(blocks[0]))]
        at = _mid_surface(blocks, frd, deck, nodes) if blocks else {}
        shapes = {n: np.array([b[at[n]] for b in blocks]) for n in nodes}
    printed = read_printed(dat, "displacements (vx,vy,vz)")
    rf = read_printed(dat, "total force (fx,fy,fz)")
    mass = read_printed(dat, "total mass for set")
    return CcxRun(freq, shapes, {int(r[0]): np.array(r[1:4]) for r in printed},
                  np.array(rf[-1][-3:]) if rf else np.zeros(3), mass[-1][0] if mass else float("nan"),
                  cpu_s, wall_s, peak_rss_mb)
