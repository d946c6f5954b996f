"""Figures and reports.

`write_report(ReportContent(...), out_dir)` writes a self-contained HTML report (plotly, offline)
with PNG figures and CSV tables beside it; the content is plain data (report.content), so any
script can build one. `plots` holds matplotlib helpers taking solver objects (states, modes).
"""

from .content import ConfigurationSection, Geometry, ModeShape, ReportContent, StabilisationData
from .html import format_value, render, table_html, write_csv, write_report

__all__ = ["ConfigurationSection", "Geometry", "ModeShape", "ReportContent", "StabilisationData",
           "format_value", "render", "table_html", "write_csv", "write_report"]
