"""The test side of a project run's report, as plain rows and arrays: the test set-up (suspension points
as identified, cords, added masses, boundary conditions, sensors), the identified modes' quality
(damping with standard deviations, MPC, MPD), their auto-MAC, COMAC per sensor, measured against
synthesised FRFs with the MIF, modelled damping, units of design variables and the reason of every
unpaired mode. Computations are flexgvt.ema's and flexgvt.correlation's; this module only gathers."""

from __future__ import annotations

import warnings

import numpy as np

from ..correlation import auto_mac, comac, shapes_of
from ..ema import frac, mif, resynthesize
from ..errors import FlexGVTError
from ..modal import mac_rows
from .content import FRFComparison

_AXES = ("X", "Y", "Z", "RX", "RY", "RZ")
_BEAM_UNITS = {"E": "Pa", "G": "Pa", "rho": "kg/m^3", "A": "m^2", "Ay": "m^2", "Az": "m^2", "Iy": "m^4",
               "Iz": "m^4", "J": "m^4", "Ip": "m^4", "width": "m", "height": "m", "thickness": "m",
               "outer_radius": "m", "inner_radius": "m"}
_OTHER_UNITS = {"mass": "kg", "offset_x": "m", "offset_y": "m", "offset_z": "m", "along": "m",
                "stiffness": "N/m", "damping": "N s/m", **{f"k{i}": "N/m" for i in (1, 2, 3)},
                **{f"k{i}": "N m/rad" for i in (4, 5, 6)}, **{f"c{i}": "N s/m" for i in (1, 2, 3)},
                **{f"c{i}": "N m s/rad" for i in (4, 5, 6)}}


def variable_unit(kind: str, attribute: str) -> str:
    """The SI unit of a design variable's attribute (models hold SI values), '' when unknown."""
    if kind == "beam":
        return _BEAM_UNITS.get(attribute, "")
    return _OTHER_UNITS.get(attribute, "")


def dof_name(point: int, code: int) -> str:
    """'10+Z' for test point 10, UFF direction code +3."""
    return f"{int(point)}{'+' if code > 0 else '-'}{_AXES[abs(int(code)) - 1]}" if 1 <= abs(code) <= 6 else \
        f"{int(point)}:{int(code)}"


def _percent(v) -> float | None:
    return None if v is None or not np.isfinite(v) else 100.0 * float(v)


def unpaired_reason(row: dict, update, name: str) -> str:
    """Why measured mode row['mode'] of configuration ``name`` is unpaired, where the updating result
    says (row keys 'unpaired_reason' or 'reason', a dict or text under 'unpaired', or the result's
    ``unpaired`` {configuration: [{mode, reason}]}); '' when it does not."""
    for key in ("unpaired_reason", "reason"):
        if row.get(key):
            return str(row[key])
    u = row.get("unpaired")
    if isinstance(u, dict) and u.get("reason"):
        return str(u["reason"])
    if isinstance(u, str) and u:
        return u
    listed = getattr(update, "unpaired", None)
    entries = listed.get(name) if isinstance(listed, dict) else None
    for e in entries if isinstance(entries, (list, tuple)) else ():
        if isinstance(e, dict) and e.get("mode") == row.get("mode") and e.get("reason"):
            return str(e["reason"])
    return ""


def damping_known(item) -> bool:
    """Whether the test data give damping: not when every ratio is exactly 0 with no standard deviation
    (what the readers fill in for a table of frequencies only, e.g. a CSV without damping_ratio)."""
    z = item.damping_ratio
    return z is not None and (item.damping_std is not None or bool(np.any(np.asarray(z) != 0)))


def measured_damping(item, i: int) -> dict:
    """The measured damping of mode i [%] and its standard deviation [%] (None where unknown)."""
    z = item.damping_ratio[i] if damping_known(item) else None
    sd = None if item.damping_std is None else item.damping_std[i]
    return {"measured_damping_percent": _percent(z), "measured_damping_std_percent": _percent(sd)}


def test_mode_rows(item, labels=()) -> list[dict]:
    """One row per identified mode: frequency and damping with their standard deviations, MPC, MPD
    (labels: the modes' labels where the test data have none, e.g. those of the paired FE modes)."""
    from ..ema import mpc, mpd

    q = (mpc(item.shapes), mpd(item.shapes)) if item.shapes is not None else (None, None)
    rows, known = [], damping_known(item)
    for i, f in enumerate(item.frequencies_hz):
        sd = None if item.frequency_std_hz is None else float(item.frequency_std_hz[i])
        label = item.labels[i] if i < len(item.labels) and item.labels[i] else (labels[i] if i < len(labels) else "")
        row = {"mode": i + 1, "label": label, "frequency_hz": float(f),
               "frequency_std_hz": sd, "damping_percent": _percent(item.damping_ratio[i]) if known else None,
               "damping_std_percent": None if item.damping_std is None else _percent(item.damping_std[i])}
        if q[0] is not None:
            row.update(mpc=float(q[0][i]), mpd_deg=float(q[1][i]))
        rows.append(row)
    return rows


def test_auto_mac(item) -> np.ndarray | None:
    return None if item.shapes is None else auto_mac(np.asarray(item.shapes))


def comac_rows(item, sensors, fe_modes, paired) -> list[dict]:
    """COMAC of each sensor DOF over the paired modes (paired: analytical index per measured mode,
    -1 unpaired), with the FE node each sensor reads."""
    keep = np.flatnonzero(np.asarray(paired) >= 0)
    if item.shapes is None or sensors is None or len(keep) < 2:
        return []
    A = np.asarray(item.shapes)
    B = shapes_of(fe_modes, sensors)
    values = comac(A, B, pairs=(keep, np.asarray(paired)[keep]))
    return [{"sensor": s.name, "node": s.node, "comac": float(v)} for s, v in zip(sensors, values)]


def model_damping(state, fe, n_modes: int) -> np.ndarray | None:
    """The modelled damping ratio of each real FE mode in ``fe`` (from the complex modes of the same
    state, paired by full-shape MAC), or None when the structure carries no damper (or the complex
    eigenproblem fails)."""
    from ..fem import solve_modes

    if not getattr(state.system, "has_damping", False):
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the cautions were given when the real modes were solved
            damped = solve_modes(state, n_modes, damped=True, label=False)
    except FlexGVTError:  # the table then goes without modelled damping rather than without a report
        return None
    a = np.asarray(fe.shapes).reshape(fe.n_modes, -1)
    b = np.asarray(damped.complex_shapes if damped.complex_shapes is not None else damped.shapes)
    m = mac_rows(a, b.reshape(len(b), -1))
    out = np.asarray(damped.damping_ratio)[np.argmax(m, axis=1)]
    return np.where(np.asarray(fe.frequencies_hz) > 0, out, np.nan)


def setup_tables(project, name: str, configuration, item) -> dict[str, list[dict]]:
    """The test set-up of configuration ``name``: suspension points as identified on their blocks,
    cords, added masses, held components and sensors (point, direction, FE node, arm)."""
    spec = next(c for c in project.spec.configurations if c.name == name)
    out: dict[str, list[dict]] = {}
    blocks = {b.name: b for b in project.spec.suspension_tests}
    used = [cs.block_test for cs in (spec.cords or ()) if cs.block_test]
    if used:
        from ..workflow.project import block_point

        rows = []
        for b in dict.fromkeys(used):
            p = block_point(blocks[b])
            def sd(v, many=p.n_tests > 1):  # one test: no spread to show
                return float(v) if many else None

            rows.append({"block test": b, "tests": int(p.n_tests), "block_mass_kg": float(p.mass),
                         "damped_frequency_hz": float(p.damped_frequency_hz),
                         "frequency_hz": float(p.frequency_hz), "frequency_std_hz": sd(p.frequency_std_hz),
                         "damping_percent": _percent(p.damping_ratio),
                         "damping_std_percent": _percent(sd(p.damping_ratio_std)),
                         "stiffness_n_per_m": float(p.stiffness), "stiffness_std_n_per_m": sd(p.stiffness_std),
                         "damping_ns_per_m": float(p.damping), "damping_std_ns_per_m": sd(p.damping_std)})
        out["suspension points as identified"] = rows
    cords = []
    for k, c in enumerate(configuration.suspension):
        block = spec.cords[k].block_test if spec.cords is not None and k < len(spec.cords) else None
        cords.append({"node": c.node, "anchor_m": tuple(float(v) for v in c.anchor), "from": block or "given",
                      "stiffness_n_per_m": float(c.stiffness), "damping_ns_per_m": float(c.damping),
                      "unstretched_length_m": float(c.unstretched_length),
                      "offset_m": tuple(float(v) for v in c.offset)})
    if cords:
        out["suspension cords"] = cords
    masses = [{"name": m.name or "", "node": m.node, "mass_kg": float(m.mass),
               "offset_m": tuple(float(v) for v in np.asarray(m.offset).ravel())} for m in configuration.masses]
    if masses:
        out["added masses"] = masses
    held = [{"node": int(n), "components held": str(c)} for n, c in dict(configuration.fixed).items()]
    if held:
        out["boundary conditions"] = held
    if item is not None and item.shapes is not None:
        node_map, offsets = project.sensors.get(name, ({}, {}))
        points: dict[int, dict] = {}
        for pt, code in np.asarray(item.dofs).astype(int):
            row = points.setdefault(int(pt), {"point": int(pt), "node": int(node_map.get(int(pt), int(pt))),
                                              "directions": "", "arm_m": tuple(float(v) for v in np.asarray(
                                                  offsets.get(int(pt), np.zeros(3)), float))})
            row["directions"] = (row["directions"] + " " + dof_name(pt, code)[len(str(pt)):]).strip()
        out["sensors"] = list(points.values())
    return out


def frf_comparisons(project, name: str, item, max_curves: int = 3) -> tuple[list[FRFComparison], str]:
    """Measured against synthesised FRFs per reference in the identification band ((comparisons,
    note): the note says why there are none, or that the identified modes explain the FRFs poorly
    (median FRAC below 0.9). The FRFs are the identification's, read again from the project's files
    when the identification came from the store."""
    spec = next(c for c in project.spec.configurations if c.name == name).test
    if spec is None or (spec.frfs is None and spec.time is None):
        return [], ""
    frfs = item.frfs
    if frfs is None:
        from ..workflow.identification import measured_frfs

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # said when the run identified them
                frfs, _, _ = measured_frfs(project, spec, f"configuration '{name}' test")
        except FlexGVTError as exc:
            return [], f"the measured FRFs could not be read again: {exc}"
    f = np.asarray(frfs.frequencies_hz, float)
    band = (f > 0) & ((f >= spec.band_hz[0]) & (f <= spec.band_hz[1]) if spec.band_hz is not None else True)
    f, H = f[band], np.asarray(frfs.H)[band]
    Hs = resynthesize(f, H, item.frequencies_hz, item.damping_ratio)
    outputs = np.asarray(frfs.outputs).astype(int)
    inputs = np.asarray(frfs.inputs).astype(int)
    out, poor = [], []
    for j in range(H.shape[2]):
        ref = dof_name(*inputs[j]) if len(inputs) > j else f"reference {j + 1}"
        names = [dof_name(*o) if len(outputs) > k else f"output {k + 1}" for k, o in
                 enumerate(outputs if len(outputs) else np.zeros((H.shape[1], 2), int))]
        r = frac(H[:, :, j], Hs[:, :, j])
        curves = [("sum over outputs", np.abs(H[:, :, j]).sum(axis=1), np.abs(Hs[:, :, j]).sum(axis=1))]
        drive = [k for k in range(len(outputs)) if len(inputs) > j and tuple(outputs[k]) == tuple(inputs[j])]
        if drive:
            curves.append((f"driving point {names[drive[0]]}", H[:, drive[0], j], Hs[:, drive[0], j]))
        worst = int(np.argmin(r))
        if not drive or worst != drive[0]:
            curves.append((f"lowest FRAC {names[worst]}", H[:, worst, j], Hs[:, worst, j]))
        curves = curves[:max_curves]
        order = np.argsort(r)
        fit = [{"output": names[k], "frac": float(r[k])} for k in order[:5]]
        fit.append({"output": f"median of {len(r)} outputs", "frac": float(np.median(r))})
        if np.median(r) < 0.9:
            poor.append(f"{ref} (median FRAC {np.median(r):.2f})")
        out.append(FRFComparison(ref, f, np.column_stack([c[1] for c in curves]),
                                 np.column_stack([c[2] for c in curves]), [c[0] for c in curves],
                                 mif(H[:, :, j])[:, 0], mif(Hs[:, :, j])[:, 0], fit, item.frequencies_hz))
    note = "" if not poor else (
        f"the identified modes explain the measured FRFs poorly for reference {', '.join(poor)}: where the "
        "synthesised curve misses a peak, the identification missed a mode (widen the selection, check the band "
        "edges) and the updating did not see it")
    return out, note
