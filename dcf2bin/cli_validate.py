"""Commands: validate: lint DCF/EDS files and containers (issue 4)."""
from __future__ import annotations

COMMANDS: list = []
