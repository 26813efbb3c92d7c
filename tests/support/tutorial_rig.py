"""The rig file of docs/tutorial.md: its TOML blocks, in order (the tutorial's RV-40E bench)."""

from __future__ import annotations

import re
from pathlib import Path

from rvcoax.loadcases.cases import paired_cases

__all__ = ["CASES", "PAGE", "page", "rig_text"]

PAGE = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"
CASES = paired_cases([0.801, 4.006], [82.4, 412.0])


def page() -> str:
    return PAGE.read_text(encoding="utf-8")


def rig_text() -> str:
    return "\n".join(re.findall(r"```toml\n(.*?)```", page(), re.S))
