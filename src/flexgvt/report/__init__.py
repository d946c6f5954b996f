"""Figures and reports.

`write_report(ReportContent(...), out_dir)` writes a self-contained HTML report (plotly, offline)
with PNG figures and CSV tables beside it; the content is plain data (report.content), so any
script can build one. `plots` holds matplotlib helpers taking solver objects (states, modes).
`write_project_report(result)` writes the report of a flexgvt.workflow run (report.project).
"""

from .content import (ConfigurationSection, FRFComparison, Geometry, ModeShape, ReportContent, StabilisationData,
                      StageSection)
from .html import format_value, render, table_html, write_csv, write_report

__all__ = ["ConfigurationSection", "FRFComparison", "Geometry", "ModeShape", "ReportContent", "StabilisationData",
           "StageSection", "build_report_content", "format_value", "render", "table_html", "write_csv",
           "write_project_report", "write_report"]


def __getattr__(name: str):
    if name in ("build_report_content", "write_project_report"):  # loads the workflow: only on use
        from . import project
        return getattr(project, name)
    raise AttributeError(f"module 'flexgvt.report' has no attribute {name!r}")
