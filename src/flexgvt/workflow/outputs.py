"""Outputs of a run: the updated model as Nastran bulk data, identified and predicted modes as UFF 55,
and the prediction tables as CSV."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..model import Configuration
from ..report.html import write_csv


def write_outputs(res, out: Path) -> dict[str, str]:
    """Write what the project's [outputs] table asks for into ``out``; returns {name: path}."""
    spec = res.project.spec.outputs
    files: dict[str, str] = {}
    if spec.bdf and res.update is not None:
        files["bdf"] = str(write_updated_bdf(res, out / "updated.bdf"))
    if spec.uff:
        for name, item in res.identified.items():
            path = write_identified_uff(res.project, item, out / f"identified-{name}.uff")
            if path is not None:
                files[f"identified {name}"] = str(path)
        for key, pred in res.predictions.items():
            files[f"prediction {key}"] = str(write_modes_uff(pred.free, out / f"predicted-free-free-{key}.uff"))
    for key, pred in res.predictions.items():
        path = out / f"prediction-{key}.csv"
        write_csv(pred.rows, path)  # flexgvt.report's: None as an empty cell, floats in full
        files[f"prediction table {key}"] = str(path)
    return files


def write_updated_bdf(res, path: Path) -> Path:
    """The user's deck with updated values, or a compact deck (one free-free subcase) for a built-in model."""
    from ..io import write_bdf
    project = res.project
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the writer's notes on split properties are expected here
        if project.deck is not None:
            return write_bdf(res.update.model, path, template=project.deck)
        return write_bdf(res.update.model, path, configurations=[Configuration("free_free")],
                         n_modes=project.spec.prediction.n_modes + 6)


def write_identified_uff(project, item, path: Path) -> Path | None:
    """Identified modes as UFF 55 at the test points (with their geometry, dataset 15)."""
    from ..io.uff import ModalResults, TestGeometry, shapes_at_points, write_uff
    if item.shapes is None:
        return None
    points, shapes = shapes_at_points(np.real(item.shapes), item.outputs)
    node_map, offsets = project.sensors.get(item.configuration, ({}, {}))
    model = project.model
    xyz = []
    for p in points:
        node = node_map.get(int(p), int(p))
        try:
            base = model.xyz[model.index_of([node])[0]]
        except Exception:  # a test point with no FE node: geometry left at the origin
            base = np.zeros(3)
        xyz.append(base + np.asarray(offsets.get(int(p), np.zeros(3)), float))
    return write_uff(path, geometry=TestGeometry(np.asarray(points), np.asarray(xyz)),
                     modes=ModalResults(item.frequencies_hz, item.damping_ratio, shapes, np.asarray(points)))


def write_modes_uff(modes, path: Path) -> Path:
    """FE modes (translations at every node, deformed geometry) as UFF 15 + 55."""
    from ..io.uff import ModalResults, TestGeometry, write_uff
    ids = np.asarray(modes.node_ids)
    return write_uff(path, geometry=TestGeometry(ids, np.asarray(modes.state.positions)),
                     modes=ModalResults(np.asarray(modes.frequencies_hz), np.zeros(len(modes.frequencies_hz)),
                                        np.asarray(modes.shapes)[:, :, :3], ids))
