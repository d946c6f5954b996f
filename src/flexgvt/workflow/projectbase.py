"""ProjectError and the Project container (a validated project file resolved into its model,
configurations and variables): the bottom of flexgvt.workflow, which the readers and checks
(identification, validate) import without importing the loader (project.load_project)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..errors import FlexGVTError
from ..model import Configuration, Model
from .schema import ProjectFile


class ProjectError(FlexGVTError, ValueError):
    """The project file is invalid: the message names the file, the key and the remedy."""


@dataclass
class Project:
    """A validated project: its file, the parsed spec and what it resolves to.

    model: the structure (built-in case or deck); configurations: the project's test
    configurations by name (suspension, masses, loads resolved); available: every configuration
    the model defines (a case's or a deck's), for predictions; variables: the design variables;
    sensors: {configuration: (node_map, offsets)} test point -> FE node and arm [m]; stages: the
    resolved [[stages]] (flexgvt.workflow.stages.Stage), empty for a single-stage project."""

    path: Path
    spec: ProjectFile
    model: Model
    configurations: dict[str, Configuration]
    available: dict[str, Configuration]
    variables: list
    case: object | None = None
    deck: object | None = None
    sensors: dict = field(default_factory=dict)
    stages: list = field(default_factory=list)

    @property
    def folder(self) -> Path:
        return self.path.parent

    def file(self, name: str) -> Path:
        """A path of the project file, relative to its folder."""
        p = Path(name).expanduser()
        return p if p.is_absolute() else self.folder / p

    @property
    def output(self) -> Path:
        return self.file(self.spec.outputs.directory)

    @property
    def to_update(self) -> list[str]:
        return [c.name for c in self.spec.configurations if c.role == "update"]
