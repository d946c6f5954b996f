"""The container every built-in case returns (plain data; the bottom of flexgvt.cases)."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..model import Configuration, Model


@dataclass
class Case:
    """A built-in structure: model, configurations by name, reference values and a description."""

    name: str
    model: Model
    configurations: dict[str, Configuration]
    description: str
    references: dict = field(default_factory=dict)
    sensors: dict = field(default_factory=dict)
