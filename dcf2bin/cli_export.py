"""Commands: export: other systems' object dictionaries (issue 5)."""
from __future__ import annotations

COMMANDS: list = []
