"""Rewrite docs/settings.md from the settings themselves (flexgvt.workflow.settingsdoc.settings_page).

    python bench/settingsdoc.py
"""

from __future__ import annotations

from pathlib import Path

from flexgvt.workflow.settingsdoc import settings_page

DOC = Path(__file__).resolve().parents[1] / "docs" / "settings.md"

if __name__ == "__main__":
    DOC.write_text(settings_page() + "\n", encoding="utf-8")
    print(f"wrote {DOC}")
