"""The main job: a project file -> identified modes -> updated model -> free-flying prediction.

    project = fg.workflow.load_project("project.toml")      # validated before anything long runs
    result = fg.workflow.run(project, progress=print)           # resumable from the project's store
    fg.report.write_project_report(result)                   # the report: the face renders, not the workflow

Each step is a public function a script can call on its own: identify_configuration, update_model, check,
predict, write_outputs.
"""

from .deck import SubcaseResult, solve_deck
from .identification import Identified, identify, identify_configuration, measured, read_modes
from .outputs import write_outputs
from .project import Project, ProjectError, load_project
from .runner import RunInterrupted, RunResult, identify_all, run
from .steps import Prediction, check, objective, predict, score, update_model
from .template import example_project, write_example

__all__ = ["Identified", "Prediction", "Project", "ProjectError", "RunInterrupted", "RunResult", "check",
           "example_project", "write_example", "identify", "identify_all", "identify_configuration", "measured",
           "load_project",
           "objective", "predict", "read_modes", "run", "score", "SubcaseResult", "solve_deck", "update_model",
           "write_outputs"]
